"""The executive with a hand-written planner: queues, monitoring, triggers, policies, faults."""

from __future__ import annotations

import pytest

from ocplus_plan.agents import make_controller, run_episode
from ocplus_plan.errors import ConfigError
from ocplus_plan.execution.executive import (
    Executive,
    PlanOutcome,
    PlanStep,
    Policy,
    causal_dependencies,
)
from ocplus_plan.execution.faults import (
    BlockingAgent,
    FaultSchedule,
    MessageLoss,
    force_burn,
    force_switch,
)
from ocplus_plan.execution.tasks import already_done, ready
from ocplus_plan.sim import make_rules, new_state
from ocplus_plan.sim.codes import Action, ItemState

from .toy_planner import crashing_planner, failing_planner, toy_planner


def play(rules, seed=0, policy="on_event", planner=toy_planner, faults=None, agents=None,
         extra=(), steps=None, **kw):
    state = new_state(rules, seed)
    ex = Executive(planner, policy, **kw)
    ids = list(range(rules.n_agents)) if agents is None else agents
    stats = run_episode(state, [(ex, ids), *extra], faults, steps)
    return stats, ex.info(), state


def test_policy_parsing():
    assert Policy.parse("on_event").kind == "on_event"
    assert Policy.parse("periodic(7)") == Policy("periodic", 7)
    assert str(Policy.parse("periodic=3")) == "periodic(3)"
    assert Policy.parse("never").kind == "never"
    for bad in ("sometimes", "periodic(0)", "periodic(x)"):
        with pytest.raises(ConfigError, match="policy"):
            Policy.parse(bad)


def test_causal_dependencies_link_agents_through_shared_cells_and_items():
    steps = [PlanStep(0, 0, "pickup", 5, (1,)), PlanStep(1, 0, "putdown", 9, (1,)),
             PlanStep(2, 1, "pickup", 9, (1,)), PlanStep(3, 1, "deliver", 4, (1,)),
             PlanStep(4, 0, "pickup", 7, (2,))]
    deps = causal_dependencies(steps)
    assert deps[2] == {1}  # agent 1 picks up what agent 0 put down
    assert deps[4] == frozenset()  # unrelated
    assert deps[0] == frozenset()


def test_steps_at_stations_worked_from_one_cell_wait_for_each_other():
    """A board and the counter beside it worked from the same single floor cell: the
    counter step of one cook waits for the other cook's chop, which stands on that cell."""
    steps = [PlanStep(0, 0, "chop", 20, (1,)), PlanStep(1, 1, "pickup", 21, (2,)),
             PlanStep(2, 1, "putdown", 30, (2,))]
    assert causal_dependencies(steps)[1] == frozenset()
    deps = causal_dependencies(steps, {20: 13, 21: 13, 30: 14})
    assert deps[1] == {0} and deps[2] == frozenset()


def test_easy_single_agent_serves_many_dishes():
    stats, info, _state = play(make_rules("easy", n_agents=1))
    assert stats["dishes_served"] >= 5
    assert stats["wrong_deliveries"] == 0
    assert info["failed_bumps"] == 0
    assert info["replans_by_reason"]["initial"] == 1
    assert info["replans_by_reason"].get("new_order", 0) >= 4
    assert info["statuses"] == {"solved": info["planner_calls"]}


def test_two_agents_one_idle_never_collide():
    stats, _info, _ = play(make_rules("easy", n_agents=2))
    assert stats["dishes_served"] >= 5
    assert stats["max_agents_per_cell"] == 1
    assert stats["blocked_moves"] == 0


def test_planner_failure_never_crashes_and_agents_stay_safe():
    for planner in (failing_planner, crashing_planner):
        stats, info, _state = play(make_rules("easy", n_agents=2), planner=planner, steps=60)
        assert stats["dishes_served"] == 0
        # retried with a growing back-off: t = 0, 5, 15, 30, 50, 70, ...
        assert [t for t, _ in info["replan_log"]][:4] == [0, 5, 15, 30]
        assert sum(info["statuses"].values()) == info["planner_calls"]
        assert info["triggers_by_reason"]["planner_failed"] == info["planner_calls"]


