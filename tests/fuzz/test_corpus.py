"""About thirty hand-made hostile files through the real command line, each in a forked
child limited to 600 MB of address space and 20 s: exit 2, one line, no traceback."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from tests.fuzz.corpus import build
from tests.fuzz.limited import SECONDS
from tests.render.test_replay import record_episode

ROOT = Path(__file__).resolve().parents[2]


def run_limited(argvs: list[list[str]]) -> list[dict]:
    out = subprocess.run([sys.executable, "-m", "tests.fuzz.limited"], cwd=ROOT,
                         input=json.dumps(argvs), capture_output=True, text=True,
                         timeout=SECONDS * len(argvs) + 60, check=True)
    return [json.loads(line) for line in out.stdout.splitlines()]


@pytest.fixture(scope="module")
def outcomes(tmp_path_factory) -> dict[str, dict]:
    root = tmp_path_factory.mktemp("hostile")
    rec, _ = record_episode("easy", steps=20, seed=1)
    good = rec.save(root / "good.jsonl").read_text().splitlines()
    cases = build(root, good)
    results = run_limited([argv for _, argv in cases])
    assert len(results) == len(cases)
    return {name: result for (name, _), result in zip(cases, results)}


def test_the_corpus_is_large_enough(outcomes):
    assert len(outcomes) >= 30


def test_every_hostile_input_exits_2_with_one_line_in_time(outcomes):
    bad = {}
    for name, r in outcomes.items():
        err = r["stderr"].strip()
        if (r["code"] != 2 or r["killed"] or r["seconds"] >= SECONDS or "\n" in err
                or "Traceback" in err or not err.startswith("ocplus: error: ")):
            bad[name] = r
    assert not bad, json.dumps(bad, indent=1)[:4000]


def test_a_good_recording_passes_the_same_harness(tmp_path):
    rec, _ = record_episode("easy", steps=20, seed=1)
    path = rec.save(tmp_path / "good.jsonl.gz")
    [result] = run_limited([["replay", str(path), "--check"]])
    assert result["code"] == 0 and not result["stderr"].strip()
