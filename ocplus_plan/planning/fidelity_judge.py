"""The judge of plans for several cooks: is a plan's sequence of steps something the
kitchen can carry out, with collision-free routing and waits allowed?

The planning model does not represent cooks as obstacles to each other (a cook may walk
through the cell another stands on). The strict replays (:mod:`.fidelity`,
:mod:`.fidelity_temporal`) compare step counts and positions with the model and call such
a plan unfaithful. The judge asks the question a benchmark needs: driven step by step,
does the kitchen reach the plan's goal? Each step is *realised*:

* the acting cook walks a shortest path to the cell it must stand on, around the other
  cooks; where every path is blocked by a cook, that cook first steps aside (it walks,
  one simulator step at a time, to the nearest free cell off the path; the acting cook
  waits meanwhile), then the acting cook walks;
* a cook that was put aside and must act from a given cell walks back there first;
* the interaction itself is the replay's (bumps and waits of :class:`._World`).

After every step the simulator is compared with the model (UP's ``SequentialSimulator``)
on every item (where it is and its state) but not on where the cooks stand, which the
routing is free to change; a wrong delivery, a steak burnt that the model did not give
up, a step that cannot be realised, or an item in another place than the model says,
ends the judgement with that step. At the end, every goal order must have been served.

Time-triggered (temporal) plans are first replayed as timed (:func:`.replay_temporal`);
a plan that fails there is realised as timed with waits (:func:`.realise_timed`): every
cook keeps its own actions' order and the cross-cook order the plan's timing implies, no
action starts before its planned time, walks go around cooks (who step aside), a cook
envelope's steak stays on the pan its planned number of ticks; a refused delivery, a burn
the plan does not give up, a bump the kitchen ignores or stuck cooks fail the plan step
(its index in ``plan.timed_actions``), and the goal must be served.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any

from ..sim.codes import Action
from ..sim.queries import direction, distances, walk_actions, walk_to, walks
from ..sim.state import State
from .compile import Compiled
from .fidelity import _World
from .fidelity_temporal import replay_temporal
from .fidelity_waits import realise_timed
from .fidelity_view import ModelView

#: simulator events that end a judgement at the step that caused them
_BAD_EVENTS = frozenset({"wrong_delivery", "move_blocked"})


@dataclass
class Judgement:
    """A plan's judgement: ``faithful``, and when not, the plan step (0-based) that failed
    and why. ``waits`` counts the simulator steps spent letting another cook step aside
    or walking around; ``served`` the orders the kitchen served."""

    faithful: bool
    actions: int = 0
    steps: int = 0
    waits: int = 0
    failed_step: int | None = None
    reason: str = ""
    how: str = "realised"
    served: list[int] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


class _Router(_World):
    """A :class:`._World` whose cooks walk around each other and step aside."""

    def __init__(self, state: State) -> None:
        super().__init__(state)
        self.detour = 0

    def go(self, agent: int, goal: int) -> str:
        """Walk ``agent`` to cell ``goal``, moving blocking cooks aside; '' or the problem."""
        st, geo = self.state, self.state.geo
        walk = geo.walkables[st.layout_index]
        others = frozenset(p for a, p in enumerate(st.agent_pos) if a != agent)
        path = walk_actions(geo.neighbors, walk, st.agent_pos[agent], goal, others)
        if path is None:
            cells = walk_to(walks(geo.neighbors, walk, [st.agent_pos[agent]]), goal)
            if cells is None:
                return f"cook {agent} cannot reach {geo.rc(goal)} at all"
            for other in range(st.n_agents):
                if other != agent and st.agent_pos[other] in set(cells):
                    trouble = self._step_aside(other, set(cells) | {st.agent_pos[agent]})
                    if trouble:
                        return trouble
            others = frozenset(p for a, p in enumerate(st.agent_pos) if a != agent)
            path = walk_actions(geo.neighbors, walk, st.agent_pos[agent], goal, others)
            if path is None:
                return f"cook {agent} has no free path to {geo.rc(goal)} even with waits"
        for action in path:
            self.act(agent, action)
            self.detour += 1
        return ""

    def _step_aside(self, other: int, keep_off: set[int]) -> str:
        st, geo = self.state, self.state.geo
        walk = geo.walkables[st.layout_index]
        busy = {p for a, p in enumerate(st.agent_pos) if a != other}
        near = distances(geo.neighbors, walk, [st.agent_pos[other]], busy)
        free = [c for c in range(len(near)) if near[c] > 0 and c not in keep_off]
        if not free:
            return (f"cook {other} stands in the way at {st.agent_rc(other)} and has "
                    "nowhere to step aside to")
        target = min(free, key=lambda c: (near[c], c))
        for action in walk_actions(geo.neighbors, walk, st.agent_pos[other], target,
                                   busy) or []:
            self.act(other, action)
            self.detour += 1
        return ""

    def realise(self, step: Any) -> str:
        """Carry out one mapped plan step; '' or why it cannot be done."""
        if step.kind in ("abandon", "wait") or step.agent is None:
            return ""  # the simulator has nothing to do (as in the timed replay)
        if step.spot is None:
            return self.run(step)[1]
        geo = self.state.geo
        target = geo.flat(*step.spot)
        trouble = self.go(step.agent, target)
        if trouble or step.kind == "move" or step.place is None:
            return trouble  # nothing to bump (a temporal action's end): being there is all
        if step.kind == "rescue":  # walked already: wait out the rest of its time, bump
            for _ in range(max(0, step.duration - self.detour - 1)):
                self.act(step.agent, int(Action.STAY))
            self.act(step.agent, direction(geo, target, geo.flat(*step.place)))
            return ""
        # the cook now stands on its spot: the replay's interaction
        return self.run(step)[1]


def judge(compiled: Compiled, plan: Any, state: State) -> Judgement:
    """Judge ``plan`` (of ``compiled``) from ``state`` (not changed): see the module."""
    if hasattr(plan, "timed_actions"):
        strict = replay_temporal(compiled, plan, state)
        if strict.ok and set(compiled.goal_orders) <= set(strict.served):
            return Judgement(True, strict.actions, strict.steps, 0, how="timed replay",
                             served=list(strict.served))
        done = realise_timed(compiled, plan, state)
        return Judgement(done.ok, len(plan.timed_actions), done.steps, done.waits,
                         done.failed_step, done.reason, "timed with waits", list(done.served))
    return _realise_all(compiled, [compiled.map_back(ai) for ai in plan.actions], state,
                        list(plan.actions), "realised")


def _realise_all(compiled: Compiled, steps: list[Any], state: State,
                 actions: list[Any], how: str) -> Judgement:
    world = _Router(state.copy())
    out = Judgement(True, how=how)
    from unified_planning.shortcuts import SequentialSimulator

    with SequentialSimulator(compiled.problem, name="sequential_simulator") as sim:
        return _realise_steps(compiled, world, steps, (sim, actions), out)


def _realise_steps(compiled: Compiled, world: _Router, steps: list[Any],
                   model: tuple[Any, list[Any]] | None, out: Judgement) -> Judgement:
    doomed = set(compiled.doomed)
    view = ModelView(compiled) if model is not None else None
    up_state = model[0].get_initial_state() if model is not None else None
    agents = frozenset(compiled.names.agents)
    for index, step in enumerate(steps):
        if step.kind == "abandon":
            doomed.update(step.items)
        before, t0 = len(world.events), world.state.t
        world.detour = 0
        try:
            trouble = world.realise(step)
        except (TypeError, ValueError, KeyError, IndexError) as exc:  # a step it cannot map
            trouble = f"the judge cannot realise a {step.kind} step ({type(exc).__name__})"
        out.actions, out.steps = index + 1, out.steps + world.state.t - t0
        out.waits += max(0, world.detour - (step.duration if step.kind == "move" else 0))
        events = world.events[before:]
        if not trouble:
            bad = {e.kind for e in events} & _BAD_EVENTS
            if bad:
                trouble = f"the kitchen reported {sorted(bad)}"
            elif any(e.kind == "burnt" and e.item not in doomed for e in events):
                trouble = "a steak burnt in the kitchen"
        if not trouble and model is not None and view is not None:
            up_state = model[0].apply(up_state, model[1][index])
            if up_state is None:
                trouble = "not applicable in the model"
            else:
                trouble = view.diff(up_state, world.state, frozenset(doomed),
                                    skip_agents=agents)
        if step.kind == "trash":
            doomed.difference_update(step.items)
        if trouble:
            out.faithful, out.failed_step, out.reason = False, index, trouble
            break
    out.served = [e.value for e in world.events if e.kind == "delivery"]
    if out.faithful and not set(compiled.goal_orders) <= set(out.served):
        missing = sorted(set(compiled.goal_orders) - set(out.served))
        out.faithful, out.reason = False, f"the plan ends with orders {missing} not served"
    return out


__all__ = ["Judgement", "judge"]
