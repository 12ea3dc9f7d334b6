"""The partner model's predictions and what the executive does with them.

A cook the executive does not drive (a partner) is predicted by a *partner model*, a
callable ``state -> {cook: Prediction}`` that the controller gives the executive
(``agents/partner_model.py`` builds one: the partner's own policy when it is a known agent,
else a guess from its recent moves and what it holds). A prediction is the cell the cook
will bump next and the walk it takes there. The executive uses it three ways:

- **routing**: the predicted walk is reserved in the space-time paths (the partner is a
  moving obstacle whose moves are known, not one assumed to stand still);
- **planning**: the planner is asked about the state the partner's next bump leaves
  (:func:`predicted_state`): an item it carries to a board, a pan or a plate is already
  there, so that work is not planned again, and the plan uses the item where it will be;
- **repair**: when the partner takes an item a queued step needs, and its predicted bump
  puts the item where a later step of the plan uses it, the steps that would have carried
  it there are dropped and the rest of the plan kept (:func:`repair_taken`); only when the
  prediction does not fit the plan is a new plan asked for (``taken``).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Collection, Iterable, Iterator, Mapping
from dataclasses import dataclass, replace

from ..sim.codes import Cell, Item, ItemState, Where
from ..sim.orders import matching_order, plate_recipe
from ..sim.queries import Bump, bump_effect, distances, interaction_spots
from ..sim.step import apply_bump
from ..sim.state import Geometry, State
from .claims import withhold
from .plans import PlanFunction, PlanOutcome, PlanStep, causal_dependencies, touched
from .proven import PROVEN_STATUSES
from .tasks import Task

_HAND, _CELL, _PLATE = int(Where.HAND), int(Where.CELL), int(Where.PLATE)
_WAITING = int(Where.WAITING)
_PLATE_KIND = int(Item.PLATE)
_FRESH, _CHOPPED = int(ItemState.FRESH), int(ItemState.CHOPPED)
#: steps of a predicted walk reserved in the executive's paths
PREDICT_STEPS = 8


@dataclass(frozen=True)
class Prediction:
    """What a cook the executive does not drive will do next: bump ``target`` (None: it
    stays where it is) after walking ``path`` (floor cells, the next one first)."""

    cook: int
    target: int | None
    path: tuple[int, ...] = ()
    #: predicted by running the partner's own policy (a known agent), not guessed
    by_policy: bool = False


#: state -> one prediction per cook the executive does not drive
PartnerModel = Callable[[State], Mapping[int, Prediction]]


def plan_around(planner: PlanFunction, state: State, agents: tuple[int, ...], reason: str,
                predictions: Mapping[int, Prediction] | None,
                claims: Mapping[int, int] | None = None) -> PlanOutcome:
    """Ask ``planner`` about the state the partners' predicted next bumps leave
    (:func:`predicted_state`); when that fails with a partner as a wall, ask again with the
    partners' cells open (the partner may yet move). Without predictions: the state.
    Items a partner keeps taking up (``claims``: item -> partner, :mod:`.claims`) are left
    out of every problem asked; when no plan comes without them, it is asked with them."""
    if claims:
        held = dict(claims)
        outcome = plan_around(lambda s, a, r: planner(withhold(s, held), a, r),
                              state, agents, reason, predictions)
        if outcome.ok:
            return outcome
    if predictions is None:
        return planner(state.copy(), agents, reason)
    problem = predicted_state(state, predictions)
    outcome = planner(problem, agents, reason)
    if not outcome.ok and problem.geo is not state.geo:
        outcome = planner(predicted_state(state, predictions, walls=False), agents, reason)
    if outcome.status in PROVEN_STATUSES and predictions:
        return _with_partners(planner, state, agents, reason, predictions)
    if outcome.ok and outcome.relaxed and predictions and \
            all(p.by_policy for p in predictions.values()):
        return sooner_jointly(planner, state, agents, reason, predictions, outcome)
    return outcome


def sooner_jointly(planner: PlanFunction, state: State, agents: tuple[int, ...], reason: str,
                   predictions: Mapping[int, Prediction], own: PlanOutcome) -> PlanOutcome:
    """Our cooks' plan waits for layout switches (planned relaxed: ``own``) beside partners
    predicted by their own policy: plan every cook too and, when that plan ends sooner, keep
    our steps up to the first that waits for a partner's (:func:`ours_first`), as on a split
    kitchen. The partners' steps in it are hand-overs their policy makes: a greedy partner
    takes on an item left on a counter it reaches and passes over what our cook finishes
    sooner (``agents/greedy.py``, ``_pass_sooner``). ``own`` when the plan of every cook
    fails, ends no sooner, or leaves our cooks nothing to do before a partner's step."""
    joint = planner(predicted_state(state, predictions, walls=False),
                    tuple(range(state.n_agents)), reason)
    if not joint.ok or _plan_end(joint) >= _plan_end(own):
        return own
    steps = ours_first(joint.steps, agents, prefix=True)
    if not steps:
        return own
    return replace(joint, steps=steps, planning_time=own.planning_time + joint.planning_time)


