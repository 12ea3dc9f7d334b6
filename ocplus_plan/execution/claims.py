"""Items a partner keeps taking up: left out of our plans while it does.

A partner that picks the same item up again and again (a learned policy that takes an item
and puts it down in turn, step after step) holds it as much as it leaves it: a plan that
needs the item is repaired or made again each time the partner takes it, and the cook that
carries the rest of the dish waits for an item it never gets (``gen:open:test:1``, seed 3,
beside the shipped generalist: our cook held a plate with the chopped tomato and the steak,
which one open order asks for, and planned to add the onion the partner kept taking up
for 64 steps instead of serving it).

:class:`PartnerClaims` watches the partners' hands: an item a cook we do not drive picked up
:data:`CLAIM_PICKUPS` times within the last :data:`CLAIM_STEPS` steps, the last of them
within :data:`CLAIM_RECENT` steps, is *claimed*.
:func:`withhold` leaves claimed items out of the problem the planner is asked about, as if
they were in that partner's hand (the compiler gives an item in a hand no place, so no step
uses it). Where the plan needs the item all the same (nothing else can make a dish),
:func:`~.partner.plan_around` asks again with it.
"""

from __future__ import annotations

from collections import Counter, deque
from collections.abc import Collection, Mapping
from typing import Any

from ..sim.codes import Where
from ..sim.state import State

#: pickups of one item by partners ...
CLAIM_PICKUPS = 3
#: ... within this many steps make it claimed (the stall measure's stretch) ...
CLAIM_STEPS = 30
#: ... while the last of them is at most this many steps old (a partner that has held the
#: item longer is carrying it somewhere: its predicted bump says where)
CLAIM_RECENT = 10

_HAND, _CELL = int(Where.HAND), int(Where.CELL)


class PartnerClaims:
    """The partners' recent pickups, and the items they claim by them."""

    def __init__(self) -> None:
        self.held: dict[int, int] = {}  # partner -> the item in its hand last step
        self.pickups: deque[tuple[int, int, int]] = deque()  # (step, partner, item)
        #: planner calls made with claimed items left out
        self.plans = 0

    def see(self, state: State, driven: Collection[int]) -> None:
        """Record the items partners (cooks not in ``driven``) took up since last step."""
        for cook in range(state.n_agents):
            if cook in driven:
                continue
            item = state.agent_hand[cook]
            if item >= 0 and self.held.get(cook, -1) != item:
                self.pickups.append((state.t, cook, item))
            self.held[cook] = item
        while self.pickups and self.pickups[0][0] <= state.t - CLAIM_STEPS:
            self.pickups.popleft()

    def claimed(self, now: int,
                predictions: Mapping[int, Any] | None = None) -> dict[int, int]:
        """item -> the partner that claims it at step ``now`` (the last to take it up). A
        partner predicted by its own policy (``predictions``: cook -> ``Prediction``, its
        ``by_policy``: a greedy partner) claims nothing: what it takes up it takes for a
        reason the prediction knows (a greedy partner passing items across a switching
        kitchen takes them up again and again; left out, they cost
        ``gen:switching:test:0`` seed 0 and ``gen:switching:test:1`` seed 1 a dish each)."""
        known = {c for c, p in (predictions or {}).items() if p.by_policy}
        counts: dict[int, int] = {}
        last: dict[int, tuple[int, int]] = {}
        for t, cook, item in self.pickups:
            counts[item] = counts.get(item, 0) + 1
            last[item] = (t, cook)
        return {i: last[i][1] for i, n in counts.items() if n >= CLAIM_PICKUPS
                and now - last[i][0] <= CLAIM_RECENT and last[i][1] not in known}


def withhold(state: State, claims: dict[int, int]) -> State:
    """``state`` (a copy the planner is asked about; changed in place) with each claimed item
    that lies on a cell put in its partner's hand, for the compiler only: it gets no place, so
    no step of the plan uses it. Its cell is left free: a dish served sends its items back to
    their crates, and the model serves only when each crate is free (the simulator lets an
    item wait for a taken crate), so an onion claimed on the steak crate would keep a plate
    of steak from being served. A claimed item in its partner's hand leaves that partner's
    hand empty in the copy, so the problem models neither. An open order that needs more of
    an ingredient kind than is left without the claimed items moves behind the others (the
    planner's goal is the oldest open orders): the simulator serves a dish to the oldest
    order it matches, so the plan serves the orders that can be made first."""
    hidden = [i for i, cook in claims.items() if state.item_where[i] == _CELL or (
        state.item_where[i] == _HAND and state.item_loc[i] == cook)]
    for item in hidden:
        if state.item_where[item] == _HAND:  # its partner holds it: leave both out
            state.agent_hand[claims[item]] = -1
        else:
            state.cell_item[state.item_loc[item]] = -1
        state.item_where[item], state.item_loc[item] = _HAND, claims[item]
    if hidden:
        kinds = state.geo.item_kind
        left = Counter(kinds[i] for i in range(state.n_items) if i not in hidden)
        can = [o for o in state.orders
               if all(left[int(k)] >= n for k, n in Counter(o.recipe).items())]
        state.orders = can + [o for o in state.orders if o not in can]
    return state


__all__ = ["CLAIM_PICKUPS", "CLAIM_RECENT", "CLAIM_STEPS", "PartnerClaims", "withhold"]
