"""Path features plus what a task-allocating cook decides on (``obs="tasks"``).

The path features (:mod:`.features`) say where the nearest item of each kind is, but not
whether it is still worth fetching. A behaviour clone of the greedy cook, driving on its own
on unseen kitchens, disagreed with greedy's action on 31% of cook-steps, and most of those
disagreements were at states where greedy's goal was one of the features' nearest targets:
the clone saw the way and picked another target (``experiments/clone_errors.py``). Greedy
picks by what the kitchen still lacks: the open orders' ingredients minus those already on
their way (chopped, cooking, on a board or pan, in a hand), the free boards and pans, and
which cook is nearer. This encoder appends those values, read from the same symbolic state
and valid on every map (:data:`TASK_NAMES`):

* ``unmet:KIND``: per ingredient kind, the open orders' need (on a plate matched to an
  order: what it misses; otherwise the whole recipe) less the supply on its way, / 2;
* ``unmet_fresh``: the first step (one-hot of four), path cost / 20 and a present flag of
  the nearest fresh ingredient on a counter whose kind is unmet, and ``other_nearer``: some
  other cook stands nearer to that cell;
* ``plate_ready``: the same for the nearest ready ingredient (not on a plate) that a clean
  plate matched to an order still misses;
* ``free_boards`` / ``free_pans``: empty boards and pans, / 2 (clipped to 1).

The batched engine computes the path features only: ``tasks`` runs on the loop engine.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence

import numpy as np

from ..sim.codes import COUNTERS, Cell, Item, ItemState
from ..sim.queries import order_needs
from ..sim.rules import Rules
from ..sim.state import State
from .features import INGREDIENTS, PATH_SCALE, FeatureEncoder

_FRESH = int(ItemState.FRESH)
_BOARD = int(Cell.BOARD)
_COUNTER_CODES = frozenset(int(c) for c in COUNTERS)
_NONE = (0.0,) * 7

TASK_NAMES: tuple[str, ...] = (
    *(f"unmet:{k.name.lower()}" for k in INGREDIENTS),
    *(f"unmet_fresh:{n}" for n in ("go_right", "go_down", "go_left", "go_up", "cost",
                                   "present", "other_nearer")),
    *(f"plate_ready:{n}" for n in ("go_right", "go_down", "go_left", "go_up", "cost",
                                   "present", "other_nearer")),
    "free_boards", "free_pans",
)


def unmet_need(state: State) -> tuple[Counter, Counter]:
    """(kind -> count the open orders still need beyond the supply on its way, kind -> count
    the clean plates matched to orders still miss), from
    :func:`~ocplus_plan.sim.queries.order_needs` as the greedy cook reads them."""
    needs = order_needs(state)
    missing: Counter = Counter()
    for m in needs.plate_missing.values():
        missing.update(m)
    return Counter({k: n - needs.supply[k] for k, n in needs.need.items()
                    if n > needs.supply[k]}), missing


class TaskEncoder:
    """:class:`FeatureEncoder`'s vector followed by :data:`TASK_NAMES`."""

    def __init__(self, rules: Rules) -> None:
        self._features = FeatureEncoder(rules)
        geo = self._features.geo
        self._index = [{c: i for i, c in enumerate(cells)} for cells in self._features.interact]
        self._heat = rules.tables.station_of(int(Item.STEAK))
        self._stations = [
            ([c for c, code in enumerate(t) if code == _BOARD],
             [c for c, code in enumerate(t) if code == self._heat]) for t in geo.terrains]
        self.size = self._features.size + len(TASK_NAMES)

    def feature_names(self) -> list[str]:
        return self._features.feature_names() + list(TASK_NAMES)

    def encode_all(self, state: State, agents: Sequence[int] | None = None) -> np.ndarray:
        ids = list(range(state.n_agents)) if agents is None else list(agents)
        base = self._features.encode_all(state, ids)
        unmet, missing = unmet_need(state)
        extra = np.asarray([self._tasks(state, a, unmet, missing) for a in ids], np.float32)
        return np.concatenate([base, extra], axis=1)

    def _reach(self, state: State, agent: int) -> list[tuple[int, int]]:
        pos = state.agent_pos
        others = tuple(sorted(p for b, p in enumerate(pos) if b != agent))
        return self._features.reach(state.layout_index, pos[agent], others)

    def _tasks(self, state: State, agent: int, unmet: Counter, missing: Counter) -> list[float]:
        kinds, layout = state.geo.item_kind, state.layout_index
        terrain, index = state.geo.terrains[layout], self._index[layout]
        mine = self._reach(state, agent)
        ready_of = state.rules.tables.ready_of
        fresh = ready = (1 << 30, -1, -1)  # (cost, first action, cell)
        for c, i in index.items():
            it = state.cell_item[c]
            cost, act = mine[i]
            if it < 0 or act < 0:
                continue
            k, st = kinds[it], state.item_state[it]
            if (st == _FRESH and unmet[k] > 0 and terrain[c] in _COUNTER_CODES
                    and cost < fresh[0]):
                fresh = (cost, act, c)
            elif missing[k] > 0 and st == ready_of(k) and cost < ready[0]:
                ready = (cost, act, c)
        f = [min(unmet[int(k)], 2) / 2 for k in INGREDIENTS]
        f += self._target(state, agent, fresh) + self._target(state, agent, ready)
        boards, pans = self._stations[layout]
        f += [min(sum(state.cell_item[c] < 0 for c in cells), 2) / 2 for cells in (boards, pans)]
        return f

    def _target(self, state: State, agent: int, target: tuple[int, int, int]) -> list[float]:
        cost, act, cell = target
        if act < 0:
            return list(_NONE)
        onehot = [0.0] * 4
        onehot[act] = 1.0
        i = self._index[state.layout_index][cell]
        nearer = any(self._reach(state, b)[i][0] < cost
                     for b in range(state.n_agents) if b != agent)
        return onehot + [min(cost / PATH_SCALE, 1.0), 1.0, float(nearer)]


__all__ = ["TASK_NAMES", "TaskEncoder", "unmet_need"]
