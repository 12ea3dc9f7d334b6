"""The dish upper bound: hand-computed on a tiny kitchen, and never beaten."""

from __future__ import annotations

import pytest

from ocplus_plan.agents import run_episode
from ocplus_plan.agents.greedy import GreedyAgent
from ocplus_plan.eval.bounds import bumps_per_dish, dish_bound
from ocplus_plan.sim import make_rules, new_state
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
