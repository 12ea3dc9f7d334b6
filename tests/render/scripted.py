"""A key sequence that serves one dish on easy_open, derived from the map (not typed in).

The cook walks (breadth-first shortest paths over the floor) to the spawn tile of the
first order's vegetable, picks it up, puts it on a cutting board, chops it, takes a
plate, scoops the chopped vegetable onto the plate and bumps the delivery window.
"""

from __future__ import annotations

from collections import deque

from ocplus_plan.sim import Cell, Item, State
from ocplus_plan.sim.codes import ACTION_DELTAS, Action

#: action -> the WASD key the single human presses for it
WASD_KEY = {Action.RIGHT: "d", Action.DOWN: "s", Action.LEFT: "a", Action.UP: "w",
            Action.STAY: "space"}


def _walk_and_bump(state: State, start: tuple[int, int], target: tuple[int, int]
                   ) -> tuple[list[Action], tuple[int, int]]:
    """Actions to walk from ``start`` next to ``target`` and bump it; and the cell reached."""
    grid = state.grid
    rows, cols = grid.shape
    walkable = {(r, c) for r in range(rows) for c in range(cols)
                if int(grid[r, c]) in (Cell.FLOOR, Cell.SPAWN)}
    moves = [a for a in Action if a != Action.STAY]
    prev: dict[tuple[int, int], tuple[tuple[int, int], Action] | None] = {start: None}
    queue = deque([start])
    while queue:
        cell = queue.popleft()
        for act in moves:
            dr, dc = ACTION_DELTAS[act]
            if (cell[0] + dr, cell[1] + dc) == target:
                path = [act]
                at = cell
                while prev[at] is not None:
                    at, step = prev[at]  # type: ignore[misc]
                    path.append(step)
                return path[::-1], cell
        for act in moves:
            dr, dc = ACTION_DELTAS[act]
            nxt = (cell[0] + dr, cell[1] + dc)
            if nxt in walkable and nxt not in prev:
                prev[nxt] = (cell, act)
                queue.append(nxt)
    raise AssertionError(f"no floor cell next to {target} is reachable from {start}")


def serve_one_dish_actions(state: State) -> list[Action]:
    """Actions for agent 0 (alone in the kitchen) that deliver the first open order."""
    (vegetable,) = state.orders[0].recipe
    layout = state.rules.layout
    spawn = layout.cells_of(Cell(int(vegetable)))[0]
    board = layout.cells_of(Cell.BOARD)[0]
    plate = layout.cells_of(Cell(int(Item.PLATE)))[0]
    window = layout.cells_of(Cell.DELIVERY)[0]
    at = state.agent_rc(0)
    actions: list[Action] = []
    for target, bumps in ((spawn, 1), (board, 1 + state.rules.chop_steps), (plate, 1),
                          (board, 1), (window, 1)):
        path, at = _walk_and_bump(state, at, target)
        actions += path + [path[-1]] * (bumps - 1)
    return actions


def serve_one_dish_keys(state: State) -> list[str]:
    return [WASD_KEY[a] for a in serve_one_dish_actions(state)]
