"""Walking on the kitchen grid: neighbours, shortest walks, distances, interaction spots.

The lowest floor of the kitchen's questions (:mod:`.queries` re-exports it): it knows
only flat cell indices and walkable flags, so the map parser (:mod:`.maps`), the
geometry (:mod:`.state`) and the generator's checks use it without the rules or states.
Cells are flat indices; ``neighbors[c]`` lists the cells in the directions RIGHT, DOWN,
LEFT, UP (-1 off the grid), so a neighbour's position there is the action that enters it.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import NamedTuple

from ..errors import ConfigError

Neighbors = Sequence[Sequence[int]]


def grid_neighbors(rows: int, cols: int) -> tuple[tuple[int, int, int, int], ...]:
    """Per flat cell: the neighbour in direction RIGHT, DOWN, LEFT, UP, or -1 off the grid."""
    cells = [(r, c, r * cols + c) for r in range(rows) for c in range(cols)]
    return tuple((f + 1 if c + 1 < cols else -1, f + cols if r + 1 < rows else -1,
                  f - 1 if c > 0 else -1, f - cols if r > 0 else -1) for r, c, f in cells)


class Walks(NamedTuple):
    """Shortest walks from a set of source cells (breadth-first, neighbours in action order).

    Per cell: ``dist`` steps (-1: unreachable), ``parent`` the cell it is entered from on
    one shortest walk, ``first`` the action of that walk's first step (both -1 for the
    sources and for unreachable cells); ``order`` lists the reached cells as they were
    found, sources first (among equally near cells, the one found first wins a tie)."""

    dist: list[int]
    parent: list[int]
    first: list[int]
    order: list[int]


def walks(neighbors: Neighbors, walkable: Sequence[bool], sources: Iterable[int],
          blocked: Iterable[int] = ()) -> Walks:
    """Shortest walks over ``walkable`` cells that are not ``blocked``. Sources count as
    reached (distance 0) whatever they are, so a walk may start on any cell."""
    n = len(neighbors)
    dist, parent, first = [-1] * n, [-1] * n, [-1] * n
    wall = blocked if isinstance(blocked, (set, frozenset)) else set(blocked)
    order: list[int] = []
    for s in sources:
        if not 0 <= s < n:
            raise ConfigError(f"cell {s} is outside the grid of {n} cells")
        if dist[s] < 0:
            dist[s] = 0
            order.append(s)
    n_sources = len(order)
    i = 0
    while i < len(order):  # ``order`` doubles as the queue: it is the discovery order
        cur = order[i]
        i += 1
        d = dist[cur] + 1
        for action, nxt in enumerate(neighbors[cur]):
            if nxt >= 0 and dist[nxt] < 0 and walkable[nxt] and nxt not in wall:
                dist[nxt] = d
                parent[nxt] = cur
                first[nxt] = action if i <= n_sources else first[cur]
                order.append(nxt)
    return Walks(dist, parent, first, order)


def distances(neighbors: Neighbors, walkable: Sequence[bool], sources: Iterable[int],
              blocked: Iterable[int] = ()) -> list[int]:
    """Steps from the nearest source to every cell (-1: unreachable); see :func:`walks`."""
    return walks(neighbors, walkable, sources, blocked).dist


def walk_to(found: Walks, goal: int) -> list[int] | None:
    """The cells of the shortest walk to ``goal``, after the source and ending at ``goal``
    (empty when ``goal`` is a source, None when it is unreachable)."""
    if found.dist[goal] < 0:
        return None
    cells = []
    while found.parent[goal] >= 0:
        cells.append(goal)
        goal = found.parent[goal]
    cells.reverse()
    return cells


def walk_actions(neighbors: Neighbors, walkable: Sequence[bool], start: int, goal: int,
                 blocked: Iterable[int] = ()) -> list[int] | None:
    """The actions of a shortest walk from ``start`` to ``goal`` around ``blocked`` cells
    (empty when they are the same cell, None when there is no walk)."""
    found = walks(neighbors, walkable, [start], blocked)
    cells = walk_to(found, goal)
    if cells is None:
        return None
    return [list(neighbors[found.parent[c]]).index(c) for c in cells]


def interaction_spots(neighbors: Neighbors, walkable: Sequence[bool], cell: int) -> list[int]:
    """The walkable neighbours of ``cell``: where an agent stands to bump it."""
    return [nb for nb in neighbors[cell] if nb >= 0 and walkable[nb]]


__all__ = ["Neighbors", "Walks", "distances", "grid_neighbors", "interaction_spots", "walk_actions",
           "walk_to", "walks"]
