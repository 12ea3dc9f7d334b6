"""Schedule a sequential plan over the cooks: who does each piece of work, and in what order.

A classical planner minimises the *sum* of its actions' costs, so for several cooks it
has no reason to share the work: on easy with two cooks Fast Downward's optimal plan
for two orders costs the same as with one cook, and one cook does nearly everything.
The executive runs each cook's steps in parallel, so the makespan is what matters.

This module lifts a sequential plan into a parallel one, the way a scheduler does after
a planner (partial-order lifting plus list scheduling):

* the plan is cut into *segments*: the steps one cook does from picking an item up to
  letting it go (a hand-over through a counter ends a segment), and every free-handed
  step (a chop, a wash) alone. A segment must stay with one cook, in its order;
* a segment depends on every segment with an earlier step that touches a cell or item
  one of its steps touches later (the order the sequential plan relies on); two segments
  that would have to interleave leave the plan as it is;
* list scheduling: segments are taken in the plan's order (the planner chose it for its
  cost), each by the cook that would *finish* it first, with walking times from the
  kitchen's shortest walks, bumps as the plan's costs and a steak's remaining cooking
  time on the pan; a cook that would wait (a steak still cooking) first does a later
  segment that does not delay it (backfilling). A cook that holds an item now does its
  own segment first. (Placing whichever available segment finishes first instead gave the
  same dishes with two cooks and walked a single cook further, off its cost-optimal order.)
* lookahead (a one-step rollout): at each choice the first few ready segments are also
  tried with every cook allowed to do them, the rest of the schedule is finished with the
  rule above, and the choice whose schedule ends best is kept (no steak left on a pan past
  its burn time, then the makespan, then the earliest deliveries): a cook that puts a
  steak on the pan goes to chop while it cooks even when that does not fit exactly in the
  wait, and another cook may plate it;
* identical stations: the planner does not care which of two boards (pans, sinks) an item
  goes on, the schedule does; an item's stay on a station moves to another one of its kind
  that is free over that stretch of the plan when the schedule then ends sooner;
* hand-over counters (two cooks or more): a planner that hands two items over through one
  counter makes the second hand-over wait until the first item is taken off (on MapC the
  steak waited behind an onion going the other way); an item's stay on a counter moves to
  one of the nearest free counters reached from the same parts of the kitchen
  (:func:`counter_choices`) when the schedule then ends sooner;
* dish order: a plan's dishes that share no ingredient are also scheduled in their other
  orders (:func:`dish_orders`), so a dish whose ingredients are ready first need not wait
  for the plate behind one the planner happened to list first;
* plating route: a plate can go to its ingredients (picked up, then bumped against each
  ingredient's board or pan) or the ingredients can come to the plate (each carried by hand
  onto it where it lies, the plate picked up last). The planner picks one for its cost; the
  first is a single segment one cook must walk, the second is one segment per ingredient
  that any cook can carry while another waits at the pan. The schedule tries carrying the
  first scoops of each plate trip to the plate, in each order (:func:`plate_carries`),
  leaving a plate where it lies instead of moving it from counter to counter
  (:func:`plate_stays_home`) and putting an ingredient straight on its station instead of
  parking it on a counter first (:func:`unparked`), and keeps what ends sooner;
* idle work: a segment that delivers nothing and that no later step needs is dropped
  (:func:`without_idle_work`; a satisficing planner may fetch an ingredient no order wants).
* layout switches (``switches``): walks are timed over the coming switches (a cook cut
  off now waits for the switch that opens its way; one free now may be cut off later).

The result is the plan's steps (with the plating and idle-work changes above) with cooks
reassigned, renumbered in scheduled order and stamped with their estimated start (a
time-triggered plan's own times are replaced); the executive then routes, monitors and
recovers as for any plan. The planner decides *what* is served from which items; the
schedule decides *who*, *when*, and which of the equivalent routes. Nothing here changes a
rule: the times are estimates (collisions are ignored) used only to order and assign, and
every plating variant and dish order is checked cell by cell (:func:`_cells_agree`).
"""

from __future__ import annotations

from collections.abc import Sequence

