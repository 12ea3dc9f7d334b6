"""A compact egocentric feature encoder for the RL baseline (``obs="features"``).

Why not the one-hot grid of :mod:`ocplus_plan.sim.observe`? A PPO policy on a one-hot
map must first learn to navigate; on two shared CPU cores that costs millions of steps.
This encoder gives, for each kind of *target* a cook cares about (a fresh tomato, an
empty board, a clean plate, the serving window, ...), the first action of a shortest
path that ends by bumping the nearest such cell, and its distance. It is in the spirit
of overcooked_ai's hand-made ``featurize_state`` (relative positions of the nearest
onion, dish, pot), with shortest-path directions instead of raw offsets, so it works on
every map without retraining the input layer. Nothing is hidden or cheated: it reads
the same symbolic state the planners read, and the policy still has to learn which
target to go for, when to chop, what to plate and when to serve.

Per agent, one flat ``float32`` vector of :attr:`FeatureEncoder.size` values (names in
:meth:`FeatureEncoder.feature_names`):

* per target (:data:`TARGETS`): a one-hot of the action that goes towards (or bumps) the
  nearest reachable such cell, its path cost (steps incl. the bump) / 20 clipped to 1,
  and a present flag;
* ``wanted_fresh`` / ``wanted_ready``: the nearest unprocessed / ready ingredient of a
  kind that an active order needs (the same cells as the per-kind targets, indexed by
  need, so the network need not learn the order-to-ingredient lookup itself);
* own hand: empty flag, whether an active order needs the held kind, item kind, state;
  a held plate's contents, whether they fit
  an active order, whether they complete one, and what that order still misses;
* the same plate summary for the nearest clean plate on a counter;
* the active orders (ingredient counts, oldest first, up to 3) and their total demand;
* the four neighbouring cells: walkable, and occupied by another agent;
* up to two other agents: offset, present flag, hand kind;
* time ``t / horizon``, layout index, steps to the next switch, the nearest cooking
  steak's progress and the nearest cooked steak's time left before it burns.

Paths go around the cells where other agents stand (a path only through them falls back
to ignoring them), so two agents sharing the policy do not queue behind each other for
the same board; the BFS per (layout, own cell, others' cells) is cached, so one encoding
costs a scan over the map's interaction cells.

The batched engine computes the same vector as array code
(:mod:`ocplus_plan.rl.fast.features_kernels`): a change here goes there too, and
``tests/rl/fast/test_features_batch.py`` fails until the two agree bit for bit.
"""

from __future__ import annotations

from collections import Counter

import numpy as np

from ..sim.codes import COUNTERS, Cell, Item, ItemState
from ..sim.orders import plate_recipe
from ..sim.queries import direction, plate_fits, ticks_until_burnt, walks
from ..sim.rules import Rules
from ..sim.state import State, geometry_for

#: Target kinds, in feature order.
TARGETS: tuple[str, ...] = (
    "fresh_tomato", "fresh_lettuce", "fresh_onion", "raw_steak",
    "board_to_chop", "chopped_tomato", "chopped_lettuce", "chopped_onion",
    "cooking_steak", "cooked_steak", "burnt_steak",
    "clean_plate", "dirty_plate", "sink_to_wash",
    "free_board", "free_pan", "free_sink", "free_counter",
    "delivery", "trash",
    "wanted_fresh", "wanted_ready",
)
_T = {name: i for i, name in enumerate(TARGETS)}
#: targets that also count for ``wanted_fresh`` / ``wanted_ready`` when an order needs the kind
_FRESH_TARGETS = frozenset(_T[n] for n in ("fresh_tomato", "fresh_lettuce", "fresh_onion",
                                           "raw_steak"))
_READY_TARGETS = frozenset(_T[n] for n in ("chopped_tomato", "chopped_lettuce",
                                           "chopped_onion", "cooked_steak"))
INGREDIENTS: tuple[Item, ...] = (Item.TOMATO, Item.LETTUCE, Item.ONION, Item.STEAK)
_ING_INDEX = {int(k): i for i, k in enumerate(INGREDIENTS)}
HAND_KINDS: tuple[Item, ...] = (*INGREDIENTS, Item.PLATE)
_HAND_INDEX = {int(k): i for i, k in enumerate(HAND_KINDS)}
STATES: tuple[ItemState, ...] = (
    ItemState.FRESH, ItemState.CHOPPED, ItemState.COOKED, ItemState.BURNT, ItemState.CLEAN,
    ItemState.DIRTY,
)
_STATE_INDEX = {int(s): i for i, s in enumerate(STATES)}
MAX_ORDERS = 3
MAX_OTHERS = 2
PATH_SCALE = 20.0