def waiting_planner(state, agents, reason=""):
    return PlanOutcome("waiting", [], 0.0, "our first step waits for a partner's")


def test_waiting_for_a_partner_backs_off_while_no_item_moves():
    # cook 1 stands idle: nothing a partner could hand over moves, so the asks back off
    _, info, _ = play(make_rules("easy", n_agents=2), planner=waiting_planner, agents=[0],
                      steps=40)
    assert [t for t, _ in info["replan_log"]][:4] == [0, 5, 15, 30]


def test_waiting_for_a_partner_asks_again_soon_after_an_item_moved():
    # a greedy cook 1 moves items all the time: each ask comes 5 steps after the last
    partner = (make_controller("greedy", 0), [1])
    _, info, _ = play(make_rules("easy", n_agents=2), planner=waiting_planner, agents=[0],
                      extra=[partner], steps=40)
    assert [t for t, _ in info["replan_log"]][:4] == [0, 5, 10, 15]
    assert info["statuses"] == {"waiting": info["planner_calls"]}


def test_planner_timeout_after_a_valid_plan_keeps_the_old_plan():
    calls = []

    def flaky(state, agents, reason):
        calls.append(state.t)
        return toy_planner(state, agents) if len(calls) == 1 else failing_planner(state, agents)

    stats, info, _ = play(make_rules("easy", n_agents=1), planner=flaky, policy="periodic(3)",
                          steps=60)
    assert stats["dishes_served"] >= 1  # the first plan was carried out regardless
    assert info["statuses"]["timeout"] >= 5


def test_periodic_and_never_policies():
    rules = make_rules("easy", n_agents=1)
    _, info, _ = play(rules, policy="periodic(10)", steps=50)
    assert info["replans_by_reason"].get("periodic", 0) >= 4
    stats, info, _ = play(rules, policy="never", steps=100)
    assert set(info["replans_by_reason"]) <= {"initial", "plan_finished"}
    assert stats["dishes_served"] >= 2


def test_forced_burn_leads_to_trash_recook_and_a_served_dish():
    rules = make_rules("medium", recipes=["steak"])
    faults = FaultSchedule(burns=[5])
    stats, info, _state = play(rules, faults=faults, steps=120)
    assert faults.applied and faults.applied[0][1] == "burn"
    assert stats["burns"] >= 1
    assert info["replans_by_reason"].get("burnt", 0) >= 1
    assert stats["dishes_served"] >= 1
    assert stats["wrong_deliveries"] == 0


def test_never_policy_does_worse_under_burn_faults():
    rules = make_rules("medium", recipes=["steak"])
    served = {}
    for policy in ("on_event", "never"):
        total = 0
        for seed in range(3):
            stats, _, _ = play(rules, seed=seed, policy=policy,
                               faults=FaultSchedule(burns=[5, 60, 120]), steps=200)
            total += stats["dishes_served"]
        served[policy] = total
    assert served["on_event"] > served["never"]


def test_layout_switch_mid_path_triggers_replan_without_collision():
    rules = make_rules("hard", map="hard_switch", recipes=["tomato"], dirty_plates=False,
                       map_switch_step=500)
    faults = FaultSchedule(switches=[4])
    stats, info, _state = play(rules, faults=faults, steps=100)
    assert faults.applied == [(4, "switch")]
    assert info["replans_by_reason"].get("layout_switch", 0) >= 1
    assert stats["max_agents_per_cell"] == 1
    assert stats["dishes_served"] >= 1


def test_blocking_agent_is_avoided_or_waited_for():
    rules = make_rules("easy", n_agents=2)
    blocker = BlockingAgent((2, 3), start=0, duration=40)
    stats, _info, _state = play(rules, agents=[0], extra=[(blocker, [1])], steps=120)
    assert stats["dishes_served"] >= 2
    assert stats["max_agents_per_cell"] == 1


