"""The planning model in plain English: domains, problems, plan steps and kitchen things.

Everything here is generated from the model, never written per instance: a domain's
text walks the unified-planning actions of :func:`.model.build_domain` (parameters,
conditions, effects, durations or costs) and words each fact with :data:`FACT_WORDS`,
one phrase per fluent of :mod:`.model`; a problem's text walks the objects, initial
facts, timed facts and goals of a compiled problem and says what each object is in
the kitchen through the compiler's name map. A test checks that every fluent and
every action of every encoding has words, so the text follows the model when it
changes.

The API others build on (the ``text`` observations and the language-model controller
share these words):

* :func:`position_words`, :func:`object_words`, :func:`fact_words`: one thing or one fact
  (cells and places in the words of :mod:`..sim.words`, the kitchen's one vocabulary);
* :func:`step_words`: one plan action, e.g. "cook 0 picks up onion0 from the onion
  counter at (row 4, col 4) (standing at the floor at (row 3, col 4))";
* :func:`describe_domain` (encoding, granularity) and :func:`describe_problem`
  (a :class:`~.compile.Compiled`): whole texts;
* :func:`kitchen_words`: a fidelity mismatch message with its tuples and object names
  said in words.
"""

from __future__ import annotations

import re
from typing import Any

from ..sim.stations import CELL_KINDS
from .model import FLUENTS, SWITCH_FLUENTS, build_domain

#: what a ``place`` object is, by the label its name starts with (the compiler names
#: places after their cell code); the words are the kitchen's own (:mod:`..sim.words`)
PLACE_WORDS = {k.name: k.word for k in CELL_KINDS}

TYPE_WORDS = {
    "agent": "a cook",
    "spot": "a floor cell where a cook can stand",
    "place": "a cell a cook works at by bumping into it (counter, crate, board, pan, sink, "
             "trash can, serving window)",
    "item": "a movable thing: an ingredient or a plate",
    "kind": "a kind of ingredient",
    "content": "what a plate can hold: a multiset of ingredient kinds",
    "order": "a customer's order (a dish to serve)",
    "layout": "one of the kitchen's two layouts (walls that come and go)",
}

#: one phrase per fluent; ``{0}``, ``{1}``... are its arguments, ``{n}`` a numeric value
FACT_WORDS = {
    "agent_at": "{0} stands at {1}", "vacant": "nobody stands at {0}",
    "open": "{0} is floor (walkable) now", "free_hand": "{0} has empty hands",
    "holding": "{0} holds {1}", "idle": "{0} is not busy with an action",
    "item_at": "{0} lies on {1}", "free": "nothing lies on {0}",
    "waiting": "{0} waits to respawn at its home cell", "nowait": "no item waits to respawn on {0}",
    "fresh": "{0} is unprocessed (a raw vegetable or steak)",
    "ready": "{0} is processed (chopped or cooked)", "burnt": "{0} is burnt",
    "clean": "{0} is clean", "dirty": "{0} is dirty", "partly": "{0} is partly processed",
    "untouched": "no processing of {0} has started",
    "on_plate": "{0} is on {1}", "plate_has": "{0} holds {1}",
    "up_next": "{0} is the next order of its recipe to serve", "served": "{0} has been served",
    "calm": "no steak left on a pan at the start needs rescuing",
    "cooking_on": "{0} is cooking on {1}", "on_heat": "{0} was already heating on {1} at the start",
    "window": "{0} is cooked and not yet burnt", "overdone": "{0} has burnt on the pan",
    "pan_bump": "{0} is putting a steak on a pan", "lifting": "{0} is taking {1} off {2}",
    "adj": "{0} is next to {1}", "link": "a cook can walk from {0} to {1}",
    "is_veg": "{0} is a vegetable", "is_steak": "{0} is a steak", "is_plate": "{0} is a plate",
    "ingredient": "{0} is an ingredient", "kind_of": "{0} is a {1}",
    "home": "{1} is the home (spawn) cell of {0}", "lt": "{0} comes before {1} in a fixed order",
    "holder": "{0} can hold an item", "grabbable": "an item on {0} can be picked up",
    "takes_from": "a plate can scoop an ingredient from {0}",
    "drop_ok": "{0} may be put down on {1}", "board": "{0} is a cutting board",
    "pan": "{0} is a pan", "sink": "{0} is a sink", "trash": "{0} is a trash can",
    "serving": "{0} is the serving window",
    "next_content": "adding a {1} to a plate holding {0} makes it hold {2}",
    "serves": "a plate holding {0} completes {1}", "empty": "{0} is an empty plate's content",
    "next_order": "after {0}, the next order of the same recipe is {1}",
    "plates_stay_clean": "plates stay clean after delivery",
    "plates_get_dirty": "plates come back dirty after delivery",
    "can_rescue": "{0} can reach the pan holding {1} from {2} in time",
    "now": "the kitchen is in {0}", "llink": "in {0}, a cook can walk from {1} to {2}",
    # numbers (steps of the simulator)
    "dist": "walking from {0} to {1} takes {n} steps",
    "ldist": "in {0}, walking from {1} to {2} takes {n} steps",
    "chop_full": "chopping a vegetable takes {n} steps",
    "chop_left": "chopping {0} needs {n} more steps",
    "wash_full": "washing a plate takes {n} steps",
    "wash_left": "washing {0} needs {n} more steps",
    "cook_cost_full": "cooking a steak (put on, wait, take off) takes {n} steps",
    "cook_cost_left": "finishing cooking {0} takes {n} steps",
    "cook_lo_full": "a steak is cooked after {n} steps on a pan",
    "cook_hi_full": "a steak must leave the pan within {n} steps or it burns",
    "cook_lo": "{0} is cooked after {n} more steps on a pan",
    "cook_hi": "{0} must leave the pan within {n} more steps",
    "rescue_cost": "{0} needs {n} steps to take {1} off its pan",
    **{f"size{k}": f"{{0}} has {k} ingredient{'s' if k > 1 else ''}" for k in range(1, 10)},
}

