"""The unified-planning model of the kitchen: types, fluents and actions.

The domain never contains a rule number. Every duration and cost is a static
function (``chop_full``, ``cook_cost_full``, ``dist(?from ?to)``...) whose value the
compiler reads from the simulator's :class:`~ocplus_plan.sim.Rules` and state, so
one domain file serves every preset and parameter override.

Every action is written once as a :class:`Schema` (parameters, positive
preconditions, add and delete lists, a cost) and materialised as

* ``classical``: an instantaneous action; its cost (``MinimizeActionCosts``) is
  the number of simulator steps it takes, so a plan's cost is its sequential
  duration;
* ``temporal``: a durative action of that many time units; conditions hold at
  start, deletes happen at start and adds at end (this is what stops two agents
  from grabbing the same item at once), and ``idle(?a)`` keeps each agent to one
  action at a time.

Modelling choices (see the README section "Planning model"):

* flat typing and positive preconditions only (TAMER, pyperplan and LPG need it);
* a plate's contents are a *content* object (the multiset of ingredient kinds on
  it). ``next_content(c, kind, c')`` only exists for multisets that can still
  become an open order, so a planner never builds a useless dish; ``serves(c, o)``
  says a content completes order ``o``;
* delivering or trashing a plate holding K ingredients binds them as K ordered
  parameters (``lt``) so each goes back to its own spawn tile (``home``);
* orders with the same recipe are served oldest first, as the simulator does
  (``up_next`` and the static chain ``next_order``);
* chopping, washing and cooking are one action each whose cost is the number of
  steps left (``partly`` marks an item whose progress is not zero);
* cooking, classical: ``cook`` puts a raw steak on the pan, waits until it is
  cooked and takes it off (cook_time - ticks + 1 steps). A steak already on a pan
  at compile time must be rescued by the first action of the plan (``rescue``,
  only offered when an agent can reach the pan before it burns) or ``abandon``ed
  (it is then modelled as burnt). All other actions wait for ``calm``;
* cooking, temporal: ``cook`` is an envelope: agent ``?a1`` puts the steak on
  the pan item_at its start, agent ``?a2`` takes it off item_at its end, and its duration
  lies in ``[cook_lo, cook_hi]`` so it is never taken off raw or burnt, while
  both agents are free to work in between. A steak already on a pan at compile
  time is taken off by ``take_off`` inside a window opened and closed by timed
  initial literals (``window``), or, once burnt (``overdone``), by ``take_burnt``.
  Measured (experiments/temporal_engines.py): Kairos solves both; LPG has no timed
  literals and overflows MAX_VARS on the envelope; TAMER and Aries time out (30 s).
  Alternatives: PDDL+ (a heat process with done/burn events, most faithful; only
  Kairos and ENHSP take it) and UP's intermediate effects (not writable as PDDL).
  The envelope's two ends are bumps that take their agent one step: ``pan_put_done``
  and ``pan_take_done`` (1 step each) end them;
* cells granularity: a move enters a cell only while it is ``open`` (floor); with
  ``anticipate_switches`` timed initial literals flip ``open`` at the coming layout
  switches.
* stations granularity with ``anticipate_switches`` (temporal only): a ``layout``
  type, ``now(?l)`` flipped by timed initial literals at the coming switches, and a
  move per layout: ``move(?a ?s1 ?s2 ?l)`` takes ``ldist(?l ?s1 ?s2)`` steps over a
  link of that layout (``llink``) and needs ``now(?l)`` at its start and at its end.
  Links no shorter than the switch period are left out, so a move cannot span a
  switch and the layout's return; a plan waits for the layout its walk needs.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

from ..errors import CompileError
from ..sim.codes import VEGETABLES, Item, ItemState
from ..sim.processes import PROCESSES, Process
from ..sim.stations import PLACE_FLAGS

ENCODINGS = ("classical", "temporal")
GRANULARITIES = ("stations", "cells")
TYPE_NAMES = ("agent", "spot", "place", "item", "kind", "content", "order")
#: what anticipating layout switches adds at the stations granularity (see the docstring)
SWITCH_FLUENTS: dict[str, tuple[str, ...]] = {
    "now": ("layout",), "llink": ("layout", "spot", "spot"), "ldist": ("layout", "spot", "spot"),
}

#: fluent name -> parameter types (all boolean unless listed in NUMERIC)
FLUENTS: dict[str, tuple[str, ...]] = {
    # agents and spots
    "agent_at": ("agent", "spot"), "vacant": ("spot",), "open": ("spot",), "free_hand": ("agent",),
    "holding": ("agent", "item"), "idle": ("agent",),
    # items on places
    "item_at": ("item", "place"), "free": ("place",), "waiting": ("item",), "nowait": ("place",),
    # item states
    "fresh": ("item",), "ready": ("item",), "burnt": ("item",), "clean": ("item",),
    "dirty": ("item",), "partly": ("item",), "untouched": ("item",),
    # plates and orders
    "on_plate": ("item", "item"), "plate_has": ("item", "content"),
    "up_next": ("order",), "served": ("order",),
    # cooking specials
    "calm": (), "cooking_on": ("item", "place"), "on_heat": ("item", "place"),
    "window": ("item",), "overdone": ("item",),
    "pan_bump": ("agent",), "lifting": ("agent", "item", "place"),
    # static facts
    "adj": ("spot", "place"), "link": ("spot", "spot"),
    "is_veg": ("item",), "is_steak": ("item",), "is_plate": ("item",), "ingredient": ("item",),
    "kind_of": ("item", "kind"), "home": ("item", "place"), "lt": ("item", "item"),
    "holder": ("place",), "grabbable": ("place",), "takes_from": ("place",), "drop_ok": ("item", "place"),
    "board": ("place",), "pan": ("place",), "sink": ("place",), "trash": ("place",),
    "serving": ("place",),
    "next_content": ("content", "kind", "content"), "serves": ("content", "order"),
    "empty": ("content",), "next_order": ("order", "order"),
    "plates_stay_clean": (), "plates_get_dirty": (),
    "can_rescue": ("agent", "item", "spot"),
    # static numeric functions (costs and durations, in simulator steps)
    "dist": ("spot", "spot"),
    **{f: sig for p in PROCESSES if not p.timed
       for f, sig in ((f"{p.verb}_full", ()), (f"{p.verb}_left", ("item",)))},
    "cook_cost_full": (), "cook_cost_left": ("item",),
    "cook_lo_full": (), "cook_hi_full": (), "cook_lo": ("item",), "cook_hi": ("item",),
    "rescue_cost": ("agent", "item"),
}
NUMERIC = frozenset({
    "dist", "ldist", "cook_cost_full", "cook_cost_left", "cook_lo_full", "cook_hi_full",
    "cook_lo", "cook_hi", "rescue_cost",
    *(f"{p.verb}_{end}" for p in PROCESSES if not p.timed for end in ("full", "left")),
})
#: the fluent that holds while an item is in a state
STATE_FLUENT: dict[ItemState, str] = {
    ItemState.FRESH: "fresh", ItemState.CHOPPED: "ready", ItemState.COOKED: "ready",
    ItemState.BURNT: "burnt", ItemState.CLEAN: "clean", ItemState.DIRTY: "dirty",
}
for _k in range(1, 10):
    FLUENTS[f"size{_k}"] = ("content",)

Lit = tuple[str, ...]


@dataclass(frozen=True)
class Schema:
    """One action, independent of the encoding. ``cost`` is an int or a numeric fluent call."""

    name: str
    kind: str
    params: tuple[tuple[str, str], ...]
    pre: tuple[Lit, ...]
    add: tuple[Lit, ...]
    delete: tuple[Lit, ...]
    cost: int | Lit
    agent: str | None = "a"


def _schema(name: str, kind: str, params: str, pre: str, add: str = "", delete: str = "",
            cost: int | str = 1, agent: str | None = "a") -> Schema:
    """Build a schema from a compact text form: ``"a:agent s:spot"``, ``"item_at i p; free p"``."""
    def lits(text: str) -> tuple[Lit, ...]:
        return tuple(tuple(x.split()) for x in text.split(";") if x.strip())

    ps = tuple(tuple(p.split(":")) for p in params.split())  # type: ignore[misc]
    c: int | Lit = cost if isinstance(cost, int) else tuple(cost.split())
    return Schema(name, kind, ps, lits(pre), lits(add), lits(delete), c, agent)  # type: ignore[arg-type]


AGENT_AT = "agent_at a s; adj s p"
HAND = "a:agent i:item p:place s:spot"


def schemas(encoding: str, granularity: str, k_max: int = 3,
            switches: bool = False) -> list[Schema]:
    """All action schemas of one encoding and granularity (``switches``: the stations
    moves of anticipated layout switches)."""
    return ([_move_schema(granularity, switches), *_hand_schemas()] + _plate_schemas(k_max)
            + _cook_schemas(encoding))


def _move_schema(granularity: str, switches: bool) -> Schema:
    """The move between spots (stations) or cells, or per layout with ``switches``."""
    move_cost: int | str = "dist s1 s2" if granularity == "stations" else 1
    move_params = "a:agent s1:spot s2:spot"
    # cells: a cell is entered only while it is floor (``open``; timed initial literals
    # flip it when layout switches are anticipated)
    move_pre = "agent_at a s1; vacant s2; link s1 s2" + ("; open s2" if granularity == "cells"
                                                          else "")
    if switches and granularity == "stations":
        move_params += " l:layout"
        move_pre, move_cost = "agent_at a s1; vacant s2; llink l s1 s2; now l", "ldist l s1 s2"
    return _schema("move", "move", move_params, move_pre,
                   "agent_at a s2; vacant s1", "agent_at a s1; vacant s2", move_cost)


def _hand_schemas() -> list[Schema]:
    """Picking, putting, chopping, washing, plating and trashing one item."""
    return [
        _schema("pick", "pick", HAND, f"{AGENT_AT}; free_hand a; item_at i p; nowait p; grabbable p",
                "holding a i; free p", "free_hand a; item_at i p"),
        *(_pick_done(p) for p in _BUMPED),
        _schema("pick_release", "pick", f"{HAND} w:item",
                f"{AGENT_AT}; free_hand a; item_at i p; holder p; waiting w; home w p",
                "holding a i; item_at w p; nowait p", "free_hand a; item_at i p; waiting w"),
        _schema("put", "put", HAND, f"{AGENT_AT}; holding a i; free p; drop_ok i p",
                "item_at i p; free_hand a", "holding a i; free p"),
        *(_put_station(p) for p in _BUMPED),
        *(sch for p in _BUMPED for sch in _work(p)),
        # temporal: item_at q p is deleted at start and added back at end, so no other
        # agent picks the plate up while the ingredient goes on it (the simulator would put
        # the ingredient on the bare counter: found by the temporal fidelity replay)
        _schema("plate_put", "plate_put", f"{HAND} q:item k:kind c1:content c2:content",
                f"{AGENT_AT}; holding a i; ready i; item_at q p; holder p; clean q; plate_has q c1; "
                "kind_of i k; next_content c1 k c2",
                "free_hand a; on_plate i q; plate_has q c2; item_at q p",
                "holding a i; plate_has q c1; item_at q p"),
        _schema("plate_take", "plate_take", f"{HAND} q:item k:kind c1:content c2:content",
                f"{AGENT_AT}; holding a q; clean q; item_at i p; ready i; takes_from p; "
                "plate_has q c1; kind_of i k; next_content c1 k c2",
                "free p; on_plate i q; plate_has q c2", "item_at i p; plate_has q c1"),
        _schema("trash_item", "trash", f"{HAND} h:place",
                f"{AGENT_AT}; holding a i; ingredient i; trash p; home i h; free h",
                "free_hand a; item_at i h; fresh i; untouched i",
                "holding a i; free h; ready i; burnt i; partly i"),
    ]


#: the bump-driven process records: each has its own pick, put and work schemas
_BUMPED: tuple[Process, ...] = tuple(p for p in PROCESSES if not p.timed)


def _kind_guard(p: Process) -> str:
    """The static fact that an item is of a kind the process takes ("" when its taken state
    says so already: only plates get dirty)."""
    if set(p.takes) <= VEGETABLES:
        return "is_veg i; "
    if set(p.takes) == {Item.STEAK}:
        return "is_steak i; "
    if set(p.takes) == {Item.PLATE}:
        return ""
    raise CompileError(f"the planning model has no kind fact for the items of {p.verb!r}")


def _pick_done(p: Process) -> Schema:
    """Picking up what the process made (the station holds it while it is worked)."""
    return _schema(f"pick_{p.past}", "pick", HAND,
                   f"{AGENT_AT}; free_hand a; item_at i p; {PLACE_FLAGS[int(p.station)]} p; "
                   f"{STATE_FLUENT[p.makes_state]} i",
                   "holding a i; free p", "free_hand a; item_at i p")


def _put_station(p: Process) -> Schema:
    """Putting down an item to be worked on at the process's station."""
    place = PLACE_FLAGS[int(p.station)]
    return _schema(f"put_{place}", "put", HAND,
                   f"{AGENT_AT}; holding a i; free p; {place} p; {_kind_guard(p)}"
                   f"{STATE_FLUENT[p.takes_state]} i",
                   "item_at i p; free_hand a", "holding a i; free p")