def _plan_end(outcome: PlanOutcome) -> float:
    """When the last step of a scheduled plan ends (steps from when it was made)."""
    return max(((s.start or 0.0) + (s.duration or 0.0) for s in outcome.steps), default=0.0)


def _with_partners(planner: PlanFunction, state: State, agents: tuple[int, ...], reason: str,
                   predictions: Mapping[int, Prediction]) -> PlanOutcome:
    """Our cooks alone can serve nothing (a kitchen split between the cooks: the partner's
    half holds a station every dish needs): plan every cook, and keep our steps up to the
    first that waits for a partner's (:func:`ours_first`). Our cooks do their half and
    leave the work on the counters between the halves; the partner's policy decides the
    rest, and we plan again when our steps are done. ``waiting`` (not a plan) when our
    first step already waits for the partner: the executive asks again later."""
    joint = planner(predicted_state(state, predictions, walls=False),
                    tuple(range(state.n_agents)), reason)
    if not joint.ok:
        return joint
    steps = ours_first(joint.steps, agents, meeting_counters(state))
    if not steps:
        return PlanOutcome("waiting", [], joint.planning_time,
                           "every cook planned: our first step waits for a partner's")
    return replace(joint, steps=steps)


def ours_first(steps: list[PlanStep], agents: tuple[int, ...],
               meet: Collection[int] = (), prefix: bool = False) -> list[PlanStep]:
    """The steps of ``agents`` that do not wait for any step of another cook. A step that
    touches a cell or item a partner's earlier step touches
    (:func:`~.plans.causal_dependencies`) is cut, and so is a later step of ours that touches
    a cell or item a cut step of ours touches, or waits for a cut step; the others are kept,
    in their order (the steak carried to the pan while the lettuce waits for the partner's
    hand-over). A kept pickup whose item's next step of ours is cut ends its cook's steps:
    where that step works one of ``meet`` (free plain counters: the plan meets the partner
    there, say to plate the steak on the plate the partner brings), the cook puts the item
    down there and stops; elsewhere it stops before the pickup (it would stand holding the
    item). With ``prefix``, a cook's steps end at its first step that is cut (each cook
    keeps only what comes before it waits for a partner)."""
    order = sorted(steps, key=lambda s: (s.start or 0.0, s.index))
    deps = causal_dependencies(order)
    cut: set[int] = set()
    held: dict[int, set[tuple[str, int]]] = {a: set() for a in agents}
    for s in order:
        mine = touched(s)
        if s.agent not in agents or deps[s.index] & cut or mine & held[s.agent] \
                or (prefix and held[s.agent]):
            cut.add(s.index)
            if s.agent in agents:
                held[s.agent] |= mine
    ours = [s for s in order if s.agent in agents]
    if prefix:
        return [s for s in ours if s.index not in cut]
    stopped: set[int] = set()
    out: list[PlanStep] = []
    spare = max((s.index for s in steps), default=0)
    for k, s in enumerate(ours):
        if s.index in cut or s.agent in stopped:
            continue
        nxt = next((x for x in ours[k + 1:] if x.agent == s.agent
                    and set(x.items) & set(s.items)), None)
        if s.kind == "pickup" and nxt is not None and nxt.index in cut:
            stopped.add(s.agent)
            if nxt.target in meet:  # the hand-over the plan meant: put it down there
                spare += 1
                out += [s, PlanStep(spare, s.agent, "putdown", nxt.target, s.items, nxt.start)]
            continue
        out.append(s)
    return out


