"""The comparison both fidelity replays share: a replay's outcome (:class:`Replay`) and
:class:`ModelView`, which reads where every item and agent is out of a UP state of a
compiled problem and names the first disagreement with a simulator state.

Sequential replays (:mod:`.fidelity`) and time-triggered ones (:mod:`.fidelity_temporal`)
both import it; neither imports the other's internals.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ..sim.codes import ItemState, Where
from ..sim.state import State
from .compile import Compiled

_STATE_FLAG = {ItemState.FRESH: "fresh", ItemState.CHOPPED: "ready", ItemState.COOKED: "ready",
               ItemState.BURNT: "burnt", ItemState.CLEAN: "clean", ItemState.DIRTY: "dirty"}
_FLAGS = ("fresh", "ready", "burnt", "clean", "dirty")



@dataclass
class Replay:
    """The outcome of replaying one plan."""

    ok: bool
    steps: int = 0
    actions: int = 0
    mismatch: str = ""
    category: str = ""
    served: list[int] = field(default_factory=list)
    #: the plan runs past the episode's horizon and was checked up to it only
    outlasted: bool = False
    #: the simulator state the replay ends in (temporal replays that agree to the end)
    final: State | None = None


class ModelView:
    """Reads item and agent facts out of a UP state of a compiled problem."""

    def __init__(self, compiled: Compiled) -> None:
        problem = compiled.problem
        names = compiled.names
        fl = {f.name: f for f in problem.fluents}
        obj = problem.object
        self.items = {name: i for name, i in names.items.items()}
        places = [n for n, c in names.cells.items() if not n.startswith("s_")]
        spots = [n for n in names.cells if n.startswith("s_")]
        plates = [n for n in names.items if n.startswith("plate")]
        self.where: dict[str, list[tuple[Any, tuple[str, Any]]]] = {}
        for item in self.items:
            cands = [(fl["holding"](obj(a), obj(item)), ("hand", names.agents[a]))
                     for a in names.agents]
            for p in places:
                cell = names.cells[p]
                cands.append((fl["item_at"](obj(item), obj(p)), ("cell", cell)))
                cands.append((fl["cooking_on"](obj(item), obj(p)), ("cell", cell)))
                cands.append((fl["on_heat"](obj(item), obj(p)), ("cell", cell)))
            for q in plates:
                if q != item:
                    cands.append((fl["on_plate"](obj(item), obj(q)), ("plate", names.items[q])))
            # temporal: a steak taken off the pan, in the hand once pan_take_done ends
            cands.extend((fl["lifting"](obj(a), obj(item), obj(p)), ("hand", names.agents[a]))
                         for a in names.agents for p in places)
            cands.append((fl["waiting"](obj(item)), ("waiting", None)))
            self.where[item] = cands
        self.flags = {item: [(fl[f](obj(item)), f) for f in _FLAGS] for item in self.items}
        self.cooking = {item: [fl["cooking_on"](obj(item), obj(p)) for p in places]
                        for item in self.items}
        # temporal: a steak on a pan at compile time, cooked inside ``window`` and burnt
        # once ``overdone`` (timed initial literals)
        self.heating = {item: ([fl["on_heat"](obj(item), obj(p)) for p in places],
                               fl["window"](obj(item)), fl["overdone"](obj(item)))
                        for item in self.items}
        self.agents = {a: [(fl["agent_at"](obj(a), obj(s)), names.cells[s]) for s in spots]
                       for a in names.agents}
        self.names = names
        self.served = {o: fl["served"](obj(o)) for o in names.orders if names.orders[o] >= 0}

    def diff(self, up_state: Any, state: State, doomed: frozenset[int],
             skip_items: frozenset[str] = frozenset(),
             skip_agents: frozenset[str] = frozenset()) -> str:
        """The first disagreement between the model state and the simulator, or ''.

        ``skip_items`` / ``skip_agents`` (object names) are left out: the temporal
        replay passes the parameters of the actions in progress."""
        def true(expr: Any) -> bool:
            return bool(up_state.get_value(expr).bool_constant_value())

        for item, i in self.items.items():
            if item in skip_items:
                continue
            model_where = [tag for expr, tag in self.where[item] if true(expr)]
            sim_where = _sim_where(state, i)
            if model_where != [sim_where]:
                return f"{item}: model says {model_where}, simulator says {sim_where}"
            sim_flag = _STATE_FLAG[ItemState(state.item_state[i])]
            if any(true(e) for e in self.cooking[item]):
                if sim_flag == "burnt" and i not in doomed:
                    return f"{item}: burnt in the simulator while the model cooks it"
                continue
            if i in doomed:
                continue
            heat, window, overdone = self.heating[item]
            if any(true(e) for e in heat):
                expected = "burnt" if true(overdone) else "ready" if true(window) else "fresh"
                if sim_flag != expected:
                    return (f"{item} on the pan: model (timed literals) says {expected}, "
                            f"simulator state {sim_flag}")
                continue
            model_flags = [f for expr, f in self.flags[item] if true(expr)]
            if model_flags != [sim_flag]:
                return f"{item}: model state {model_flags}, simulator state {sim_flag}"
        for a, cands in self.agents.items():
            if a in skip_agents:
                continue
            at = [cell for expr, cell in cands if true(expr)]
            sim = state.agent_rc(self.names.agents[a])
            if at != [sim]:
                return f"{a}: model at {at}, simulator at {sim}"
        return ""


def _sim_where(state: State, i: int) -> tuple[str, Any]:
    where, loc = state.item_where[i], state.item_loc[i]
    if where == Where.HAND:
        return ("hand", loc)
    if where == Where.PLATE:
        return ("plate", loc)
    if where == Where.WAITING:
        return ("waiting", None)
    return ("cell", state.geo.rc(loc))


def failed(out: Replay, message: str, category: str) -> Replay:
    out.ok, out.mismatch, out.category = False, message, category
    return out



__all__ = ["ModelView", "Replay", "failed"]