def _work(p: Process) -> tuple[Schema, Schema]:
    """The whole work (``<verb>``, costing ``<verb>_full``) and its rest once started
    (``<verb>_rest``, costing ``<verb>_left``): one action each."""
    pre = (f"{AGENT_AT}; free_hand a; item_at i p; {PLACE_FLAGS[int(p.station)]} p; "
           f"{_kind_guard(p)}{STATE_FLUENT[p.takes_state]} i")
    made, taken = STATE_FLUENT[p.makes_state], STATE_FLUENT[p.takes_state]
    return (_schema(p.verb, p.verb, HAND, f"{pre}; untouched i", f"{made} i", f"{taken} i",
                    f"{p.verb}_full"),
            _schema(f"{p.verb}_rest", p.verb, HAND, f"{pre}; partly i", f"{made} i; untouched i",
                    f"{taken} i; partly i", f"{p.verb}_left i"))


def _plate_schemas(k_max: int) -> list[Schema]:
    """Trashing and delivering a plate of ``k`` ingredients, ``k`` up to ``k_max``."""
    out = []
    for k in range(1, k_max + 1):
        items = " ".join(f"i{j}:item h{j}:place" for j in range(1, k + 1))
        bind = "; ".join(f"on_plate i{j} q; home i{j} h{j}; free h{j}" for j in range(1, k + 1))
        order = "".join(f"; lt i{j} i{j + 1}" for j in range(1, k))
        back_add = "; ".join(f"item_at i{j} h{j}; fresh i{j}; untouched i{j}" for j in range(1, k + 1))
        back_del = "; ".join(f"on_plate i{j} q; free h{j}; ready i{j}" for j in range(1, k + 1))
        out.append(_schema(
            f"trash_plate{k}", "trash", f"a:agent q:item c:content c0:content p:place s:spot {items}",
            f"{AGENT_AT}; holding a q; trash p; plate_has q c; size{k} c; empty c0; {bind}{order}",
            f"plate_has q c0; {back_add}", f"plate_has q c; {back_del}"))
        for dirty in (False, True):
            plate_add = "dirty q; untouched q" if dirty else "clean q"
            out.append(_schema(
                f"deliver{k}" + ("_dirty" if dirty else ""), "deliver",
                f"a:agent q:item c:content c0:content o:order o2:order p:place s:spot hq:place "
                f"{items}",
                f"{AGENT_AT}; holding a q; clean q; serving p; plate_has q c; size{k} c; empty c0; "
                f"serves c o; up_next o; next_order o o2; home q hq; free hq; "
                f"{'plates_get_dirty' if dirty else 'plates_stay_clean'}; {bind}{order}",
                f"served o; up_next o2; free_hand a; item_at q hq; plate_has q c0; {plate_add}; {back_add}",
                f"up_next o; holding a q; free hq; plate_has q c{'; clean q' if dirty else ''}; "
                f"{back_del}"))
    return out