def test_message_loss_is_counted_and_recovered_from():
    loss = MessageLoss(0.5, seed=1)
    stats, info, _ = play(make_rules("easy", n_agents=1), deliver_plan=loss, steps=200)
    assert info["messages_lost"] == loss.dropped >= 1
    assert stats["dishes_served"] >= 2


def test_fault_helpers():
    rules = make_rules("medium", recipes=["steak"])
    state = new_state(rules, 0)
    assert force_burn(state) == []  # no steak on the pan yet
    pan = state.geo.pans[0]
    steak = next(i for i, k in enumerate(state.geo.item_kind) if k == 10)
    state.cell_item[state.item_loc[steak]] = -1
    state.cell_item[pan], state.item_loc[steak] = steak, pan
    assert force_burn(state)[0].kind == "fault_burn"
    from ocplus_plan.sim import transition
    events = transition(state, [4]).events
    assert state.item_state[steak] == ItemState.BURNT
    assert "burnt" in [e.kind for e in events]
    with pytest.raises(ConfigError, match="not a pan"):
        force_burn(state, pan=0)
    hard = new_state(make_rules("hard", map="hard_switch"), 0)
    assert [e.kind for e in force_switch(hard)] == ["layout_switch"]
    assert hard.layout_index == 1
    assert force_switch(new_state(make_rules("easy"), 0)) == []
    with pytest.raises(ConfigError, match="rate"):
        MessageLoss(1.5)


def test_executive_rejects_unknown_agents():
    state = new_state(make_rules("easy", n_agents=1), 0)
    with pytest.raises(ConfigError, match="do not exist"):
        Executive(toy_planner).reset(state, [3])


def test_outcome_ok():
    assert PlanOutcome("solved").ok and not PlanOutcome("timeout").ok


def test_anticipated_switches_on_schedule_are_not_surprises():
    rules = make_rules("hard", map="hard_switch", recipes=["tomato"], dirty_plates=False,
                       map_switch_step=10)
    stats, reactive, state = play(rules, steps=120)
    assert state.stats["layout_switches"] >= 10
    assert reactive["replans_by_reason"].get("layout_switch", 0) >= 1
    stats_a, ahead, state_a = play(rules, steps=120, anticipate_switches=True)
    assert state_a.stats["layout_switches"] >= 10
    assert "layout_switch" not in ahead["replans_by_reason"]
    assert "unreachable" not in ahead["replans_by_reason"]
    assert stats_a["max_agents_per_cell"] == 1
    assert stats_a["dishes_served"] >= stats["dishes_served"] >= 1


def _relaxed_planner(state, agents, reason=""):
    from dataclasses import replace

    return replace(toy_planner(state, agents, reason), relaxed=True)


def test_a_plan_made_on_the_relaxed_kitchen_waits_for_switches_instead_of_replanning():
    """MapC, one cook: no layout connects the cook to every station, so a plan made on the
    relaxed kitchen is carried out across the switches."""
    rules = make_rules("hard", n_agents=1, recipes=["tomato"], dirty_plates=False,
                       map_switch_step=10)
    stats, waited, state = play(rules, steps=120, planner=_relaxed_planner)
    assert state.stats["layout_switches"] >= 10
    for reason in ("layout_switch", "unreachable", "deadlock"):
        assert reason not in waited["replans_by_reason"]
    assert stats["dishes_served"] >= 1


def test_a_relaxed_plan_is_replaced_once_a_layout_connects_the_cooks_to_every_station():
    """hard_switch, two cooks: every layout lets them reach every station, so a switch
    that changes their walks makes a plan for the real kitchen (as for any plan)."""
    rules = make_rules("hard", map="hard_switch", recipes=["tomato"], dirty_plates=False,
                       map_switch_step=10)
    stats, info, state = play(rules, steps=120, planner=_relaxed_planner)
    assert state.stats["layout_switches"] >= 10
    assert info["replans_by_reason"].get("layout_switch", 0) >= 1
    assert stats["max_agents_per_cell"] == 1


# a 3x7 kitchen with a pan (0, 3) and a sink (2, 3) (map G of tests/sim/test_items.py)
G = [[1, 10, 1, 9, 1, 3, 1], [5, 0, 0, 0, 0, 0, 7], [1, 12, 6, 11, 1, 1, 1]]