_FLOORISH = frozenset({int(Cell.FLOOR), int(Cell.SPAWN), int(Cell.BLOCK)})
_COUNTER_CODES = frozenset(int(c) for c in COUNTERS)
_BOARD, _PAN, _SINK = int(Cell.BOARD), int(Cell.PAN), int(Cell.SINK)
_DELIVERY, _TRASH = int(Cell.DELIVERY), int(Cell.TRASH)
_PLATE, _STEAK = int(Item.PLATE), int(Item.STEAK)
_FRESH, _CHOPPED, _COOKED = int(ItemState.FRESH), int(ItemState.CHOPPED), int(ItemState.COOKED)
_BURNT, _CLEAN = int(ItemState.BURNT), int(ItemState.CLEAN)
_FRESH_VEG = {int(Item.TOMATO): _T["fresh_tomato"], int(Item.LETTUCE): _T["fresh_lettuce"],
              int(Item.ONION): _T["fresh_onion"]}
_CHOPPED_VEG = {int(Item.TOMATO): _T["chopped_tomato"], int(Item.LETTUCE): _T["chopped_lettuce"],
                int(Item.ONION): _T["chopped_onion"]}
_NO_PATH = 1 << 30


def _plate_names(prefix: str) -> list[str]:
    names = [f"{prefix}:has_{k.name.lower()}" for k in INGREDIENTS]
    names += [f"{prefix}:fits_order", f"{prefix}:completes_order"]
    names += [f"{prefix}:missing_{k.name.lower()}" for k in INGREDIENTS]
    return names


