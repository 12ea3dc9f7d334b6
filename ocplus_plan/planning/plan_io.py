"""IPC plan files in and out: read a plan written anywhere, write our own plans the same way.

The formats are the International Planning Competition's, as Fast Downward, LPG, OPTIC,
POPF, TFD and VAL read and write them:

* sequential (classical): one action per line, ``(pick a0 tomato0 tomato_0_2 s_1_2)``,
  optionally numbered ``3: (pick ...)`` and followed by a cost ``[1]`` (LPG's style);
* time-stamped (temporal): ``0.000: (move a0 s_1_1 s_1_2) [3.000]``, start time, action,
  duration;
* ``;`` starts a comment (Fast Downward ends its plans with ``; cost = 51 (general cost)``);
  blank lines are skipped; names are case-insensitive (PDDL's rule).

A plan text is parsed, never evaluated: every line is matched against the grammar above,
every number must be a plain non-negative decimal, every name must be an action or object
of the problem with the action's arity and the parameters' types. Anything else raises
:class:`~ocplus_plan.errors.PlanFormatError` with the source, the line number and what
the line should look like, never a traceback. A file over :data:`MAX_PLAN_BYTES` or a line
over :data:`MAX_LINE_CHARS` is refused before it is read into memory.

Typical use::

    plan = read_plan("p01/classical.plan", compiled.problem)
    text = plan_text(plan)          # the same plan in IPC format
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any

from ..errors import PlanFormatError
from .validate import plan_from_steps, plan_to_steps

#: a kitchen plan has at most a few thousand actions; a bigger file is not a plan of ours
MAX_PLAN_BYTES = 4_000_000
MAX_LINE_CHARS = 4_000
#: no kitchen episode lasts this many steps; bigger numbers are typos (or overflow floats)
MAX_TIME = 10**9

_NAME = r"[A-Za-z][A-Za-z0-9_\-]*"
_NUMBER = re.compile(r"\d+(?:\.\d*)?(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?")
_LINE = re.compile(
    r"\s*(?:(?P<time>[^\s:()\[\]]+)\s*:)?\s*\((?P<body>[^()]*)\)\s*"
    r"(?:\[(?P<dur>[^\[\]]*)\])?\s*$")
_SHAPES = ("sequential: '(action arg ...)' or 'N: (action arg ...)'; "
           "time-stamped: 'T: (action arg ...) [D]'")


@dataclass(frozen=True)
class PlanLine:
    """One action line of a plan text, parsed but not yet checked against a problem."""

    line: int
    action: str
    args: tuple[str, ...]
    time: Fraction | None
    duration: Fraction | None


def _number(text: str, what: str, where: str) -> Fraction:
    token = text.strip()
    if not _NUMBER.fullmatch(token):
        raise PlanFormatError(f"{where}: {what} {token!r} is not a number "
                              "(a plain non-negative decimal such as 3 or 0.001)")
    value = Fraction(token)
    if value > MAX_TIME:
        raise PlanFormatError(f"{where}: {what} {token} is too large (at most {MAX_TIME})")
    return value


def parse_plan_text(text: str, source: str = "<plan>") -> list[PlanLine]:
    """The action lines of an IPC plan text (comments and blank lines dropped)."""
    out: list[PlanLine] = []
    for number, raw in enumerate(text.splitlines(), start=1):
        where = f"{source}, line {number}"
        if len(raw) > MAX_LINE_CHARS:
            raise PlanFormatError(f"{where}: {len(raw)} characters; a plan line has at most "
                                  f"{MAX_LINE_CHARS}")
        line = raw.split(";", 1)[0]
        if not line.strip():
            continue
        match = _LINE.fullmatch(line)
        if match is None:
            shown = line.strip()
            shown = shown if len(shown) <= 60 else shown[:57] + "..."
            raise PlanFormatError(f"{where}: cannot read {shown!r}; a plan line is {_SHAPES}")
        tokens = match["body"].split()
        if not tokens:
            raise PlanFormatError(f"{where}: '()' names no action")
        for token in tokens:
            if not re.fullmatch(_NAME, token):
                raise PlanFormatError(f"{where}: {token!r} is not a PDDL name (a letter, then "
                                      "letters, digits, '_' or '-')")
        time = None if match["time"] is None else _number(match["time"], "time", where)
        dur = None if match["dur"] is None else _number(match["dur"], "duration", where)
        out.append(PlanLine(number, tokens[0].lower(), tuple(t.lower() for t in tokens[1:]),
                            time, dur))
    return out


def _lookup(problem: Any) -> tuple[dict[str, Any], dict[str, Any]]:
    actions = {a.name.lower(): a for a in problem.actions}
    objects = {o.name.lower(): o for o in problem.all_objects}
    return actions, objects


def is_temporal(problem: Any) -> bool:
    """Whether ``problem`` has durative actions (its plans are time-stamped)."""
    return any(type(a).__name__ == "DurativeAction" for a in problem.actions)


def bind_plan(problem: Any, lines: list[PlanLine], source: str = "<plan>") -> Any:
    """A UP plan of ``problem`` from parsed lines; every name, arity and type is checked."""
    actions, objects = _lookup(problem)
    temporal = is_temporal(problem)
    steps: list[dict[str, Any]] = []
    for pl in lines:
        where = f"{source}, line {pl.line}"
        action = actions.get(pl.action)
        if action is None:
            known = ", ".join(sorted(actions))
            raise PlanFormatError(f"{where}: unknown action {pl.action!r}; this domain's "
                                  f"actions are {known}")
        params = action.parameters
        if len(pl.args) != len(params):
            raise PlanFormatError(f"{where}: {pl.action} takes {len(params)} arguments "
                                  f"({' '.join(p.name for p in params)}), got {len(pl.args)}")
        for param, arg in zip(params, pl.args):
            obj = objects.get(arg)
            if obj is None:
                raise PlanFormatError(f"{where}: no object named {arg!r} in the problem")
            if not param.type.is_compatible(obj.type):
                raise PlanFormatError(f"{where}: {arg!r} is a {obj.type}, but parameter "
                                      f"{param.name} of {pl.action} takes a {param.type}")
        step: dict[str, Any] = {"action": action.name,
                                "args": [objects[a].name for a in pl.args]}
        if temporal:
            if pl.time is None or pl.duration is None:
                raise PlanFormatError(f"{where}: a temporal plan line needs a start time and a "
                                      "duration: 'T: (action arg ...) [D]'")
            step["start"], step["duration"] = float(pl.time), float(pl.duration)
        steps.append(step)
    return plan_from_steps(problem, steps, temporal)


def read_plan_text(path: str | Path) -> str:
    """The text of a plan file, refused (with the reason) when too big or not text."""
    p = Path(path)
    if not p.is_file():
        raise PlanFormatError(f"{p}: no such plan file")
    size = p.stat().st_size
    if size > MAX_PLAN_BYTES:
        raise PlanFormatError(f"{p}: {size} bytes; a plan file has at most {MAX_PLAN_BYTES} "
                              "(is this a plan?)")
    data = p.read_bytes()
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise PlanFormatError(f"{p}, line {line}: not UTF-8 text") from None


def read_plan(path: str | Path, problem: Any) -> Any:
    """Read, parse and bind a plan file to ``problem`` (see the module docstring)."""
    return parse_plan(read_plan_text(path), problem, str(path))


def parse_plan(text: str, problem: Any, source: str = "<plan>") -> Any:
    """Parse and bind a plan text to ``problem``."""
    if len(text) > MAX_PLAN_BYTES:
        raise PlanFormatError(f"{source}: {len(text)} characters; a plan has at most "
                              f"{MAX_PLAN_BYTES}")
    return bind_plan(problem, parse_plan_text(text, source), source)


def _num(x: float) -> str:
    short = f"{x:.3f}"
    return short if float(short) == x else repr(float(x))


def plan_text(plan: Any, comment: str = "") -> str:
    """A UP plan in IPC format: numbered sequential lines, or time-stamped with durations."""
    lines = [f"; {c}" for c in comment.splitlines() if c.strip()]
    for k, step in enumerate(plan_to_steps(plan)):
        call = "(" + " ".join([step["action"], *map(str, step["args"])]) + ")"
        if "start" in step:
            lines.append(f"{_num(step['start'])}: {call} [{_num(step['duration'] or 0.0)}]")
        else:
            lines.append(f"{k}: {call}")
    return "\n".join(lines) + "\n"


__all__ = ["MAX_LINE_CHARS", "MAX_PLAN_BYTES", "PlanLine", "bind_plan", "is_temporal",
           "parse_plan", "parse_plan_text", "plan_text", "read_plan", "read_plan_text"]