def test_burn_eta_waits_wash_steps_for_a_wash_not_chop_steps():
    """A wash before taking a steak off the pan delays it by ``wash_steps`` bumps; the ETA used
    to count ``chop_steps`` (hidden while both were 3)."""
    from collections import deque

    from ocplus_plan.execution.executive import Task
    from ocplus_plan.sim.codes import Item

    from ..sim.helpers import item_of, place

    etas = {}
    for wash_steps in (3, 7):
        spec = {"name": "g", "game_map": G, "agent_spawn_points": [[1, 1]]}
        rules = make_rules("medium", map=spec, n_agents=1, recipes=["tomato+steak"],
                           chop_steps=2, wash_steps=wash_steps)
        state = new_state(rules, 0)
        geo = state.geo
        plate, steak = item_of(state, Item.PLATE), item_of(state, Item.STEAK)
        place(state, plate, (2, 3))
        state.item_state[plate] = int(ItemState.DIRTY)
        place(state, steak, (0, 3))
        sink, pan = geo.flat(2, 3), geo.flat(0, 3)
        ex = Executive(toy_planner)
        ex.reset(state)
        ex.queues[0] = deque([Task(PlanStep(0, 0, "wash", sink, (plate,)), frozenset()),
                              Task(PlanStep(1, 0, "pickup", pan, (steak,)), frozenset())])
        etas[wash_steps] = ex._eta(state, pan)
    # walk to the sink's spot (2) + wash_steps bumps + step over to the pan's spot (0) + bump
    assert etas == {3: 2 + 3 + 0 + 1, 7: 2 + 7 + 0 + 1}


def test_burn_eta_of_a_plan_scheduled_over_the_switches_waits_for_the_way():
    """MapC, the cook in the top room and the pan in the bottom one: no walk reaches the pan
    in this layout (plain ETA: none), so a plan scheduled over the switches times the walk
    over them (``SwitchingWalks``), as the schedule did."""
    from collections import deque

    from ocplus_plan.execution.executive import Task
    from ocplus_plan.sim.queries import switching_walks

    state = new_state(make_rules("hard", n_agents=1), 0)
    geo = state.geo
    pan = geo.pans[0]
    ex = Executive(toy_planner)
    ex.reset(state)
    ex.queues[0] = deque([Task(PlanStep(0, 0, "pickup", pan, ()), frozenset())])
    assert ex._eta(state, pan) is None
    ex.plan_over_switches = True
    walk, _ = switching_walks(geo, state.rules.map_switch_step).arrival(
        state.agent_pos[0], pan, state.layout_index, state.next_switch - state.t)
    assert walk > 15 and ex._eta(state, pan) == walk + 1


