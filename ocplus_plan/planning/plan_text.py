"""Plans written as text (IPC format) read back against a compiled problem, never evaluated.

Two line forms, as planners print them::

    (pick a0 tomato0 s_1_2 tomato_0_2)                  sequential
    0.000: (pick a0 tomato0 s_1_2 tomato_0_2) [1.000]   time-stamped (start, duration)

Blank lines and ``;`` comments are skipped (a line may end in a comment); a line of three
backticks (a Markdown fence around a model's reply) is skipped too. Everything else must
be an action of the problem with objects of the problem, in the right number: any other
line raises :class:`~ocplus_plan.errors.UnreadableText` naming the line and what was
expected. Numbers are read with ``float`` on a checked pattern; a text longer than
``max_chars`` is refused before it is read.

:func:`read_plan_text` returns the steps as dicts (``{"action", "args", "start",
"duration", "line"}``), the form :func:`.validate.plan_from_steps` rebuilds a UP plan from;
:func:`plan_from_text` does both.
"""

from __future__ import annotations

import math
import re
from typing import Any

from ..errors import UnreadableText

#: the default limit on a plan text (characters); a longer one is refused unread
MAX_PLAN_CHARS = 1_000_000
_NUMBER = r"[0-9]+(?:\.[0-9]*)?(?:[eE][+-]?[0-9]+)?"
_LINE = re.compile(
    rf"^(?:(?P<start>{_NUMBER})\s*:\s*)?\(\s*(?P<body>[^()]*?)\s*\)"
    rf"(?:\s*\[\s*(?P<dur>{_NUMBER})\s*\])?$")
_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_\-]*$")


def _show(text: str, limit: int = 80) -> str:
    """A line as quoted in an error: repr, shortened."""
    return repr(text if len(text) <= limit else text[:limit] + "...")


def _number(text: str | None, what: str, line: int) -> float | None:
    if text is None:
        return None
    value = float(text)
    if not math.isfinite(value):
        raise UnreadableText(f"line {line}: the {what} {text!r} is not a finite number", line)
    return value


def check_size(text: Any, max_chars: int, what: str = "plan") -> str:
    """``text`` if it is a string of at most ``max_chars`` characters; else the error names
    the line where the limit is crossed."""
    if not isinstance(text, str):
        raise UnreadableText(f"the {what} is a {type(text).__name__}, not text", 0)
    if len(text) > max_chars:
        line = text.count("\n", 0, max_chars) + 1
        raise UnreadableText(
            f"the {what} has {len(text)} characters, more than the limit of {max_chars}: "
            f"it is refused unread (the limit falls in line {line})", line)
    return text


def read_plan_text(text: Any, problem: Any, max_chars: int = MAX_PLAN_CHARS,
                   temporal: bool | None = None) -> list[dict[str, Any]]:
    """The plan's steps, checked line by line against ``problem`` (a UP problem).

    ``temporal``: True requires ``START: (...) [DURATION]`` lines, False refuses time
    stamps, None takes either (but not a mix). An empty plan is allowed (the goal may
    already hold)."""
    check_size(text, max_chars)
    steps: list[dict[str, Any]] = []
    stamped: bool | None = temporal
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split(";", 1)[0].strip()
        if not line or line.startswith("```"):
            continue
        match = _LINE.match(line)
        if match is None:
            raise UnreadableText(
                f"line {number}: {_show(raw.strip())} is not a plan step; expected "
                "'(action arg ...)' or 'START: (action arg ...) [DURATION]'", number)
        start = _number(match["start"], "start time", number)
        duration = _number(match["dur"], "duration", number)
        has_time = start is not None
        if stamped is None:
            stamped = has_time
        if has_time != stamped:
            want = "'START: (action ...) [DURATION]'" if stamped else "'(action ...)' without a time"
            raise UnreadableText(f"line {number}: {_show(raw.strip())}: every step must be "
                                 f"{want} in this plan", number)
        if duration is not None and not has_time:
            raise UnreadableText(f"line {number}: a [duration] needs a start time "
                                 "('START: (action ...) [DURATION]')", number)
        steps.append(_step(match["body"], problem, number, start, duration))
    return steps


def _step(body: str, problem: Any, number: int, start: float | None,
          duration: float | None) -> dict[str, Any]:
    words = body.split()
    if not words:
        raise UnreadableText(f"line {number}: '()' names no action", number)
    bad = [w for w in words if not _NAME.match(w)]
    if bad:
        raise UnreadableText(f"line {number}: {_show(bad[0])} is not a PDDL name (letters, "
                             "digits, '_' and '-', starting with a letter)", number)
    # PDDL is case-insensitive; the problem's own spelling is tried first
    name = words[0] if problem.has_action(words[0]) else words[0].lower()
    args = [w if problem.has_object(w) else w.lower() for w in words[1:]]
    if not problem.has_action(name):
        known = ", ".join(sorted(a.name for a in problem.actions))
        raise UnreadableText(f"line {number}: unknown action {name!r}; this problem's actions: "
                             f"{known}", number)
    action = problem.action(name)
    params = action.parameters
    if len(args) != len(params):
        raise UnreadableText(
            f"line {number}: {name} takes {len(params)} arguments "
            f"({' '.join(f'{p.name} - {p.type}' for p in params)}), got {len(args)}", number)
    for arg, param in zip(args, params):
        if not problem.has_object(arg):
            raise UnreadableText(f"line {number}: {name}: unknown object {arg!r}", number)
        kind = problem.object(arg).type
        if not kind.is_subtype(param.type):
            raise UnreadableText(f"line {number}: {name}: {arg!r} is a {kind}, but parameter "
                                 f"{param.name} needs a {param.type}", number)
    return {"action": name, "args": args, "start": start, "duration": duration, "line": number}


def plan_from_text(text: Any, problem: Any, temporal: bool,
                   max_chars: int = MAX_PLAN_CHARS) -> tuple[Any, list[dict[str, Any]]]:
    """(the UP plan bound to ``problem``, its steps) from a plan text (see module doc)."""
    from .validate import plan_from_steps

    steps = read_plan_text(text, problem, max_chars, temporal)
    if temporal:
        for s in steps:
            if s["duration"] is None and problem.action(s["action"]).__class__.__name__ == \
                    "DurativeAction":
                raise UnreadableText(f"line {s['line']}: {s['action']} is durative: give its "
                                     "duration as '[DURATION]' after the action", s["line"])
    return plan_from_steps(problem, steps, temporal), steps


__all__ = ["MAX_PLAN_CHARS", "check_size", "plan_from_text", "read_plan_text"]
