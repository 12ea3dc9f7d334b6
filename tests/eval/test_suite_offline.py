"""Rebuilding chosen instances of a set in place, and reference plans found offline
(``eval/suite_offline``): bound to their problem, validated, judged, never trusted.
Each set is one or two easy instances solved in about a second."""

from __future__ import annotations

import json
import shutil
import warnings
from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.errors import ConfigError
from ocplus_plan.eval.suite import Cell, SuiteSpec, export_suite
from ocplus_plan.eval.suite_offline import FORMAT, problem_digest
from ocplus_plan.planning.engines import availability

warnings.simplefilter("ignore", UserWarning)
LAMA = {"classical": ("fast-downward",)}


@pytest.fixture(autouse=True)
def _lama():
    if not availability("fast-downward").ok:
        pytest.skip("fast-downward unavailable")


def _files(root: Path) -> dict[str, bytes]:
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*"))
            if p.is_file()}


def _spec(**kw) -> SuiteSpec:
    return SuiteSpec(encodings=("classical",), planners=LAMA, timeout=20, fallback=False,
                     witness_timeout=0, **kw)


def test_rebuilding_chosen_cells_in_place_gives_the_whole_builds_bytes(tmp_path):
    spec = _spec(cells=(Cell("easy", None, 1, 1, 0), Cell("easy", None, 1, 1, 1)))
    export_suite(spec, tmp_path / "whole")
    again = tmp_path / "again"
    shutil.copytree(tmp_path / "whole", again)
    shutil.rmtree(again / "p02")
    (again / "p07").mkdir()  # an instance the set no longer has
    (again / "maps").mkdir()
    (again / "maps" / "old.yaml").write_text("name: old\n")  # a kitchen no cell uses
    export_suite(spec, again, select={1})
    assert _files(again) == _files(tmp_path / "whole")
    shutil.rmtree(again / "p01")
    with pytest.raises(ConfigError, match="lacks p01"):
        export_suite(spec, again, select={1})
    with pytest.raises(ConfigError, match="not empty"):
        export_suite(spec, tmp_path / "whole")


def _offline(folder: Path, problem_text: str, plan_text: str) -> Path:
    folder.mkdir()
    (folder / "p01.plan").write_text(plan_text)
    (folder / "refs.json").write_text(json.dumps({"format": FORMAT, "instances": {"p01": {
        "planner": "lama-offline", "engine": "fast-downward", "plan": "p01.plan",
        "problem_sha256": problem_digest(problem_text)}}}))
    return folder


def test_an_offline_plan_is_validated_judged_and_ranked_after_the_planners(tmp_path):
    cells = (Cell("easy", None, 1, 1, 0),)
    export_suite(_spec(cells=cells), tmp_path / "a")
    problem = (tmp_path / "a" / "p01" / "classical.pddl").read_text()
    plan = (tmp_path / "a" / "p01" / "classical.plan").read_text()
    refs = _offline(tmp_path / "refs", problem, plan)
    spec = _spec(cells=cells, offline_plans=(("classical", str(refs)),))
    export_suite(spec, tmp_path / "b")
    top = json.loads((tmp_path / "b" / "manifest.json").read_text())
    assert top["arguments"]["offline_plans"] == {"classical": str(refs)}
    ref = json.loads((tmp_path / "b" / "p01" / "manifest.json").read_text())[
        "encodings"]["classical"]["reference"]
    offline = ref["portfolio"]["offline:lama-offline"]
    assert offline["status"] == "solved" and offline["faithful"] is True
    assert offline["value"] == ref["portfolio"]["fast-downward"]["value"]
    assert ref["planner"] == "fast-downward"  # a tie goes to the planner run first


def test_a_broken_offline_plan_is_not_a_reference_and_a_stale_one_is_refused(tmp_path):
    cells = (Cell("easy", None, 1, 1, 0),)
    export_suite(_spec(cells=cells), tmp_path / "a")
    problem = (tmp_path / "a" / "p01" / "classical.pddl").read_text()
    plan = (tmp_path / "a" / "p01" / "classical.plan").read_text().splitlines()
    steps = [line for line in plan if line.strip() and not line.startswith(";")]
    short = _offline(tmp_path / "short", problem, "\n".join(steps[:-1]) + "\n")
    export_suite(_spec(cells=cells, offline_plans=(("classical", str(short)),)),
                 tmp_path / "b")
    ref = json.loads((tmp_path / "b" / "p01" / "manifest.json").read_text())[
        "encodings"]["classical"]["reference"]
    assert ref["portfolio"]["offline:lama-offline"]["status"] == "not validated"
    assert ref["planner"] == "fast-downward"
    stale = _offline(tmp_path / "stale", problem + " ", "\n".join(steps) + "\n")
    with pytest.raises(ConfigError, match="another problem text"):
        export_suite(_spec(cells=cells, offline_plans=(("classical", str(stale)),)),
                     tmp_path / "c")
