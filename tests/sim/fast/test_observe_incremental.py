"""The incremental encoder gives the from-scratch encoder's observation, bit for bit, at
every step of random rollouts: layout switches, 1-3 agents, windows from r = 0 (whole map)
to beyond the map, received messages, resets, copies, snapshots, jumps back in time and
steps that are never encoded."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ocplus_plan.agents.greedy import GreedyAgent
from ocplus_plan.sim import Item, ItemState, make_rules, new_state, transition
from ocplus_plan.sim.codes import Action
from ocplus_plan.sim.observe import VectorEncoder, snapshot
from ocplus_plan.sim.fast.observe_incremental import IncrementalEncoder

from ..conftest import kitchen
from ..helpers import give, item_of, place, set_pos

R, D, L, U, S = (int(a) for a in (Action.RIGHT, Action.DOWN, Action.LEFT, Action.UP, Action.STAY))

# (preset, map, agents): dynamic maps switch every few steps
CONFIGS = [
    ("hard", "mapC", 1), ("hard", "mapC", 2), ("hard", "hard_switch", 2),
    ("hard", "trio_kitchen", 3), ("easy", "corridor3", 3), ("medium", "medium_kitchen", 2),
]
RADII = [0, 1, 2, 30]  # 30: every window holds the whole map and unknown cells around it
OPS = ["step"] * 12 + ["skip", "reset", "copy", "snapshot", "rewind", "forget"]


def _rules(config, limit):
    preset, map_name, n = config
    extra = {"map_switch_step": 5} if preset == "hard" else {}
    return make_rules(preset, map=map_name, n_agents=n, order_time_limit=limit, **extra)


@st.composite
def rollouts(draw):
    config = draw(st.sampled_from(CONFIGS))
    return {
        "config": config,
        "radius": draw(st.sampled_from(RADII)),
        "vocab": draw(st.sampled_from([0, 3])) if config[2] > 1 else 0,
        "limit": draw(st.sampled_from([None, 30])),
        "seed": draw(st.integers(0, 2**31 - 1)),
        # share of random actions over the greedy cook's (greedy serves dishes: plates
        # with contents, pans, sinks, deliveries; random ones wander and drop things)
        "noise": draw(st.sampled_from([0.05, 0.3, 1.0])),
        "ops": draw(st.lists(st.sampled_from(OPS), min_size=20, max_size=260)),
    }


@settings(max_examples=70, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(rollouts())
def test_incremental_observation_equals_the_from_scratch_one_every_step(ro):
    rules = _rules(ro["config"], ro["limit"])
    n = rules.n_agents
    scratch = VectorEncoder(rules, ro["radius"], comm_vocab=ro["vocab"])
    live = IncrementalEncoder(scratch)
    rng = np.random.default_rng(ro["seed"])
    cook = GreedyAgent(ro["seed"])
    state = new_state(rules, ro["seed"])
    cook.reset(state)
    saved = [state.copy()]

    for op in ro["ops"]:
        if op in ("step", "skip"):
            joint = [a if rng.random() >= ro["noise"] else int(rng.integers(5))
                     for a in cook.act(state)]
            if transition(state, joint).truncated:
                op = "reset"
            elif rng.random() < 0.1:
                saved.append(state.copy())
        if op == "reset":
            state = new_state(rules, int(rng.integers(2**31 - 1)))
            cook.reset(state)
        elif op == "copy":
            state = state.copy()
        elif op == "rewind":
            state = saved[int(rng.integers(len(saved)))].copy()
            cook.reset(state)
        elif op == "forget":
            live.forget()
        if op == "skip":
            continue
        received = None
        if ro["vocab"] and rng.random() < 0.8:
            received = rng.integers(-1, ro["vocab"], size=(n, n - 1))
        shown = snapshot(state) if op == "snapshot" else state
        got = live.encode(shown, received)
        want = scratch.encode(shown, received)
        assert got.dtype == want.dtype and got.shape == want.shape
        assert np.array_equal(got, want), (
            f"t={state.t} op={op}: differs at {np.argwhere(got != want)[:5].tolist()}"
        )


@pytest.mark.parametrize("radius", [0, 2])
def test_returned_observations_are_independent_of_later_calls(radius):
    rules = make_rules("hard", n_agents=2)
    live = IncrementalEncoder(VectorEncoder(rules, radius))
    state = new_state(rules, 0)
    first = live.encode(state)
    kept = first.copy()
    for joint in ([0, 2], [1, 3], [4, 4]):
        transition(state, joint)
        live.encode(state)
    assert np.array_equal(first, kept)


@pytest.mark.parametrize("radius", [0, 2])
def test_long_served_episodes_stay_exact_through_every_kind_of_change(radius):
    """A mostly-greedy kitchen over several episodes passes through layout switches,
    plates carried with contents, cooking, washing and deliveries; equal every step."""
    rules = make_rules("hard", n_agents=2, map_switch_step=7)
    scratch = VectorEncoder(rules, radius, comm_vocab=2)
    live = IncrementalEncoder(scratch)
    rng = np.random.default_rng(7)
    cook = GreedyAgent(7)
    state = new_state(rules, 7)
    cook.reset(state)
    seen: set[str] = set()
    for _ in range(1200):
        joint = [a if rng.random() >= 0.1 else int(rng.integers(5)) for a in cook.act(state)]
        result = transition(state, joint)
        seen.update(e.kind for e in result.events)
        held = [h for h in state.agent_hand if h >= 0]
        if any(state.plate_contents(h) for h in held):
            seen.add("carried plate with contents")
        if any(state.item_progress[state.cell_item[p]] for p in state.geo.pans
               if state.cell_item[p] >= 0):
            seen.add("steak on a pan")
        received = rng.integers(-1, 2, size=(2, 1))
        assert np.array_equal(live.encode(state, received), scratch.encode(state, received))
        if result.truncated:
            state = new_state(rules, int(rng.integers(1000)))
            cook.reset(state)
    assert {"layout_switch", "plate_add", "delivery", "cook_done", "wash_done",
            "carried plate with contents", "steak on a pan"} <= seen


# map G of test_items (3x7): steak, pan, tomato on top; plate, delivery in the middle row;
# trash, board, sink below
G = [
    [1, 10, 1, 9, 1, 3, 1],
    [5, 0, 0, 0, 0, 0, 7],
    [1, 12, 6, 11, 1, 1, 1],
]


@pytest.mark.parametrize("radius", [0, 1])
def test_changes_on_a_held_plate_alone_are_exact(radius):
    """Steps that change only what lies on a held plate (an ingredient taken onto it, its
    contents trashed while the plate stays in the hand), plus cooking, step by step."""
    rules, s = kitchen(G, [[1, 1]], preset="medium", recipes=["tomato+steak"])
    scratch = VectorEncoder(rules, radius)
    live = IncrementalEncoder(scratch)

    def steps(*moves: int) -> None:
        for m in moves:
            transition(s, [m])
            assert np.array_equal(live.encode(s), scratch.encode(s)), f"t={s.t}"

    tomato, steak, plate = (item_of(s, k) for k in (Item.TOMATO, Item.STEAK, Item.PLATE))
    steps(S)
    give(s, 0, tomato)
    set_pos(s, 0, (1, 2))
    steps(*[D] * (rules.chop_steps + 1))  # onto the board, chopped
    assert s.item_state[tomato] == ItemState.CHOPPED
    steps(L, L)  # to (1, 1), pick up the plate
    assert s.agent_hand[0] == plate
    steps(R, D)  # the held plate takes the chopped tomato from the board
    assert s.plate_contents(plate) == [tomato]
    place(s, steak, (0, 3))  # a raw steak on the pan (set by hand), cooking
    steps(R, *[S] * rules.cook_time, U)  # the held plate takes it, cooked
    assert sorted(s.plate_contents(plate)) == sorted([tomato, steak])
    steps(L, L, D)  # trash: the contents go home, the plate stays in the hand
    assert s.agent_hand[0] == plate and s.plate_contents(plate) == []


def test_windows_of_three_random_cooks_stay_exact():
    rules = make_rules("hard", n_agents=3, map="trio_kitchen")
    scratch = VectorEncoder(rules, 2)
    live = IncrementalEncoder(scratch)
    state, rng = new_state(rules, 3), np.random.default_rng(3)
    for _ in range(300):
        transition(state, rng.integers(0, 5, size=3).tolist())
        assert np.array_equal(live.encode(state), scratch.encode(state))
