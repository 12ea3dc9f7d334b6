"""The partner model: what each cook a controller does not drive will do next.

:class:`PartnerModel` is the callable the planner-backed controller gives its executive
(:data:`~ocplus_plan.execution.partner.PartnerModel`). Each step it predicts, per cook the
controller does not drive, the cell it bumps next and the walk it takes there
(:class:`~ocplus_plan.execution.partner.Prediction`):

- a **known** partner whose policy is the greedy controller's is predicted by running that
  policy's decision (:meth:`GreedyAgent.goals`, the same code the partner runs) on the
  current state, with a copy of the controller driving the partner's cooks;
- any **other** partner (idle, random, a learned policy) is predicted from its recent moves
  and what it holds: a cook that has neither moved nor changed what it holds for
  ``patience`` steps is expected to stay; one that moves is expected to do what a greedy
  cook would do in its place (carry what it holds where it is useful, or fetch what the
  open orders need). Such a guess is dropped (the cook is expected to stay) once the cook
  has come no closer to the guessed target for ``doubt`` steps: a cook that carries an item
  round the kitchen is not on its way to the plate the guess names, and our cook would
  otherwise keep the way clear for it and wait for an item that never comes.
"""

from __future__ import annotations

from collections.abc import Sequence

from ..execution.partner import Prediction
from ..sim.state import State
from .base import Controller
from .greedy import GreedyAgent


class PartnerModel:
    """Predicts the cooks a controller does not drive (see the module docstring)."""

    def __init__(self, known: Controller | None = None, patience: int = 3,
                 doubt: int = 10) -> None:
        self.known = known
        self.patience = patience
        self.doubt = doubt
        self.cooks: tuple[int, ...] = ()

    @property
    def by_policy(self) -> bool:
        """Is the partner a known greedy cook, predicted by its own policy?"""
        return isinstance(self.known, GreedyAgent)

    def reset(self, state: State, driven: Sequence[int]) -> None:
        self.cooks = tuple(c for c in range(state.n_agents) if c not in set(driven))
        self.shadow = GreedyAgent(getattr(self.known, "seed", 0))
        self.shadow.reset(state, self.cooks)
        self.last = {c: (state.agent_pos[c], state.agent_hand[c]) for c in self.cooks}
        self.still = dict.fromkeys(self.cooks, 0)
        self.seen_t = state.t
        #: (cook, guessed target) -> (closest walk to it, step it was first that close,
        #: step it was last guessed)
        self.chase: dict[tuple[int, int], tuple[int, int, int]] = {}

    def _watch(self, state: State) -> None:
        """Count the steps each cook has stood still with the same hand."""
        if state.t == self.seen_t:
            return
        self.seen_t = state.t
        for c in self.cooks:
            now = (state.agent_pos[c], state.agent_hand[c])
            self.still[c] = self.still[c] + 1 if now == self.last[c] else 0
            self.last[c] = now

    def __call__(self, state: State) -> dict[int, Prediction]:
        self._watch(state)
        if not self.cooks:
            return {}
        view, goals = self.shadow.goals(state)
        out: dict[int, Prediction] = {}
        for c in self.cooks:
            goal = goals.get(c)
            if goal is None or (not self.by_policy and self.still[c] >= self.patience):
                out[c] = Prediction(c, None, by_policy=self.by_policy)
                continue
            # the walk the policy takes: around the other cooks, which it treats as walls (a
            # walk through our cook is one the partner never takes: it goes round); with no
            # way round, the walk it waits to take (a cook of ours with nothing to do on it
            # steps off)
            pos, others = state.agent_pos[c], frozenset(
                p for b, p in enumerate(state.agent_pos) if b != c)
            step, path = self.shadow.step_towards(view, pos, goal[0], others)
            if step is None:
                step, path = self.shadow.step_towards(view, pos, goal[0], frozenset())
            if not self.by_policy and self._astray(state.t, c, goal[0],
                                                   len(path) if step is not None else 1 << 30):
                out[c] = Prediction(c, None)
                continue
            out[c] = Prediction(c, goal[0], tuple(path) if step is not None else (),
                                self.by_policy)
        return out

    def _astray(self, t: int, cook: int, target: int, walk: int) -> bool:
        """Has ``cook`` come no closer to the guessed ``target`` (``walk`` steps away now)
        for :attr:`doubt` steps? The count goes on while the guess turns to other targets
        and back within :attr:`patience` steps (a cook that keeps taking an item up and
        putting it down is guessed to carry it somewhere every other step, and comes no
        closer); it starts again at a new closest walk or after a longer turn away."""
        best, since, seen = self.chase.get((cook, target), (walk, t, t))
        if t - seen > self.patience or walk < best:
            best, since = walk, t
        self.chase[(cook, target)] = (best, since, t)
        return t - since >= self.doubt


__all__ = ["PartnerModel"]
