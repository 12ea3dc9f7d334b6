"""One exception tree for everything a user can get wrong.

Outcomes (a planner timing out, an unsolvable problem) are data, not exceptions;
these are for bad input, and every message says what is wrong and how to fix it.
"""

from __future__ import annotations


class OcplusError(Exception):
    """Base class of every error this package raises on purpose."""


class MapFormatError(OcplusError):
    """A map file (or dict) is malformed: the message names the file, row, column and value."""


class ConfigError(OcplusError):
    """A preset, parameter or combination of them is invalid or impossible."""


class InvalidActionError(OcplusError):
    """An action (or joint action) is out of range or of the wrong shape."""


class CompileError(OcplusError):
    """A simulator state cannot be compiled into a planning problem."""


class PlannerError(OcplusError):
    """A planner name is unknown or a planner is misconfigured (not: it failed to find a plan)."""


class DependencyNotInstalled(OcplusError):
    """An optional dependency is missing; the message names the extra to install."""


class DisplayUnavailable(OcplusError):
    """A window was asked for where none can be shown (no display); the message names the
    headless alternative (``--gif``, ``--check``, ``render_mode='rgb_array'``)."""


class UnreadableText(OcplusError):
    """Text from outside the package (a language model's reply, a plan file) cannot be read.

    It is parsed, never evaluated; the message names the line (``line``, 1-based; 0 when the
    text as a whole is refused, e.g. too long) and says what was expected there."""

    def __init__(self, message: str, line: int = 0) -> None:
        super().__init__(message)
        self.line = line
