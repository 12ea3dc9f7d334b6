"""The UP domain (planning/model.py): encodings, granularities, rule numbers never typed in."""

from __future__ import annotations

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.errors import CompileError
from ocplus_plan.planning import compile
from ocplus_plan.planning.model import ENCODINGS, GRANULARITIES, build_domain, schemas
from ocplus_plan.sim import make_rules, new_state


@pytest.mark.parametrize("encoding", ENCODINGS)
@pytest.mark.parametrize("granularity", GRANULARITIES)
def test_domain_has_every_kitchen_action(encoding: str, granularity: str) -> None:
    dom = build_domain(encoding, granularity)
    kinds = {s.kind for s in dom.schemas.values()}
    assert {"move", "pick", "put", "chop", "wash", "plate_put", "plate_take", "trash",
            "deliver"} <= kinds
    assert "cook" in dom.actions and "cook_rest" in dom.actions
    if encoding == "classical":
        assert all(not hasattr(a, "duration") for a in dom.actions.values())
        assert set(dom.costs) == set(dom.actions.values())
    else:
        assert all(hasattr(a, "duration") for a in dom.actions.values())


def test_domain_is_built_once_per_options() -> None:
    # plan map-back looks the domain up once per plan action: it must not rebuild it
    assert build_domain("classical", "stations", 3) is build_domain("classical", "stations", 3)
    assert build_domain("temporal", "cells") is not build_domain("classical", "cells")


def test_move_cost_is_distance_for_stations_and_one_for_cells() -> None:
    move = {g: next(s for s in schemas("classical", g) if s.name == "move")
            for g in GRANULARITIES}
    assert move["stations"].cost == ("dist", "s1", "s2")
    assert move["cells"].cost == 1


def test_temporal_cook_is_an_envelope_between_cook_and_burn_time() -> None:
    cook = build_domain("temporal", "stations").actions["cook"]
    interval = cook.duration
    assert str(interval.lower) == "cook_lo_full" and str(interval.upper) == "cook_hi_full"
    assert not interval.is_left_open() and not interval.is_right_open()


def test_deliver_and_trash_exist_for_every_plate_size_up_to_k_max() -> None:
    names = set(build_domain("classical", "stations", 4).actions)
    for k in range(1, 5):
        assert {f"deliver{k}", f"deliver{k}_dirty", f"trash_plate{k}"} <= names
    assert "deliver5" not in names


def test_unknown_options_are_compile_errors_that_name_the_choices() -> None:
    with pytest.raises(CompileError, match="classical, temporal"):
        build_domain("pddl+", "stations")
    with pytest.raises(CompileError, match="stations, cells"):
        build_domain("classical", "rooms")
    with pytest.raises(CompileError, match="1 to 9"):
        build_domain("classical", "stations", 0)


def _numbers(preset: str, **overrides: object) -> dict:
    state = new_state(make_rules(preset, **overrides), 0)
    return compile(state).numbers


def test_rule_numbers_come_from_the_rules_object() -> None:
    default = _numbers("medium")
    assert default[("chop_full", ())] == 3
    assert default[("cook_cost_full", ())] == 10 + 1
    changed = _numbers("medium", chop_steps=5, cook_time=4, burn_time=9, wash_steps=2)
    assert changed[("chop_full", ())] == 5
    assert changed[("cook_cost_full", ())] == 4 + 1
    assert changed[("wash_full", ())] == 2
    temporal = compile(new_state(make_rules("medium", cook_time=4, burn_time=9), 0),
                       encoding="temporal").numbers
    assert temporal[("cook_lo_full", ())] == 4 and temporal[("cook_hi_full", ())] == 8


def test_the_domain_does_not_depend_on_rule_numbers() -> None:
    from ocplus_plan.planning.pddl import problem_texts

    a = compile(new_state(make_rules("medium"), 0))
    b = compile(new_state(make_rules("medium", chop_steps=7, cook_time=3, burn_time=5), 0))
    assert problem_texts(a)[0] == problem_texts(b)[0]
