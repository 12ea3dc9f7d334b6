"""The kitchen loader: any name a kitchen goes by, one floor above the map parser.

``load_kitchen`` takes a ``gen:`` name (a generated kitchen, :mod:`.generate`), a
registered map name (``"mapC"``), a path to a map file or a map dict, and returns the
:class:`.maps.Layout`. The map parser (:mod:`.maps`) knows files and dicts only, so the
generator, which builds map dicts and checks them, sits beside it rather than under it.
"""

from __future__ import annotations

import os
from typing import Any

from .maps import Layout, load_map

#: the prefix of a generated kitchen's name: ``gen:FAMILY:SPLIT:INDEX[:PRESET]``
GEN_PREFIX = "gen:"


def load_kitchen(spec: str | os.PathLike[str] | dict[str, Any] | Layout, *,
                 source: str | None = None) -> Layout:
    """The layout of a ``gen:`` name, a registered map name, a path or a map dict."""
    if isinstance(spec, Layout):
        return spec
    if isinstance(spec, str) and spec.startswith(GEN_PREFIX):
        from .generate import map_from_name  # the generator loads only for a gen: name

        return load_map(map_from_name(spec), source=source or spec)
    return load_map(spec, source=source)


__all__ = ["GEN_PREFIX", "load_kitchen"]