def _cook_schemas(encoding: str) -> list[Schema]:
    """Cooking a steak: the classical one-action cook (with rescue and abandon of a steak
    already on a pan) or the temporal take-offs (the envelope is built separately)."""
    if encoding == "classical":
        return [
            _schema("cook", "cook", HAND,
                    f"{AGENT_AT}; holding a i; is_steak i; fresh i; untouched i; pan p; free p",
                    "ready i", "fresh i", "cook_cost_full"),
            _schema("cook_rest", "cook", HAND,
                    f"{AGENT_AT}; holding a i; is_steak i; fresh i; partly i; pan p; free p",
                    "ready i; untouched i", "fresh i; partly i", "cook_cost_left i"),
            _schema("rescue", "rescue", "a:agent i:item p:place s1:spot s:spot",
                    "agent_at a s1; vacant s; adj s p; free_hand a; cooking_on i p; "
                    "can_rescue a i s",
                    "agent_at a s; vacant s1; holding a i; ready i; free p; calm",
                    "agent_at a s1; vacant s; free_hand a; cooking_on i p; fresh i; partly i",
                    "rescue_cost a i"),
            _schema("rescue_here", "rescue", HAND,
                    f"{AGENT_AT}; free_hand a; cooking_on i p; can_rescue a i s",
                    "holding a i; ready i; free p; calm",
                    "free_hand a; cooking_on i p; fresh i; partly i", "rescue_cost a i"),
            _schema("abandon", "abandon", "i:item p:place", "cooking_on i p",
                    "item_at i p; burnt i; calm", "cooking_on i p; fresh i; ready i; partly i", 0,
                    agent=None),
        ]
    return [
        _schema("take_off", "take_off", HAND,
                f"{AGENT_AT}; free_hand a; on_heat i p; window i",
                "holding a i; ready i; free p; untouched i",
                "free_hand a; on_heat i p; fresh i; partly i"),
        _schema("take_burnt", "take_off", HAND,
                f"{AGENT_AT}; free_hand a; on_heat i p; overdone i",
                "holding a i; burnt i; free p; untouched i",
                "free_hand a; on_heat i p; fresh i; ready i; partly i"),
    ]


