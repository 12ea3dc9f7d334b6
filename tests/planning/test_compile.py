"""compile(state, ...): objects, initial facts, goals, the name map and map-back."""

from __future__ import annotations

import statistics
import time

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.errors import CompileError
from ocplus_plan.planning import compile
from ocplus_plan.planning.fidelity import sample_states
from ocplus_plan.sim import make_rules, new_state, transition
from ocplus_plan.sim.codes import Action, ItemState

R, D, L, U, S = (int(a) for a in Action)  # right, down, left, up, stay


def medium(actions: list[int], **overrides: object):
    """medium_kitchen after a scripted single-agent action sequence.

    Agent 0 starts at (2, 2); tomato0 spawns at (0, 2), steak0 at (2, 0), the pan is
    (3, 0), a board (1, 6), plate0 (4, 0).
    """
    state = new_state(make_rules("medium", **overrides), 0)
    for a in actions:
        transition(state, [a])
    return state


def facts(compiled) -> set[str]:
    return {str(k) for k, v in compiled.problem.explicit_initial_values.items()
            if v.is_true()}


def test_initial_state_objects_and_goal() -> None:
    state = new_state(make_rules("hard"), 0)
    c = compile(state)
    names = c.names
    assert set(names.agents) == {"a0", "a1"}
    assert set(names.items) == set(state.geo.item_names)
    assert [o.order_id for o in state.orders] == list(c.goal_orders)
    goals = {str(g) for g in c.problem.goals}
    assert goals == {f"served(o{o.order_id})" for o in state.orders}
    f = facts(c)
    assert "plates_get_dirty" in f  # hard: plates are dirty after delivery
    for a, pos in enumerate(state.agent_pos):
        assert f"agent_at(a{a}, {names.cell(state.geo.rc(pos))})" in f


def test_max_orders_and_explicit_orders() -> None:
    state = new_state(make_rules("hard"), 0)
    assert compile(state, max_orders=1).goal_orders == (state.orders[0].order_id,)
    assert compile(state, max_orders=0).problem.goals == []
    late = state.orders[1]
    c = compile(state, orders=[late])
    assert c.goal_orders == (late.order_id,)
    with pytest.raises(CompileError, match="not open"):
        compile(state, orders=[late._replace(order_id=99)])
    with pytest.raises(CompileError, match="max_orders"):
        compile(state, max_orders=-1)


def test_held_item_and_half_chopped_vegetable() -> None:
    held = compile(medium([U, U]))  # up to (1, 2), bump the tomato tile: pick it up
    assert "holding(a0, tomato0)" in facts(held)
    # carry it to the board at (1, 6), put it down, chop once
    state = medium([U, U, R, R, R, R, R])
    assert state.item_progress[0] == 1 and state.item_state[0] == ItemState.FRESH
    c = compile(state)
    f = facts(c)
    assert {"item_at(tomato0, board_1_6)", "partly(tomato0)", "fresh(tomato0)"} <= f
    assert c.numbers[("chop_left", ("tomato0",))] == 2
    # an empty hand bumping a board with a fresh vegetable chops it: no generic pick there
    assert "grabbable(board_1_6)" not in f and "takes_from(board_1_6)" in f
    assert "grabbable(pan_3_0)" in f and "grabbable(counter_0_3)" in f


def test_steak_on_the_pan_classical_rescue_or_doomed() -> None:
    on_pan = [L, L, D, L]  # pick the steak at (2, 0), step down, put it on the pan (3, 0)
    c = compile(medium(on_pan))
    f = facts(c)
    assert "cooking_on(steak0, pan_3_0)" in f and "calm" not in f
    assert "can_rescue(a0, steak0, s_3_1)" in f
    # rescue_here: wait until cooked (ticks 1 -> 10), then one bump
    assert c.numbers[("rescue_cost", ("a0", "steak0"))] == 10
    # walk 4 cells away and let it reach 17 ticks: it burns before anyone returns
    far = compile(medium(on_pan + [R, R, R, R] + [S] * 12))
    assert far.doomed == frozenset({2})
    f = facts(far)
    assert {"item_at(steak0, pan_3_0)", "burnt(steak0)", "calm"} <= f
    burnt = compile(medium(on_pan + [S] * 25))
    assert "burnt(steak0)" in facts(burnt) and not burnt.doomed


def test_steak_on_the_pan_temporal_window_is_timed_initial_literals() -> None:
    state = medium([L, L, D, L] + [S] * 3)  # 4 ticks on the pan
    c = compile(state, encoding="temporal")
    assert "on_heat(steak0, pan_3_0)" in facts(c)
    timed = {(float(t.delay), str(e.fluent), e.value.is_true())
             for t, effects in c.problem.timed_effects.items() for e in effects}
    rules = state.rules
    assert (rules.cook_time - 4, "window(steak0)", True) in timed
    assert (rules.burn_time - 4 + 1, "window(steak0)", False) in timed
    assert (rules.burn_time - 4 + 1, "overdone(steak0)", True) in timed


