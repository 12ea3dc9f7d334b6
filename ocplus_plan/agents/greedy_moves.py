"""How the greedy cook steps (:class:`GreedyMoves`, a part of
:class:`~ocplus_plan.agents.greedy.GreedyAgent`): each driven cook walks a shortest way to the
cell it bumps next, avoiding the other cooks and the cells already taken this step, waits
``patience`` steps when blocked and then sidesteps, and an idle cook in another's way steps
off the path (or back along it, away from the busy cooks).

The mixin reads and writes the agent's episode state (``waited``, ``stuck``, ``hands_off``,
``seen``, ``counts``, ``rng``, ``patience``), set by ``GreedyAgent._reset``.
"""

from __future__ import annotations

from ..sim.codes import Action
from ..sim.queries import direction, interaction_spots, walk_to, walks
from .greedy_view import KitchenView

_STAY = int(Action.STAY)
_STUCK = 4  # blocked steps (net) before a cook relays what it carries through a counter
_WAITING = 3  # steps a cook it does not drive stands beside an idle cook before that one moves off


class GreedyMoves:
    """The greedy cook's movement: :meth:`_moves` turns goals into one action per cook."""

    def _moves(self, v: KitchenView, goals: dict[int, tuple[int, str]]) -> list[int]:
        s = v.s
        actions: dict[int, int] = {}
        reserved: set[int] = set()
        paths: set[int] = set()
        busy = sorted(goals, key=lambda a: (v.reach(a, goals[a][0]), a))
        for a in busy:
            cell, label = goals[a]
            pos = s.agent_pos[a]
            if cell in v.nbrs[pos]:
                actions[a] = direction(s.geo, pos, cell)
                self.waited[a] = self.stuck[a] = 0
                if label in ("handover", "relay", "pass"):
                    self.counts[label + ("es" if label == "pass" else "s")] += 1
                if label in ("relay", "pass"):  # left there a while for the taker
                    self.hands_off[s.agent_hand[a]] = (a, s.t + 2 * _STUCK + 8)
                continue
            others = frozenset(p for b, p in enumerate(s.agent_pos) if b != a) | reserved
            step, path = self.step_towards(v, pos, cell, others)
            if step is None:
                paths.update(self.step_towards(v, pos, cell, frozenset())[1])
                self.waited[a] += 1
                self.stuck[a] += 1
                step = self._sidestep(v, a, others) if self.waited[a] > self.patience else None
                if step is not None:
                    self.counts["yields"] += 1
            else:
                self.waited[a] = 0
                self.stuck[a] = max(0, self.stuck[a] - 1)
                paths.update(path)
            if step is None:
                actions[a] = _STAY
            else:
                actions[a] = direction(s.geo, pos, step)
                reserved.add(step)
        for a in self.agent_ids:
            if a in actions:
                continue
            pos = s.agent_pos[a]
            actions[a] = _STAY
            reserved.add(pos)
            waiting = [c for c, _, t in self.seen.values()  # (``seen``: as of ``goals``)
                       if s.t - t >= _WAITING and c in v.nbrs[pos]]
            if pos in paths or waiting:  # idle and in the way: step off the path, or back along it
                others = frozenset(p for b, p in enumerate(s.agent_pos) if b != a) | reserved
                step = self._sidestep(v, a, others | paths | {
                    n for c in waiting for n in v.nbrs[c]})  # not to stay beside the waiting cook
                if step is None:
                    step = self._retreat(v, a, others, [s.agent_pos[b] for b in busy] + waiting)
                if step is not None:
                    actions[a] = direction(s.geo, pos, step)
                    reserved.add(step)
                    self.counts["yields"] += 1
        return [int(actions[a]) for a in self.agent_ids]

    def step_towards(self, v: KitchenView, pos: int, cell: int, blocked: frozenset[int],
                     walk: tuple[bool, ...] | None = None) -> tuple[int | None, list[int]]:
        """First step of a shortest path to a floor cell next to ``cell`` avoiding ``blocked``.

        When the current layout has no path but a switch would open one, head along the
        path over both layouts' floors as far as the current layout allows."""
        walkable = v.walk if walk is None else walk
        goals = set(interaction_spots(v.nbrs, walkable, cell))
        found = walks(v.nbrs, walkable, [pos], blocked)
        goal = next((f for f in found.order if f in goals), None)  # the nearest, first found
        path = walk_to(found, goal) if goal is not None else None
        if path:
            return path[0], path
        if walk is None and v.dynamic:
            step, path = self.step_towards(v, pos, cell, blocked, v.walk_any)
            if step is not None and v.walk[step]:
                return step, path
            if step is not None:  # wait for the switch off the cells that it changes
                return None, path
        return None, []

    def _retreat(self, v: KitchenView, a: int, blocked: frozenset[int], busy: list[int]) -> int | None:
        """The free neighbouring cell farthest from the busy cooks, if farther than here."""
        def gap(f: int) -> int:
            r, c = v.s.geo.rc(f)
            return min((abs(r - br) + abs(c - bc) for br, bc in map(v.s.geo.rc, busy)),
                       default=0)

        pos = v.s.agent_pos[a]
        opts = [n for n in interaction_spots(v.nbrs, v.walk, pos) if n not in blocked]
        best = max(opts, key=gap, default=None)
        return best if best is not None and gap(best) > gap(pos) else None

    def _sidestep(self, v: KitchenView, a: int, blocked: frozenset[int] | set[int]) -> int | None:
        pos = v.s.agent_pos[a]
        opts = [n for n in interaction_spots(v.nbrs, v.walk, pos) if n not in blocked]
        if not opts:
            return None
        return int(opts[int(self.rng.integers(len(opts)))])


__all__ = ["GreedyMoves"]
