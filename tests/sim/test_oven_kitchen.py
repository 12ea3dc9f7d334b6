"""The shipped example of an added process station: ``examples/oven_kitchen.yaml``, a kitchen
whose steak is baked in an oven (cell code 13, one record in ``sim/processes.ADDED``) and
burns when left. Every layer follows the record: the map format, the reference step, the
numba and JAX mirrors, greedy, the text and vector observations, and both planning
encodings (the planner tests run with ``OCPLUS_SLOW=1``)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from ocplus_plan.agents.greedy import GreedyAgent
from ocplus_plan.errors import MapFormatError
from ocplus_plan.eval.mirrors import check_mirror, kitchens
from ocplus_plan.sim import make_rules, new_state, transition
from ocplus_plan.sim.codes import Action, Cell, Item, ItemState
from ocplus_plan.sim.fast.batch import numba_available
from ocplus_plan.sim.maps import load_map
from ocplus_plan.sim.observe import GRID_CHANNELS, VectorEncoder
from ocplus_plan.sim.observe_text import rules_text, text_observations
from ocplus_plan.sim.processes import ADDED, PROCESSES

OVEN_MAP = str(Path(__file__).resolve().parents[2] / "examples" / "oven_kitchen.yaml")
R, D, L, U, S = (int(a) for a in Action)
#: from the first spawn point: take the steak from its counter and put it in the oven
TO_OVEN = [L, L, D, L]


def oven_rules(**overrides):
    return make_rules("medium", map=OVEN_MAP, **overrides)


def test_the_kitchen_file_gives_the_oven_the_steak_and_drops_the_pan_record():
    procs = load_map(OVEN_MAP).processes
    assert [p.station for p in procs] == [Cell.BOARD, Cell.SINK, Cell.OVEN]
    oven = procs[-1]
    assert (oven.verb, oven.takes, oven.drive, oven.duration, oven.overrun_state,
            oven.overrun) == ("bake", (Item.STEAK,), "time", 8, ItemState.BURNT, 16)
    assert oven == ADDED[0]  # the file spells out the default record
    assert any(Item.STEAK in r for r in oven_rules().recipes)


def test_an_oven_without_a_record_is_refused_naming_the_cell_and_the_fix(tmp_path):
    text = Path(OVEN_MAP).read_text()
    bare = tmp_path / "bare.yaml"
    bare.write_text(text[: text.index("processes:")])
    with pytest.raises(MapFormatError, match=r"cell code 13 \(oven\) at \[3, 0\] has no record; "
                                             r"add one under 'processes'"):
        load_map(str(bare))


def test_the_oven_bakes_the_steak_and_burns_it_when_left():
    state = new_state(oven_rules(), 0)
    for a in TO_OVEN:
        transition(state, [a])
    steak = state.cell_item[state.geo.flat(3, 0)]
    assert state.geo.item_kind[steak] == Item.STEAK and state.geo.pans == (state.geo.flat(3, 0),)
    for _ in range(7):  # one tick already happened in the step that put it in
        transition(state, [S])
    assert state.item_state[steak] == ItemState.COOKED and state.stats["cooks"] == 1
    for _ in range(9):
        transition(state, [S])
    assert state.item_state[steak] == ItemState.BURNT and state.stats["burns"] == 1


def test_the_kitchen_files_menu_is_two_dishes_that_need_the_oven():
    rules = oven_rules()
    assert rules.recipes == ((Item.TOMATO, Item.STEAK),
                             (Item.LETTUCE, Item.ONION, Item.STEAK))
    assert rules.recipe_rewards == (250.0, 400.0)
    assert all((Item.STEAK, ItemState.COOKED) in d.ingredients for d in rules.dishes)


def test_greedy_serves_dishes_in_the_oven_kitchen_and_earns_their_rewards():
    rules = oven_rules(n_agents=2)
    state = new_state(rules, 0)
    agent = GreedyAgent()
    agent.reset(state)
    paid = []
    for _ in range(120):
        served = {o.order_id: o.recipe for o in state.orders}
        res = transition(state, agent.act(state))
        for e in res.events:
            if e.kind == "delivery":
                paid.append((res.rewards[e.agent], rules.reward_of[served[e.value]]))
    assert state.stats["dishes_served"] >= 1 and state.stats["cooks"] >= 1, state.stats
    assert paid and all(got == pytest.approx(dish + rules.rewards.step_penalty)
                        for got, dish in paid), paid


def test_the_observations_show_the_oven():
    rules = oven_rules()
    state = new_state(rules, 0)
    for a in TO_OVEN:
        transition(state, [a])
    text = text_observations(state)[0]
    assert "- oven at (row 3, col 0)" in text and "raw steak on the oven" in text
    assert "A raw steak put in an oven cooks by itself: cooked after 8 steps, burnt after 17" \
        in rules_text(rules)
    # the vector observation keeps the shipped channels: the oven reads as a pan
    enc = VectorEncoder(rules)
    grid = enc.encode(state)[0][: len(GRID_CHANNELS) * 49].reshape(len(GRID_CHANNELS), 7, 7)
    assert grid[GRID_CHANNELS.index("terrain:pan"), 3, 0] == 1.0


def test_the_shipped_records_have_no_oven():
    assert all(p.station != Cell.OVEN for p in PROCESSES)
    assert make_rules("medium").tables.station_of(int(Item.STEAK)) == int(Cell.PAN)


@pytest.mark.parametrize("mirror", [
    pytest.param("numba", marks=pytest.mark.skipif(not numba_available(),
                                                   reason="numba is not installed")),
    "kernels",
    pytest.param("jax", marks=pytest.mark.skipif(
        not os.environ.get("OCPLUS_SLOW"),
        reason="a JAX compile of its own (tests/sim/fast/test_mirrors.py steps the oven "
               "kitchen in its JAX batch): set OCPLUS_SLOW=1"))])
def test_the_mirrors_step_the_oven_kitchen_as_the_reference(mirror):
    if mirror == "jax":
        pytest.importorskip("jax", reason="jax is not installed (the 'jax' extra)")
    rules = kitchens([OVEN_MAP], "medium", n_agents=2, horizon=60)
    totals = check_mirror(mirror, rules, steps=70, seed=3)
    assert totals["cooks"] and totals["dishes_served"], totals


slow = pytest.mark.skipif(not os.environ.get("OCPLUS_SLOW"),
                          reason="planner runs: set OCPLUS_SLOW=1")


@pytest.fixture
def _private_cwd(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)  # Fast Downward writes output.sas into the working directory


def _need(planner: str) -> None:
    pytest.importorskip("unified_planning")
    from ocplus_plan.planning.engines import availability

    avail = availability(planner)
    if not avail.ok:
        pytest.skip(f"{planner} unavailable: {avail.reason}")


@slow
@pytest.mark.usefixtures("_private_cwd")
@pytest.mark.parametrize("baking", [0, 5], ids=["fresh", "steak-in-the-oven"])
def test_fast_downward_plans_in_the_oven_kitchen_validate_and_are_faithful(baking):
    _need("fast-downward")
    from ocplus_plan.planning import compile
    from ocplus_plan.planning.engines import solve
    from ocplus_plan.planning.fidelity import replay

    state = new_state(oven_rules(), 0)
    for a in (TO_OVEN + [S] * baking) if baking else []:
        transition(state, [a])
    compiled = compile(state, max_orders=1)
    result = solve(compiled.problem, "fast-downward", timeout=60, use_val=True)
    assert result.status == "solved" and result.validated, result.reason
    kinds = [compiled.map_back(a).kind for a in result.plan.actions]
    assert ("rescue" if baking else "cook") in kinds
    rep = replay(compiled, result.plan, state)
    assert rep.ok, (rep.category, rep.mismatch)
    assert sorted(rep.served) == sorted(compiled.goal_orders)


@slow
@pytest.mark.usefixtures("_private_cwd")
def test_kairos_plans_in_the_oven_kitchen_validate_and_are_faithful():
    _need("kairos")
    from ocplus_plan.planning import compile
    from ocplus_plan.planning.engines import solve
    from ocplus_plan.planning.fidelity_temporal import replay_temporal

    state = new_state(oven_rules(), 0)
    compiled = compile(state, encoding="temporal", max_orders=1)
    result = solve(compiled.problem, "kairos", timeout=60, use_val=True)
    assert result.status == "solved" and result.validated, result.reason
    rep = replay_temporal(compiled, result.plan, state)
    assert rep.ok, (rep.category, rep.mismatch)
    assert sorted(rep.served) == sorted(compiled.goal_orders)
