"""A set's JSON files read as untrusted data: within a size and a nesting limit."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

#: an instance's manifest.json or state.json (a hard kitchen's state is about 10 kB)
MAX_INSTANCE_JSON_BYTES = 4_000_000
#: lists and objects inside one another (an instance's files need 5)
MAX_JSON_DEPTH = 32


def read_json(path: Path, limit: int = MAX_INSTANCE_JSON_BYTES,
              depth: int = MAX_JSON_DEPTH) -> Any:
    """A JSON file of an instance, read within a size and a nesting limit (``ValueError``
    naming the file otherwise): nothing past ``limit`` bytes is read, and the nesting is
    measured before the text is parsed, so a file nested 100,000 deep is refused, not a
    ``RecursionError``."""
    with open(path, "rb") as fh:
        data = fh.read(limit + 1)
    if len(data) > limit:
        raise ValueError(f"{path.name} is over {limit} bytes")
    text = data.decode("utf-8")
    deepest = _nesting(text)
    if deepest > depth:
        raise ValueError(f"{path.name} is nested {deepest} deep; the limit is {depth}")
    return json.loads(text)


_BRACKETS = re.compile(r'"(?:[^"\\]|\\.)*"|[\[\]{}]')


def _nesting(text: str) -> int:
    """The deepest nesting of lists and objects in JSON text (strings skipped)."""
    level = deepest = 0
    for m in _BRACKETS.finditer(text):
        c = m.group()
        if c in "[{":
            level += 1
            deepest = max(deepest, level)
        elif c in "]}":
            level -= 1
    return deepest


__all__ = ["MAX_INSTANCE_JSON_BYTES", "MAX_JSON_DEPTH", "read_json"]
