"""A progress bar: tqdm when it is installed, else a small built-in one on stderr."""

from __future__ import annotations

import sys
import time
from typing import Any, TextIO


class SimpleBar:
    """``[#####.....] 12/40 eta 0:31 last: greedy easy s3`` redrawn in place on a terminal,
    one line per 10% otherwise (logs stay short)."""

    def __init__(self, total: int, desc: str = "", stream: TextIO | None = None,
                 disable: bool = False) -> None:
        self.total, self.n, self.desc = total, 0, desc
        self.stream = stream or sys.stderr
        self.disable = disable
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.start = time.monotonic()
        self.postfix = ""
        self._last_decile = -1

    def set_postfix_str(self, text: str) -> None:
        self.postfix = text

    def update(self, n: int = 1) -> None:
        self.n += n
        self._draw()

    def _draw(self) -> None:
        if self.disable or self.total <= 0:
            return
        frac = min(1.0, self.n / self.total)
        elapsed = time.monotonic() - self.start
        eta = elapsed / self.n * (self.total - self.n) if self.n else 0.0
        bar = "#" * int(frac * 24) + "." * (24 - int(frac * 24))
        line = (f"{self.desc} [{bar}] {self.n}/{self.total} "
                f"{int(elapsed)}s eta {int(eta)}s {self.postfix}")
        if self.tty:
            self.stream.write("\r" + line[:119].ljust(119))
            self.stream.flush()
        elif int(frac * 10) != self._last_decile:
            self._last_decile = int(frac * 10)
            self.stream.write(line + "\n")
            self.stream.flush()

    def close(self) -> None:
        if not self.disable and self.tty:
            self.stream.write("\n")
            self.stream.flush()


def progress_bar(total: int, desc: str = "eval", disable: bool = False) -> Any:
    """A tqdm bar if tqdm is importable, else :class:`SimpleBar` (same small API:
    ``update``, ``set_postfix_str``, ``close``)."""
    try:
        from tqdm import tqdm  # optional; never required
    except ImportError:
        return SimpleBar(total, desc, disable=disable)
    return tqdm(total=total, desc=desc, disable=disable, unit="ep", dynamic_ncols=True)


__all__ = ["SimpleBar", "progress_bar"]
