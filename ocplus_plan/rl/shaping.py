"""Training rewards: the game's rewards with the subtask part turned into annealed shaping.

The rules' rewards (SPEC section 6) already pay ``subtask_finished`` for each chop, cook
and wash. For learning we treat that part, plus milestone bonuses that only pay for
work towards an active order, as *shaping*:
it is multiplied by a coefficient that the trainer anneals from 1 to 0, so the final
policy is trained on the true objective (deliveries, wrong deliveries, burns, expired
orders, the step penalty) alone.

Milestones (each paid at most once per item life, so they cannot be farmed by picking
an item up and putting it down again; an item's life ends when it respawns):

* ``stage``: a fresh vegetable put on a cutting board, a raw steak put on a pan (both only
  when an active order needs that kind), a dirty plate put in the sink;
* ``ready_pickup``: a chopped vegetable or cooked steak that an active order needs is
  picked up;
* ``useful_plate``: an ingredient added to a clean plate whose contents still fit an
  active order;
* ``dish_in_hand``: an agent holds a plate whose contents complete an active order (the
  last step before serving).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from ..errors import ConfigError
from ..sim.codes import Cell, Item, ItemState
from ..sim.orders import plate_recipe
from ..sim.state import Event, State
from ..sim.step import is_plateable

_SUBTASK_EVENTS = frozenset({"chop_done", "cook_done", "wash_done"})
_BOARD, _PAN, _SINK = int(Cell.BOARD), int(Cell.PAN), int(Cell.SINK)
_FRESH, _DIRTY = int(ItemState.FRESH), int(ItemState.DIRTY)
_PLATE_KIND = int(Item.PLATE)


@dataclass(frozen=True)
class Shaping:
    """Weights of the shaping terms (multiplied by the annealed coefficient)."""

    subtask_scale: float = 1.0  # times the rules' subtask_finished reward
    stage: float = 3.0
    ready_pickup: float = 3.0
    useful_plate: float = 10.0
    dish_in_hand: float = 10.0

    def __post_init__(self) -> None:
        for name in ("subtask_scale", "stage", "ready_pickup", "useful_plate", "dish_in_hand"):
            value = getattr(self, name)
            if not isinstance(value, (int, float)) or value < 0:
                raise ConfigError(f"shaping weight {name} must be a number >= 0, got {value!r}")


def _fits_an_order(state: State, plate: int, complete: bool = False) -> bool:
    """The plate's contents are a sub-multiset of an active order (equal to one if
    ``complete``)."""
    recipe = plate_recipe(state, plate)
    if recipe is None:
        return False
    if complete:
        return any(order.recipe == recipe for order in state.orders)
    for order in state.orders:
        need = list(order.recipe)
        ok = True
        for k in recipe:
            if k in need:
                need.remove(k)
            else:
                ok = False
                break
        if ok:
            return True
    return False


def _needed(state: State, item: int) -> bool:
    """Some active order's recipe contains this item's kind."""
    kind = state.geo.item_kind[item]
    return any(kind in order.recipe for order in state.orders)


class RewardShaper:
    """Splits one kitchen's step rewards into true and shaping parts, per agent.

    Call :meth:`reset` at each episode start and :meth:`step` after each transition.
    """

    def __init__(self, shaping: Shaping) -> None:
        self.shaping = shaping
        # (milestone, item) pairs already paid in the item's current life
        self._paid: set[tuple[str, int]] = set()

    def reset(self) -> None:
        self._paid.clear()

    def step(
        self, state: State, events: Sequence[Event], rewards: Sequence[float]
    ) -> tuple[list[float], list[float]]:
        """``(true, shaping)`` per agent: ``true`` is the game reward without the subtask
        part; ``shaping`` the unweighted-by-coefficient shaping reward."""
        n = len(rewards)
        true = list(rewards)
        shaped = [0.0] * n
        sub = state.rules.rewards.subtask_finished
        sh = self.shaping
        kinds = state.geo.item_kind
        for ev in events:
            kind, a = ev.kind, ev.agent
            if kind in _SUBTASK_EVENTS:
                if 0 <= a < n:
                    true[a] -= sub
                    shaped[a] += sh.subtask_scale * sub
            elif kind in ("respawn", "respawn_waiting"):
                for m in ("stage", "ready", "dish"):
                    self._paid.discard((m, ev.item))
            elif kind == "trash":
                self._paid.discard(("dish", ev.item))  # an emptied plate may earn it again
            elif kind == "pickup" and sh.ready_pickup and ("ready", ev.item) not in self._paid:
                if is_plateable(state, ev.item) and _needed(state, ev.item):
                    shaped[a] += sh.ready_pickup
                    self._paid.add(("ready", ev.item))
            elif kind == "putdown" and sh.stage and ("stage", ev.item) not in self._paid:
                row, col = ev.cell
                code = state.geo.terrains[state.layout_index][row * state.geo.cols + col]
                st = state.item_state[ev.item]
                # the putdown rules already restrict what each station takes
                if (code == _BOARD and _needed(state, ev.item)) or (
                    code == _PAN and st == _FRESH and _needed(state, ev.item)
                ) or (code == _SINK and st == _DIRTY):
                    shaped[a] += sh.stage
                    self._paid.add(("stage", ev.item))
            elif kind == "plate_add" and sh.useful_plate and _fits_an_order(state, ev.value):
                shaped[a] += sh.useful_plate
        if sh.dish_in_hand:
            for a, held in enumerate(state.agent_hand):
                if (held >= 0 and kinds[held] == _PLATE_KIND and ("dish", held) not in self._paid
                        and _fits_an_order(state, held, complete=True)):
                    shaped[a] += sh.dish_in_hand
                    self._paid.add(("dish", held))
        return true, shaped


__all__ = ["RewardShaper", "Shaping"]
