"""Layout switching (SPEC section 5): schedule and the wait rule."""

from __future__ import annotations

from ocplus_plan.sim.codes import Action

from .conftest import kitchen
from .helpers import item_of, kinds, place, run, set_pos
from ocplus_plan.sim import Item

R, D, L, U, S = (int(a) for a in (Action.RIGHT, Action.DOWN, Action.LEFT, Action.UP, Action.STAY))
MAIN = [
    [1, 3, 1, 6, 1, 1],
    [1, 0, -1, 0, 0, 1],
    [5, 0, 0, 0, 1, 7],
    [1, 1, 1, 1, 1, 1],
]
SWITCH = [
    [1, 3, 1, 6, 1, 1],
    [1, 0, 0, 0, -1, 1],
    [5, 0, 0, 0, 0, 7],
    [1, 1, 1, 1, 1, 1],
]


def dyn(step=5, spawns=([2, 1],)):
    return kitchen(MAIN, [list(p) for p in spawns], switch=SWITCH, switch_step=step, dynamic=True)


def test_first_switch_happens_at_map_switch_step_then_alternates():
    rules, s = dyn(step=5)
    run(s, *[S] * 4)
    assert s.layout_index == 0
    ev, _ = run(s, S)
    assert s.t == 5 and s.layout_index == 1 and "layout_switch" in kinds(ev)
    assert s.geo.walkables[1][s.geo.flat(1, 2)]  # the block opened
    run(s, *[S] * 4)
    assert s.layout_index == 1
    run(s, S)
    assert s.t == 10 and s.layout_index == 0


def test_a_switch_waits_while_an_agent_stands_on_a_cell_that_would_block():
    rules, s = dyn(step=5)
    set_pos(s, 0, (1, 4))  # (1,4) becomes a block in the switch layout
    ev, _ = run(s, *[S] * 6)
    assert s.layout_index == 0 and kinds(ev).count("switch_waiting") == 2
    ev, _ = run(s, L)  # step 7: the agent leaves, the switch happens in that step
    assert s.layout_index == 1 and "layout_switch" in kinds(ev)
    assert s.next_switch == 7 + 5  # the schedule restarts from the actual switch


def test_a_switch_waits_while_an_item_lies_on_a_counter_that_would_vanish():
    rules, s = dyn(step=3, spawns=([2, 1],))
    tomato = item_of(s, Item.TOMATO)
    place(s, tomato, (2, 4))  # counter in MAIN, floor in SWITCH
    run(s, *[S] * 4)
    assert s.layout_index == 0
    s.cell_item[s.geo.flat(2, 4)] = -1  # take it away (test shortcut): give it to the agent
    s.agent_hand[0] = tomato
    s.item_where[tomato], s.item_loc[tomato] = 1, 0
    run(s, S)
    assert s.layout_index == 1


def test_static_presets_never_switch():
    rules, s = kitchen(MAIN, [[2, 1]], switch=SWITCH, switch_step=2, dynamic=False)
    run(s, *[S] * 10)
    assert s.layout_index == 0 and s.stats["layout_switches"] == 0


def test_an_agent_cannot_walk_into_a_block():
    rules, s = dyn(step=50)
    set_pos(s, 0, (1, 1))
    run(s, R)
    assert s.agent_rc(0) == (1, 1)
