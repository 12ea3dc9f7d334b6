"""The second group of the hostile corpus (tests/fuzz/corpus_data.py: checkpoints, --rules,
result files, check-plan, small argument cases) through the real command line, each in a
forked child limited to 600 MB of address space and 20 s: the documented exit code, at
most one line on stderr, no traceback; and no planted checkpoint ever runs its code."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.fuzz.corpus_data import LOCKED, MARKER, build_data
from tests.fuzz.limited import SECONDS
from tests.fuzz.test_corpus import run_limited


def run_cases(root: Path) -> list[tuple[object, dict]]:
    from ocplus_plan.eval.results import folder_lock

    cases = build_data(root)
    with folder_lock(root / LOCKED):  # another run holds this folder
        results = run_limited([case.argv for case in cases])
    assert len(results) == len(cases)
    return list(zip(cases, results))


@pytest.fixture(scope="module")
def outcomes(tmp_path_factory) -> tuple[Path, list]:
    root = tmp_path_factory.mktemp("hostile-data")
    return root, run_cases(root)


def test_every_case_ends_as_documented_in_one_line(outcomes):
    _, pairs = outcomes
    bad = {}
    for case, r in pairs:
        err = r["stderr"].strip()
        one_line = "\n" not in err and "Traceback" not in err
        said = err.startswith("ocplus") if case.expected == 2 else True
        if r["code"] != case.expected or r["killed"] or r["seconds"] >= SECONDS \
                or not one_line or not said:
            bad[case.name] = r
    assert not bad, json.dumps(bad, indent=1)[:4000]


def test_no_planted_checkpoint_ran(outcomes):
    root, pairs = outcomes
    assert not (root / MARKER).exists()
    assert any(case.name.startswith("ppo_planted") for case, _ in pairs)


def test_resumed_folders_hold_only_trusted_rows(outcomes):
    from ocplus_plan.eval.results import scan_results

    root, _ = outcomes
    torn = scan_results(root / "torn")
    assert sorted(r["seed"] for r in torn.rows) == [0, 1] and torn.bad == []
    forged = scan_results(root / "forged")
    assert [r["horizon"] for r in forged.rows] == [5]  # rerun; the forged row not trusted
