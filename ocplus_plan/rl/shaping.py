"""Training rewards: the game's rewards with the subtask part turned into annealed shaping.

The rules' rewards (SPEC section 6) already pay ``subtask_finished`` for each chop, cook
and wash. For learning we treat that part, plus the terms below, as *shaping*: it is
multiplied by a coefficient that the trainer anneals from 1 to 0, so the final policy
is trained on the true objective (deliveries, wrong deliveries, burns, expired orders,
the step penalty) alone.

Milestones (paid at most once per item life, so picking an item up and putting it down
again cannot farm them; an item's life ends when it respawns):

* ``stage``: a fresh vegetable put on a cutting board, a raw steak put on a pan (both only
  when an active order needs that kind), a dirty plate put in the sink;
* ``useful_plate``: an ingredient added to a clean plate whose contents still fit an
  active order (a plate only fills up, so this cannot be farmed either).

Potential-based terms (Ng et al. 1999: a reward ``phi(s') - phi(s)`` leaves the optimal
policy unchanged, and putting a carried thing down *costs* what picking it up paid):

* ``carry_fresh``: an agent carries an unprocessed ingredient an order needs (so leaving a
  raw steak on a counter costs, putting it on the pan pays the ``stage`` bonus);
* ``carry_ready``: an agent carries a chopped vegetable or cooked steak an order needs;
* ``carry_dish``: an agent carries a plate that completes an active order; the potential
  grows from 1x to 2x the weight as the agent nears the serving window.

The batched engine pays the same rewards from array code
(:func:`ocplus_plan.rl.fast.features_kernels.shaping_range`): a change here goes there too, and
``tests/rl/fast/test_features_batch.py`` fails until the two agree bit for bit.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass

from ..errors import ConfigError
from ..sim.codes import Cell, Item, ItemState
from ..sim.orders import plate_recipe
from ..sim.queries import distances, interaction_spots, is_plateable, plate_fits
from ..sim.state import Event, Geometry, State

_SUBTASK_EVENTS = frozenset({"chop_done", "cook_done", "wash_done"})
_BOARD, _PAN, _SINK = int(Cell.BOARD), int(Cell.PAN), int(Cell.SINK)
_FRESH, _DIRTY = int(ItemState.FRESH), int(ItemState.DIRTY)
_PLATE_KIND = int(Item.PLATE)
_DELIVERY = int(Cell.DELIVERY)


@dataclass(frozen=True)
class Shaping:
    """Weights of the shaping terms (multiplied by the annealed coefficient)."""

    subtask_scale: float = 1.0  # times the rules' subtask_finished reward
    stage: float = 3.0
    useful_plate: float = 10.0
    carry_fresh: float = 1.0
    carry_ready: float = 3.0
    carry_dish: float = 10.0

    def __post_init__(self) -> None:
        for name in ("subtask_scale", "stage", "useful_plate", "carry_fresh", "carry_ready",
                     "carry_dish"):
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
    return any(plate_fits(Counter(recipe), Counter(order.recipe)) for order in state.orders)


def delivery_distances(geo: Geometry, layout: int) -> list[int]:
    """Per cell of ``layout``: steps to the nearest cell next to a serving window (-1:
    unreachable); the ``carry_dish`` potential grows as this shrinks."""
    terrain, walk = geo.terrains[layout], geo.walkables[layout]
    spots = [v for c, code in enumerate(terrain) if code == _DELIVERY
             for v in interaction_spots(geo.neighbors, walk, c)]
    return distances(geo.neighbors, walk, spots)


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
        self._potential: list[float] = []
        # (id(rules), layout) -> (rules, distances); holding the rules keeps the id unique
        self._to_delivery: dict[tuple[int, int], tuple[object, list[int]]] = {}

    def reset(self, state: State | None = None) -> None:
        """Start an episode (pass its initial state so the potential starts right)."""
        self._paid.clear()
        n = state.n_agents if state is not None else 0
        self._potential = [self.potential(state, a) for a in range(n)] if state else []

    def _delivery_distance(self, state: State) -> list[int]:
        """Per cell: steps to the nearest cell next to a serving window (-1 unreachable)."""
        key = (id(state.rules), state.layout_index)
        hit = self._to_delivery.get(key)
        if hit is None:
            hit = self._to_delivery[key] = (
                state.rules, delivery_distances(state.geo, state.layout_index))
        return hit[1]

    def potential(self, state: State, agent: int) -> float:
        """The potential of what ``agent`` carries (see the module docstring)."""
        held = state.agent_hand[agent]
        if held < 0:
            return 0.0
        sh = self.shaping
        if state.geo.item_kind[held] == _PLATE_KIND:
            if sh.carry_dish and _fits_an_order(state, held, complete=True):
                d = self._delivery_distance(state)[state.agent_pos[agent]]
                near = 1.0 - min(d, 20) / 20 if d >= 0 else 0.0
                return sh.carry_dish * (1.0 + near)
            return 0.0
        if not _needed(state, held):
            return 0.0
        if is_plateable(state, held):
            return sh.carry_ready
        return sh.carry_fresh if state.item_state[held] == _FRESH else 0.0

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
        for ev in events:
            kind, a = ev.kind, ev.agent
            if kind in _SUBTASK_EVENTS:
                if 0 <= a < n:
                    true[a] -= sub
                    shaped[a] += sh.subtask_scale * sub
            elif kind in ("respawn", "respawn_waiting"):
                self._paid.discard(("stage", ev.item))
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
        potential = [self.potential(state, a) for a in range(n)]
        before = self._potential if len(self._potential) == n else [0.0] * n  # hands start empty
        for a in range(n):
            shaped[a] += potential[a] - before[a]
        self._potential = potential
        return true, shaped


__all__ = ["RewardShaper", "Shaping", "delivery_distances"]
