"""Hostile user code and planner binaries (tests/fuzz/processes.py) through the real command
line, each in a forked child limited to 600 MB of address space and 20 s: the expected exit
code, at most one line on stderr, no traceback, the failure recorded as ``error`` rows, and
no process left behind."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import psutil

from tests.fuzz.limited import SECONDS
from tests.fuzz.processes import SLEEP_MARK, build

ROOT = Path(__file__).resolve().parents[2]


def _sleepers() -> list[psutil.Process]:
    found = []
    for p in psutil.process_iter(["cmdline"]):
        try:
            if p.info["cmdline"] == ["sleep", SLEEP_MARK] and p.status() != "zombie":
                found.append(p)
        except psutil.Error:
            continue
    return found


def test_hostile_processes_end_as_documented_and_leave_nothing(tmp_path):
    cases = build(tmp_path)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), str(ROOT)])}
    out = subprocess.run([sys.executable, "-m", "tests.fuzz.limited"], cwd=ROOT, env=env,
                         input=json.dumps([argv for _, argv, _ in cases]), capture_output=True,
                         text=True, timeout=SECONDS * len(cases) + 60, check=True)
    results = [json.loads(line) for line in out.stdout.splitlines()]
    assert len(results) == len(cases)
    bad = {}
    for (name, _, expected), r in zip(cases, results):
        err = r["stderr"].strip()
        if r["code"] != expected or r["killed"] or r["seconds"] >= SECONDS \
                or "\n" in err or "Traceback" in err:
            bad[name] = r
    assert not bad, json.dumps(bad, indent=1)[:4000]
    for case in ("exit", "segv", "loop"):
        rows = [json.loads(x) for x in (tmp_path / f"run_{case}/results.jsonl").open()]
        assert [r["status"] for r in rows] == ["error"], (case, rows)
        assert (tmp_path / f"run_{case}/summary.csv").is_file()
    deadline = time.monotonic() + 5
    while _sleepers() and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not _sleepers()
