"""Reading a map file's YAML safely: bounded size, nesting, aliases and nodes.

A map file comes from anywhere, so its YAML is read with limits that a map never
reaches but a hostile file does ("billion laughs" aliases, thousands of nested
brackets, megabytes of rows). Every refusal is a :class:`~ocplus_plan.errors.MapFormatError`
naming the file and the line and column (or key) at fault. The text must be UTF-8; a
byte-order mark is accepted. A key written twice in one mapping is refused.

The limits (see ``docs/input-limits.md``) are module constants:

* ``MAX_MAP_BYTES``: the file's size (a 64x64 map with a switch layout is about 25 kB);
* ``MAX_DEPTH``: nesting of mappings and lists (a map needs 3);
* ``MAX_NODES``: values in the document with every alias expanded (two 64x64 grids are
  about 8,300), so an alias cannot multiply the work or the memory.

This module imports PyYAML at its top: import it only when a file is to be read.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import yaml
from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from ..errors import MapFormatError

if TYPE_CHECKING:
    from importlib.resources.abc import Traversable

#: the largest map file read (bytes)
MAX_MAP_BYTES = 256 * 1024
#: the deepest nesting of lists and mappings
MAX_DEPTH = 16
#: the most values (scalars, lists, mappings) in a document, aliases expanded
MAX_NODES = 50_000
_BOM = "\ufeff"


def _where(mark: Any) -> str:
    return f"line {mark.line + 1}, column {mark.column + 1}" if mark is not None else "?"


class _Refused(Exception):
    """A limit was hit while composing; turned into a MapFormatError with the file name."""


class _BoundedLoader(yaml.SafeLoader):
    """PyYAML's safe loader, with limits checked while the document is composed."""

    def __init__(self, stream: str) -> None:
        super().__init__(stream)
        self._depth = 0
        self._size: dict[int, int] = {}  # id(node) -> its value count, aliases expanded

    def compose_node(self, parent: Node | None, index: Any) -> Node:
        alias = self.check_event(yaml.AliasEvent)
        mark = self.peek_event().start_mark
        self._depth += 1
        if self._depth > MAX_DEPTH:
            raise _Refused(f"{_where(mark)}: nested more than {MAX_DEPTH} levels deep; a map "
                           "needs three (the file, a grid, a row)")
        try:
            node = super().compose_node(parent, index)
        finally:
            self._depth -= 1
        if alias and id(node) not in self._size:
            raise _Refused(f"{_where(mark)}: an alias refers to a list or mapping that "
                           "contains it (a recursive structure)")
        size = self._size.get(id(node), 1) if alias else self._count(node)
        if size > MAX_NODES:
            raise _Refused(f"{_where(mark)}: more than {MAX_NODES} values once the aliases "
                           "(*name) are expanded; write the values out, a map needs far fewer")
        self._size[id(node)] = size
        return node

    def _count(self, node: Node) -> int:
        if isinstance(node, ScalarNode):
            return 1
        if isinstance(node, SequenceNode):
            return 1 + sum(self._size.get(id(n), 1) for n in node.value)
        return 1 + sum(self._size.get(id(k), 1) + self._size.get(id(v), 1)
                       for k, v in node.value)

    def compose_mapping_node(self, anchor: str | None) -> MappingNode:
        node = super().compose_mapping_node(anchor)
        seen: dict[tuple[str, str], Any] = {}
        for key, _value in node.value:
            if isinstance(key, ScalarNode):
                if (key.tag, key.value) in seen:
                    raise _Refused(
                        f"{_where(key.start_mark)}: key {key.value[:40]!r} repeats the one at "
                        f"{_where(seen[key.tag, key.value])}; each key may appear once"
                    )
                seen[key.tag, key.value] = key.start_mark
        return node


def read_bytes(path: Traversable) -> bytes:
    """The file's bytes, refused (without reading them all) beyond ``MAX_MAP_BYTES``."""
    try:
        with path.open("rb") as fh:
            data = fh.read(MAX_MAP_BYTES + 1)
    except OSError as exc:
        raise MapFormatError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    if len(data) > MAX_MAP_BYTES:
        raise MapFormatError(f"{path}: larger than {MAX_MAP_BYTES} bytes; a map file is "
                             "far smaller (grids are at most 64x64)")
    return data


def decode(data: bytes, path: Any) -> str:
    """UTF-8 text (a leading byte-order mark dropped); other bytes name their line."""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        column = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        raise MapFormatError(f"{path}: line {line}, column {column}: byte "
                             f"0x{data[exc.start]:02x} is not UTF-8; save the map as UTF-8 "
                             "text") from None
    return text[1:] if text.startswith(_BOM) else text


def load_yaml(path: Traversable) -> Any:
    """The parsed YAML document of a map file, read within the limits above."""
    text = decode(read_bytes(path), path)
    loader = None
    try:
        loader = _BoundedLoader(text)  # its reader refuses control characters at once
        return loader.get_single_data()
    except _Refused as exc:
        raise MapFormatError(f"{path}: {exc}") from None
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        problem = " ".join(str(exc.problem or exc.context or "malformed YAML").split())[:200]
        what = ("a value of a kind maps do not hold (plain YAML values only)"
                if isinstance(exc, yaml.constructor.ConstructorError) else "YAML syntax error")
        raise MapFormatError(f"{path}: {what} at {_where(mark)}: {problem}") from None
    except yaml.YAMLError as exc:
        raise MapFormatError(f"{path}: not YAML text: {' '.join(str(exc).split())[:200]}") from None
    except (ValueError, OverflowError) as exc:  # a number or date beyond Python's limits
        raise MapFormatError(f"{path}: a value cannot be read: "
                             f"{' '.join(str(exc).split())[:200]}") from None
    finally:
        if loader is not None:
            loader.dispose()


__all__ = ["MAX_DEPTH", "MAX_MAP_BYTES", "MAX_NODES", "decode", "load_yaml", "read_bytes"]