def test_ready_steps_are_what_the_step_then_does_on_sampled_states():
    """On sampled states the executive's expectations agree with the step: a chop / wash
    step is ready exactly when the agent's bump chops / washes, and done exactly when an
    empty hand's bump would no longer; at a pan, a ready step takes a steak that is not raw
    or plates a cooked one. (Other steps are tried as soon as the hand fits them: a bump that
    changes nothing is how the executive learns that the plan is stale.)"""
    from ocplus_plan.execution.executive import Task
    from ocplus_plan.sim.codes import Cell
    from ocplus_plan.sim.queries import Bump, bump_effect, direction, interaction_spots

    from ..sim.helpers import run, sampled_states

    def bump(state, a, spot, cell):
        copy = state.copy()
        copy.agent_pos[a] = spot
        joint = [int(Action.STAY)] * copy.n_agents
        joint[a] = direction(state.geo, spot, cell)
        ev, _ = run(copy, joint)
        return {e.kind for e in ev if e.agent == a}

    checked = 0
    for preset in ("easy", "medium", "hard"):
        for state in sampled_states(preset, 2, 25, seed=5, max_steps=199):
            geo = state.geo
            walk = geo.walkables[state.layout_index]
            ex = Executive(toy_planner)
            ex.reset(state)
            for a in range(state.n_agents):
                for cell in range(len(walk)):
                    spots = [p for p in interaction_spots(geo.neighbors, walk, cell)
                             if p not in state.agent_pos or p == state.agent_pos[a]]
                    if walk[cell] or not spots:
                        continue
                    code = geo.terrains[state.layout_index][cell]
                    for kind, done_by in (("chop", {"chop", "chop_done"}),
                                          ("wash", {"wash", "wash_done"})):
                        task = Task(PlanStep(0, a, kind, cell), frozenset())
                        effect = bump_effect(state, -1, cell)
                        assert already_done(state, task, ex.done_steps) == (effect != Bump[kind.upper()])
                        if already_done(state, task, ex.done_steps):
                            continue
                        is_ready = ready(state, a, task, ex.done_steps)
                        done = bump(state, a, spots[0], cell)
                        assert is_ready == bool(done & done_by), (preset, state.t, a, kind, done)
                        checked += 1
                    if code != Cell.PAN or state.cell_item[cell] < 0:
                        continue
                    steak, held = state.cell_item[cell], state.agent_hand[a]
                    for kind in ("pickup", "plate"):
                        step = Task(PlanStep(0, a, kind, cell), frozenset())
                        if not ready(state, a, step, ex.done_steps):
                            continue
                        assert state.item_state[steak] != ItemState.FRESH  # never a raw steak
                        if held >= 0 and bump_effect(state, held, cell) == Bump.TAKE_ONTO_PLATE:
                            assert "plate_add" in bump(state, a, spots[0], cell)
                        checked += 1
    assert checked >= 20


def test_a_chop_is_not_done_before_its_vegetable_is_on_the_board():
    """Cook 0 is to chop the tomato cook 1 puts on the board (1,6); reaching the empty board
    first, it waits for cook 1's step and the tomato instead of taking the chop as done."""
    from ocplus_plan.execution.executive import Task

    state = new_state(make_rules("easy", n_agents=2), 0)
    board = state.geo.flat(1, 6)
    tomato = state.cell_item[state.geo.flat(0, 2)]
    ex = Executive(toy_planner)
    ex.reset(state)
    chop = Task(PlanStep(1, 0, "chop", board, (tomato,)), frozenset({0}))
    assert not already_done(state, chop, ex.done_steps), "cook 1 has not put the tomato there yet"
    ex.done_steps.add(0)
    assert not already_done(state, chop, ex.done_steps), "the board is still empty"
    state.cell_item[board], state.item_loc[tomato] = tomato, board
    state.cell_item[state.geo.flat(0, 2)] = -1
    assert not already_done(state, chop, ex.done_steps), "a fresh tomato waits to be chopped"
    state.item_state[tomato] = int(ItemState.CHOPPED)
    assert already_done(state, chop, ex.done_steps)


def _oldest_only(state, agents, reason=""):
    """The toy plan (the oldest order, by the first cook), saying it serves that order only."""
    from dataclasses import replace

    return replace(toy_planner(state, agents, reason), orders=(state.orders[0].order_id,))


def test_an_order_the_plan_leaves_out_waits_for_a_cook_that_had_work():
    """easy, two cooks, two open orders, plans for the oldest only (cook 0's work): cook 1,
    idle in every plan, does not make the executive replan each step; once cook 0 (who had
    work) runs out, the left-out order is planned for."""
    rules = make_rules("easy", n_agents=2)
    stats, info, _ = play(rules, steps=100, planner=_oldest_only)
    assert stats["dishes_served"] >= 2
    assert info["planner_calls"] <= 2 * stats["dishes_served"] + 2, info["replan_log"]
    state = new_state(rules, 0)
    ex = Executive(_oldest_only)
    ex.reset(state, [0, 1])
    ex.act(state)
    assert ex.idle_in_plan == {1} and len(state.orders) == 2
    assert "new_order" not in ex._monitor(state)
    ex.idle_in_plan = set()  # as if cook 1 had had work in the plan and finished it
    assert "new_order" in ex._monitor(state)
