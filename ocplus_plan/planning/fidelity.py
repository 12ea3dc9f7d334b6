"""Fidelity: does the simulator do what the planning model predicts?

For a sampled reachable state: compile it, solve it, then replay the plan in the
simulator one action at a time (the acting agent walks a shortest path that
avoids the other agents and bumps; everybody else stays) while UP's
``SequentialSimulator`` applies the same actions to the model. After every action
the two worlds are compared: where each item is (a place, a hand, a plate, waiting
to respawn), its state (fresh / ready / burnt / clean / dirty), where each agent
stands, and the number of steps the action took against its modelled cost. At the
end the served orders must agree. The first disagreement ends the replay and is
reported with the action that caused it. Temporal plans are replayed time-triggered
by :mod:`.fidelity_temporal`, which shares the comparison (:class:`ModelView`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..sim import make_rules, new_state, transition
from ..sim.codes import Action
from ..sim.queries import direction, distances, walk_actions, walk_to, walks
from ..sim.state import State
from .compile import Compiled
from .fidelity_temporal import replay_temporal
from .fidelity_view import ModelView, Replay, failed
from .names import MappedAction

def sample_states(preset: str, n: int, seed: int = 0, max_steps: int = 120,
                  **rule_overrides: Any) -> list[State]:
    """``n`` reachable states: random rollouts of random length (seeded, reproducible)."""
    rules = make_rules(preset, **rule_overrides)
    return [sample_state(rules, seed, k, max_steps) for k in range(n)]


#: how :func:`sample_state` reaches its state, in words (instance manifests quote it)
SAMPLE_RECIPE = ("episode seed = seed * 100003 + k; rng = numpy.random.default_rng([seed, k]); "
                 "rng.integers(0, max_steps + 1) uniformly random joint actions, each "
                 "rng.integers(0, 5, size=n_agents)")


def sample_state(rules: Any, seed: int, k: int, max_steps: int = 120) -> State:
    """The ``k``-th reachable state of :func:`sample_states` for ``rules`` and ``seed``."""
    rng = np.random.default_rng([seed, k])
    state = new_state(rules, seed * 100_003 + k)
    for _ in range(int(rng.integers(0, max_steps + 1))):
        transition(state, rng.integers(0, 5, size=rules.n_agents).tolist())
    return state


class _World:
    """The simulator side of a replay: runs plan steps, collects events."""

    def __init__(self, state: State, make_way: bool = False) -> None:
        self.state = state
        self.events: list[Any] = []
        #: a cook the plan does not move steps aside when it stands in the acting cook's
        #: way (``advance``: the next plan starts from roughly where everybody is)
        self.make_way = make_way

    def act(self, agent: int, action: int) -> None:
        joint = [int(Action.STAY)] * self.state.n_agents
        joint[agent] = action
        self.events.extend(transition(self.state, joint).events)

    def run(self, step: MappedAction) -> tuple[int, str]:
        """Execute one plan step; returns (simulator steps taken, problem or '')."""
        st, geo = self.state, self.state.geo
        if step.kind == "abandon":
            return 0, ""
        agent = step.agent
        assert agent is not None
        spot = geo.flat(*step.spot) if step.spot else None
        taken = 0
        if step.kind in ("move", "rescue") and spot is not None:
            others = frozenset(p for a, p in enumerate(st.agent_pos) if a != agent)
            walk = geo.walkables[st.layout_index]
            path = walk_actions(geo.neighbors, walk, st.agent_pos[agent], spot, others)
            if path is None and self.make_way:
                path = self._make_way(agent, spot)
            if path is None:
                return 0, f"agent {agent} has no free path to {step.spot}"
            for action in path:
                self.act(agent, action)
                taken += 1
            if step.kind == "move":
                return taken, ""
        if spot is not None and st.agent_pos[agent] != spot:
            return taken, f"agent {agent} is at {st.agent_rc(agent)}, not at {step.spot}"
        bump = direction(geo, spot, geo.flat(*step.place))
        if step.kind in ("chop", "wash"):
            bumps, waits = step.duration, 0
        elif step.kind == "cook":
            self.act(agent, bump)
            taken += 1
            bumps, waits = 1, step.duration - 2
        elif step.kind == "rescue":
            bumps, waits = 1, step.duration - taken - 1
        else:
            bumps, waits = 1, 0
        for _ in range(waits):
            self.act(agent, int(Action.STAY))
            taken += 1
        for _ in range(bumps):
            self.act(agent, bump)
            taken += 1
        return taken, ""

    def _make_way(self, agent: int, goal: int) -> list[int] | None:
        """A shortest walk of ``agent`` to ``goal`` through the other cooks, each of which
        on it is first moved (placed, not walked) to the nearest free floor cell off it (the
        cell ``agent`` leaves included: in a one-lane corridor they trade places)."""
        st, geo = self.state, self.state.geo
        walk = geo.walkables[st.layout_index]
        cells = walk_to(walks(geo.neighbors, walk, [st.agent_pos[agent]]), goal)
        if cells is None:
            return None
        keep_off = set(cells)
        for other in range(st.n_agents):
            if other == agent or st.agent_pos[other] not in keep_off:
                continue
            taken = {p for a, p in enumerate(st.agent_pos) if a != agent} | keep_off
            near = distances(geo.neighbors, walk, [st.agent_pos[other]])
            free = [c for c in range(len(near)) if near[c] >= 0 and c not in taken]
            if not free:
                return None
            st.agent_pos[other] = min(free, key=lambda c: (near[c], c))
        others = frozenset(p for a, p in enumerate(st.agent_pos) if a != agent)
        return walk_actions(geo.neighbors, walk, st.agent_pos[agent], goal, others)


def advance(compiled: Compiled, plan: Any, state: State, freeze_layout: bool = False) -> State | None:
    """The state a plan leaves: a sequential plan's steps run in a copy of ``state`` as in a
    replay (the acting cook walks a shortest free path and bumps; the others stay, or are
    put aside when they stand on its walk, see ``_World._make_way``); a
    time-triggered plan is replayed by :func:`.fidelity_temporal.replay_temporal` (every
    cook acts at its planned times). None when a step cannot run or the simulator
    disagrees (a blocked move, a wrong delivery, a burn, a model mismatch): what comes
    after it could not be planned from a state the plan predicts.

    ``freeze_layout``: on a switching map, the copy keeps the current layout (as the plan's
    model does); the state returned has the real rules back, and its layout is the current
    one: a prediction of where the items will be, not of the layout then."""
    if hasattr(plan, "timed_actions"):
        result = replay_temporal(compiled, plan, state, freeze_layout=freeze_layout)
        final = result.final if result.ok else None
    else:
        copy = state.copy()
        if freeze_layout and copy.rules.dynamic:
            from ..sim.rules import with_overrides

            copy.rules = with_overrides(copy.rules, dynamic=False)
        world = _World(copy, make_way=True)
        final = world.state
        for ai in plan.actions:
            before = len(world.events)
            _, trouble = world.run(compiled.map_back(ai))
            kinds = {e.kind for e in world.events[before:]}
            if trouble or kinds & {"wrong_delivery", "move_blocked", "burnt", "layout_switch"}:
                final = None
                break
    if final is not None and final.rules is not state.rules:
        final.rules = state.rules
        final.next_switch = max(final.next_switch, final.t)
    return final


def replay(compiled: Compiled, plan: Any, state: State, freeze_layout: bool = False) -> Replay:
    """Replay a sequential plan in a copy of ``state`` and compare with the model.

    ``freeze_layout`` replays with the layout switches turned off (the model's own
    assumption: the current layout holds), to tell model bugs from switch effects.
    """
    from unified_planning.shortcuts import SequentialSimulator

    from ..sim.rules import with_overrides

    copy = state.copy()
    if freeze_layout and copy.rules.dynamic:
        copy.rules = with_overrides(copy.rules, dynamic=False)
    world = _World(copy)
    view = ModelView(compiled)
    out = Replay(ok=True)
    # steaks the model calls burnt while the simulator may still be cooking them: doomed at
    # compile time, or abandoned by the plan (classical); they burn on the pan in due course
    doomed = set(compiled.doomed)
    with SequentialSimulator(compiled.problem, name="sequential_simulator") as sim:
        up_state = sim.get_initial_state()
        problem = view.diff(up_state, world.state, frozenset(doomed))
        if problem:
            return Replay(False, 0, 0, f"before the plan: {problem}", "initial")
        for index, ai in enumerate(plan.actions):
            step = compiled.map_back(ai)
            if step.kind == "abandon":
                doomed.update(step.items)
            before = len(world.events)
            taken, trouble = world.run(step)
            out.steps += taken
            out.actions = index + 1
            up_state = sim.apply(up_state, ai)
            if up_state is None:
                return failed(out, f"{ai}: not applicable in the model", "model")
            events = world.events[before:]
            kinds = {e.kind for e in events}
            switched = "layout_switch" in {e.kind for e in world.events}
            category = "layout_switch" if switched else "effect"
            if trouble:
                return failed(out, f"{ai}: {trouble}", "blocked" if not switched else category)
            if any(e.kind == "burnt" and e.item not in doomed for e in events):
                return failed(out, f"{ai}: a steak burnt in the simulator", category)
            bad = kinds & {"wrong_delivery", "move_blocked"}
            if bad:
                return failed(out, f"{ai}: simulator events {sorted(bad)}", category)
            problem = view.diff(up_state, world.state, frozenset(doomed))
            if problem:
                return failed(out, f"{ai}: {problem}", category)
            if step.kind == "trash":
                doomed.difference_update(step.items)  # back home fresh: checked again
            if taken != step.duration:
                return failed(out, f"{ai}: took {taken} steps, modelled {step.duration}",
                             "blocked" if step.kind in ("move", "rescue") else "cost")
        out.served = [e.value for e in world.events if e.kind == "delivery"]
        model_served = sorted(view.names.orders[o] for o, expr in view.served.items()
                              if up_state.get_value(expr).bool_constant_value())
        if sorted(out.served) != model_served:
            return failed(out, f"served {sorted(out.served)}, model served {model_served}",
                         "orders")
    return out


__all__ = ["SAMPLE_RECIPE", "Replay", "replay", "sample_state", "sample_states"]
