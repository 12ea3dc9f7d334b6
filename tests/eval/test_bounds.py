"""The dish upper bound: hand-computed on a tiny kitchen, and never beaten."""

from __future__ import annotations

import pytest

from ocplus_plan.agents import run_episode
from ocplus_plan.agents.greedy import GreedyAgent
from ocplus_plan.eval.bounds import bumps_per_dish, dish_bound, plan_bound
from ocplus_plan.sim import make_rules, new_state, transition
from ocplus_plan.sim.codes import Item

# onion (0,1), board (0,2), plate (1,0), serving window (1,4); one lane of floor
TINY = {"name": "tiny", "game_map": [[1, 8, 6, 1, 1],
                                     [5, 0, 0, 0, 7],
                                     [1, 1, 1, 1, 1]],
        "agent_spawn_points": [[1, 1]]}


def test_bumps_per_dish_counts_pick_put_chops_plate_and_serve() -> None:
    rules = make_rules("easy", map=TINY, n_agents=1)
    assert bumps_per_dish(rules, (Item.ONION,), dirty=False) == 2 + 3 + rules.chop_steps
    assert bumps_per_dish(rules, (Item.ONION,), dirty=True) == 2 + 3 + rules.chop_steps + 2 \
        + rules.wash_steps
    assert bumps_per_dish(rules, (Item.STEAK,), dirty=False) == 2 + 3


def test_bound_on_a_hand_drawn_kitchen() -> None:
    rules = make_rules("easy", map=TINY, n_agents=1)
    bumps = 2 + 3 + rules.chop_steps
    # closed tour from the window's spot (1,3): plate + onion at (1,1) (2 steps), board
    # at (1,2) (1), back to (1,3) (1): 4 steps; first dish from (1,1): board (1), window (1)
    cycle, first = 4 + bumps, 2 + bumps
    bound = dish_bound(rules, 200)
    assert bound.cycles == {"onion": cycle}
    assert bound.first == (first,)
    # 200 steps + the first dish's head start buy floor(202 / cycle) dishes
    assert bound.dishes == (200 + cycle - first) // cycle
    assert bound.orders == "cheapest"


def test_an_unreachable_kitchen_bounds_at_zero() -> None:
    walled = dict(TINY, game_map=[[1, 8, 6, 1, 1], [5, 0, 1, 0, 7], [1, 1, 1, 1, 1]])
    bound = dish_bound(make_rules("easy", map=walled, n_agents=1), 200)
    assert bound.dishes == 0 and bound.first == (-1,)


def test_seeded_stream_is_never_looser_than_the_cheapest_recipe() -> None:
    rules = make_rules("medium", n_agents=1)
    loose = dish_bound(rules).dishes
    for seed in range(5):
        tight = dish_bound(rules, seed=seed)
        assert tight.orders == "seeded" and tight.dishes <= loose


@pytest.mark.parametrize("preset,n", [("easy", 1), ("easy", 2), ("medium", 1), ("medium", 2),
                                      ("hard", 2)])
def test_the_greedy_cook_never_beats_the_bound(preset: str, n: int) -> None:
    rules = make_rules(preset, n_agents=n)
    for seed in range(4):
        state = new_state(rules, seed)
        stats = run_episode(state, [(GreedyAgent(seed), list(range(n)))])
        bound = dish_bound(rules, stats["t"], seed=seed)
        assert 0 < stats["dishes_served"] <= bound.dishes, (seed, stats["dishes_served"], bound)


# ------------------------------------------------------------- plan quality bound

def _tiny(spawns: list[list[int]]):  # the TINY kitchen, one onion order first
    state = new_state(make_rules("easy", map=dict(TINY, agent_spawn_points=spawns),
                                 n_agents=len(spawns)), 0)
    assert state.orders[0].recipe == (Item.ONION,)
    return state