def predicted_state(state: State, predictions: Mapping[int, Prediction],
                    walls: bool = True) -> State:
    """A copy of ``state`` in which every partner's held item is where its predicted bump
    puts it (put down on a counter, a board or a pan, or onto a plate lying there), and a
    dish an open order takes is served as the simulator serves it (:func:`delivering`);
    other bumps (throwing away) leave the item in its hand. A partner predicted to stay
    with empty hands is a wall where it stands (:func:`blocked_geometry`): the plan does
    not count on passing it or on working from its cell."""
    out = state.copy()
    still = []
    for cook, pred in predictions.items():
        if pred.target is None and out.agent_hand[cook] < 0:
            still.append(out.agent_pos[cook])
        held = out.agent_hand[cook]
        if held < 0 or pred.target is None:
            continue
        effect = bump_effect(out, held, pred.target)
        if effect == Bump.PUT_DOWN:
            out.cell_item[pred.target] = held
            out.item_where[held], out.item_loc[held] = _CELL, pred.target
        elif effect == Bump.ONTO_PLATE:
            out.item_where[held], out.item_loc[held] = _PLATE, out.cell_item[pred.target]
        elif held in delivering(out, {cook: pred}):
            # the dish is served: its order is gone (the next is drawn as the simulator
            # would) and the plate and its contents go home, as the simulator sends them
            apply_bump(out, cook, pred.target)
            continue
        else:
            continue
        out.agent_hand[cook] = -1
    if still and walls:
        out.geo = blocked_geometry(state.geo, frozenset(still))
    return out


def delivering(state: State, predictions: Mapping[int, Prediction]) -> set[int]:
    """The plates (and what lies on them) that partners serve with their predicted next
    bump: a plate in a partner's hand that an open order takes, carried to the window."""
    out: set[int] = set()
    for cook, pred in predictions.items():
        held = state.agent_hand[cook]
        if held < 0 or pred.target is None or \
                bump_effect(state, held, pred.target) != Bump.DELIVER or \
                state.geo.item_kind[held] != _PLATE_KIND or \
                matching_order(state, plate_recipe(state, held)) < 0:
            continue
        out.add(held)
        out.update(state.plate_contents(held))
    return out


_BLOCKED: dict[tuple[int, frozenset[int]], tuple[Geometry, Geometry]] = {}


def blocked_geometry(geo: Geometry, cells: frozenset[int]) -> Geometry:
    """``geo`` with ``cells`` walls in every layout (kept: the planner's caches key on it)."""
    key = (id(geo), cells)
    known = _BLOCKED.get(key)
    if known is None or known[0] is not geo:
        wall = int(Cell.BLOCK)
        terrains = tuple(tuple(wall if c in cells else v for c, v in enumerate(t))
                         for t in geo.terrains)
        walkables = tuple(tuple(w and c not in cells for c, w in enumerate(ws))
                          for ws in geo.walkables)
        if len(_BLOCKED) > 256:
            _BLOCKED.clear()
        known = _BLOCKED[key] = (geo, replace(geo, terrains=terrains, walkables=walkables))
    return known[1]


def expected_by_plan(queues: Mapping[int, deque[Task]], item: int, target: int | None) -> bool:
    """Does the first queued step that uses ``item`` at the partner's predicted ``target``
    come before any step that would carry the item (so the plan already counts on it)? Not
    when that step is a delivery: the partner's bump serves the dish, and a cook of ours
    waiting to do it would stand in front of the window in the partner's way."""
    if target is None:
        return False
    for q in queues.values():
        for task in q:
            if item not in task.step.items:
                continue
            if task.step.target == target:
                # a delivery the partner's bump makes itself is not ours to wait for
                return task.step.kind != "deliver"
            if task.step.kind == "pickup":
                return False
    return False


