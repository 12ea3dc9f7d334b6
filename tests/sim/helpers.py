"""Direct state set-up for rule tests (keeps every item in exactly one place)."""

from __future__ import annotations

from ocplus_plan.sim import State, Where, transition
from ocplus_plan.sim.codes import Item


def detach(state: State, item: int) -> None:
    """Take an item out of wherever it is (cell, hand)."""
    where, loc = state.item_where[item], state.item_loc[item]
    if where == Where.CELL:
        state.cell_item[loc] = -1
    elif where == Where.HAND:
        state.agent_hand[loc] = -1


def give(state: State, agent: int, item: int) -> None:
    detach(state, item)
    state.agent_hand[agent] = item
    state.item_where[item], state.item_loc[item] = int(Where.HAND), agent
    state.item_agent[item] = agent


def place(state: State, item: int, rc: tuple[int, int]) -> None:
    detach(state, item)
    f = state.geo.flat(*rc)
    assert state.cell_item[f] < 0, "cell occupied"
    state.cell_item[f] = item
    state.item_where[item], state.item_loc[item] = int(Where.CELL), f


def on_plate(state: State, item: int, plate: int) -> None:
    detach(state, item)
    state.item_where[item], state.item_loc[item] = int(Where.PLATE), plate


def item_of(state: State, kind: Item, k: int = 0) -> int:
    ids = [i for i, kk in enumerate(state.geo.item_kind) if kk == kind]
    return ids[k]


def set_pos(state: State, agent: int, rc: tuple[int, int]) -> None:
    state.agent_pos[agent] = state.geo.flat(*rc)


def run(state: State, *joint_actions):
    """Apply several joint actions (each an int for one agent, or a list); return all events."""
    events, rewards = [], []
    for ja in joint_actions:
        res = transition(state, [ja] if isinstance(ja, int) else list(ja))
        events += res.events
        rewards.append(res.rewards)
    return events, rewards


def kinds(events) -> list[str]:
    return [e.kind for e in events]


def sampled_states(preset: str, n_agents: int, count: int, seed: int = 0,
                   max_steps: int = 150) -> list[State]:
    """Reachable states with things in hands, on plates and in the sink: greedy cooks, with a
    random joint action now and then, stopped after a random number of steps (seeded)."""
    import numpy as np

    from ocplus_plan.agents.greedy import GreedyAgent
    from ocplus_plan.sim import make_rules, new_state

    rules = make_rules(preset, n_agents=n_agents)
    out = []
    for k in range(count):
        rng = np.random.default_rng([seed, k])
        state = new_state(rules, seed * 1000 + k)
        cooks = GreedyAgent(k)
        cooks.reset(state)
        for _ in range(int(rng.integers(0, max_steps + 1))):
            joint = cooks.act(state)
            if rng.random() < 0.2:
                joint = [int(a) for a in rng.integers(0, 5, size=n_agents)]
            transition(state, joint)
        out.append(state)
    return out


# tomato spawn (0, 1), board (0, 3), plate spawn (2, 0), window (2, 5), lettuce spawn (3, 1)
TOMATO_GRID = [
    [1, 3, 1, 6, 1, 1],
    [1, 0, 0, 0, 0, 1],
    [5, 0, 0, 0, 0, 7],
    [1, 4, 1, 1, 1, 1],
]


def tomato_kitchen(spawns=([1, 1], [2, 4])):
    """A 6x4 easy kitchen (:data:`TOMATO_GRID`) with one open order, a tomato salad:
    ``(rules, state)``, a cook at each of ``spawns``."""
    from ocplus_plan.sim import make_rules, new_state
    from ocplus_plan.sim.records import Order

    spec = {"name": "test", "game_map": TOMATO_GRID,
            "agent_spawn_points": [list(p) for p in spawns]}
    rules = make_rules("easy", map=spec, n_agents=len(spawns))
    state = new_state(rules, 0)
    state.orders = [Order(0, (int(Item.TOMATO),), 0, 10_000)]
    return rules, state