def hand_change(schema: Schema) -> str:
    """What an action does to its agent's hand, read off its effects: "take" (it adds
    ``holding``), "release" (it adds ``free_hand``) or "keep"."""
    added = {lit[0] for lit in schema.add}
    if "holding" in added:
        return "take"
    return "release" if "free_hand" in added else "keep"


@dataclass
class Domain:
    """The materialised UP domain: fluents and actions to add to each problem."""

    encoding: str
    granularity: str
    k_max: int
    types: dict[str, Any]
    fluents: dict[str, Any]
    actions: dict[str, Any]
    schemas: dict[str, Schema]
    costs: dict[Any, Any] = field(default_factory=dict)
    #: classical: the action-cost metric every problem of this domain minimises
    metric: Any = None


def _check_options(encoding: str, granularity: str) -> None:
    if encoding not in ENCODINGS:
        raise CompileError(f"unknown encoding {encoding!r}; use one of {', '.join(ENCODINGS)}")
    if granularity not in GRANULARITIES:
        raise CompileError(
            f"unknown granularity {granularity!r}; use one of {', '.join(GRANULARITIES)}"
        )


@lru_cache(maxsize=16)
def parameter_names(signature: tuple[str, ...]) -> list[tuple[str, str]]:
    """A fluent's parameters named after their types (``("spot", "spot")`` -> ``spot``,
    ``spot2``): one name per type and position everywhere, so PDDL writers keep the names
    (numbered names like ``x0`` used with different types come out mangled, ``?x0_1``)."""
    seen: dict[str, int] = {}
    out = []
    for t in signature:
        seen[t] = seen.get(t, 0) + 1
        out.append((t if seen[t] == 1 else f"{t}{seen[t]}", t))
    return out


