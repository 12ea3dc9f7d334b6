"""The reversible name map between PDDL objects and simulator things, and plan steps.

``Names`` turns every object name of a compiled problem back into what it stands
for (an agent index, an item id, a cell, an order id, a content multiset) and the
other way round. ``MappedAction`` is what a plan action means in the simulator: who,
what kind of interaction, which items, standing where, bumping into which cell,
and for how many steps. An executive turns plan steps into simulator actions
without parsing strings.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ..errors import CompileError

Cell_ = tuple[int, int]


@dataclass(frozen=True)
class MappedAction:
    """One plan action in simulator terms.

    ``spot`` is the floor cell the agent stands on while it acts (for a move, the
    cell it walks to); ``place`` is the cell it bumps into (None for a move);
    ``duration`` is the number of simulator steps the action takes when executed
    alone (for a temporal cook: the planned duration); ``bumps`` is how many of
    those steps are bumps into ``place`` (the rest are walking or waiting).
    """

    action: str
    kind: str
    agent: int | None
    items: tuple[int, ...] = ()
    place: Cell_ | None = None
    spot: Cell_ | None = None
    from_spot: Cell_ | None = None
    duration: int = 0
    order: int | None = None
    start: float | None = None
    #: the second agent of a temporal cook envelope (who takes the steak off)
    other_agent: int | None = None
    other_spot: Cell_ | None = None
    #: what the action does to its agent's hand: "take", "release" or "keep"
    #: (:func:`~ocplus_plan.planning.model.hand_change`; a cook envelope keeps it)
    hand: str = "keep"


@dataclass
class Names:
    """Object name <-> simulator thing, both ways."""

    agents: dict[str, int] = field(default_factory=dict)
    items: dict[str, int] = field(default_factory=dict)
    cells: dict[str, Cell_] = field(default_factory=dict)
    orders: dict[str, int] = field(default_factory=dict)
    contents: dict[str, tuple[str, ...]] = field(default_factory=dict)
    kinds: dict[str, str] = field(default_factory=dict)
    layouts: dict[str, int] = field(default_factory=dict)
    _reverse: dict[tuple[str, Any], str] = field(default_factory=dict)

    def add(self, table: str, name: str, value: Any) -> str:
        getattr(self, table)[name] = value
        self._reverse[(table, value)] = name
        return name

    def lookup(self, name: str) -> Any:
        """The simulator value behind an object name (agent index, item id, cell, ...)."""
        for table in (self.agents, self.items, self.cells, self.orders, self.contents, self.kinds,
                      self.layouts):
            if name in table:
                return table[name]
        raise CompileError(f"no object named {name!r} in this compiled problem")

    def name(self, table: str, value: Any) -> str:
        """The object name of ``value`` in ``table`` (agents, items, cells, orders, ...)."""
        try:
            return self._reverse[(table, value)]
        except KeyError:
            raise CompileError(f"{table[:-1]} {value!r} is not an object of this problem") from None

    def agent(self, index: int) -> str:
        return self.name("agents", index)

    def item(self, item_id: int) -> str:
        return self.name("items", item_id)

    def cell(self, rc: Cell_) -> str:
        return self.name("cells", tuple(rc))

    def order(self, order_id: int) -> str:
        return self.name("orders", order_id)
