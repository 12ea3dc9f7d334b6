"""The feature encoder and the reward shaper (numpy only: these run without the rl extra)."""

from __future__ import annotations

import numpy as np

from ocplus_plan.rl.features import TARGETS, FeatureEncoder
from ocplus_plan.rl.shaping import RewardShaper, Shaping
from ocplus_plan.sim import Action, Item, make_rules, new_state, transition

R, D, L, U, S = (int(a) for a in Action)


def _value(enc: FeatureEncoder, x: np.ndarray, name: str) -> float:
    return float(x[enc.feature_names().index(name)])


def _go(enc: FeatureEncoder, x: np.ndarray, target: str) -> int:
    """The action the features point to for a target, or -1 when absent."""
    for a, d in enumerate(("right", "down", "left", "up")):
        if _value(enc, x, f"{target}:go_{d}"):
            return a
    return -1


def test_names_match_size_and_values_are_bounded_on_every_preset():
    for preset in ("easy", "medium", "hard"):
        rules = make_rules(preset)
        enc = FeatureEncoder(rules)
        assert len(enc.feature_names()) == enc.size == len(set(enc.feature_names()))
        state = new_state(rules, 3)
        rng = np.random.default_rng(0)
        for _ in range(60):
            x = enc.encode_all(state)
            assert x.shape == (rules.n_agents, enc.size) and x.dtype == np.float32
            assert np.all(x >= -1.0) and np.all(x <= 1.0)
            transition(state, [int(a) for a in rng.integers(0, 5, rules.n_agents)])


def test_same_size_on_every_map_so_one_policy_fits_all():
    sizes = {FeatureEncoder(make_rules(p)).size for p in ("easy", "medium", "hard")}
    assert len(sizes) == 1


def test_following_the_features_reaches_and_bumps_the_target():
    """Walking the pointed direction to the nearest fresh tomato ends with a pickup."""
    rules = make_rules("easy")
    enc = FeatureEncoder(rules)
    state = new_state(rules, 0)
    for _ in range(20):
        x = enc.encode(state, 0)
        assert _value(enc, x, "fresh_tomato:present") == 1.0
        result = transition(state, [_go(enc, x, "fresh_tomato")])
        if any(e.kind == "pickup" for e in result.events):
            break
    held = state.agent_hand[0]
    assert held >= 0 and state.item_kind(held) == Item.TOMATO
    x = enc.encode(state, 0)
    assert _value(enc, x, "hand:tomato") == 1.0 and _value(enc, x, "hand:empty") == 0.0
    # now a free board is the way forward, and its cost shrinks as we follow it
    cost = _value(enc, x, "free_board:cost")
    transition(state, [_go(enc, x, "free_board")])
    assert _value(enc, enc.encode(state, 0), "free_board:cost") < cost


def test_costs_are_path_lengths_including_the_bump():
    rules = make_rules("easy")
    enc = FeatureEncoder(rules)
    state = new_state(rules, 0)
    # agent 0 starts at (1, 1); the tomato spawn is (0, 2): one step right, then bump up
    assert state.agent_rc(0) == (1, 1)
    x = enc.encode(state, 0)
    assert round(_value(enc, x, "fresh_tomato:cost") * 20, 4) == 2
    assert _go(enc, x, "fresh_tomato") == R


def test_orders_and_other_agents_are_encoded():
    rules = make_rules("hard")
    enc = FeatureEncoder(rules)
    state = new_state(rules, 0)
    x0, x1 = enc.encode_all(state)
    total = sum(len(o.recipe) for o in state.orders)
    order_counts = sum(_value(enc, x0, f"order{o}:{k}") * 2 for o in range(2)
                       for k in ("tomato", "lettuce", "onion", "steak"))
    assert order_counts == total
    assert _value(enc, x0, "other0:present") == 1.0 and _value(enc, x0, "other1:present") == 0.0
    assert _value(enc, x0, "other0:drow") == -_value(enc, x1, "other0:drow") != 0.0
    assert len(TARGETS) == 22