#: how each action reads as a step of a plan (parameters by name)
ACTION_WORDS = {
    "move": "{a} walks from {s1} to {s2}",
    "pick": "{a} picks up {i} from {p} (standing at {s})",
    "pick_chopped": "{a} picks up the chopped {i} from {p} (standing at {s})",
    "pick_washed": "{a} picks up the washed {i} from {p} (standing at {s})",
    "pick_release": "{a} picks up {i} from {p}, where {w} then respawns (standing at {s})",
    "put": "{a} puts {i} down on {p} (standing at {s})",
    "put_board": "{a} puts {i} on {p} to chop it (standing at {s})",
    "put_sink": "{a} puts {i} in {p} to wash it (standing at {s})",
    "chop": "{a} chops {i} on {p} (standing at {s})",
    "chop_rest": "{a} finishes chopping {i} on {p} (standing at {s})",
    "wash": "{a} washes {i} in {p} (standing at {s})",
    "wash_rest": "{a} finishes washing {i} in {p} (standing at {s})",
    "plate_put": "{a} puts {i} on {q}, which lies on {p} (standing at {s})",
    "plate_take": "{a}, holding {q}, scoops {i} from {p} onto it (standing at {s})",
    "trash_item": "{a} throws {i} into {p}; it respawns at {h} (standing at {s})",
    "trash_plate": "{a} empties {q} into {p} (standing at {s})",
    "deliver": "{a} serves {q} at {p} for {o} (standing at {s})",
    "cook": "{a} cooks {i} on {p} (standing at {s})",
    "cook_rest": "{a} finishes cooking {i} on {p} (standing at {s})",
    "rescue": "{a} walks from {s1} to {s} and takes the cooking {i} off {p}",
    "rescue_here": "{a} takes the cooking {i} off {p} (standing at {s})",
    "abandon": "{i} is left to burn on {p}",
    "take_off": "{a} takes the cooked {i} off {p} (standing at {s})",
    "take_burnt": "{a} takes the burnt {i} off {p} (standing at {s})",
    "pan_put_done": "{a} finishes putting a steak on a pan",
    "pan_take_done": "{a} finishes taking {i} off {p}",
}
#: the temporal cook envelope: two cooks, one puts the steak on, one takes it off
_ENVELOPE_WORDS = ("{a1} puts {i} on {p} (standing at {s1}); {a2} takes it off when it is "
                   "cooked (standing at {s2})")


def action_template(name: str) -> str:
    """The :data:`ACTION_WORDS` template of an action name (``deliver2_dirty`` -> deliver)."""
    if name in ACTION_WORDS:
        return ACTION_WORDS[name]
    base = re.sub(r"\d+(_dirty)?$", "", name)
    return ACTION_WORDS.get(base, name + " with " + "{_args}")


def position_words(rc: tuple[int, int]) -> str:
    """``(1, 2)`` -> ``(row 1, col 2)``, as :func:`..sim.words.at` says a cell."""
    return f"(row {rc[0]}, col {rc[1]})"