def test_plate_with_contents() -> None:
    # tomato: pick, board, chop 3x, pick; then down to (4, 1) and bump the plate at (4, 0)
    state = medium([U, U, R, R, R, R, R, R, R, R, D, D, D, L, L, L, L, L])
    assert state.plate_contents(3) == [0]
    c = compile(state)
    f = facts(c)
    assert {"on_plate(tomato0, plate0)", "plate_has(plate0, c_tomato)", "ready(tomato0)",
            "item_at(plate0, plate_4_0)", "free_hand(a0)"} <= f
    assert c.names.contents["c_tomato"] == ("tomato",)


def test_random_states_compile_in_every_option() -> None:
    """Sampled states (items on plates, in hands, waiting) compile in every option, and
    every item is in exactly one place in the initial facts."""
    for state in sample_states("medium", 8, seed=5):
        for encoding in ("classical", "temporal"):
            for granularity in ("stations", "cells"):
                c = compile(state, encoding=encoding, granularity=granularity)
                located: dict[str, int] = {}
                for fact in facts(c):
                    fluent, _, rest = fact.partition("(")
                    args = [a.strip() for a in rest.rstrip(")").split(",")]
                    if fluent in ("item_at", "on_plate", "waiting", "cooking_on", "on_heat"):
                        located[args[0]] = located.get(args[0], 0) + 1
                    elif fluent == "holding":
                        located[args[1]] = located.get(args[1], 0) + 1
                assert located == {name: 1 for name in state.geo.item_names}


def test_names_are_reversible() -> None:
    state = sample_states("hard", 1, seed=2)[0]
    c = compile(state)
    names = c.names
    for obj in c.problem.all_objects:
        value = names.lookup(obj.name)
        table = next(t for t in ("agents", "items", "cells", "orders", "contents", "kinds")
                     if obj.name in getattr(names, t))
        assert names.name(table, value) == obj.name
    assert names.agent(1) == "a1" and names.item(0) == state.geo.item_names[0]
    with pytest.raises(CompileError):
        names.lookup("nothing_here")


def test_map_back_gives_simulator_terms() -> None:
    from unified_planning.plans import ActionInstance

    state = new_state(make_rules("medium"), 0)
    c = compile(state)
    p = c.problem
    move = ActionInstance(p.action("move"), (p.object("a0"), p.object("s_2_2"),
                                             p.object("s_3_1")))
    step = c.map_back(move)
    assert (step.kind, step.agent, step.spot, step.from_spot, step.duration) == \
        ("move", 0, (3, 1), (2, 2), 2)
    pick = ActionInstance(p.action("pick"), (p.object("a0"), p.object("steak0"),
                                             p.object("steak_2_0"), p.object("s_2_1")))
    step = c.map_back(pick)
    assert (step.kind, step.items, step.place, step.spot, step.duration) == \
        ("pick", (2,), (2, 0), (2, 1), 1)
    cook = ActionInstance(p.action("cook"), (p.object("a0"), p.object("steak0"),
                                             p.object("pan_3_0"), p.object("s_3_1")))
    assert c.map_back(cook).duration == state.rules.cook_time + 1


def test_stations_counters_include_the_hand_over_wall() -> None:
    state = new_state(make_rules("easy", map="easy_divided", n_agents=2), 0)
    c = compile(state)
    wall = {name for name in c.names.cells if name.startswith("counter_") and
            name.endswith("_4")}
    assert wall, "the wall between the two cooks must offer a hand-over counter"


def test_anticipate_switches_is_refused_where_it_cannot_be_expressed() -> None:
    state = new_state(make_rules("hard"), 0)
    with pytest.raises(CompileError, match="temporal"):
        compile(state, anticipate_switches=True)
    with pytest.raises(CompileError, match="temporal"):
        compile(state, granularity="cells", anticipate_switches=True)


def test_anticipated_switches_at_stations_move_in_the_layout_of_the_moment() -> None:
    rules = make_rules("hard", n_agents=1)
    state = new_state(rules, 0)
    c = compile(state, encoding="temporal", anticipate_switches=True)
    f = facts(c)
    assert "now(layout0)" in f and "now(layout1)" not in f
    # the top-right room of MapC is closed off from the serving window in layout 0
    # (column 3 rows 1-3 are blocks) and open in layout 1; the bottom-right the other way
    assert any(x.startswith("llink(layout1, s_3_7, s_4_1") for x in f)
    assert not any(x.startswith("llink(layout0, s_3_7, s_4_1") for x in f)
    assert any(x.startswith("llink(layout0, s_7_5, s_4_1") for x in f)
    assert all(v < rules.map_switch_step for (name, _), v in c.numbers.items() if name == "ldist")
    timed = {(int(t.delay), str(e.fluent), e.value.is_true())
             for t, effects in c.problem.timed_effects.items() for e in effects}
    first = rules.map_switch_step
    assert {(first, "now(layout0)", False), (first, "now(layout1)", True),
            (2 * first, "now(layout1)", False), (2 * first, "now(layout0)", True)} <= timed
    move = c.problem.action("move")
    assert [p.name for p in move.parameters] == ["a", "s1", "s2", "l"]
    # the layout must hold at the start and at the end of the move
    assert sum("now(l)" in str(cs) for cs in move.conditions.values()) == 2


