"""The value types of the ``ocplus`` options: each checks one value while the command line
is parsed, before any work starts, and refuses a bad one with a line that says what is
wrong and what is allowed (argparse turns it into ``ocplus CMD: error: ...``, exit 2).

The limits are stated here once and in ``docs/cli.md``; they bound what a command line can
ask for (memory, time), not what the simulator could do.
"""

from __future__ import annotations

import argparse
import math
import os
import re
from collections.abc import Callable
from pathlib import Path

#: seeds are whole numbers in [0, MAX_SEED] (numpy and torch both take them)
MAX_SEED = 2**32 - 1
#: ``--seeds`` selects at most this many episodes per configuration
MAX_SEEDS = 10_000
#: steps per episode (the presets play 200), and random steps before compiling a state
MAX_HORIZON = 10_000
#: worker processes or Ray tasks at once
MAX_JOBS = 256
#: cooks in one kitchen (a map may allow fewer: its spawn points decide)
MAX_AGENTS = 16
#: any time limit, in seconds (one week)
MAX_SECONDS = 7 * 24 * 3600.0

Type = Callable[[str], object]

#: a whole number as typed: ASCII digits only (Python's ``int`` also reads full-width and
#: other Unicode digits, and ``1_000``)
WHOLE = re.compile(r"[+-]?[0-9]+")


def _fail(message: str) -> argparse.ArgumentTypeError:
    return argparse.ArgumentTypeError(message)


def _whole(text: str, what: str, lo: int, hi: int | None) -> int:
    allowed = f"a whole number from {lo} to {hi}" if hi is not None else \
        f"a whole number, at least {lo}"
    stripped = str(text).strip()
    if not WHOLE.fullmatch(stripped):
        raise _fail(f"{text!r} is not a whole number (ASCII digits); {what} is {allowed}")
    value = int(stripped)
    if value < lo or (hi is not None and value > hi):
        raise _fail(f"{value} is out of range; {what} is {allowed}")
    return value


def whole(what: str, lo: int, hi: int | None = None) -> Type:
    """A type for a whole number in ``[lo, hi]``; ``what`` names it in the message."""

    def parse(text: str) -> int:
        return _whole(text, what, lo, hi)

    parse.__name__ = what.replace(" ", "_")
    return parse


def number(what: str, lo: float, hi: float, *, lo_open: bool = True) -> Type:
    """A type for a finite number in ``(lo, hi]`` (``[lo, hi]`` without ``lo_open``):
    ``nan``, ``inf`` and anything outside are refused."""
    left = "(" if lo_open else "["

    def parse(text: str) -> float:
        try:
            if not str(text).isascii():
                raise ValueError(text)
            value = float(str(text).strip())
        except ValueError:
            raise _fail(f"{text!r} is not a number; {what} is a number in "
                        f"{left}{lo:g}, {hi:g}]") from None
        if not math.isfinite(value) or value > hi or value < lo or (lo_open and value == lo):
            raise _fail(f"{text} is out of range; {what} is a finite number in "
                        f"{left}{lo:g}, {hi:g}]")
        return value

    parse.__name__ = what.replace(" ", "_")
    return parse


seed = whole("a seed", 0, MAX_SEED)
horizon = whole("the horizon (steps per episode)", 1, MAX_HORIZON)
random_steps = whole("the number of random steps", 0, MAX_HORIZON)
jobs = whole("--jobs", 1, MAX_JOBS)
n_agents = whole("the number of cooks", 1, MAX_AGENTS)
seconds = number("a time limit in seconds", 0.0, MAX_SECONDS)
positive = whole("the value", 1)


class SeedText(str):
    """A checked ``--seeds`` value. Its own type, so that argparse never takes a given
    value for the default (one-character strings are shared objects)."""


def seeds(text: str) -> str:
    """``--seeds``: a count (``10`` = seeds 0-9), a list (``0,4,7``) or a range (``5-9``), of
    at most :data:`MAX_SEEDS` seeds, each in [0, MAX_SEED]. Counted, never expanded, here."""
    return SeedText(_seed_selection(text, single_is_count=True))


def seed_selection(text: str) -> str:
    """``--save-replays``: one seed (``3``), a list (``0,4``) or a range (``5-9``); empty: none."""
    return text if not str(text).strip() else _seed_selection(text, single_is_count=False)