def this_life(plan: list[tuple[int, Task]], is_plate: bool) -> list[tuple[int, Task]]:
    """The steps of ``plan`` (cook, task; by step index, each using one item) up to the one
    that sends the item back to its crate: a delivery (the plate and what it holds), or
    throwing away (an ingredient; a plate stays in the hand). The steps after it use the
    item afresh: a plan for two dishes takes the steak crate's one steak twice."""
    for k, (_a, t) in enumerate(plan):
        if t.step.kind == "deliver" or (t.step.kind == "trash" and not is_plate):
            return plan[:k + 1]
    return plan


def repair_taken(queues: Mapping[int, deque[Task]], done_steps: set[int], item: int,
                 target: int | None, is_plate: bool = False) -> bool:
    """The partner took ``item`` and will bump ``target`` with it: drop the queued steps that
    would have fetched the item and carried it to ``target`` (they count as done, so the
    steps waiting for them go on) and keep the rest. False (nothing changed) when no queued
    step of the item's present life (:func:`this_life`) uses it at ``target``: the plan does
    not fit the prediction. A step of a later life never fits: on ``gen:corridor:test:1``,
    seed 2, beside the shipped generalist, the partner carried the steak the plan's first
    dish was to get onto the plate at the plate crate where the second dish would take it,
    and the repair dropped the first dish's steps, its delivery with them: our cook waited
    at the plate crate, holding the plate of that dish, for a plate that never came back."""
    if target is None:
        return False
    plan = [(a, t) for a, q in queues.items() for t in q if item in t.step.items]
    plan.sort(key=lambda at: at[1].step.index)
    plan = this_life(plan, is_plate)
    at_target = next((i for i, (_a, t) in enumerate(plan) if t.step.target == target), None)
    if at_target is None:
        return False
    drop = [t for _a, t in plan[:at_target]]
    a, last = plan[at_target]
    carriers = {x for x, t in plan[:at_target] if t.step.kind == "pickup"}
    if last.step.kind in ("putdown", "deliver") or (last.step.kind == "plate" and a in carriers):
        drop.append(last)  # the partner's bump does this very step
    gone = {id(t) for t in drop}
    for cook, q in queues.items():
        keep = [t for t in q if id(t) not in gone]
        if len(keep) != len(q):
            queues[cook].clear()  # type: ignore[attr-defined]
            queues[cook].extend(keep)  # type: ignore[attr-defined]
    done_steps.update(t.step.index for t in drop)
    return True


def held_by_partner(state: State, items: Iterable[int],
                    driven: Collection[int] | Mapping[int, object]) -> tuple[int, int] | None:
    """(cook, item): one of ``items`` in the hand of a cook not in ``driven``, or None. Also
    what frees a lone cook that handed its item off after a livelock: the partner has taken
    it on (``Executive._decide``)."""
    for i in items:
        if state.item_where[i] == _HAND and state.item_loc[i] not in driven:
            return state.item_loc[i], i
    return None


def answer_taken(state: State, task: Task, queues: Mapping[int, deque[Task]],
                 done_steps: set[int], predictions: Mapping[int, Prediction]) -> str | None:
    """A partner holds an item of ``task``: ``expected`` (its predicted bump puts the item
    where the plan uses it), ``repaired`` (:func:`repair_taken` fitted the plan to it) or
    ``taken`` (the plan does not fit: plan again). None when no partner holds one."""
    found = held_by_partner(state, task.step.items, queues)
    if found is None:
        return None
    pred = predictions.get(found[0])
    target = None if pred is None else pred.target
    if expected_by_plan(queues, found[1], target):
        return "expected"
    if await_on_plate(state, queues, *found, target):
        return "expected"
    if repair_taken(queues, done_steps, found[1], target,
                    state.geo.item_kind[found[1]] == _PLATE_KIND) or \
            substitute(state, queues, found[1]):
        return "repaired"
    return "taken"


