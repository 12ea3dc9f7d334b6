"""A plan step in a cook's queue and the checks on it: is it done already, is it time to
bump, what did the bump find, and when will a queued step reach a pan.

Kept apart from :mod:`.executive` (which owns the queues and decides when to replan).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from ..sim.codes import Cell, ItemState, Where
from ..sim.queries import (
    Bump,
    bump_effect,
    bumps_needed,
    interaction_spots,
    is_plateable,
    switching_walks,
)
from ..sim.state import State
from .paths import DistanceOracle
from .plans import PlanStep

_PAN = int(Cell.PAN)
_HAND = int(Where.HAND)
_RAW = int(ItemState.FRESH)
#: the bump that processes the item of a chop / wash step (several of them finish it)
PROCESS = {"chop": Bump.CHOP, "wash": Bump.WASH}


@dataclass
class Task:
    """A plan step in an agent's queue, with what the executive learned while doing it."""

    step: PlanStep
    deps: frozenset[int]
    bumps: int = 0
    failures: int = 0
    waited: int = 0
    unreachable: bool = False


@dataclass
class BumpRecord:
    """What a bump found: its task, the hand, the item there, its state and plate sizes."""

    task: Task
    hand: int
    here: int
    here_state: tuple[int, int]
    plate_sizes: tuple[int, int]


def already_done(state: State, task: Task, done_steps: set[int]) -> bool:
    """Chop/wash of an item that is already processed (e.g. per-level chop steps): an
    empty hand's bump there would no longer chop or wash. Not before the other cooks'
    steps it waits for are done and its item lies there: a cook that reaches the board
    before another has put the vegetable on it finds nothing to chop, which does not
    mean the chopping is done."""
    kind = task.step.kind
    if kind == "goto":
        return state.agent_pos[task.step.agent] == task.step.target
    if kind in PROCESS:
        here = state.cell_item[task.step.target]
        if not task.deps <= done_steps:
            return False
        if task.step.items and here not in task.step.items:
            return False
        return bump_effect(state, -1, task.step.target) != PROCESS[kind]
    return False

def ready(state: State, agent: int, task: Task, done_steps: set[int]) -> bool:
    """Time to bump for this step? A chop or a wash once the bump would chop or wash
    (``bump_effect``); at a pan once the steak may be taken (never raw) or plated
    (cooked); any other step as soon as the hand holds what the step needs and, for a
    step that takes something, something lies there: a bump that then changes nothing
    tells the executive that the plan and the world disagree (``action_failed``)."""
    if not task.deps <= done_steps:
        return False
    s = task.step
    if any(state.item_where[i] == _HAND and state.item_loc[i] != agent for i in s.items):
        return False  # another cook carries it here (a partner's predicted bump): wait
    held, here = state.agent_hand[agent], state.cell_item[s.target]
    if s.kind in PROCESS:
        return bump_effect(state, held, s.target) == PROCESS[s.kind]
    code = state.geo.terrains[state.layout_index][s.target]
    if code == _PAN and here >= 0 and s.kind != "putdown":
        # never take a raw steak off the pan; only a cooked one goes on a plate
        if s.kind == "plate" or held >= 0:
            return is_plateable(state, here)
        return state.item_state[here] != _RAW
    if s.kind == "pickup":
        return held < 0 and here >= 0
    if s.kind in ("putdown", "deliver", "trash"):
        return held >= 0
    if s.kind == "plate":
        return held >= 0 and here >= 0
    return True


def snapshot(state: State, task: Task, agent: int) -> BumpRecord:
    held, here = state.agent_hand[agent], state.cell_item[task.step.target]
    here_state = (state.item_state[here], state.item_progress[here]) if here >= 0 else (-1, -1)
    sizes = (len(state.plate_contents(held)) if held >= 0 else -1,
             len(state.plate_contents(here)) if here >= 0 else -1)
    return BumpRecord(task, held, here, here_state, sizes)


def pan_eta(state: State, pan: int, queues: Mapping[int, Sequence[Task]],
            oracle: DistanceOracle, over_switches: bool) -> int | None:
    """Estimated steps until a queued task bumps ``pan`` to take its steak (None: no task).
    With a plan scheduled over the switches, walks are timed over them too."""
    best = None
    layout = state.layout_index
    timed = switching_walks(state.geo, state.rules.map_switch_step) \
        if over_switches and len(state.geo.walkables) == 2 else None
    due = max(0, state.next_switch - state.t)
    for a, queue in queues.items():
        pos, total = state.agent_pos[a], 0
        for task in queue:
            if timed is not None:
                found = timed.arrival(pos, task.step.target,
                                      *timed.phase(layout, due, total))
                if found is None:
                    break
                d, spot = found
            else:
                d = oracle.to_station(layout, task.step.target)[pos]
                if d < 0:
                    break
                spots = interaction_spots(state.geo.neighbors, state.geo.walkables[layout],
                                           task.step.target)
                spot = min(spots, key=lambda c: oracle.to_goals(layout, [pos])[c]) \
                    if spots else pos
            total += d + 1
            if task.step.target == pan and task.step.kind != "putdown":
                best = total if best is None else min(best, total)
                break
            if task.step.kind in PROCESS:
                total += bumps_needed(state.rules, PROCESS[task.step.kind]) - 1
            pos = spot
    return best


__all__ = ["PROCESS", "BumpRecord", "Task", "already_done", "pan_eta", "ready", "snapshot"]