def _seed_selection(text: str, *, single_is_count: bool) -> str:
    s = str(text).strip()
    form = ("a count (10 = seeds 0-9), a list (0,4,7) or a range (5-9)" if single_is_count
            else "a seed (3), a list (0,4,7) or a range (5-9)")
    if not s:
        raise _fail(f"no seeds given; give {form}")
    if "," in s:
        parts = [p for p in s.split(",") if p.strip()]
        if not parts:
            raise _fail(f"{text!r} lists no seeds; give {form}")
        if len(parts) > MAX_SEEDS:
            raise _fail(f"{len(parts)} seeds listed; at most {MAX_SEEDS} are allowed")
        values = [_whole(p, "a seed", 0, MAX_SEED) for p in parts]
        if len(set(values)) != len(values):
            raise _fail(f"{text!r} lists a seed twice; give each seed once")
        return s
    if "-" in s[1:]:
        a, b = (_whole(p, "a seed", 0, MAX_SEED) for p in s.split("-", 1))
        if b < a:
            raise _fail(f"the range {s} is empty (it ends before it starts); write it low-high, "
                        f"e.g. {b}-{a}")
        if b - a + 1 > MAX_SEEDS:
            raise _fail(f"the range {s} holds {b - a + 1} seeds; at most {MAX_SEEDS} are allowed")
        return s
    if single_is_count:
        _whole(s, "a count of seeds", 1, MAX_SEEDS)
    else:
        _whole(s, "a seed", 0, MAX_SEED)
    return s


def name(text: str) -> str:
    """A name or a comma-separated list of names (presets, maps, agents): not empty, and
    no empty item in the list (``greedy,,greedy``)."""
    if not str(text).strip() or "\0" in text:
        raise _fail(f"{text!r} names nothing; give a name (or a comma-separated list)")
    if "," in text and any(not part.strip() for part in text.split(",")):
        raise _fail(f"{text!r} has an empty item; write the names with one comma between "
                    "each two")
    return text


def faults(text: str) -> str:
    """``--faults``: KEY:VALUE pairs joined by commas; neither empty nor with empty items
    (omit the option for no faults)."""
    if not str(text).strip() or any(not p.strip() for p in str(text).split(",")):
        raise _fail(f"{text!r} has an empty item; give KEY:VALUE pairs joined by commas "
                    "(e.g. burns:3,switches:40), or leave --faults out for none")
    if not str(text).isascii():
        raise _fail(f"{text!r}: write faults in ASCII (digits 0-9)")
    return text


def whole_list(what: str, lo: int, hi: int) -> Type:
    """A type for a comma-separated list of whole numbers in ``[lo, hi]`` (kept as text)."""

    def parse(text: str) -> str:
        parts = [p for p in str(text).split(",") if p.strip()]
        if not parts:
            raise _fail(f"{text!r} lists nothing; give comma-separated whole numbers, e.g. 1,2")
        for p in parts:
            _whole(p, what, lo, hi)
        return text

    parse.__name__ = what.replace(" ", "_") + "_list"
    return parse


def out_dir(text: str) -> str:
    """``--out``: a folder that exists and is writable, or that can be made (its nearest
    existing parent is a writable folder). A file there is refused."""
    path = _path(text, "--out")
    try:
        if path.exists():
            if not path.is_dir():
                raise _fail(f"{text} is a file; --out names a folder (a new one, or one to "
                            "write into)")
            _writable(path, text, "write into it")
            return text
        parent = _nearest_existing(path)
        if not parent.is_dir():
            raise _fail(f"{text} cannot be made: {parent} is a file, not a folder")
        _writable(parent, text, f"make it in {parent}")
    except OSError as exc:
        raise _fail(f"{text} cannot be used as a folder: {exc.strerror or exc}") from None
    return text


def out_file(text: str) -> str:
    """A file to write (``--gif``, ``--record``): not a folder, in a writable folder."""
    path = _path(text, "the output file")
    try:
        if path.is_dir():
            raise _fail(f"{text} is a folder; give a file name (e.g. {path / 'out'})")
        parent = path.parent if path.parent.exists() else _nearest_existing(path)
        if not parent.is_dir():
            raise _fail(f"{text} cannot be written: {parent} is a file, not a folder")
        _writable(parent, text, f"write it in {parent}")
        if path.exists() and not os.access(path, os.W_OK):
            raise _fail(f"{text} exists and is read-only; give another file name")
    except OSError as exc:
        raise _fail(f"{text} cannot be written: {exc.strerror or exc}") from None
    return text


def _path(text: str, what: str) -> Path:
    if not str(text).strip() or "\0" in text:
        raise _fail(f"{text!r} is not a path; {what} needs one")
    return Path(text).expanduser()


def _nearest_existing(path: Path) -> Path:
    for parent in path.absolute().parents:
        if parent.exists():
            return parent
    return Path(path.absolute().anchor)


def _writable(folder: Path, text: str, doing: str) -> None:
    if not os.access(folder, os.W_OK | os.X_OK):
        raise _fail(f"{text}: cannot {doing} (permission denied or a read-only file system); "
                    "give a folder you can write to")