def onto_our_plate(state: State, queues: Mapping[int, deque[Task]], cook: int, item: int,
                   target: int | None) -> bool:
    """Does the partner's predicted bump put ``item`` onto a plate lying at ``target`` that the
    plan's first step with the item carries with it (a plan made from the state that bump
    leaves: the item is on the plate already, and only the plate is moved on)?"""
    if target is None or bump_effect(state, state.agent_hand[cook], target) != Bump.ONTO_PLATE:
        return False
    plate = state.cell_item[target]
    first = min((t for q in queues.values() for t in q if item in t.step.items),
                key=lambda t: t.step.index, default=None)
    return first is not None and plate in first.step.items


def await_on_plate(state: State, queues: Mapping[int, deque[Task]], cook: int, item: int,
                   target: int | None) -> bool:
    """Does the partner ``cook``'s predicted bump put ``item`` onto the plate at ``target``,
    which the plan takes on as if the item lay there already (:func:`onto_our_plate`)? Then
    our first queued step that takes the plate waits for the item too
    (:func:`~.tasks.ready` waits while another cook holds an item of the step), or the cook
    carries the plate off before the partner gets there and serves it without the item
    (hard seed 0 beside greedy: a refused delivery at step 177, the third dish lost)."""
    if not onto_our_plate(state, queues, cook, item, target):
        return False
    plate = state.cell_item[target]
    first = min((t for q in queues.values() for t in q if plate in t.step.items),
                key=lambda t: t.step.index, default=None)
    if first is not None and item not in first.step.items:
        first.step = replace(first.step, items=(*first.step.items, item))
    return True


def await_partner_plates(state: State, queues: Mapping[int, deque[Task]],
                         predictions: Mapping[int, Prediction]) -> None:
    """A new plan made from the state the partners' predicted bumps leave: where such a
    bump puts an item onto a plate the plan carries on, our first step that takes the
    plate waits for the item (:func:`await_on_plate`) from the plan's first action on, not
    from the next check of the queued steps: taken at once, the plate left before the
    partner got there (``gen:multiroom:test:0``, seed 0, beside greedy
    with every cook's plan asked: our cook picked up the plate the partner was bringing
    the lettuce to, and the plans flipped between serving it and clearing the other plate
    for 12 steps)."""
    for cook, pred in predictions.items():
        if state.agent_hand[cook] >= 0:
            await_on_plate(state, queues, cook, state.agent_hand[cook], pred.target)


def substitute(state: State, queues: Mapping[int, deque[Task]], item: int) -> bool:
    """Items of one kind in one state are interchangeable: when the plan's first step with
    ``item`` picks it up from a cell and somebody else has it, the plan takes the nearest
    free item of the same kind and state lying on a cell (or coming back to its crate)
    instead, in every queued step. False when there is none or the plan's first step with
    the item is not such a pickup."""
    tasks = sorted((t for q in queues.values() for t in q if item in t.step.items),
                   key=lambda t: t.step.index)
    if not tasks or tasks[0].step.kind != "pickup" or len(tasks[0].step.items) != 1:
        return False
    used = {i for q in queues.values() for t in q for i in t.step.items}
    kind, st = state.geo.item_kind[item], state.item_state[item]
    rc = state.geo.rc
    here = rc(tasks[0].step.target)
    free = [i for i in range(state.n_items) if i not in used and state.geo.item_kind[i] == kind
            and state.item_state[i] == st and state.item_where[i] in (_CELL, _WAITING)]
    if not free:
        return False

    def far(i: int) -> tuple[int, int]:
        r, c = rc(state.item_loc[i])
        return abs(r - here[0]) + abs(c - here[1]), i

    other = min(free, key=far)
    for task in tasks:
        step = task.step
        items = tuple(other if i == item else i for i in step.items)
        target = state.item_loc[other] if task is tasks[0] else step.target
        task.step = replace(step, items=items, target=target)
    return True