def test_plan_bound_by_hand_on_the_tiny_kitchen_one_cook() -> None:
    b = plan_bound(_tiny([[1, 1]]), max_orders=1)
    chop = make_rules("easy").chop_steps
    # work: onion pick + put on board + chops + onto the plate; plate pick + serve
    assert b.work_classical == b.work_temporal == 1 + 1 + chop + 1 + 2
    # from (1,1) the cook stands by the onion and the plate; board spot (1,2), window (1,3)
    assert b.walk == 2
    assert b.cost == 2 + 5 + chop
    # onion: pick, carry 1, put, chops, plate it, carry 1 to the window, serve
    assert b.critical_path == 1 + 1 + 1 + chop + 1 + 1 + 1
    assert b.makespan == max(b.critical_path, b.cost)  # one cook: its busy time counts


def test_plan_cost_bound_is_at_least_every_critical_path() -> None:
    for preset, n in (("easy", 1), ("easy", 2), ("medium", 2), ("hard", 2)):
        b = plan_bound(new_state(make_rules(preset, n_agents=n), 4), max_orders=1)
        assert b.cost == max(b.walk + b.work_classical, b.critical_path)
        assert b.makespan >= b.critical_path


def test_plan_bound_two_cooks_share_the_walk_but_not_the_chain() -> None:
    b = plan_bound(_tiny([[1, 1], [1, 3]]), max_orders=1)
    chop = make_rules("easy").chop_steps
    assert b.walk == 1  # the second cook already stands by the window
    assert b.cost == 1 + 5 + chop
    assert b.makespan == b.critical_path == 6 + chop  # (walk + work) / 2 is smaller


def test_plan_bound_counts_what_is_done_already() -> None:
    state = _tiny([[1, 1]])
    transition(state, [3])  # bump the onion tile: the cook now holds the onion
    assert state.agent_hand[0] >= 0
    b = plan_bound(state, max_orders=1)
    chop = make_rules("easy").chop_steps
    assert b.work_classical == 1 + chop + 1 + 2  # no pick any more
    assert b.walk == 2 and b.cost == 2 + 4 + chop


def test_plan_bound_cooking_costs_a_classical_cook_but_two_temporal_bumps() -> None:
    rules = make_rules("medium", n_agents=1)
    state = next(new_state(rules, s) for s in range(50)
                 if Item.STEAK in new_state(rules, s).orders[0].recipe)
    b = plan_bound(state, max_orders=1)
    assert b.work_classical - b.work_temporal == rules.cook_time + 1 - 2
    assert b.critical_path >= rules.cook_time + 4  # pick, cook, take off, plate, serve
    assert b.makespan <= b.cost  # one cook: the temporal bound never exceeds the classical


def test_more_orders_never_lower_the_bound() -> None:
    for preset, n in (("easy", 2), ("medium", 2), ("hard", 2)):
        state = new_state(make_rules(preset, n_agents=n), 4)
        one, two = plan_bound(state, max_orders=1), plan_bound(state)
        assert two.cost >= one.cost and two.makespan >= one.makespan
        assert two.orders == tuple(o.order_id for o in state.orders)


def _planner_or_skip(name: str) -> None:
    pytest.importorskip("unified_planning")
    from ocplus_plan.planning.engines import availability

    avail = availability(name)
    if not avail.ok:
        pytest.skip(f"{name} unavailable: {avail.reason}")


@pytest.mark.parametrize("planner,encoding", [("fast-downward-opt", "classical"),
                                              ("kairos", "temporal")])
def test_no_plan_beats_the_plan_bound(planner: str, encoding: str) -> None:
    """Optimal classical costs (Fast Downward A* + LM-cut) and Kairos' makespans on
    sampled states, 1 and 2 cooks, never fall below the bound."""
    _planner_or_skip(planner)
    from ocplus_plan.planning import compile
    from ocplus_plan.planning.engines import solve
    from ocplus_plan.planning.fidelity import sample_states

    checked = 0
    for preset, n in (("easy", 1), ("easy", 2), ("medium", 1)):
        for state in sample_states(preset, 3, seed=11, n_agents=n):
            bound = plan_bound(state, max_orders=1)
            result = solve(compile(state, encoding=encoding, max_orders=1).problem, planner,
                           timeout=20)
            if not result.solved:
                continue
            value = result.cost if encoding == "classical" else result.makespan
            limit = bound.cost if encoding == "classical" else bound.makespan
            assert value >= limit, (preset, n, value, bound)
            checked += 1
    assert checked >= 5, f"only {checked} states solved: the check says too little"
