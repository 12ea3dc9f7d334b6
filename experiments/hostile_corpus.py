"""Hostile inputs through the command line: exit code, time and address space of each.

Writes the corpus of ``tests/fuzz/corpus.py`` (alias bombs, huge and deep maps, non-UTF-8,
tampered recordings, plan paths that are no files) to a temporary folder and runs every
case with ``tests/fuzz/limited.py`` (one forked child each, 600 MB address space, 20 s).
One JSON line per case goes to ``experiments/results/hostile-input-corpus/outcomes.jsonl``
with the commit and the load average.

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
    from tests.fuzz.corpus import build
    from tests.render.test_replay import record_episode

    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                            capture_output=True, text=True).stdout.strip()
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        rec, _ = record_episode("easy", steps=20, seed=1)
        cases = build(root, rec.save(root / "good.jsonl").read_text().splitlines())
        load_before = os.getloadavg()[0]
        done = subprocess.run([sys.executable, "-m", "tests.fuzz.limited"], cwd=ROOT,
                              input=json.dumps([argv for _, argv in cases]),
                              capture_output=True, text=True, check=True)
        load_after = os.getloadavg()[0]
    OUT.parent.mkdir(parents=True, exist_ok=True)
    with OUT.open("w") as fh:
        for (name, argv), line in zip(cases, done.stdout.splitlines()):
            r = json.loads(line)
            r.pop("argv")
            r["stderr"] = r["stderr"].replace(tmp, "TMP").strip()[:300]
            row = {"case": name, "command": argv[0], **r, "commit": commit,
                   "machine": "2 shared cores", "load_1min": [load_before, load_after]}
            fh.write(json.dumps(row) + "\n")
    print(f"{len(cases)} cases -> {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