from ..sim.state import State
from .paths import DistanceOracle
from .plan_variants import (
    MAX_DISHES_REORDERED,
    PlateTrip,
    Stay,
    _best_plating,
    _best_stations,
    _cells_agree,
    counter_choices,
    dish_orders,
    plate_carries,
    plate_stays_home,
    plate_trips,
    plating_variants,
    station_stays,
    unparked,
    without_idle_work,
)
from .plans import PlanStep
from .scheduler import (
    _BURN_MARGIN,
    KEEP,
    LOOKAHEAD,
    RELEASE,
    TAKE,
    Segment,
    _in_plan_order,
    _Scheduler,
    _Walks,
    segments,
)


def schedule(steps: Sequence[tuple[PlanStep, str, int]], state: State,
             agents: Sequence[int], oracle: DistanceOracle | None = None,
             lookahead: int = LOOKAHEAD, swap_stations: bool = True,
             reorder_dishes: bool = True, carry_to_plates: bool = True,
             switches: bool = False, fallback: bool = True) -> list[PlanStep] | None:
    """Reassign and reorder a sequential plan's steps over ``agents`` (see the module doc).

    ``steps`` are in plan order, each with its hand effect (TAKE, RELEASE, KEEP) and the
    bumps it takes. The plain rule: segments are taken in the plan's order (the planner
    chose it for its cost), each by the cook that finishes it first, and a cook that would
    wait for the next one (a steak still cooking, a board still busy) first does a later
    segment that does not delay it (backfilling). With ``lookahead=K`` each choice also
    tries the first K ready segments with every cook allowed to do them, finishes the
    schedule from each with the plain rule, and keeps the one that ends best: no steak left
    to burn, then the shortest makespan, then the earliest deliveries (a cook that puts a
    steak on the pan goes to chop while it cooks and another cook may plate it).

    ``swap_stations``: a planner minimising cost does not care which of two identical
    boards (pans, sinks) it uses, but the schedule does: two vegetables planned on one board
    must be chopped one after the other. Each stay of an item on a station (from the step
    that puts it there to the one that takes it off) may move to another station of the
    same kind that is free over that stretch of the plan (:func:`station_stays`); a stay is
    moved when the plain rule's schedule then ends better.

    ``reorder_dishes``: the plan's dishes are also scheduled in every other order they can
    be served in (:func:`dish_orders`), and the schedule that ends best is kept.

    ``carry_to_plates``: the plan's plating route may change (:func:`plating_variants`: a
    plate that stays where it lies while its ingredients are carried to it, an ingredient
    put straight on its station); the variant whose schedule ends best is kept.

    ``switches`` (a switching map): walks are timed over the coming layout switches (a cook
    cut off now waits for the switch that opens its way; one free now may be cut off when
    it gets there), so the work goes to the cook that can get there at that time.

    Work that serves no order is dropped first (:func:`without_idle_work`). A plan with
    steps of cooks outside ``agents`` is left as it is, and so is a plan whose segments
    cannot be scheduled (two cooks' segments that must interleave), unless ``fallback`` is
    False: then None says so (the caller may schedule a shorter plan)."""
    agents = tuple(agents)
    if not agents or any(s.agent not in agents for s, _, _ in steps):
        return _in_plan_order(steps)
    walks = _Walks(state, oracle or DistanceOracle(state.geo), switches)
    steps = without_idle_work(list(steps), state)
    best = None
    for order in dish_orders(steps, state) if reorder_dishes else [steps]:
        if carry_to_plates:
            order = _best_plating(order, state, agents, walks, lookahead, swap_stations)
        elif swap_stations:
            order = _best_stations(order, state, agents, walks, lookahead)
        if swap_stations:  # hand-overs through other counters (:func:`counter_choices`)
            order = _best_stations(order, state, agents, walks, lookahead, counters=True)
        out = _Scheduler(order, state, agents, walks, lookahead).run()
        if out is not None and (best is None or out[1] < best[1]):
            best = out
    if best is None:
        return _in_plan_order(steps) if fallback else None
    return best[0]



__all__ = ["KEEP", "LOOKAHEAD", "MAX_DISHES_REORDERED", "RELEASE", "TAKE", "PlateTrip", "Segment",
           "Stay", "counter_choices", "dish_orders", "plate_carries", "plate_stays_home", "plate_trips",
           "plating_variants", "schedule", "segments", "station_stays", "unparked",
           "without_idle_work", "_BURN_MARGIN", "_cells_agree"]
