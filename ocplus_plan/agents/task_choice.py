"""A learned policy that picks each free cook's subtask; the greedy cook's skills do the rest.

The greedy cook (:mod:`.greedy`) does two things each step: it gives every free cook a
subtask (chop here, fetch that tomato, serve this plate: by a fixed priority, then by
distance), and it walks each cook to its subtask and works it, carrying what a cook holds to
where it is useful. :class:`TaskChoice` keeps the second and hands the first to a policy
(``ocplus train --obs choice``, PPO's actions are these choices; docs/rl.md):

* Each free cook is shown up to :data:`SLOTS` subtasks it can do now: those the greedy cook
  itself would consider for it (useful, reachable, not claimed by a cook holding something,
  their shared budgets not used up). Slot 0 is the cook's current subtask while it still is
  one; the rest follow by walking cost.
* Its observation is the ``tasks`` vector (:mod:`ocplus_plan.rl.task_features`) followed by
  one row of :data:`FEATURES` values per slot: whether the slot holds a subtask, its kind
  (one-hot of :data:`KINDS`), the kind of its item, the walking cost / 20 (clipped to 2),
  whether it is the current one and whether another cook stands nearer to it. The greedy
  cook's priorities are not shown: what to do first is what the policy learns.
* Action ``i < SLOTS`` takes slot ``i``; :data:`SLOTS` (or an empty slot) leaves the cook
  idle. Cooks take their choices in index order: a cell another of its cooks took this step,
  or a subtask whose budget an earlier choice used up, leaves the cook idle.

A cook that holds something carries it as the greedy cook does (its action is not used).
Without a policy (``choose`` None) every free cook takes slot 0: its current subtask, else
the nearest one (the agent ``nearest``: what the options give with no learning).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ..rl.task_features import TaskEncoder
from ..rl.weights import CHOICE_SLOTS, n_actions as actions_of
from ..sim.codes import Item
from ..sim.rules import Rules
from ..sim.state import State
from .greedy import GreedyAgent, Subtask
from .greedy_view import KitchenView

#: subtasks shown to each free cook (action SLOTS: none)
SLOTS = CHOICE_SLOTS
#: the subtask kinds of :meth:`GreedyAgent._candidates`, in one-hot order
KINDS = ("serve", "wash", "dirty_to_sink", "unsink", "clear_plate", "rescue", "chop",
         "clear_board", "trash", "gather", "fetch")
_ITEMS = (int(Item.TOMATO), int(Item.LETTUCE), int(Item.ONION), int(Item.STEAK),
          int(Item.PLATE))
#: values per slot: present, kind, item kind, cost, current, another cook nearer
FEATURES = 1 + len(KINDS) + len(_ITEMS) + 3
_COST_SCALE, _COST_CLIP = 20.0, 2.0


class TaskChoice(GreedyAgent):
    """The greedy cook with each free cook's subtask chosen by ``choose`` (rows of
    :meth:`prepare` -> one slot index per driven cook), or slot 0 without it."""

    name = "nearest"

    def __init__(self, seed: int = 0,
                 choose: Callable[[np.ndarray], Sequence[int]] | None = None) -> None:
        super().__init__(seed)
        self.choose = choose

    @staticmethod
    def obs_size(rules: Rules) -> int:
        """The length of one cook's observation on ``rules``."""
        return TaskEncoder(rules).size + SLOTS * FEATURES

    n_actions = actions_of("choice")  # the slots and none

    def _reset(self, state: State) -> None:
        super()._reset(state)
        self._encoder = TaskEncoder(state.rules)
        self._pending: tuple | None = None

    def act(self, state: State) -> list[int]:
        obs = self.prepare(state)
        picks = [0] * len(self.agent_ids) if self.choose is None else self.choose(obs)
        return self.drive(state, picks)

    def prepare(self, state: State) -> np.ndarray:
        """The driven cooks' observations (one row each, in ``agent_ids`` order), keeping
        this step's subtasks for :meth:`drive`."""
        v, goals, claimed, budget, partners = self._holders(state)
        by_cell = self._task_cells(v, budget)
        slots = np.zeros((len(self.agent_ids), SLOTS, FEATURES), dtype=np.float32)
        options: dict[int, list[int]] = {}
        for i, a in enumerate(self.agent_ids):
            options[a] = []
            if state.agent_hand[a] >= 0:
                continue
            ranked = []
            for cell, ts in by_cell.items():
                d = None if self._spent(ts, budget) else \
                    self._cost(v, a, cell, ts, claimed, partners)
                if d is not None:
                    ranked.append((not self._kept(a, cell, ts), d, cell))
            for k, (other, d, cell) in enumerate(sorted(ranked)[:SLOTS]):
                options[a].append(cell)
                slots[i, k] = self._slot(v, a, by_cell[cell][0], d, not other)
        self._pending = (state.t, v, goals, claimed, budget, by_cell, options)
        rows = self._encoder.encode_all(state, self.agent_ids)
        return np.concatenate([rows, slots.reshape(len(rows), -1)], axis=1)

    def drive(self, state: State, picks: Sequence[int]) -> list[int]:
        """One action per driven cook, each free cook working the subtask of its slot
        ``picks[i]`` (from the :meth:`prepare` of this same step)."""
        if self._pending is None or self._pending[0] != state.t:
            raise RuntimeError("drive() needs prepare() on the same state first")
        _, v, goals, claimed, budget, by_cell, options = self._pending
        self._pending = None
        if len(picks) != len(self.agent_ids):
            raise ValueError(f"{len(picks)} choices for {len(self.agent_ids)} cooks")
        for a, pick in zip(self.agent_ids, picks):
            if state.agent_hand[a] >= 0:
                continue
            cells = options[a]
            pick = int(pick)
            if not (0 <= pick < len(cells)
                    and self._take(v, a, cells[pick], by_cell[cells[pick]], claimed, budget,
                                   goals)):
                self.tasks[a] = None
                self.counts["idle_steps"] += 1
        return self._moves(v, goals)

    def _slot(self, v: KitchenView, a: int, task: Subtask, cost: float, current: bool
              ) -> np.ndarray:
        row = np.zeros(FEATURES, dtype=np.float32)
        row[0] = 1.0
        row[1 + KINDS.index(task.kind)] = 1.0
        kind = int(v.kind[task.item])
        if kind in _ITEMS:
            row[1 + len(KINDS) + _ITEMS.index(kind)] = 1.0
        row[-3] = min(cost / _COST_SCALE, _COST_CLIP)
        row[-2] = float(current)
        row[-1] = float(any(v.reach(b, task.cell) < cost
                            for b in range(v.s.n_agents) if b != a))
        return row


__all__ = ["FEATURES", "KINDS", "SLOTS", "TaskChoice"]