def vacate(state: State, queues: Mapping[int, deque[Task]], predictions: Mapping[int, Prediction],
           index: int, warned: set) -> int:
    """A board that holds our chopped item, waiting there for a later step of the plan, while
    a partner carries a raw vegetable to it (or waits there for it): a greedy partner would
    stand in front of the board until it is free, and where the board is worked from one
    cell, nobody else can reach the item again. A free cook of ours moves the item to the
    nearest free counter first (the later steps take it there). The steps added (0 or 2)."""
    geo = state.geo
    walk, board = geo.walkables[state.layout_index], int(Cell.BOARD)
    terrain = geo.terrains[state.layout_index]
    wanted = {p.target for c, p in predictions.items() if p.target is not None
              and state.agent_hand[c] >= 0 and terrain[p.target] == board
              and state.item_state[state.agent_hand[c]] == _FRESH}
    for cell in wanted:
        item = state.cell_item[cell]
        if item < 0 or state.item_state[item] != _CHOPPED or ("vacate", item) in warned:
            continue
        users = [t for q in queues.values() for t in q if item in t.step.items]
        if not users or any(t.step.kind == "chop" for t in users):
            continue
        spots = interaction_spots(geo.neighbors, walk, cell)
        free = [a for a, q in queues.items() if state.agent_hand[a] < 0
                and not (q and q[0].step.kind != "goto" and q[0].bumps)]
        reach = {a: distances(geo.neighbors, walk, [state.agent_pos[a]]) for a in free}
        cook = min((a for a in free if any(reach[a][n] >= 0 for n in spots)),
                   key=lambda a: min(reach[a][n] for n in spots if reach[a][n] >= 0), default=None)
        if cook is None:
            continue
        counter = _free_counter(state, reach[cook], cell)
        if counter is None:
            continue
        warned.add(("vacate", item))
        for t in users:
            if t.step.target == cell:
                t.step = replace(t.step, target=counter)
            if t not in queues[cook]:
                t.deps = t.deps | {index}
        queues[cook].extendleft([Task(PlanStep(index, cook, "putdown", counter, (item,)), frozenset()),
                                 Task(PlanStep(index - 1, cook, "pickup", cell, (item,)), frozenset())])
        return 2
    return 0


def brings(state: State, task: Task, predictions: Mapping[int, Prediction],
           driven: Mapping[int, object]) -> bool:
    """Does a partner carry an item of ``task`` to the task's own station (its predicted
    bump is there)? A cook of ours waiting for it there stands in the partner's way."""
    found = held_by_partner(state, task.step.items, driven)
    pred = None if found is None else predictions.get(found[0])
    return pred is not None and pred.target == task.step.target


def shut_out(state: State, spots: list[int], predictions: Mapping[int, Prediction]) -> bool:
    """Is every floor cell a station is worked from (``spots``) held by a partner predicted
    to stay there (its own policy gives it nothing to do)? Then it will not make way."""
    still = {state.agent_pos[c] for c, p in predictions.items() if p.target is None}
    return bool(spots) and all(n in still for n in spots)


def meeting_counters(state: State) -> set[int]:
    """The free plain counters of the current layout (where a plan of every cook may meet a
    partner: :func:`ours_first`)."""
    counter = int(Cell.COUNTER)
    return {c for c, code in enumerate(state.geo.terrains[state.layout_index])
            if code == counter and state.cell_item[c] < 0}


def _free_counters(state: State, reach: list[int]) -> Iterator[tuple[int, list[int], int]]:
    """(counter, the floor cells it is worked from, steps to the nearest of them) of every
    free plain counter that a cook with walking distances ``reach`` works, in cell order."""
    geo = state.geo
    walk = geo.walkables[state.layout_index]
    for c in sorted(meeting_counters(state)):
        spots = interaction_spots(geo.neighbors, walk, c)
        d = min((reach[n] for n in spots if reach[n] >= 0), default=-1)
        if d >= 0:
            yield c, spots, d


def _free_counter(state: State, reach: list[int], near: int) -> int | None:
    """The free plain counter nearest ``near`` that a cook with distances ``reach`` works."""
    rn, cn = state.geo.rc(near)
    best = min(((abs(r - rn) + abs(k - cn), d, c) for c, _spots, d in _free_counters(state, reach)
                for r, k in [state.geo.rc(c)]), default=None)
    return None if best is None else best[2]


