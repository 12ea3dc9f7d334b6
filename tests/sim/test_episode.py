"""Orders, rewards, horizon and termination over whole episodes."""

from __future__ import annotations

import pytest

from ocplus_plan.sim import Item, make_rules, new_state, transition
from ocplus_plan.sim.codes import Action

from .helpers import give, item_of, kinds, on_plate, run, set_pos

S = int(Action.STAY)


def test_orders_are_drawn_from_the_seeded_rng_and_differ_across_seeds():
    rules = make_rules("hard")
    a, b = new_state(rules, 1), new_state(rules, 1)
    assert [o.recipe for o in a.orders] == [o.recipe for o in b.orders]
    draws = {tuple(o.recipe for o in new_state(rules, s).orders) for s in range(20)}
    assert len(draws) > 1 and all(len(d) == rules.n_orders for d in draws)


def test_horizon_truncates_and_step_penalty_is_per_agent():
    rules = make_rules("easy", n_agents=2, horizon=7)
    s = new_state(rules, 0)
    for t in range(7):
        res = transition(s, [S, S])
        assert res.rewards == [pytest.approx(rules.rewards.step_penalty)] * 2
        assert res.truncated == (t == 6) and not res.terminated
    assert s.done


def test_stop_after_orders_terminates():
    rules = make_rules("easy", stop_after_orders=1, recipes=["tomato"])
    s = new_state(rules, 0)
    tomato, plate = item_of(s, Item.TOMATO), item_of(s, Item.PLATE)
    s.item_state[tomato] = 1
    on_plate(s, tomato, plate)
    give(s, 0, plate)
    set_pos(s, 0, (3, 2))  # above the delivery window of easy_open
    res = transition(s, [int(Action.DOWN)])
    assert res.terminated and not res.truncated and s.done


def test_shared_reward_mode_gives_each_agent_the_team_sum():
    rules = make_rules("easy", n_agents=2, reward_mode="shared", recipes=["tomato"])
    s = new_state(rules, 0)
    tomato, plate = item_of(s, Item.TOMATO), item_of(s, Item.PLATE)
    s.item_state[tomato] = 1
    on_plate(s, tomato, plate)
    give(s, 0, plate)
    set_pos(s, 0, (3, 2))
    res = transition(s, [int(Action.DOWN), S])
    team = rules.rewards.correct_delivery + 2 * rules.rewards.step_penalty
    assert res.rewards == [pytest.approx(team)] * 2


def test_orders_expire_with_a_penalty_and_are_replaced():
    rules = make_rules("easy", order_time_limit=3, n_agents=2)
    s = new_state(rules, 0)
    first = [o.order_id for o in s.orders]
    ev, rw = run(s, [S, S], [S, S])
    assert s.stats["orders_expired"] == 0
    ev, rw = run(s, [S, S])
    assert kinds(ev).count("order_expired") == 2 and s.stats["orders_expired"] == 2
    assert not set(first) & {o.order_id for o in s.orders} and len(s.orders) == 2
    expected = rules.rewards.step_penalty + rules.rewards.order_expired  # 2 orders / 2 agents
    assert rw[-1] == [pytest.approx(expected)] * 2


def _serve_first_order(s) -> None:
    """Put the first order's (single-vegetable) dish in cook 0's hand above easy_open's window
    and serve it."""
    kind = s.orders[0].recipe[0]
    veg, plate = item_of(s, kind), item_of(s, Item.PLATE)
    s.item_state[veg] = 1
    on_plate(s, veg, plate)
    give(s, 0, plate)
    set_pos(s, 0, (3, 2))
    res = transition(s, [int(Action.DOWN)] + [S] * (s.n_agents - 1))
    assert "delivery" in kinds(res.events)


def test_fixed_orders_are_the_same_every_episode_and_come_back_once_served():
    rules = make_rules("easy", fixed_orders=["onion", "tomato"])
    assert rules.n_orders == 2 and set(rules.recipes) == {(Item.ONION,), (Item.TOMATO,)}
    for seed in (0, 1, 7):
        assert [o.recipe for o in new_state(rules, seed).orders] == [(Item.ONION,), (Item.TOMATO,)]
    s = new_state(rules, 3)
    _serve_first_order(s)  # the onion order is served and an onion order replaces it
    assert sorted(o.recipe for o in s.orders) == sorted([(Item.ONION,), (Item.TOMATO,)])
    assert s.orders[0].order_id != 0


def test_fixed_orders_true_draws_once_from_the_pool_independent_of_the_episode_seed():
    rules = make_rules("hard", fixed_orders=True)
    assert rules.fixed_orders is not None and len(rules.fixed_orders) == rules.n_orders
    assert set(rules.fixed_orders) <= set(rules.recipes)
    assert make_rules("hard", fixed_orders=True).fixed_orders == rules.fixed_orders
    assert {tuple(o.recipe for o in new_state(rules, s).orders) for s in range(10)} == {
        rules.fixed_orders}


@pytest.mark.parametrize("kw, words", [
    ({"fixed_orders": ["steak"]}, "cannot be made"),
    ({"fixed_orders": []}, "at least one"),
    ({"fixed_orders": ["tomato"], "n_orders": 3}, "n_orders=3"),
    ({"fixed_orders": ["tomato"], "recipes": ["onion"]}, "not among the recipes"),
    ({"fixed_orders": "yes"}, "True or a list"),
])
def test_bad_fixed_orders_are_clear_errors(kw, words):
    from ocplus_plan.errors import ConfigError

    with pytest.raises(ConfigError, match=words):
        make_rules("easy", **kw)