def object_words(compiled: Any, name: str) -> str:
    """What a problem object is in the kitchen, e.g. ``the cutting board at (row 1, col 6)``."""
    n = compiled.names
    if name in n.agents:
        return f"cook {n.agents[name]}"
    if name in n.items:
        return name
    if name in n.cells:
        rc = n.cells[name]
        if name.startswith("s_"):
            return f"the floor at {position_words(rc)}"
        label = name.rsplit("_", 2)[0]
        return f"the {PLACE_WORDS.get(label, label)} at {position_words(rc)}"
    if name in n.orders:
        return "no further order" if n.orders[name] < 0 else f"order {n.orders[name]}"
    if name in n.contents:
        kinds = n.contents[name]
        return ("an empty plate" if not kinds else "a plate of " + ", ".join(kinds))
    if name in n.kinds:
        return n.kinds[name]
    if name in n.layouts:
        return f"layout {n.layouts[name]}"
    return name


def fact_words(fluent: str, args: list[str] | tuple[str, ...], value: Any = None) -> str:
    """One fact in words: ``fact_words("holding", ["a0", "tomato0"])`` -> ``a0 holds tomato0``."""
    template = FACT_WORDS.get(fluent)
    if template is None:
        return f"{fluent}({', '.join(args)})" + ("" if value is None else f" = {value}")
    return template.format(*args, n=value)


def step_words(compiled: Any, action: str, args: list[str] | tuple[str, ...]) -> str:
    """One plan action in kitchen words (object names replaced by what they are)."""
    problem_action = compiled.problem.action(action)
    names = [p.name for p in problem_action.parameters]
    said = {p: object_words(compiled, a) for p, a in zip(names, args)}
    template = _ENVELOPE_WORDS if "a1" in said and "a2" in said else action_template(action)
    return template.format(**said, _args=", ".join(said.values()))


# ------------------------------------------------------------------ domains
def _expr_words(expr: Any, value: Any = None) -> str:
    if expr.is_fluent_exp():
        return fact_words(expr.fluent().name, [str(a) for a in expr.args], value)
    if expr.is_not():
        return "not: " + _expr_words(expr.arg(0))
    return str(expr)


def _number_words(expr: Any) -> str:
    """A duration or cost: ``1 step``, ``N steps, where chopping ... takes N steps``."""
    if expr.is_int_constant() or expr.is_real_constant():
        value = expr.constant_value()
        return f"{value} step" + ("" if value == 1 else "s")
    if expr.is_fluent_exp():
        words = fact_words(expr.fluent().name, [str(a) for a in expr.args], "N")
        return f"N steps, where {words}"
    return str(expr)


def _effects_words(effects: list[Any]) -> list[str]:
    out = []
    for eff in effects:
        fact = _expr_words(eff.fluent)
        value = eff.value
        if value.is_bool_constant():
            out.append(fact if value.bool_constant_value() else f"no longer: {fact}")
        else:
            out.append(f"{fact} becomes {value}")
    return out


def _timing_words(timing: Any) -> str:
    return "at its start" if timing.is_from_start() else "at its end"


def _action_text(action: Any, cost: Any) -> list[str]:
    params = ", ".join(f"{p.name} ({p.type})" for p in action.parameters)
    head = f"{action.name}({params})"
    example = action_template(action.name) if not {"a1", "a2"} <= {
        p.name for p in action.parameters} else _ENVELOPE_WORDS
    lines = [head, "  means: " + example.format(
        **{p.name: p.name for p in action.parameters},
        _args=", ".join(p.name for p in action.parameters))]
    if hasattr(action, "preconditions"):
        lines.append(f"  takes {_number_words(cost)}" if cost is not None else "")
        lines += [f"  needs: {_expr_words(c)}" for c in action.preconditions]
        lines += [f"  then: {w}" for w in _effects_words(action.effects)]
    else:
        lo, hi = action.duration.lower, action.duration.upper
        if lo == hi:
            lines.append(f"  lasts {_number_words(lo)}")
        else:
            lines.append(f"  lasts at least {_number_words(lo)} and at most {_number_words(hi)}")
        for interval, conds in action.conditions.items():
            when = "at its start" if interval.lower.is_from_start() and \
                interval.upper.is_from_start() else "at its end"
            lines += [f"  needs {when}: {_expr_words(c)}" for c in conds]
        for timing, effs in action.effects.items():
            lines += [f"  then {_timing_words(timing)}: {w}" for w in _effects_words(effs)]
    return [ln for ln in lines if ln]