@lru_cache(maxsize=16)
def build_domain(encoding: str = "classical", granularity: str = "stations",
                 k_max: int = 3, switches: bool = False) -> Domain:
    """The UP types, fluents and actions of one encoding and granularity (cached).

    ``switches`` (temporal, stations): the per-layout moves of anticipated switches."""
    _check_options(encoding, granularity)
    if not 1 <= k_max <= 9:
        raise CompileError(f"k_max={k_max}: plates are modelled with 1 to 9 ingredients")
    switches = switches and granularity == "stations"
    if switches and encoding != "temporal":
        raise CompileError("anticipated layout switches are timed initial literals: they need "
                           "encoding='temporal'")
    from unified_planning.environment import get_environment
    from unified_planning.model import EndTiming, Fluent

    tm = get_environment().type_manager
    types = {t: tm.UserType(t) for t in TYPE_NAMES + (("layout",) if switches else ())}
    fluents = {}
    for name, sig in {**FLUENTS, **(SWITCH_FLUENTS if switches else {})}.items():
        if name.startswith("size") and int(name[4:]) > k_max:
            continue
        typ = tm.IntType() if name in NUMERIC else tm.BoolType()
        fluents[name] = Fluent(name, typ, **{p: types[t] for p, t in parameter_names(sig)})
    dom = Domain(encoding, granularity, k_max, types, fluents, {}, {})
    for sch in schemas(encoding, granularity, k_max, switches):
        dom.schemas[sch.name] = sch
        if encoding == "classical":
            act, cost = _instantaneous(sch, dom)
            dom.costs[act] = cost
        else:
            act = _durative(sch, dom)
            if switches and sch.name == "move":  # the layout still holds when it arrives
                act.add_condition(EndTiming(), fluents["now"](act.parameter("l")))
        dom.actions[sch.name] = act
    if encoding == "classical":
        from unified_planning.model.metrics import MinimizeActionCosts

        dom.metric = MinimizeActionCosts(dom.costs, default=None)
    if encoding == "temporal":
        dom.actions["cook"] = _temporal_cook(dom, rest=False)
        dom.actions["cook_rest"] = _temporal_cook(dom, rest=True)
        dom.actions.update(_pan_bumps_done(dom))
    return dom