def test_shaping_pays_milestones_once_and_true_reward_drops_the_subtask_part():
    """Walk the easy kitchen by the features: tomato -> board -> chop -> plate -> serve."""
    rules = make_rules("easy", recipes=["tomato"])
    state = new_state(rules, 0)
    enc = FeatureEncoder(rules)
    shaper = RewardShaper(Shaping())
    plan = ["fresh_tomato", "free_board", "board_to_chop", "board_to_chop", "board_to_chop",
            "chopped_tomato", "clean_plate", "clean_plate", "delivery"]
    totals = {"true": 0.0, "shaped": 0.0}
    kinds_seen: list[str] = []
    for target in plan:
        for _ in range(30):
            x = enc.encode(state, 0)
            result = transition(state, [_go(enc, x, target)])
            true, shaped = shaper.step(state, result.events, result.rewards)
            assert true[0] == result.rewards[0] - 10.0 * sum(
                e.kind == "chop_done" for e in result.events)
            totals["true"] += true[0]
            totals["shaped"] += shaped[0]
            done = [e.kind for e in result.events if e.kind not in ("move_blocked",)]
            if done:
                kinds_seen += done
                break
    assert state.stats["dishes_served"] == 1, kinds_seen
    # stage 3 + chop 10 + useful plate 10; the carry potentials return to 0 once the
    # ingredient is on the plate and the dish is served
    assert abs(totals["shaped"] - 23.0) < 1e-9
    assert totals["true"] > 190.0  # the delivery, minus step penalties


def test_taking_a_steak_off_the_pan_and_back_cannot_farm_the_stage_bonus():
    rules = make_rules("medium")
    enc = FeatureEncoder(rules)
    state = new_state(rules, 0)
    shaper = RewardShaper(Shaping())
    paid, events = 0.0, []
    for target, want in (("raw_steak", "pickup"), ("free_pan", "putdown"),
                         ("cooking_steak", "pickup"), ("free_pan", "putdown")):
        for _ in range(30):
            x = enc.encode(state, 0)
            result = transition(state, [_go(enc, x, target)])
            paid += shaper.step(state, result.events, result.rewards)[1][0]
            if any(e.kind == want for e in result.events):
                events.append(want)
                break
    assert events == ["pickup", "putdown", "pickup", "putdown"]
    assert paid == 3.0


def test_putting_a_finished_dish_down_costs_what_carrying_it_earned():
    rules = make_rules("easy", recipes=["tomato"])
    state = new_state(rules, 0)
    enc = FeatureEncoder(rules)
    shaper = RewardShaper(Shaping())
    shaper.reset(state)
    plan = [("fresh_tomato", "pickup"), ("free_board", "putdown"), ("board_to_chop", "chop_done"),
            ("chopped_tomato", "pickup"), ("clean_plate", "plate_add"), ("clean_plate", "pickup"),
            ("free_counter", "putdown"), ("clean_plate", "pickup")]
    gains = []
    for target, want in plan:
        for _ in range(30):
            result = transition(state, [_go(enc, enc.encode(state, 0), target)])
            shaped = shaper.step(state, result.events, result.rewards)[1][0]
            if any(e.kind == want for e in result.events):
                gains.append(shaped)
                break
    assert len(gains) == len(plan)
    carry = shaper.potential(state, 0)
    assert carry >= Shaping().carry_dish  # a finished dish in hand
    assert gains[5] > 0 and gains[6] < 0 and abs(gains[6] + gains[7]) < 1e-9


def test_paths_go_around_other_agents_when_they_can():
    rules = make_rules("easy", n_agents=2)
    enc = FeatureEncoder(rules)
    state = new_state(rules, 0)
    geo = state.geo
    state.agent_pos[:] = [geo.flat(1, 1), geo.flat(2, 4)]
    x = enc.encode(state, 0)
    assert _go(enc, x, "free_board") == R  # straight along row 1 to (1, 5), bump right
    assert round(_value(enc, x, "free_board:cost") * 20) == 5
    state.agent_pos[1] = geo.flat(1, 2)  # now the other cook stands in the way
    x = enc.encode(state, 0)
    assert _go(enc, x, "free_board") == D  # around it, through row 2
    assert round(_value(enc, x, "free_board:cost") * 20) == 7
    # the tomato's only access cell is taken: fall back to the direct way
    state.agent_pos[1] = geo.flat(1, 2)
    assert _go(enc, enc.encode(state, 0), "fresh_tomato") == R