def hand_off(state: State, cook: int, index: int,
             predictions: Mapping[int, Prediction] | None = None) -> list[Task]:
    """The step of a cook that gives way beside partners: put what it holds on the nearest
    free plain counter it reaches round the partners guessed to stay (one behind a partner
    standing in a lane is never reached; one a partner on its way stands in front of is, and
    so is one a greedy partner stands in front of: its policy steps off for a cook waiting
    beside it) that a partner reaches too (a partner can take it on; greedy gathers onto a
    plate lying free, never onto one in somebody else's hand); none when its hand is empty
    or no such counter exists."""
    held = state.agent_hand[cook]
    if held < 0:
        return []
    geo = state.geo
    walk = geo.walkables[state.layout_index]
    others = [p for b, p in enumerate(state.agent_pos) if b != cook]
    stay = [state.agent_pos[b] for b, p in (predictions or {}).items()
            if b != cook and p.target is None and not p.by_policy]
    mine = distances(geo.neighbors, walk, [state.agent_pos[cook]], blocked=stay)
    theirs = distances(geo.neighbors, walk, others)
    best = min(((d, c) for c, spots, d in _free_counters(state, mine)
                if any(theirs[n] >= 0 for n in spots)), default=None)
    if best is None:
        return []
    steps = [Task(PlanStep(index, cook, "putdown", best[1], (held,)), frozenset())]
    away = _out_of_the_way(state, cook, best[1])
    if away is not None:  # then off the counter's way in: a partner takes the item from there
        steps.append(Task(PlanStep(index - 1, cook, "goto", away), frozenset()))
    return steps


def _out_of_the_way(state: State, cook: int, counter: int) -> int | None:
    """The nearest floor cell, from where ``cook`` stands to put an item on ``counter``,
    on which it leaves the other cooks a way to the counter (None: no such cell)."""
    geo = state.geo
    walk = geo.walkables[state.layout_index]
    spots = interaction_spots(geo.neighbors, walk, counter)
    mine = distances(geo.neighbors, walk, [state.agent_pos[cook]])
    start = min((n for n in spots if mine[n] >= 0), key=lambda n: mine[n], default=None)
    if start is None:
        return None
    others = [p for b, p in enumerate(state.agent_pos) if b != cook]
    near = distances(geo.neighbors, walk, [start])
    for _, cell in sorted((d, c) for c, d in enumerate(near) if d > 0):
        if cell in spots or cell in others:
            continue
        reach = distances(geo.neighbors, walk, others, blocked=[cell])
        if any(reach[n] >= 0 for n in spots):
            return cell
    return None


def reserved_walks(state: State, predictions: Mapping[int, Prediction],
                   driven: Mapping[int, object], steps: int = PREDICT_STEPS) -> dict[int, object]:
    """What the executive's paths hold for every cook it does not drive: its predicted walk
    (cells per step from now, its current cell first) when it has one that none of our
    cooks with work (``driven``: cook -> its queued steps) stands on, else its current cell
    (it stays). A cook of ours with nothing to do steps off a partner's walk: one that has
    just handed an item off and stands in front of that counter lets the partner take it;
    one whose next step waits for the item a partner brings (:func:`brings`) lets it by."""
    ours = {state.agent_pos[a] for a, work in driven.items() if work and not (
        isinstance(work, deque) and brings(state, work[0], predictions, driven))}
    out: dict[int, object] = {}
    for b in range(state.n_agents):
        if b in driven:
            continue
        pred = predictions.get(b)
        walk = (state.agent_pos[b], *pred.path[:steps]) if pred is not None else ()
        out[b] = walk if len(walk) > 1 and not ours & set(walk) else state.agent_pos[b]
    return out


__all__ = ["PREDICT_STEPS", "PartnerModel", "Prediction", "answer_taken",
           "await_partner_plates", "brings", "blocked_geometry", "delivering",
           "expected_by_plan", "hand_off", "held_by_partner",
           "meeting_counters", "onto_our_plate", "ours_first", "plan_around",
           "predicted_state", "repair_taken", "reserved_walks", "shut_out", "sooner_jointly",
           "substitute", "this_life", "vacate"]
