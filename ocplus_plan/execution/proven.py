"""Answers a planner proved, so that the same question is never asked twice.

A planner that reports ``unsolvable`` has proven that the problem has no plan; asking it
again for the same problem costs a planner call and returns the same answer. Two records:

- :class:`ProvenOutcomes` keeps proven outcomes by the key of the problem asked
  (:func:`problem_key`: everything the compiler reads from the state for that question);
- one-cook refusals: a problem that models fewer cooks than are driven (``one-cook``, or
  partners left out) and is proven unsolvable is remembered by :func:`reach_key` (the
  layout, the floor each modelled cook can reach and the recipes asked for): while that
  holds, the pipeline models every driven cook at once instead of asking again (a kitchen
  whose halves meet only at pass-through counters needs a hand-over, which one cook alone
  cannot do).
"""

from __future__ import annotations

from collections.abc import Hashable, Sequence
from typing import Any

from ..sim.queries import distances
from ..sim.state import State

#: the statuses that are proofs, not failures to find a plan in time
PROVEN_STATUSES = frozenset({"unsolvable"})


def problem_key(state: State, modelled: Sequence[int] | None, max_orders: int | None,
                granularity: str, temporal: bool = False) -> Hashable:
    """The key of one planner question: the cooks modelled, their places and hands, every
    item's place and state, the kitchen's walkable cells (a relaxed kitchen, with every
    switching cell open, is another question) and layout, the orders asked for (and, for a
    temporal problem, cooking progress and the time to the next switch)."""
    cooks = tuple(range(state.n_agents)) if modelled is None else tuple(sorted(modelled))
    orders = state.orders if max_orders is None else state.orders[:max_orders]
    return (granularity, cooks, max_orders, state.geo.walkables, state.layout_index,
            tuple(state.agent_pos[a] for a in cooks), tuple(state.agent_hand),
            tuple(state.item_where), tuple(state.item_loc), tuple(state.item_state),
            tuple(o.recipe for o in orders),
            (tuple(state.item_progress), state.next_switch - state.t) if temporal else ())


def reach_key(state: State, modelled: Sequence[int], max_orders: int | None) -> Hashable:
    """What makes a problem with fewer cooks unsolvable in a lasting way: the layout, the
    floor each modelled cook can reach, and the recipes asked for."""
    geo = state.geo
    walk = geo.walkables[state.layout_index]
    floors = []
    for a in sorted(modelled):
        dist = distances(geo.neighbors, walk, [state.agent_pos[a]])
        floors.append(frozenset(c for c, d in enumerate(dist) if d >= 0))
    orders = state.orders if max_orders is None else state.orders[:max_orders]
    return (state.layout_index, tuple(floors), tuple(sorted(o.recipe for o in orders)))


class ProvenOutcomes:
    """Proven planner outcomes by problem key, and the reaches where fewer cooks fail."""

    def __init__(self) -> None:
        self.outcomes: dict[Hashable, Any] = {}
        self.too_few_cooks: set[Hashable] = set()
        #: questions answered from the record instead of a planner call
        self.hits = 0
        #: problems with fewer cooks proven unsolvable, then asked with every driven cook
        self.fallbacks = 0
        #: reach -> failed tries (timeouts, errors) of the one-cook problem there
        self.failures: dict[Hashable, int] = {}
        self.failure_fallbacks = 0  # every cook modelled after repeated failures, not a proof
        self.planner_fallbacks = 0  # calls answered by the default planner instead

    def get(self, key: Hashable) -> Any | None:
        """The proven outcome for ``key`` (counted as a hit), or None."""
        found = self.outcomes.get(key)
        if found is not None:
            self.hits += 1
        return found

    def put(self, key: Hashable, result: Any) -> None:
        """Remember ``result`` if it is a proof (see :data:`PROVEN_STATUSES`)."""
        if getattr(result, "status", None) in PROVEN_STATUSES:
            self.outcomes[key] = result

    def info(self) -> dict[str, int]:
        return {"proven_answers_reused": self.hits, "all_cooks_fallbacks": self.fallbacks,
                "failure_fallbacks": self.failure_fallbacks,
                "default_planner_fallbacks": self.planner_fallbacks}


__all__ = ["PROVEN_STATUSES", "ProvenOutcomes", "problem_key", "reach_key"]