class FeatureEncoder:
    """Egocentric shortest-path features for the agents of one :class:`Rules`."""

    def __init__(self, rules: Rules) -> None:
        self.rules = rules
        self.geo = geo = geometry_for(rules)
        n_cells = geo.rows * geo.cols
        #: per layout: the cells an agent can interact with (not floor, not block)
        self.interact = [
            tuple(c for c in range(n_cells) if terrain[c] not in _FLOORISH)
            for terrain in geo.terrains
        ]
        self._reach_cache: dict[tuple[int, int, tuple[int, ...]], list[tuple[int, int]]] = {}
        self._names = self._build_names()
        self.size = len(self._names)

    # ------------------------------------------------------------ public
    def feature_names(self) -> list[str]:
        return list(self._names)

    def encode(self, state: State, agent: int) -> np.ndarray:
        """The feature vector of one agent."""
        return np.asarray(self._encode(state, agent), dtype=np.float32)

    def encode_all(
        self, state: State, agents: list[int] | tuple[int, ...] | None = None
    ) -> np.ndarray:
        """``(len(agents), size)`` features (all agents by default)."""
        ids = range(state.n_agents) if agents is None else agents
        return np.asarray([self._encode(state, a) for a in ids], dtype=np.float32)

    # ------------------------------------------------------------ internals
    def _build_names(self) -> list[str]:
        names: list[str] = []
        for t in TARGETS:
            names += [f"{t}:go_{d}" for d in ("right", "down", "left", "up")]
            names += [f"{t}:cost", f"{t}:present"]
        names += ["hand:empty", "hand:wanted"] + [f"hand:{k.name.lower()}" for k in HAND_KINDS]
        names += [f"hand:state_{s.name.lower()}" for s in STATES]
        names += _plate_names("hand_plate") + _plate_names("near_plate")
        for o in range(MAX_ORDERS):
            names += [f"order{o}:{k.name.lower()}" for k in INGREDIENTS] + [f"order{o}:present"]
        names += [f"demand:{k.name.lower()}" for k in INGREDIENTS]
        for d in ("right", "down", "left", "up"):
            names += [f"adj_{d}:walkable", f"adj_{d}:agent"]
        for k in range(MAX_OTHERS):
            names += [f"other{k}:drow", f"other{k}:dcol", f"other{k}:present", f"other{k}:empty"]
            names += [f"other{k}:{h.name.lower()}" for h in HAND_KINDS]
        names += ["time", "layout", "switch_in", "cooking_progress", "cooked_burn_risk"]
        return names

    def reach(
        self, layout: int, pos: int, others: tuple[int, ...] = ()
    ) -> list[tuple[int, int]]:
        """Per interaction cell of ``layout``: (path cost incl. bump, first action), or
        (``_NO_PATH``, -1). Paths avoid the cells where other agents stand (``others``);
        a cell reachable only through them falls back to the path that ignores them.
        Cached: geometry is static."""
        key = (layout, pos, others)
        hit = self._reach_cache.get(key)
        if hit is not None:
            return hit
        if others:
            free = self.reach(layout, pos)
            out = [b if b[1] >= 0 else f for b, f in zip(self._bfs(layout, pos, others), free)]
        else:
            out = self._bfs(layout, pos, ())
        self._reach_cache[key] = out
        return out

    def _bfs(self, layout: int, pos: int, others: tuple[int, ...]) -> list[tuple[int, int]]:
        geo = self.geo
        nbrs = geo.neighbors
        dist, _parent, first, _order = walks(nbrs, geo.walkables[layout], [pos], others)
        out = []
        for c in self.interact[layout]:
            best, act = _NO_PATH, -1
            for v in nbrs[c]:
                # v is the standing cell (reached: walkable and not another agent's)
                if v >= 0 and 0 <= dist[v] < best:
                    best = dist[v]
                    act = direction(geo, v, c) if v == pos else first[v]
            out.append((best + 1 if act >= 0 else _NO_PATH, act))
        return out

    def _plate_summary(self, state: State, plate: int) -> list[float]:
        kinds = state.geo.item_kind
        contents = Counter(kinds[i] for i in state.plate_contents(plate))
        counts = [contents[int(k)] for k in INGREDIENTS]
        recipe = plate_recipe(state, plate)
        fits = complete = 0.0
        missing = [0.0] * 4
        best = None
        for order in state.orders:
            need = Counter(int(k) for k in order.recipe)
            if plate_fits(contents, need):
                gap = [need[int(k)] - contents[int(k)] for k in INGREDIENTS]
                if best is None or sum(gap) < sum(best):
                    best = gap
        clean = state.item_state[plate] == _CLEAN
        if best is not None and clean and (recipe is not None or sum(counts) == 0):
            fits = 1.0
            complete = 1.0 if sum(best) == 0 else 0.0
            missing = best
        return [c / 2 for c in counts] + [fits, complete] + [m / 2 for m in missing]

    def _encode(self, state: State, agent: int) -> list[float]:
        best_cost, best_act, best_cell, wanted = self._nearest(state, agent)
        kinds, istate, cell_item = self.geo.item_kind, state.item_state, state.cell_item
        f: list[float] = []
        for t in range(len(TARGETS)):
            if best_act[t] < 0:
                f += (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
            else:
                onehot = [0.0, 0.0, 0.0, 0.0]
                onehot[best_act[t]] = 1.0
                f += onehot
                f += (min(best_cost[t] / PATH_SCALE, 1.0), 1.0)

        held = state.agent_hand[agent]
        hand = [0.0] * (2 + len(HAND_KINDS) + len(STATES))
        if held < 0:
            hand[0] = 1.0
        else:
            hand[1] = 1.0 if kinds[held] in wanted else 0.0
            hand[2 + _HAND_INDEX[kinds[held]]] = 1.0
            hand[2 + len(HAND_KINDS) + _STATE_INDEX[istate[held]]] = 1.0
        f += hand
        if held >= 0 and kinds[held] == _PLATE:
            f += self._plate_summary(state, held)
        else:
            f += [0.0] * 10
        near = best_cell[_T["clean_plate"]]
        f += self._plate_summary(state, cell_item[near]) if near >= 0 else [0.0] * 10

        f += self._demand(state)
        f += self._around(state, agent)
        f += self._clock(state, best_cell)
        return f

    def _nearest(self, state: State, agent: int
                 ) -> tuple[list[int], list[int], list[int], set[int]]:
        """Per target: the cheapest walk's cost, its first action and the cell (-1: none
        reachable); and the item kinds the open orders want."""
        geo = self.geo
        layout = state.layout_index
        terrain = geo.terrains[layout]
        pos = state.agent_pos[agent]
        others = tuple(sorted(p for b, p in enumerate(state.agent_pos) if b != agent))
        reach = self.reach(layout, pos, others)
        cell_item, kinds, istate = state.cell_item, geo.item_kind, state.item_state
        n_t = len(TARGETS)
        best_cost = [_NO_PATH] * n_t
        best_act = [-1] * n_t
        best_cell = [-1] * n_t
        wanted = {int(k) for order in state.orders for k in order.recipe}
        for idx, c in enumerate(self.interact[layout]):
            cost, act = reach[idx]
            if act < 0:
                continue
            code = terrain[c]
            it = cell_item[c]
            if code == _DELIVERY:
                t = _T["delivery"]
            elif code == _TRASH:
                t = _T["trash"]
            elif it < 0:
                if code == _BOARD:
                    t = _T["free_board"]
                elif code == _PAN:
                    t = _T["free_pan"]
                elif code == _SINK:
                    t = _T["free_sink"]
                elif code in _COUNTER_CODES:
                    t = _T["free_counter"]
                else:
                    continue
            else:
                k, s = kinds[it], istate[it]
                if k == _PLATE:
                    if s == _CLEAN:
                        t = _T["clean_plate"]
                    else:
                        t = _T["sink_to_wash"] if code == _SINK else _T["dirty_plate"]
                elif k == _STEAK:
                    if s == _FRESH:
                        t = _T["cooking_steak"] if code == _PAN else _T["raw_steak"]
                    elif s == _COOKED:
                        t = _T["cooked_steak"]
                    else:
                        t = _T["burnt_steak"]
                elif s == _FRESH:
                    t = _T["board_to_chop"] if code == _BOARD else _FRESH_VEG[k]
                elif s == _CHOPPED:
                    t = _CHOPPED_VEG[k]
                else:
                    continue
            if cost < best_cost[t]:
                best_cost[t], best_act[t], best_cell[t] = cost, act, c
            if it >= 0 and kinds[it] in wanted:
                w = (_T["wanted_fresh"] if t in _FRESH_TARGETS
                     else _T["wanted_ready"] if t in _READY_TARGETS else -1)
                if w >= 0 and cost < best_cost[w]:
                    best_cost[w], best_act[w], best_cell[w] = cost, act, c
        return best_cost, best_act, best_cell, wanted

    @staticmethod
    def _demand(state: State) -> list[float]:
        """Per order slot: its ingredient counts and a presence flag; then the total demand."""
        f: list[float] = []
        demand = [0.0] * 4
        for o in range(MAX_ORDERS):
            if o < len(state.orders):
                counts = [0.0] * 4
                for k in state.orders[o].recipe:
                    counts[_ING_INDEX[int(k)]] += 1
                demand = [d + c for d, c in zip(demand, counts)]
                f += [c / 2 for c in counts] + [1.0]
            else:
                f += (0.0, 0.0, 0.0, 0.0, 0.0)
        f += [min(d / 3, 1.0) for d in demand]
        return f

    def _around(self, state: State, agent: int) -> list[float]:
        """The four neighbours (walkable, taken) and the other cooks (offset, hand)."""
        geo, layout, pos = self.geo, state.layout_index, state.agent_pos[agent]
        kinds = geo.item_kind
        f: list[float] = []
        walk = geo.walkables[layout]
        others = {state.agent_pos[b] for b in range(state.n_agents) if b != agent}
        for v in geo.neighbors[pos]:
            f += (1.0 if v >= 0 and walk[v] else 0.0, 1.0 if v in others else 0.0)

        row, col = divmod(pos, geo.cols)
        n = state.n_agents
        for k in range(1, MAX_OTHERS + 1):
            if k < n:
                b = (agent + k) % n
                brow, bcol = divmod(state.agent_pos[b], geo.cols)
                bh = state.agent_hand[b]
                kind = [0.0] * (1 + len(HAND_KINDS))
                kind[0 if bh < 0 else 1 + _HAND_INDEX[kinds[bh]]] = 1.0
                f += [(brow - row) / geo.rows, (bcol - col) / geo.cols, 1.0] + kind
            else:
                f += [0.0] * (3 + 1 + len(HAND_KINDS))
        return f

    def _clock(self, state: State, best_cell: list[int]) -> list[float]:
        """Time, layout, the next switch, the nearest cooking steak's progress and burn risk."""
        terrain, progress, cell_item = (self.geo.terrains[state.layout_index],
                                        state.item_progress, state.cell_item)
        layout = state.layout_index
        rules = self.rules
        switch_in = 0.0
        if rules.dynamic:
            switch_in = min(max(state.next_switch - state.t, 0) / rules.map_switch_step, 1.0)
        cooking = best_cell[_T["cooking_steak"]]
        tables = rules.tables  # the pan's record: cook and burn times
        cook, burn = tables.duration_at(_PAN), tables.overrun_at(_PAN)
        cook_prog = progress[cell_item[cooking]] / cook if cooking >= 0 else 0.0
        cooked = best_cell[_T["cooked_steak"]]
        burn_in = 0.0
        if cooked >= 0 and terrain[cooked] == _PAN:
            left = ticks_until_burnt(rules, progress[cell_item[cooked]])
            burn_in = max(0.0, 1.0 - left / (burn + 1 - cook))
        return [state.t / rules.horizon, float(layout), switch_in, min(cook_prog, 1.0), burn_in]


__all__ = ["TARGETS", "FeatureEncoder"]