def test_anticipated_stations_moves_map_back_with_their_layout_distance() -> None:
    state = new_state(make_rules("hard", n_agents=1), 0)
    c = compile(state, encoding="temporal", anticipate_switches=True)
    p = c.problem
    move = p.action("move")
    from unified_planning.plans import ActionInstance

    ai = ActionInstance(move, (p.object("a0"), p.object("s_1_7"), p.object("s_3_7"),
                               p.object("layout1")))
    step = c.map_back(ai, 15.0)
    assert step.kind == "move" and step.spot == (3, 7) and step.start == 15.0
    assert step.duration == c.numbers[("ldist", ("layout1", "s_1_7", "s_3_7"))] == 2


def test_anticipated_switches_open_and_close_cells_on_schedule() -> None:
    rules = make_rules("easy", map="mapC", dynamic=True)
    state = new_state(rules, 0)
    now = compile(state, encoding="temporal", granularity="cells")
    assert not now.problem.timed_effects
    assert "s_2_3" not in now.names.cells  # a block now: not a spot of the current layout
    c = compile(state, encoding="temporal", granularity="cells", anticipate_switches=True)
    f = facts(c)
    assert "open(s_5_3)" in f and "open(s_2_3)" not in f
    timed = {(int(t.delay), str(e.fluent), e.value.is_true())
             for t, effects in c.problem.timed_effects.items() for e in effects}
    first = rules.map_switch_step  # the first switch, after map_switch_step steps
    assert (first, "open(s_2_3)", True) in timed and (first, "open(s_5_3)", False) in timed
    second = first + rules.map_switch_step
    assert (second, "open(s_2_3)", False) in timed and (second, "open(s_5_3)", True) in timed


def test_fast_path_builds_the_same_problem_as_the_public_api() -> None:
    for state in sample_states("hard", 3, seed=9):
        for encoding in ("classical", "temporal"):
            a = compile(state, encoding=encoding)
            b = compile(state, encoding=encoding, _fast=False)
            assert a.problem == b.problem
            assert a.problem.explicit_initial_values == b.problem.explicit_initial_values


def test_compile_is_fast_when_warm() -> None:
    """The target is < 5 ms median (experiments/bench_compile.py); loose here for CI."""
    state = new_state(make_rules("hard"), 0)
    compile(state)
    times = []
    for _ in range(15):
        t0 = time.perf_counter()
        compile(state)
        times.append(time.perf_counter() - t0)
    assert statistics.median(times) < 0.05


def test_a_subset_of_cooks_is_modelled() -> None:
    """agents=(1,): only cook 1 is an object; the other cook's cell is not occupied."""
    state = new_state(make_rules("medium", n_agents=2), 0)
    c = compile(state, agents=(1,))
    assert set(c.names.agents) == {"a1"}
    f = facts(c)
    assert f"agent_at(a1, {c.names.cell(state.geo.rc(state.agent_pos[1]))})" in f
    assert f"vacant({c.names.cell(state.geo.rc(state.agent_pos[0]))})" in f
    with pytest.raises(CompileError, match="cooks 0..1"):
        compile(state, agents=(2,))


def test_a_cook_holding_an_item_cannot_be_left_out() -> None:
    state = new_state(make_rules("medium", n_agents=2), 0)
    transition(state, [U, S])  # cook 0 at (2, 2) goes up to (1, 2)
    transition(state, [U, S])  # and bumps the tomato at (0, 2): holds it
    assert state.agent_hand[0] >= 0
    with pytest.raises(CompileError, match=r"cooks \[0\] hold an item"):
        compile(state, agents=(1,))
    assert set(compile(state, agents=(0,)).names.agents) == {"a0"}


def test_hand_change_is_read_off_the_schemas() -> None:
    from ocplus_plan.planning.model import hand_change, schemas

    by_name = {s.name: hand_change(s) for s in schemas("classical", "stations")}
    assert by_name["pick"] == by_name["rescue"] == "take"
    assert by_name["put"] == by_name["plate_put"] == by_name["deliver1"] == "release"
    assert by_name["trash_item"] == "release" and by_name["trash_plate1"] == "keep"
    assert by_name["chop"] == by_name["plate_take"] == by_name["move"] == "keep"
    temporal = {s.name: hand_change(s) for s in schemas("temporal", "stations")}
    assert temporal["take_off"] == "take"
