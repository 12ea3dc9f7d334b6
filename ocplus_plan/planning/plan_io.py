"""IPC plan files in and out: read a plan file written anywhere, write our plans the same way.

The formats are the International Planning Competition's, as Fast Downward, LPG, OPTIC,
POPF, TFD and VAL read and write them:

* sequential (classical): one action per line, ``(pick a0 tomato0 tomato_0_2 s_1_2)``,
  optionally numbered ``3: (pick ...)`` and followed by a cost ``[1]`` (LPG's style);
* time-stamped (temporal): ``0.000: (move a0 s_1_1 s_1_2) [3.000]``;
* ``;`` starts a comment (Fast Downward ends its plans with ``; cost = 51 (general cost)``);
* a UTF-8 byte-order mark and Windows (CRLF) or old Mac (CR) line ends are accepted.

The lines are read by :mod:`.plan_text` (the one reader of plan texts: parsed, never
evaluated, every name, arity and type checked, errors naming the line); this module adds
what files need: a size limit checked before the file is read, a UTF-8 check that names
the line of the first bad byte, the source in every message, the numbered sequential
variant, and writing plans out. Every error is an :class:`~ocplus_plan.errors.UnreadableText`.

Typical use::

    plan = read_plan("p01/classical.plan", compiled.problem)
    text = format_plan(plan)          # the same plan in IPC format
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from ..errors import UnreadableText
from .validate import plan_to_steps

#: a kitchen plan has at most a few thousand actions; a bigger file is not a plan of ours
MAX_PLAN_BYTES = 4_000_000
#: a sequential step number ``3:`` and a trailing cost ``[1]`` (LPG prints both)
_STEP_NUMBER = re.compile(r"^(\s*)[0-9]+\s*:\s*(?=\()", re.MULTILINE)
_STEP_COST = re.compile(r"\)\s*\[\s*[0-9]+(?:\.[0-9]*)?\s*\]\s*(?=;|$)", re.MULTILINE)


def is_temporal(problem: Any) -> bool:
    """Whether ``problem`` has durative actions (its plans are time-stamped)."""
    return any(type(a).__name__ == "DurativeAction" for a in problem.actions)


def parse_plan(text: str, problem: Any, source: str = "<plan>") -> Any:
    """A UP plan of ``problem`` from an IPC plan text (see the module docstring)."""
    from .plan_text import plan_from_text

    temporal = is_temporal(problem)
    if isinstance(text, str):  # a byte-order mark and CRLF / CR line ends read as plain text
        text = text.removeprefix("\ufeff").replace("\r\n", "\n").replace("\r", "\n")
    if not temporal and isinstance(text, str):
        text = _STEP_COST.sub(")", _STEP_NUMBER.sub(r"\1", text))
    try:
        return plan_from_text(text, problem, temporal, max_chars=MAX_PLAN_BYTES)[0]
    except UnreadableText as exc:
        raise UnreadableText(f"{source}, {exc}", exc.line) from None


def plan_file_problem(path: str | Path, limit: int | None = MAX_PLAN_BYTES) -> str | None:
    """Why ``path`` cannot be read as a plan (or PDDL) file, or None when it can: it is
    missing, not a regular file (a directory, a device such as /dev/zero, a pipe),
    unreadable, or over ``limit`` bytes. Nothing beyond the first byte is read."""
    p = Path(path)
    try:
        if not p.exists():
            return f"{p}: no such file"
        if p.is_dir():
            return f"{p}: is a directory, not a file"
        if not p.is_file():
            return f"{p}: not a regular file (a device or a pipe?)"
        size = p.stat().st_size
        with p.open("rb") as fh:
            fh.read(1)
    except OSError as exc:
        return f"{p}: cannot be read ({exc.strerror or exc})"
    if limit is not None and size > limit:
        return f"{p}: {size} bytes; a plan file has at most {limit} (is this a plan?)"
    return None


def read_plan_file(path: str | Path) -> str:
    """The text of a plan file, refused (with the reason) when too big or not text."""
    p = Path(path)
    problem = plan_file_problem(p)
    if problem is not None:
        raise UnreadableText(problem.replace("no such file", "no such plan file"))
    with p.open("rb") as fh:
        data = fh.read(MAX_PLAN_BYTES + 1)  # the file may have grown since it was measured
    if len(data) > MAX_PLAN_BYTES:
        raise UnreadableText(f"{p}: more than {MAX_PLAN_BYTES} bytes; a plan file has at most "
                             f"{MAX_PLAN_BYTES} (is this a plan?)")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise UnreadableText(f"{p}, line {line}: not UTF-8 text", line) from None


def read_plan(path: str | Path, problem: Any) -> Any:
    """Read a plan file and bind it to ``problem``."""
    return parse_plan(read_plan_file(path), problem, str(path))


def _num(x: float) -> str:
    short = f"{x:.3f}"
    return short if float(short) == x else repr(float(x))


def format_plan(plan: Any, comment: str = "") -> str:
    """A UP plan in IPC format: numbered sequential lines, or time-stamped with durations."""
    lines = [f"; {c}" for c in comment.splitlines() if c.strip()]
    for k, step in enumerate(plan_to_steps(plan)):
        call = "(" + " ".join([step["action"], *map(str, step["args"])]) + ")"
        if "start" in step:
            lines.append(f"{_num(step['start'])}: {call} [{_num(step['duration'] or 0.0)}]")
        else:
            lines.append(f"{k}: {call}")
    return "\n".join(lines) + "\n"


__all__ = ["MAX_PLAN_BYTES", "format_plan", "is_temporal", "parse_plan", "plan_file_problem",
           "read_plan", "read_plan_file"]
