"""Hostile command lines against ``ocplus``: exit code, stderr lines, wall time and peak
memory of each, one JSON line per case.

Each case runs as its own process (``PYTHON -m ocplus_plan.cli ...``) in a fresh temporary
folder, under an address-space limit (``--max-mb``, default 600 MB) and a wall limit
(``--wall``, default 20 s); a case that runs past the wall limit is killed and recorded as
``"timed_out": true``. ``--python`` picks the interpreter, and so the checkout it imports
(compare two checkouts by running the script with each one's venv).

    .venv/bin/python experiments/cli_hostile_arguments.py \\
        --out experiments/results/cli-hostile-arguments/checked.jsonl
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

#: the argument cases of the hostile-input report, and a few more of the same kinds
#: the argument cases of the hostile-input report, and a few more of the same kinds; the
#: commands that once required --out get one, so that the bad value itself is reached
_EVAL = ["eval", "--agents", "random", "--horizon", "5", "--preset", "easy", "--out", "run"]
CASES: list[list[str]] = [
    ["rollout", "--seed", "-1"],
    [*_EVAL, "--seed", "-1"],
    ["solve", "--seed", "-1"],
    ["pddl", "--seed", "-1"],
    ["export-suite", "--seed", "-1", "--presets", "easy", "--out", "run"],
    [*_EVAL, "--seeds", "0-10000000000"],
    [*_EVAL, "--seeds", "0-20000000"],
    [*_EVAL, "--seeds", "5-2"],
    [*_EVAL, "--seeds", "1", "--episode-timeout", "-1"],
    [*_EVAL, "--seeds", "1", "--episode-timeout", "nan"],
    [*_EVAL, "--seeds", "1", "--episode-timeout", "inf"],
    ["rollout", "--horizon", str(10**18)],
    ["rollout", "--steps", str(10**18)],
    ["eval", "--agents", "random", "--horizon", "5", "--preset", "easy", "--seeds", "1",
     "--out", "a-file"],
    ["eval", "--agents", "random", "--horizon", "5", "--preset", "easy", "--seeds", "1",
     "--out", "a-file/run"],
    ["train", "--out", "a-file", "--steps", "10"],
    ["export-suite", "--out", "a-file", "--presets", "easy"],
    ["pddl", "--out", "a-file/x"],
    [*_EVAL, "--seeds", "1", "--jobs", "0"],
    [*_EVAL, "--seeds", "1", "--jobs", "-1"],
    ["rollout", "--n-agents", "0"],
    ["solve", "--timeout", "nan"],
    ["solve", "--step", "-1"],
    ["export-suite", "--timeout", "-1", "--presets", "easy", "--out", "run"],
    ["replay", "x.jsonl", "--every", "0"],
    ["play", "--fps", "0"],
]


def _limit(max_bytes: int):
    def apply() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (max_bytes, max_bytes))
        os.setsid()
    return apply


def run_case(python: str, argv: list[str], *, max_mb: int, wall: float) -> dict:
    folder = Path(tempfile.mkdtemp(prefix="ocplus-hostile-"))
    (folder / "a-file").write_text("not a folder\n")
    t0 = time.perf_counter()
    proc = subprocess.Popen([python, "-m", "ocplus_plan.cli", *argv], cwd=folder,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            preexec_fn=_limit(max_mb * 2**20))
    chunks: list[bytes] = []
    reader = threading.Thread(target=lambda: chunks.append(proc.stderr.read()), daemon=True)
    reader.start()
    timed_out, status, usage = False, 0, None
    while usage is None:
        pid, status, rusage = os.wait4(proc.pid, os.WNOHANG)
        if pid:
            usage = rusage
        elif time.perf_counter() - t0 > wall and not timed_out:
            timed_out = True
            os.killpg(proc.pid, 9)
        else:
            time.sleep(0.02)
    seconds = time.perf_counter() - t0
    reader.join()
    proc.returncode = os.waitstatus_to_exitcode(status)
    err = b"".join(chunks)
    shutil.rmtree(folder, ignore_errors=True)
    text = err.decode(errors="replace").strip()
    lines = text.splitlines()
    return {"argv": argv, "exit": proc.returncode, "timed_out": timed_out,
            "stderr_lines": len(lines), "traceback": "Traceback" in text,
            "first_line": lines[0][:200] if lines else "", "last_line": lines[-1][:200] if lines
            else "", "wall_s": round(seconds, 2),
            "max_rss_mb": round(usage.ru_maxrss / 1024, 1)}


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--python", default=sys.executable,
                   help="interpreter whose ocplus_plan is tried (default: this one)")
    p.add_argument("--max-mb", type=int, default=600, help="address-space limit per case")
    p.add_argument("--wall", type=float, default=20.0, help="seconds before a case is killed")
    p.add_argument("--out", default=None, help="also write the JSON lines to this file")
    args = p.parse_args(argv)
    rows = []
    print(json.dumps({"python": args.python, "load_1min_at_start": os.getloadavg()[0]}))
    for case in CASES:
        row = run_case(args.python, case, max_mb=args.max_mb, wall=args.wall)
        rows.append(row)
        print(json.dumps(row), flush=True)
    good = sum(r["exit"] == 2 and r["stderr_lines"] == 1 and not r["timed_out"] for r in rows)
    summary = {"summary": True, "cases": len(rows), "exit_2_with_one_line": good,
               "tracebacks": sum(r["traceback"] for r in rows),
               "timed_out": sum(r["timed_out"] for r in rows),
               "max_wall_s": max(r["wall_s"] for r in rows),
               "max_rss_mb": max(r["max_rss_mb"] for r in rows), "max_mb": args.max_mb,
               "wall_limit_s": args.wall, "load_1min_at_end": os.getloadavg()[0]}
    print(json.dumps(summary), flush=True)
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text("".join(json.dumps(r) + "\n" for r in [*rows, summary]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
