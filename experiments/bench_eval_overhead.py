"""CPU seconds of small ``ocplus eval`` sweeps with ``--jobs 1``: what running every
episode in a child process costs.

Each sweep runs as its own ``ocplus`` process ``--repeats`` times; the CPU seconds
(user + system of the command and everything it started, from ``getrusage``) and the
wall seconds of each run are printed as one JSON line per sweep, with the commit, the
machine and the load average. Compare two commits by running it on each, in one
sitting.

    nice -n 10 .venv/bin/python experiments/bench_eval_overhead.py --repeats 3
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OCPLUS = [sys.executable, "-m", "ocplus_plan.cli"]
SWEEPS = {
    "greedy+random easy,medium x10 seeds": ["eval", "--presets", "easy,medium", "--agents",
                                           "greedy,random", "--seeds", "10", "--jobs", "1",
                                           "--quiet"],
    "planner:fast-downward easy x2 seeds": ["eval", "--presets", "easy", "--agents",
                                            "planner:fast-downward", "--seeds", "2",
                                            "--horizon", "100", "--jobs", "1", "--quiet"],
}


def run_once(argv: list[str], code: Path) -> tuple[float, float]:
    """(CPU seconds, wall seconds) of one command (the package under ``code``), children
    included."""
    env = {**os.environ, "PYTHONPATH": str(code)}
    with tempfile.TemporaryDirectory() as tmp:
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        subprocess.run([*OCPLUS, *argv, "--out", str(Path(tmp) / "run")], cwd=tmp,
                       check=True, stdout=subprocess.DEVNULL, env=env)
        wall = time.perf_counter() - t0
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--code", type=Path, default=ROOT,
                        help="a checkout whose package to run (e.g. `git archive` of a base "
                             "commit unpacked in /tmp); default: this one")
    args = parser.parse_args()
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=args.code,
                            capture_output=True, text=True).stdout.strip() or str(args.code)
    for name, argv in SWEEPS.items():
        load = os.getloadavg()[0]
        runs = [run_once(argv, args.code.resolve()) for _ in range(args.repeats)]
        cpus = sorted(c for c, _ in runs)
        print(json.dumps({"sweep": name, "command": "ocplus " + " ".join(argv),
                          "cpu_s": [round(c, 2) for c, _ in runs],
                          "cpu_s_median": round(cpus[len(cpus) // 2], 2),
                          "wall_s": [round(w, 2) for _, w in runs], "commit": commit,
                          "machine": f"{platform.machine()}, 2 shared cores",
                          "load_1min": [round(load, 2), round(os.getloadavg()[0], 2)]}))


if __name__ == "__main__":
    main()
