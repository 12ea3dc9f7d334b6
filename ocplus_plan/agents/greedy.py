"""A strong scripted baseline: per-agent task allocation over the open orders.

Each step the controller reads the symbolic state and builds a list of useful
subtasks (serve a finished plate, rescue a cooked steak from the pan before it
burns, chop, carry a ready ingredient to a plate, wash a dirty plate, fetch a raw
ingredient that the open orders still need, clear a wrong plate or a burnt steak).
Free agents are matched to subtasks by priority, then by walking distance; an agent
keeps its subtask while it stays valid so that agents do not swap jobs back and
forth. An agent that holds something carries it to where it is useful (a board, a
pan, a plate, the window, the sink, the trash) or, when it cannot reach such a
place, puts it on a counter that a cook who can reach it also reaches (hand-over
through counters, SPEC section 3).

Relays and rescues count only on the cooks this controller drives. A hand-over goes to a cook
it drives when one can finish the job, else to a cook it does not drive (a partner on the
other side of a split kitchen: a "pass"), but only while fewer than ``_PASSES`` items it
passed still lie untaken where it put them: beside a partner that never takes them (an idle
cook) the counters do not fill up. On a switching kitchen a lone cook whose destination lies
behind a switch also passes to such a cook that reaches it now, when the partner's way over a
counter ends sooner than its own wait and walk (``_pass_sooner``); a passed item, like a
relayed one, is left alone a while for the taker. Beside a partner that has moved or changed
what it holds lately, a cook on a switching kitchen works as it would beside a cook it drives:
in the part of the kitchen it reaches now, handing over through counters what the partner
finishes, instead of walking over the switches itself (two cooks that each cross the wall
trade rooms and wait for every switch). A cook holding a vegetable in the only way in to a
board on which a partner's raw vegetable lies puts its own down and chops that one, instead of
waiting there for the board to be free (nobody else can get to it).
Movement (:mod:`.greedy_moves`): breadth-first paths on the current layout with the other
agents' cells and the cells already claimed this step as obstacles (so the controller itself
never causes a swap or a contested move); an agent whose way is blocked steps
aside at random after waiting, and an idle agent steps off a busy agent's path, and away from
a cook it does not drive that has stood beside it for ``_WAITING`` steps (waiting, perhaps, for
the cell it holds: the only way to a station or along a one-lane corridor).
The choice of subtasks is split in steps another controller reuses
(:mod:`.task_choice`, where a learned policy picks each free cook's subtask): the holders'
goals (``_holders``), the subtasks by cell (``_task_cells``), a cook's cost of one
(``_cost``) and taking it (``_take``).
Nothing here re-implements a rule: where a held item can go is what
``sim.queries.bump_effect`` says a bump there does; plateability is ``is_plateable``.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..sim.codes import COUNTERS, Cell, Item, ItemState, Where
from ..sim.queries import (
    Bump,
    bump_effect,
    distances,
    is_plateable,
    ticks_until_burnt,
)
from ..sim.state import State
from .base import Controller
from .greedy_moves import _STUCK, GreedyMoves
from .greedy_view import _VEG, KitchenView

_COUNTER_CODES = frozenset(int(c) for c in COUNTERS)
_STEAK, _PLATE = int(Item.STEAK), int(Item.PLATE)
_FRESH, _COOKED = int(ItemState.FRESH), int(ItemState.COOKED)
_BURNT, _CLEAN, _DIRTY = int(ItemState.BURNT), int(ItemState.CLEAN), int(ItemState.DIRTY)
#: destinations only one cook should head for at a time (many may bump a plate or the window)
_EXCLUSIVE = frozenset({"to_board", "to_pan", "to_sink", "put_down", "handover", "relay", "pass"})
_MARGIN = 4  # spare steps a cook keeps between reaching a cooked steak and its burning
_PASSES = 2  # items passed to cooks this controller does not drive that may lie untaken
#: a partner that has neither moved nor changed what it holds for this many steps is not
#: counted on as a teammate on a switching kitchen (an idle cook would never take anything)
_IDLE_PARTNER = 30


@dataclass(frozen=True)
class Subtask:
    """A job for an empty-handed agent: bump ``cell`` (to pick up or work ``item``)."""

    kind: str
    cell: int
    item: int
    priority: float
    budget: tuple[str, int] | None = None  # a shared, limited need this task uses up


class GreedyAgent(GreedyMoves, Controller):
    """Scripted task-allocation controller (see the module docstring)."""

    name = "greedy"

    def __init__(self, seed: int = 0, patience: int = 2) -> None:
        self.seed = seed
        self.patience = patience
        self.rng = np.random.default_rng(seed)

    def _reset(self, state: State) -> None:
        self.rng = np.random.default_rng([self.seed, state.seed or 0])
        self.tasks: dict[int, Subtask | None] = {a: None for a in self.agent_ids}
        self.waited: dict[int, int] = {a: 0 for a in self.agent_ids}
        self.stuck: dict[int, int] = {a: 0 for a in self.agent_ids}
        #: item -> (agent, step): an agent that relayed an item leaves it alone until then
        self.hands_off: dict[int, tuple[int, int]] = {}
        self.counts: Counter = Counter()
        #: cook -> pan: it put its load down to save the steak there, so it goes next
        self.pan_duty: dict[int, int] = {}
        #: item -> counter: passed to a cook this controller does not drive, not yet taken
        self.passed: dict[int, int] = {}
        #: cook not driven -> (cell, hand, step it last moved or changed what it held)
        self.seen: dict[int, tuple[int, int, int]] = {
            b: (state.agent_pos[b], state.agent_hand[b], state.t)
            for b in range(state.n_agents) if b not in self.agent_ids}

    def info(self) -> dict[str, object]:
        """Task choices, hand-overs, yields and idle steps of the episode."""
        return {f"greedy_{k}": v for k, v in sorted(self.counts.items())}

    # ---------------------------------------------------------------- main loop
    def act(self, state: State) -> list[int]:
        v, goals = self.goals(state)
        return self._moves(v, goals)

    def goals(self, state: State) -> tuple[KitchenView, dict[int, tuple[int, str]]]:
        """Where each driven cook heads this step: cook -> (cell to bump, label); a cook
        with nothing to do has none. (A partner model runs this to predict a greedy cook.)"""
        v, goals, claimed, budget, partners = self._holders(state)
        self._assign(v, [a for a in self.agent_ids if state.agent_hand[a] < 0], claimed,
                     budget, goals, partners)
        return v, goals

    def _holders(self, state: State) -> tuple[KitchenView, dict[int, tuple[int, str]], set[int],
                                              Counter, list[int]]:
        """The goals of the driven cooks that hold something (their destinations are claims
        too): ``(view, goals, claimed cells, budgets, partners)`` for the free cooks' pass."""
        v = KitchenView(state, driven=len(self.agent_ids) + len(self._active(state)))
        goals: dict[int, tuple[int, str]] = {}  # agent -> (cell to bump, label)
        claimed: set[int] = set()
        budget = self._budgets(v)
        partners = self._partners(v)
        for a in self.agent_ids:
            if state.agent_hand[a] >= 0:
                goal = self._carry(v, a, claimed, budget, partners)
                if goal is not None:
                    goals[a] = goal
                    if goal[1] in _EXCLUSIVE:
                        claimed.add(goal[0])
                    if goal[1] == "pass" and goal[0] in v.nbrs[state.agent_pos[a]]:
                        self.passed[state.agent_hand[a]] = goal[0]  # its bump puts it there
        return v, goals, claimed, budget, partners

    def _active(self, state: State) -> list[int]:
        """The cooks this controller does not drive that moved or changed what they hold in
        the last ``_IDLE_PARTNER`` steps: on a switching kitchen a cook beside one works as
        beside a teammate (in reach now, handing over), not alone over the switches."""
        for b, (pos, hand, _) in self.seen.items():
            if (pos, hand) != (state.agent_pos[b], state.agent_hand[b]):
                self.seen[b] = (state.agent_pos[b], state.agent_hand[b], state.t)
        return [b for b, (_, _, t) in self.seen.items() if state.t - t < _IDLE_PARTNER]

    def _partners(self, v: KitchenView) -> list[int]:
        """The cooks this controller does not drive that it may pass work to now: all of them
        while fewer than ``_PASSES`` items it passed still lie where it put them, else none."""
        s = v.s
        self.passed = {i: c for i, c in self.passed.items()
                       if s.item_where[i] == Where.CELL and s.item_loc[i] == c}
        if len(self.passed) >= _PASSES:
            return []
        return [b for b in range(s.n_agents) if b not in self.agent_ids]

    def _budgets(self, v: KitchenView) -> Counter:
        s = v.s
        b: Counter = Counter()
        for k in (int(Item.TOMATO), int(Item.LETTUCE), int(Item.ONION), _STEAK):
            b[("need", k)] = max(0, v.need[k] - v.supply[k])
        b[("board", 0)] = sum(1 for f in v.stations(Cell.BOARD) if s.cell_item[f] < 0)
        b[("pan", 0)] = sum(1 for f in v.stations(v.heat) if s.cell_item[f] < 0)
        for p, miss in v.plate_missing.items():
            for k, n in miss.items():
                b[("plate", k)] += n
        return b

    # ---------------------------------------------------------------- holding agents
    def _carry(self, v: KitchenView, a: int, claimed: set[int], budget: Counter,
               partners: list[int] | tuple[()] = ()) -> tuple[int, str] | None:
        """Where agent ``a`` takes what it holds: a useful station, or a counter."""
        s = v.s
        item = s.agent_hand[a]
        k, st = v.kind[item], s.item_state[item]
        dests: list[int] = []
        label = "put_down"
        urgent = self._urgent_pan(v, a)
        if urgent is not None and not (k == _PLATE and st == _CLEAN and v.plate_wants(item, _STEAK)):
            # a cooked steak burns before anyone else gets there: free the hands for it
            spot = self._nearest(v, a, [f for f in v.free_counters() if f not in claimed])
            if spot is not None:
                self.counts["drops_for_pan"] += 1
                self.pan_duty[a] = urgent  # and then take the steak (see _assign)
                return spot, "put_down"
        if urgent is not None:  # holding a plate that takes the steak: plate it straight away
            return urgent, "collect"
        if k == _PLATE and st == _CLEAN:
            if v.exact_match(item):
                dests, label = v.stations(Cell.DELIVERY), "deliver"
            elif item in v.bad_plates and v.stations(Cell.TRASH):
                dests, label = v.stations(Cell.TRASH), "empty_plate"
            else:
                dests = [f for f in range(len(s.cell_item)) if s.cell_item[f] >= 0
                         and bump_effect(s, item, f) == Bump.TAKE_ONTO_PLATE
                         and v.plate_wants(item, v.kind[s.cell_item[f]])]
                label = "collect"
        elif k == _PLATE:
            dests = [f for f in v.stations(Cell.SINK) if bump_effect(s, item, f) == Bump.PUT_DOWN]
            label = "to_sink"
        elif st == _BURNT:
            dests, label = v.stations(Cell.TRASH), "trash"
        elif k in _VEG and st == _FRESH:
            dests = [f for f in v.stations(Cell.BOARD) if bump_effect(s, item, f) == Bump.PUT_DOWN]
            label = "to_board"
        elif k == _STEAK and st == _FRESH:
            dests = [f for f in v.stations(v.heat) if bump_effect(s, item, f) == Bump.PUT_DOWN]
            label = "to_pan"
        elif is_plateable(s, item):
            plates = [p for p in v.plate_contents if s.item_where[p] == Where.CELL
                      and bump_effect(s, item, s.item_loc[p]) == Bump.ONTO_PLATE
                      and v.plate_wants(p, k)]
            plates.sort(key=lambda p: (p not in v.plate_missing
                                       or not v.plate_missing[p][k], -len(v.plate_contents[p])))
            dests = [s.item_loc[p] for p in self._last_of_kind(v, a, item, plates)]
            label = "to_plate"
        if label in _EXCLUSIVE:
            dests = [d for d in dests if d not in claimed]
        dests = [d for d in dests if v.near_pan(d)]
        if label in ("to_board", "to_pan") and not dests:
            # every board / pan is busy: wait at the nearest one (a bump there is harmless)
            code = Cell.BOARD if label == "to_board" else v.heat
            wait = self._nearest(v, a, [f for f in v.stations(code)
                                        if f not in claimed and v.near_pan(f)])
            if wait is not None and label == "to_board" and partners \
                    and v.raw_on_board(a, wait):
                # a partner's raw vegetable lies on the board in front of this cook, which
                # holds the only way in: put its own down and chop that one (the partner
                # cannot get there while this cook waits)
                spot = self._nearest(v, a, [f for f in v.free_counters()
                                            if f not in claimed and v.near_pan(f)])
                if spot is not None:
                    self.counts["drops_for_board"] += 1
                    return spot, "put_down"
            if wait is not None:
                return wait, "wait_station"
        if dests and self.stuck[a] >= _STUCK:
            # blocked in a lane by another cook: leave it on a counter that cook can reach
            spot = self._relay_spot(v, a, dests, claimed)
            if spot is not None:
                return spot, "relay"
        best = self._nearest(v, a, dests)
        if best is not None and partners:
            # a partner finishes the job sooner than this cook's walk over the switches
            spot = self._pass_sooner(v, a, dests, best, claimed, partners)
            if spot is not None:
                return spot, "pass"
        if best is not None:
            if label == "to_board":
                budget[("board", 0)] -= 1
            elif label == "to_pan":
                budget[("pan", 0)] -= 1
            elif label == "to_plate":
                budget[("plate", k)] -= 1
            return best, label
        mates = [b for b in self.agent_ids if b != a]
        if dests and any(v.reach(b, d) < float("inf") for b in mates for d in dests):
            handover = self._handover(v, a, dests, claimed, mates)
            if handover is not None:
                return handover, "handover"
        if dests and partners:  # nobody it drives can finish: a partner may
            handover = self._handover(v, a, dests, claimed, partners)
            if handover is not None:
                return handover, "pass"
        # nothing useful in reach right now: free the hands
        spot = self._nearest(v, a, [f for f in v.free_counters()
                                    if f not in claimed and v.near_pan(f)])
        return None if spot is None else (spot, "put_down")

    def _pass_sooner(self, v: KitchenView, a: int, dests: list[int], best: int,
                     claimed: set[int], partners: list[int]) -> int | None:
        """A free counter to pass the item to a partner (a cook this controller does not
        drive) through, when ``a`` reaches no destination in the current layout (its walk to
        ``best`` waits for a switch), a partner does, and the partner's way there over the
        counter ends sooner than ``a``'s own walk. None otherwise (always on a kitchen that
        does not switch: there ``a`` either reaches a destination now or passes anyway)."""
        if not v.dynamic or any(v.reach_in(v.dist[a], d) < float("inf") for d in dests):
            return None
        own = v.reach(a, best)
        spots = [f for f in v.free_counters() if f not in claimed
                 and v.reach_in(v.dist[a], f) < float("inf")]
        options = []
        for b in partners:
            if v.s.agent_hand[b] >= 0 or not any(v.reach_in(v.dist[b], d) < float("inf")
                                                 for d in dests):
                continue
            for f in spots:
                give, take = v.reach_in(v.dist[a], f), v.reach_in(v.dist[b], f)
                if take == float("inf"):
                    continue
                onward = self._onward(v, f, dests)
                done = max(give + 1, take) + 1 + onward  # put down, then taken on
                if done < own:
                    options.append((give, done, f))
        return min(options)[2] if options else None

    @staticmethod
    def _onward(v: KitchenView, counter: int, dests: list[int]) -> float:
        """Steps from the floor in front of ``counter`` to the nearest of ``dests`` (in the
        current layout)."""
        starts = [n for n in v.nbrs[counter] if n >= 0 and v.walk[n]]
        if not starts:
            return float("inf")
        d = distances(v.nbrs, v.walk, starts)
        return min(v.reach_in(d, f) for f in dests)

    @staticmethod
    def _last_of_kind(v: KitchenView, a: int, item: int, plates: list[int]) -> list[int]:
        """The plates ``item`` may go onto: only those holding food already when it is the
        last of its kind off the plates (on an empty plate it would leave every plate that
        waits for its kind unfinishable: a kitchen with one steak, a plate with the lettuce
        and the onion, the steak put on the other plate)."""
        s, k = v.s, v.kind[item]
        if any(v.kind[i] == k and i != item and s.item_where[i] != Where.PLATE
               for i in range(s.n_items)):
            return plates
        return [p for p in plates if v.plate_contents[p]
                and v.reach(a, s.item_loc[p]) < float("inf")] or plates

    def _handover(self, v: KitchenView, a: int, dests: list[int], claimed: set[int],
                  mates: list[int]) -> int | None:
        """A free counter that ``a`` reaches and some cook of ``mates`` who reaches a
        destination reaches."""
        reach = v.reach
        helpers = [b for b in mates if any(reach(b, d) < float("inf") for d in dests)]
        spots = [f for f in v.free_counters() if f not in claimed
                 and any(reach(b, f) < float("inf") for b in helpers)]
        return self._nearest(v, a, spots)

    def _urgent_pan(self, v: KitchenView, a: int) -> int | None:
        """A pan whose cooked steak burns unless ``a`` (the nearest cook) heads there now."""
        s = v.s
        for p in s.geo.pans:
            it = s.cell_item[p]
            if it < 0 or s.item_state[it] != _COOKED:
                continue
            left = ticks_until_burnt(s.rules, s.item_progress[it]) - 1  # the last tick burns it
            d = v.reach(a, p)
            if d == float("inf") or left > d + _MARGIN:
                continue
            if all(v.reach(b, p) >= d for b in self.agent_ids if b != a):
                return p
        return None

    def _relay_spot(self, v: KitchenView, a: int, dests: list[int], claimed: set[int]) -> int | None:
        """A free counter next to where ``a`` can walk now, from which a cook that ``a`` blocks
        could take the item on to a destination once ``a`` steps back."""
        s = v.s
        spots = [f for f in v.free_counters() if f not in claimed and v.reach_now(a, f) < 4]
        mine = min(v.reach(a, d) for d in dests)
        takers = []  # spots a cook nearer to a destination reaches (it may relay again)
        for b in self.agent_ids:  # only cooks this controller drives take an item on
            if b == a or not min(v.reach(b, d) for d in dests) < mine:
                continue
            walls = frozenset(p for c, p in enumerate(s.agent_pos) if c not in (a, b))
            dist_b = v.bfs(s.agent_pos[b], walls)
            takers += [f for f in spots if v.reach_in(dist_b, f) < float("inf")]
        return self._nearest(v, a, takers, v.reach_now)

    @staticmethod
    def _nearest(v: KitchenView, a: int, cells: list[int],
                 steps: Callable[[int, int], float] | None = None) -> int | None:
        """The first of ``cells`` that ``a`` reaches in the fewest ``steps`` (``v.reach``);
        None when it reaches none."""
        steps = steps or v.reach
        best = min(cells, key=lambda f: steps(a, f), default=None)
        return best if best is not None and steps(a, best) < float("inf") else None

    # ---------------------------------------------------------------- free agents
    def _candidates(self, v: KitchenView, budget: Counter) -> list[Subtask]:
        s = v.s
        out: list[Subtask] = []
        for f, it in enumerate(s.cell_item):
            if it < 0:
                continue
            code, k, st = v.terrain[f], v.kind[it], s.item_state[it]
            if k == _PLATE:
                if st == _CLEAN and v.exact_match(it) and code in _COUNTER_CODES:
                    out.append(Subtask("serve", f, it, 0))
                elif st == _DIRTY and code == Cell.SINK:
                    out.append(Subtask("wash", f, it, 3 if self._plates_short(v) else 6))
                elif st == _DIRTY and v.stations(Cell.SINK):
                    out.append(Subtask("dirty_to_sink", f, it, 4))
                elif st == _CLEAN and code == Cell.SINK:
                    out.append(Subtask("unsink", f, it, 3))
                elif it in v.bad_plates and v.stations(Cell.TRASH):
                    out.append(Subtask("clear_plate", f, it, 6))
            elif code == v.heat and st in (_COOKED, _BURNT):
                out.append(Subtask("rescue", f, it, 1))
            elif code == Cell.BOARD and st == _FRESH:
                out.append(Subtask("chop", f, it, 2))
            elif code == Cell.BOARD and budget[("plate", k)] <= 0:
                # a chopped vegetable nobody can plate now: free the board for the next one
                out.append(Subtask("clear_board", f, it, 7))
            elif st == _BURNT and v.stations(Cell.TRASH):
                out.append(Subtask("trash", f, it, 6))
            elif is_plateable(s, it):
                # a plate in the hand of a cook this controller does not drive is out of
                # its control: gathering for it would pick the item up and put it back
                if any(v.plate_wants(p, k) for p in v.plate_contents
                       if s.item_where[p] != Where.HAND or s.item_loc[p] in self.agent_ids):
                    out.append(Subtask("gather", f, it, 3, ("plate", k)))
            elif st == _FRESH and code in _COUNTER_CODES:
                station = ("pan", 0) if k == _STEAK else ("board", 0)
                prio = 5 + 0.1 * min(v.first_need.get(k, 9), 9)
                out.append(Subtask("fetch", f, it, prio, ("need", k)))
                out.append(Subtask("fetch", f, it, prio, station))
        return out

    def _plates_short(self, v: KitchenView) -> bool:
        return len(v.plate_contents) < len(v.recipes)

    def _assign(self, v: KitchenView, free: list[int], claimed: set[int], budget: Counter,
                goals: dict[int, tuple[int, str]], partners: list[int]) -> None:
        """Match free agents to subtasks: priority first, then distance (kept tasks win ties)."""
        by_cell = self._task_cells(v, budget)
        options = []
        for a in free:
            for cell, ts in by_cell.items():
                d = self._cost(v, a, cell, ts, claimed, partners)
                if d is None:
                    continue
                keep = self._kept(a, cell, ts)
                duty = self.pan_duty.get(a) == cell and ts[0].kind == "rescue"
                options.append((-1 if duty else ts[0].priority, d - (3 if keep else 0), a, cell))
        options.sort()
        taken: set[int] = set()
        for _, _, a, cell in options:
            if a not in taken and self._take(v, a, cell, by_cell[cell], claimed, budget, goals):
                taken.add(a)
        for a in free:
            if a not in taken:
                self.tasks[a] = None
                self.counts["idle_steps"] += 1

    def _task_cells(self, v: KitchenView, budget: Counter) -> dict[int, list[Subtask]]:
        """The subtasks of this step by the cell they bump (a pan's duty ends with its steak)."""
        by_cell: dict[int, list[Subtask]] = {}
        for t in self._candidates(v, budget):
            by_cell.setdefault(t.cell, []).append(t)
        for a, pan in list(self.pan_duty.items()):
            if pan not in by_cell or by_cell[pan][0].kind != "rescue":
                del self.pan_duty[a]  # the steak is off the pan: duty done
        return by_cell

    def _cost(self, v: KitchenView, a: int, cell: int, ts: list[Subtask], claimed: set[int],
              partners: list[int]) -> float | None:
        """Steps for free cook ``a`` to the subtasks ``ts`` at ``cell`` (a way behind another
        cook costs 20 more), or None where they are not a choice for it: claimed, an item it
        relayed and leaves alone a while, out of a pan's reach, no way there, or of no use
        (:meth:`_useful_for`)."""
        if cell in claimed:
            return None
        owner, until = self.hands_off.get(ts[0].item, (-1, -1))
        if (owner == a and until > v.s.t) or not v.near_pan(cell):
            return None
        d = v.reach_now(a, cell)
        if d == float("inf"):  # behind another cook: possible, but costs a detour
            d = v.reach(a, cell) + 20
        if d == float("inf") or not self._useful_for(v, a, ts[0], partners):
            return None
        return d

    def _take(self, v: KitchenView, a: int, cell: int, ts: list[Subtask], claimed: set[int],
              budget: Counter, goals: dict[int, tuple[int, str]]) -> bool:
        """Give free cook ``a`` the subtasks ``ts`` at ``cell`` if the cell is not claimed and
        their shared budgets last (using them up); False if not."""
        if cell in claimed or self._spent(ts, budget):
            return False
        for t in ts:
            if t.budget is not None:
                budget[t.budget] -= 1
        claimed.add(cell)
        goals[a] = (cell, ts[0].kind)
        if self.tasks.get(a) is None or self.tasks[a].cell != cell:
            self.counts[f"task_{ts[0].kind}"] += 1
        self.tasks[a] = ts[0]
        return True

    @staticmethod
    def _spent(ts: list[Subtask], budget: Counter) -> bool:
        """Has a shared budget the subtasks ``ts`` use run out?"""
        return any(t.budget is not None and budget[t.budget] <= 0 for t in ts)

    def _kept(self, a: int, cell: int, ts: list[Subtask]) -> bool:
        """Are the subtasks ``ts`` at ``cell`` the ones cook ``a`` already works on?"""
        prev = self.tasks.get(a)
        return prev is not None and prev.cell == cell and prev.kind == ts[0].kind

    def _useful_for(self, v: KitchenView, a: int, task: Subtask, partners: list[int]) -> bool:
        """Whether ``a`` should pick this up: it can finish the job, or it is the hand-over
        side (nobody who can finish can reach the item where it lies): finishers are the
        other cooks it drives, else the ``partners`` it may pass work to."""
        s = v.s
        if task.kind in ("chop", "wash"):
            return True
        it = task.item
        k = v.kind[it]
        if task.kind == "serve":
            dests = v.stations(Cell.DELIVERY)
        elif task.kind in ("dirty_to_sink",):
            dests = v.stations(Cell.SINK)
        elif task.kind in ("clear_plate", "trash"):
            dests = v.stations(Cell.TRASH)
        elif task.kind == "fetch":
            dests = v.stations(v.heat) if k == _STEAK else v.stations(Cell.BOARD)
        elif task.kind in ("gather", "rescue") and s.item_state[it] != _BURNT:
            dests = [s.item_loc[p] for p in v.plate_contents if s.item_where[p] == Where.CELL
                     and v.plate_wants(p, k)] or v.free_counters()
        elif task.kind == "rescue":
            dests = v.stations(Cell.TRASH) or v.free_counters()
        else:  # unsink: any counter will do
            return True
        if any(v.reach(a, d) < float("inf") for d in dests):
            return True
        for mates in ([b for b in self.agent_ids if b != a], partners):
            finishers = [b for b in mates if any(v.reach(b, d) < float("inf") for d in dests)]
            if finishers:
                return all(v.reach(b, task.cell) == float("inf") for b in finishers)
        return False


__all__ = ["GreedyAgent", "Subtask"]