def _lit(dom: Domain, params: dict[str, Any], lit: Lit) -> Any:
    return dom.fluents[lit[0]](*(params[x] for x in lit[1:]))


def _cost_expr(dom: Domain, params: dict[str, Any], cost: int | Lit) -> Any:
    from unified_planning.environment import get_environment

    return get_environment().expression_manager.Int(cost) if isinstance(cost, int) else _lit(dom, params, cost)


def _instantaneous(sch: Schema, dom: Domain) -> tuple[Any, Any]:
    from unified_planning.model import InstantaneousAction

    act = InstantaneousAction(sch.name, **{n: dom.types[t] for n, t in sch.params})
    params = {p.name: p for p in act.parameters}
    pre = sch.pre if sch.name in ("rescue", "rescue_here", "abandon") else sch.pre + (("calm",),)
    for lit in pre:
        act.add_precondition(_lit(dom, params, lit))
    for lit in sch.delete:
        if lit not in sch.add:
            act.add_effect(_lit(dom, params, lit), False)
    for lit in sch.add:
        if lit not in sch.delete:  # in both lists: held by the durative action; no effect here
            act.add_effect(_lit(dom, params, lit), True)
    return act, _cost_expr(dom, params, sch.cost)


def _durative(sch: Schema, dom: Domain) -> Any:
    from unified_planning.model import DurativeAction, EndTiming, StartTiming

    act = DurativeAction(sch.name, **{n: dom.types[t] for n, t in sch.params})
    params = {p.name: p for p in act.parameters}
    act.set_fixed_duration(_cost_expr(dom, params, sch.cost))
    start, end = StartTiming(), EndTiming()
    pre = sch.pre + ((("idle", sch.agent),) if sch.agent else ())
    for lit in pre:
        act.add_condition(start, _lit(dom, params, lit))
    deletes = sch.delete + ((("idle", sch.agent),) if sch.agent else ())
    adds = sch.add + ((("idle", sch.agent),) if sch.agent else ())
    for lit in deletes:
        act.add_effect(start, _lit(dom, params, lit), False)
    for lit in adds:
        act.add_effect(end, _lit(dom, params, lit), True)
    return act


