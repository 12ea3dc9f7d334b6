"""Hostile inputs through the command line: exit code, time and address space of each.

A second group, hostile processes (``tests/fuzz/processes.py``: user code that exits,
crashes or loops at import, and processes left behind in a new session), goes to
``experiments/results/hostile-input-corpus/processes.jsonl``.

The corpus of ``tests/fuzz/corpus.py`` (alias bombs, huge and deep maps, non-UTF-8,
tampered recordings, plan paths that are no files; each expected to exit 2), a legal
64x64 map and the shipped recording (each expected to exit 0), and the data group of
``tests/fuzz/corpus_data.py`` (planted checkpoints, ``--rules`` past the limits, damaged,
forged and locked result files, check-plan limits, small argument cases; each with its
documented exit code, and the planted checkpoints' marker file must not appear) are
written to a temporary folder; the Python API group of ``tests/fuzz/corpus_api.py`` (env
and JAX actions and sizes, a checkpoint header) runs after them, each case raising the
package's own error; every case runs with ``tests/fuzz/limited.py`` (one forked child each, 600 MB of
address space, 20 s). One JSON line per case goes to
``experiments/results/hostile-input-corpus/outcomes.jsonl``, with the commit and the
load average.

    .venv/bin/python experiments/hostile_corpus.py
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "experiments/results/hostile-input-corpus/outcomes.jsonl"


def main() -> None:
    sys.path.insert(0, str(ROOT))
    from ocplus_plan.eval.results import folder_lock
    from tests.fuzz.corpus import build
    from tests.fuzz.corpus_data import LOCKED, MARKER, build_data
    from tests.render.test_replay import record_episode
    from tests.sim.test_maps_limits import square

    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                            capture_output=True, text=True).stdout.strip()
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        rec, _ = record_episode("easy", steps=20, seed=1)
        cases = build(root, rec.save(root / "good.jsonl").read_text().splitlines())
        expected = dict.fromkeys((name for name, _ in cases), 2)
        (root / "legal_64x64.yaml").write_text(square(64))
        shipped = str(ROOT / "docs/figures/hard_greedy.jsonl.gz")
        for name, argv in (("legal_64x64.yaml", ["check-map", str(root / "legal_64x64.yaml")]),
                           ("shipped_recording", ["replay", shipped, "--check"])):
            cases.append((name, argv))
            expected[name] = 0
        group = dict.fromkeys(expected, "files")
        data = root / "data"
        data.mkdir()
        for case in build_data(data):
            cases.append((case.name, case.argv))
            expected[case.name], group[case.name] = case.expected, "data"
        load_before = os.getloadavg()[0]
        with folder_lock(data / LOCKED):  # another run holds this folder
            done = subprocess.run([sys.executable, "-m", "tests.fuzz.limited"], cwd=ROOT,
                                  input=json.dumps([argv for _, argv in cases]),
                                  capture_output=True, text=True, check=True)
        load_after = os.getloadavg()[0]
        planted_ran = (data / MARKER).exists()
    OUT.parent.mkdir(parents=True, exist_ok=True)
    with OUT.open("w") as fh:
        for (name, argv), line in zip(cases, done.stdout.splitlines()):
            r = json.loads(line)
            r.pop("argv")
            err = r["stderr"].strip()
            one_line = "\n" not in err and "Traceback" not in err
            r["stderr"] = err.replace(tmp, "TMP")[:300]
            row = {"case": name, "group": group[name], "command": argv[0],
                   "expected": expected[name], "one_line": one_line, **r,
                   **({"planted_checkpoint_ran": planted_ran} if group[name] == "data" else {}),
                   "commit": commit,
                   "machine": "2 shared cores", "load_1min": [load_before, load_after]}
            fh.write(json.dumps(row) + "\n")
        api = subprocess.run([sys.executable, "-m", "tests.fuzz.corpus_api"], cwd=ROOT,
                             capture_output=True, text=True, check=True)
        load_end = os.getloadavg()[0]
        for line in api.stdout.splitlines():  # the Python API group
            r = json.loads(line)
            r["one_line"] = "\n" not in r["message"]
            fh.write(json.dumps({"group": "api", "expected": "the package's own error", **r,
                                 "commit": commit, "machine": "2 shared cores",
                                 "load_1min": [load_after, load_end]}) + "\n")
    _process_cases(commit)
    print(f"{len(cases)} command-line cases and {len(api.stdout.splitlines())} API cases -> "
          f"{OUT.relative_to(ROOT)}")
    every = [json.loads(x) for x in OUT.read_text().splitlines()]
    rows = [r for r in every if r["group"] != "api"]
    api_rows = [r for r in every if r["group"] == "api"]
    print(f"planted checkpoint code ran: {planted_ran}")
    print(f"as expected: {sum(r['code'] == r['expected'] for r in rows)}/{len(rows)}; "
          f"one line, no traceback: {sum(r['one_line'] for r in rows)}/{len(rows)}; "
          f"slowest {max(r['seconds'] for r in rows):.2f} s wall, "
          f"{max(r['cpu_seconds'] for r in rows):.2f} s CPU; "
          f"largest address space {max(r['vm_peak_mb'] for r in rows):.0f} MB")
    for name in ("files", "data"):
        part = [r for r in rows if r["group"] == name]
        print(f"  {name}: {sum(r['code'] == r['expected'] and r['one_line'] for r in part)}"
              f"/{len(part)} as expected in one line; slowest "
              f"{max(r['seconds'] for r in part):.2f} s wall, "
              f"{max(r['cpu_seconds'] for r in part):.2f} s CPU, "
              f"{max(r['vm_peak_mb'] for r in part):.0f} MB")
    limited = [r for r in api_rows if r["address_space_limited"]]
    print(f"  api: {sum(r['package_error'] and r['one_line'] for r in api_rows)}/"
          f"{len(api_rows)} raise the package's error in one line; slowest "
          f"{max(r['seconds'] for r in api_rows):.2f} s wall; largest address space "
          f"{max(r['vm_peak_mb'] for r in limited):.0f} MB under the limit, "
          f"{max(r['vm_peak_mb'] for r in api_rows):.0f} MB (RSS "
          f"{max(r['max_rss_mb'] for r in api_rows):.0f} MB) for the JAX cases, run without it")


# ---------------------------------------------------------------- hostile processes
PROCESS_OUT = ROOT / "experiments/results/hostile-input-corpus/processes.jsonl"


def _process_cases(commit: str) -> None:
    """The group of ``tests/fuzz/processes.py`` (user code that exits, crashes or loops at
    import; processes left in a new session), with its modules on PYTHONPATH; one JSON
    line per case to ``PROCESS_OUT``, with the sleepers left 5 s after the last case."""
    import time

    import psutil

    from tests.fuzz.processes import SLEEP_MARK, build

    with tempfile.TemporaryDirectory() as tmp:
        cases = build(Path(tmp))
        env = {**os.environ, "PYTHONPATH": os.pathsep.join([tmp, str(ROOT)])}
        load_before = os.getloadavg()[0]
        done = subprocess.run([sys.executable, "-m", "tests.fuzz.limited"], cwd=ROOT, env=env,
                              input=json.dumps([argv for _, argv, _ in cases]),
                              capture_output=True, text=True, check=True)
        time.sleep(5)
        left = [p.pid for p in psutil.process_iter(["cmdline"])
                if p.info["cmdline"] == ["sleep", SLEEP_MARK]]
        load_after = os.getloadavg()[0]
        with PROCESS_OUT.open("w") as fh:
            for (name, argv, expected), line in zip(cases, done.stdout.splitlines()):
                r = json.loads(line)
                r.pop("argv")
                r["stderr"] = r["stderr"].replace(tmp, "TMP").strip()[:300]
                fh.write(json.dumps({"case": name, "command": argv[0], "expected": expected,
                                     **r, "sleepers_left_after_5s": len(left),
                                     "commit": commit, "machine": "2 shared cores",
                                     "load_1min": [load_before, load_after]}) + "\n")
    rows = [json.loads(x) for x in PROCESS_OUT.read_text().splitlines()]
    print(f"processes: as expected {sum(r['code'] == r['expected'] for r in rows)}/{len(rows)}"
          f"; slowest {max(r['seconds'] for r in rows):.2f} s wall; sleepers left after 5 s: "
          f"{len(left)} -> {PROCESS_OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