def describe_domain(encoding: str, granularity: str = "stations", k_max: int = 3,
                    switches: bool = False) -> str:
    """The whole domain in English, generated from :func:`.model.build_domain`."""
    dom = build_domain(encoding, granularity, k_max, switches)
    if encoding == "classical":
        timing = ("Actions happen one after another. Each has a cost: the number of "
                  "simulator steps it takes. A plan's cost is the sum; lower is better.")
    else:
        timing = ("Actions are durative and may run in parallel, at most one per cook at a "
                  "time. Durations are simulator steps. A plan's makespan (when its last "
                  "action ends) is to be as short as possible.")
    lines = [
        f"Kitchen planning domain ({encoding}, {granularity} granularity).",
        "Cooks in a grid kitchen fetch ingredients, chop vegetables on cutting boards, cook "
        "steaks on pans, put the ingredients on plates and serve the plates that match open "
        "orders at the serving window. A cook carries one item at a time and works at a cell "
        "by standing on the floor next to it.",
        timing, "", "Types of objects:",
    ]
    lines += [f"- {t}: {TYPE_WORDS.get(t, t)}" for t in dom.types]
    lines += ["", "Actions:"]
    for name, action in dom.actions.items():
        lines += _action_text(action, dom.costs.get(action))
        lines.append("")
    return "\n".join(lines).rstrip() + "\n"


# ------------------------------------------------------------------ problems
def _arg_names(expr: Any) -> list[str]:
    return [str(a) for a in expr.args]


def describe_problem(compiled: Any) -> str:
    """A compiled problem in English: what each object is, the facts at the start (static
    numbers included), facts that change at given times, and the goal."""
    problem = compiled.problem
    by_type: dict[str, list[str]] = {}
    for obj in problem.all_objects:
        by_type.setdefault(str(obj.type), []).append(obj.name)
    lines = [f"Kitchen problem ({compiled.encoding}, {compiled.granularity} granularity).",
             "", "Objects:"]
    for typ, objs in by_type.items():
        lines.append(f"- {TYPE_WORDS.get(typ, typ)}:")
        lines += [f"  - {o}: {object_words(compiled, o)}" for o in objs]
    lines += ["", "At the start:"]
    for fluent_exp, value in problem.explicit_initial_values.items():
        name = fluent_exp.fluent().name
        if value.is_bool_constant():
            if value.bool_constant_value():
                lines.append(f"- {fact_words(name, _arg_names(fluent_exp))}")
        else:
            lines.append(f"- {fact_words(name, _arg_names(fluent_exp), value)}")
    lines.append("- every other fact is false")
    timed = getattr(problem, "timed_effects", {}) or {}
    if timed:
        lines += ["", "Changes at given times (steps from now):"]
        for timing in sorted(timed, key=lambda t: float(t.delay)):
            for w in _effects_words(timed[timing]):
                lines.append(f"- at {float(timing.delay):g}: {w}")
    lines += ["", "Goal:"]
    recipes = {}
    for fluent_exp, value in problem.explicit_initial_values.items():
        if fluent_exp.fluent().name == "serves" and value.bool_constant_value():
            content, order = _arg_names(fluent_exp)
            recipes[order] = object_words(compiled, content)
    for goal in problem.goals:
        for g in (goal.args if goal.is_and() else [goal]):
            order = _arg_names(g)[0]
            lines.append(f"- serve {order} ({object_words(compiled, order)}): "
                         f"{recipes.get(order, 'a dish')}")
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------ messages
_TAGS = [
    (re.compile(r"\('hand', (\d+)\)"), lambda m: f"held by cook {m[1]}"),
    (re.compile(r"\('cell', \((\d+), (\d+)\)\)"),
     lambda m: f"on the cell at {position_words((int(m[1]), int(m[2])))}"),
    (re.compile(r"\('plate', (\d+)\)"), lambda m: f"on plate item {m[1]}"),
    (re.compile(r"\('waiting', None\)"), lambda m: "waiting to reappear"),
    (re.compile(r"\((\d+), (\d+)\)"), lambda m: position_words((int(m[1]), int(m[2])))),
]


def kitchen_words(message: str, compiled: Any = None) -> str:
    """A fidelity message with its ``('hand', 0)``-style tuples, and (given ``compiled``)
    the cooks' and places' object names, said in words."""
    for pattern, words in _TAGS:
        message = pattern.sub(words, message)
    if compiled is not None:
        names = compiled.names
        for name in sorted({*names.agents, *(c for c in names.cells if not c.startswith("s_"))},
                           key=len, reverse=True):
            message = re.sub(rf"\b{re.escape(name)}\b", object_words(compiled, name), message)
    return message


def check_complete() -> list[str]:
    """Fluents of the model that have no words (empty when the words cover the model)."""
    return sorted(f for f in {**FLUENTS, **SWITCH_FLUENTS} if f not in FACT_WORDS)


__all__ = ["ACTION_WORDS", "FACT_WORDS", "PLACE_WORDS", "TYPE_WORDS", "action_template",
           "check_complete", "describe_domain", "describe_problem", "fact_words",
           "kitchen_words", "object_words", "position_words", "step_words"]