def _temporal_cook(dom: Domain, rest: bool) -> Any:
    """The cooking envelope: ``?a1`` puts the steak on at start, ``?a2`` takes it off at end.

    Each end is a bump, one simulator step of its agent: the envelope's start leaves
    ``?a1`` not idle (``pan_bump``) until ``pan_put_done`` (1 step) ends, and its end
    leaves ``?a2`` not idle, ``lifting`` the steak, until ``pan_take_done`` (1 step)
    puts the steak in its hand and frees the pan. Without them an agent would put the
    steak on (or take it off) and start its next action in the same simulator step
    (the temporal fidelity replay found it).
    """
    from unified_planning.model import DurativeAction, EndTiming, StartTiming

    t = dom.types
    act = DurativeAction("cook_rest" if rest else "cook", a1=t["agent"], a2=t["agent"],
                         i=t["item"], p=t["place"], s1=t["spot"], s2=t["spot"])
    a1, a2, i, p, s1, s2 = act.parameters
    f = dom.fluents
    if rest:
        act.set_closed_duration_interval(f["cook_lo"](i), f["cook_hi"](i))
    else:
        act.set_closed_duration_interval(f["cook_lo_full"](), f["cook_hi_full"]())
    start, end = StartTiming(), EndTiming()
    for cond in (f["idle"](a1), f["agent_at"](a1, s1), f["adj"](s1, p), f["holding"](a1, i),
                 f["is_steak"](i), f["fresh"](i), f["pan"](p), f["free"](p),
                 f["partly"](i) if rest else f["untouched"](i)):
        act.add_condition(start, cond)
    act.add_effect(start, f["holding"](a1, i), False)
    act.add_effect(start, f["free"](p), False)
    act.add_effect(start, f["idle"](a1), False)
    act.add_effect(start, f["pan_bump"](a1), True)
    act.add_effect(start, f["free_hand"](a1), True)
    act.add_effect(start, f["cooking_on"](i, p), True)
    for cond in (f["idle"](a2), f["agent_at"](a2, s2), f["adj"](s2, p), f["free_hand"](a2)):
        act.add_condition(end, cond)
    act.add_effect(end, f["cooking_on"](i, p), False)
    act.add_effect(end, f["free_hand"](a2), False)
    act.add_effect(end, f["idle"](a2), False)
    act.add_effect(end, f["lifting"](a2, i, p), True)
    act.add_effect(end, f["fresh"](i), False)
    act.add_effect(end, f["ready"](i), True)
    if rest:
        act.add_effect(end, f["partly"](i), False)
        act.add_effect(end, f["untouched"](i), True)
    return act


#: actions with no simulator step of their own (see :func:`_temporal_cook`): map-back kind
BUMP_DONE_KINDS = {"pan_put_done": "wait", "pan_take_done": "wait"}


def _pan_bumps_done(dom: Domain) -> dict[str, Any]:
    """The one-step ends of the cook envelope's two bumps (see :func:`_temporal_cook`)."""
    from unified_planning.model import DurativeAction, EndTiming, StartTiming

    t, f = dom.types, dom.fluents
    start, end = StartTiming(), EndTiming()
    put = DurativeAction("pan_put_done", a=t["agent"])
    (a,) = put.parameters
    put.set_fixed_duration(1)
    put.add_condition(start, f["pan_bump"](a))
    put.add_effect(start, f["pan_bump"](a), False)
    put.add_effect(end, f["idle"](a), True)
    take = DurativeAction("pan_take_done", a=t["agent"], i=t["item"], p=t["place"])
    a, i, p = take.parameters
    take.set_fixed_duration(1)
    take.add_condition(start, f["lifting"](a, i, p))
    take.add_effect(start, f["lifting"](a, i, p), False)
    take.add_effect(end, f["holding"](a, i), True)
    take.add_effect(end, f["free"](p), True)
    take.add_effect(end, f["idle"](a), True)
    return {"pan_put_done": put, "pan_take_done": take}
