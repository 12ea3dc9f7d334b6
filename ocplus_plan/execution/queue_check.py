"""The check of a plan's queued steps against the world beside partners: an item a
partner took or moved, answered by the partner model (:mod:`.partner`: expected, repaired,
or a new plan asked for), and what a new plan was made knowing, which is no news."""

from __future__ import annotations

from collections import deque
from collections.abc import Mapping

from ..sim.codes import Item, Where
from ..sim.state import State
from .partner import Prediction, answer_taken, delivering, substitute
from .tasks import Task

_HAND, _CELL, _PLATE = int(Where.HAND), int(Where.CELL), int(Where.PLATE)
_WAITING = int(Where.WAITING)
_PLATE_KIND = int(Item.PLATE)
_UNPREDICTED = "unpredicted"  # the last field of the key of an item no bump is predicted for


def check_queues(state: State, queues: Mapping[int, deque[Task]], done_steps: set[int],
                 predictions: Mapping[int, Prediction], warned: set) -> tuple[bool, int]:
    """Every queued step, not only the ones being done, against the world: (does the plan
    no longer fit, repairs made). The first queued step that uses each item is checked
    once: a partner holding the item is answered by :func:`answer_taken`; an item a
    pickup or a chop expects at its target that is elsewhere (and in none of our cooks'
    hands) means somebody moved it: the plan no longer fits, and so does an ingredient a
    plating step takes at its station lying elsewhere. A plating step, the first to use its
    items, whose ingredient lies on its plate already is done (dropped, a repair)."""
    repairs, seen = 0, delivering(state, predictions)  # served next step: the plan
    # was made from the state the delivery leaves (the plate and its contents at home)
    for task in _in_plan_order(queues):
        if task.step.kind == "plate" and seen.isdisjoint(task.step.items) \
                and _plated(state, task.step.items):
            # the ingredient lies on the step's plate already (a partner put it there):
            # the step is done, and the plan goes on without it. Only where no earlier
            # queued step uses those items: a served plate and its contents come back,
            # and a later dish's plating step may name the same items again
            for q in queues.values():
                if any(t is task for t in q):
                    keep = [t for t in q if t is not task]
                    q.clear()
                    q.extend(keep)
            done_steps.add(task.step.index)
            repairs += 1
            continue
        for i in task.step.items:
            # once per step, item and place: an item the partner put down and takes up
            # again later (it chopped it, then carries it on) is checked again
            if i in seen:
                continue
            seen.add(i)  # only the first queued step that uses it (checked or not)
            where, loc = state.item_where[i], state.item_loc[i]
            key = _taken_key(state, task.step.index, i, predictions)
            if key in warned:
                continue
            if where == _HAND and loc not in queues:
                warned.add(key)
                answer = answer_taken(state, task, queues, done_steps, predictions)
                if answer == "taken":
                    return True, repairs
                repairs += answer == "repaired"
            elif task.step.kind in ("pickup", "chop") and where != _HAND \
                    and not _lies_at(state, i, task.step.target):
                warned.add(key)
                if not substitute(state, queues, i):
                    return True, repairs
                repairs += 1
            elif task.step.kind == "plate" and where in (_CELL, _PLATE) \
                    and not _lies_at(state, i, task.step.target):
                # an ingredient the step takes onto a plate at its station, or the plate it
                # puts the held ingredient on, somewhere else (a partner carried it on, or
                # put the plate it held down elsewhere than the plan had it: hard seed 2
                # beside greedy, steps 102-122): the step would wait for it for ever
                warned.add(key)
                return True, repairs
    return False, repairs


def _taken_key(state: State, index: int, item: int,
               predictions: Mapping[int, Prediction]) -> tuple:
    """What :func:`check_queues` has answered about ``item`` for the step ``index``: the
    item's place, and for one in a partner's hand whether that partner's bump is predicted
    (a prediction that comes is news: the plan is checked against it)."""
    where, loc = state.item_where[item], state.item_loc[item]
    pred = predictions.get(loc) if where == _HAND else None
    unpredicted = where == _HAND and (pred is None or pred.target is None)
    return ("taken", index, item, where, loc) + ((_UNPREDICTED,) if unpredicted else ())


def known_when_planned(state: State, queues: Mapping[int, deque[Task]],
                       predictions: Mapping[int, Prediction]) -> set:
    """The answers a plan made from ``state`` holds already, as :func:`check_queues` keys
    them: every item the plan uses lay where it lies now when the plan was made (the planner
    counted on a partner for one in its hand with no predicted bump, or for carrying one to
    where the plan takes it), so the check asks again only once the item has moved or a
    bump is predicted for the partner holding it. Not an item a partner holds with a
    predicted bump: the plan was made from the state that bump leaves. Beside a learned
    partner that carries a steak about (``gen:multiroom:test:0``, seed 4) the check
    answered ``taken`` at 67 steps, each a planner call for the same plan."""
    keys, seen = set(), delivering(state, predictions)
    for task in _in_plan_order(queues):
        for i in task.step.items:
            if i in seen:
                continue
            seen.add(i)
            key = _taken_key(state, task.step.index, i, predictions)
            if state.item_where[i] != _HAND or key[-1] == _UNPREDICTED:
                keys.add(key)
    return keys


def _in_plan_order(queues: Mapping[int, deque[Task]]) -> list[Task]:
    """Every cook's queued tasks, in the plan's order (the first that uses an item first)."""
    return sorted((t for q in queues.values() for t in q), key=lambda t: t.step.index)


def _plated(state: State, items: tuple[int, ...]) -> bool:
    """Do the ingredients of a plating step (``items``: a plate and what goes on it) lie on
    that plate already?"""
    plates = [i for i in items if state.geo.item_kind[i] == _PLATE_KIND]
    food = [i for i in items if state.geo.item_kind[i] != _PLATE_KIND]
    return len(plates) == 1 and bool(food) and all(
        state.item_where[i] == _PLATE and state.item_loc[i] == plates[0] for i in food)


def _lies_at(state: State, item: int, cell: int) -> bool:
    """Is ``item`` on ``cell`` (or coming back there, or on a plate that is)?"""
    where, loc = state.item_where[item], state.item_loc[item]
    if where == _PLATE:
        return _lies_at(state, loc, cell)
    return where in (_CELL, _WAITING) and loc == cell


__all__ = ["check_queues", "known_when_planned"]
