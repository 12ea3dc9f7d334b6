"""A planner binary for the league's tests (tests/eval/test_league.py), one run per MODE.

Usage: ``league_planner.py MODE DOMAIN PROBLEM PLAN [FILE]``:

* ``copy``: writes the text of FILE as its plan (valid or not);
* ``none``: exits 0 without a plan (its claim that there is none);
* ``spin``: computes until its CPU limit stops it;
* ``sleep``: waits without computing until the wall-clock safety stops it;
* ``crash``: dies of a segmentation fault;
* ``memory``: allocates memory until its memory limit stops it.
"""

from __future__ import annotations

import os
import signal
import sys
import time
from pathlib import Path


def main() -> int:
    mode, _domain, problem, plan = sys.argv[1:5]
    Path(problem).read_text(encoding="utf-8")
    if mode == "copy":
        Path(plan).write_text(Path(sys.argv[5]).read_text(encoding="utf-8"), encoding="utf-8")
    elif mode == "spin":
        while True:
            pass
    elif mode == "sleep":
        time.sleep(600)
    elif mode == "crash":
        os.kill(os.getpid(), signal.SIGSEGV)
    elif mode == "memory":
        hoard = []
        while True:
            hoard.append(bytearray(64 * 1024 * 1024))
    return 0


if __name__ == "__main__":
    sys.exit(main())
