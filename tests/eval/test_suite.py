"""export-suite and check-plan on one small set (easy, 1 and 2 cooks, one state each).

The set is written once per module (two planner calls per encoding: a few seconds) and
once more for the byte-for-byte comparison.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.cli import main
from ocplus_plan.errors import ConfigError
from ocplus_plan.eval.suite import SuiteSpec, export_suite, load_instance
from ocplus_plan.planning.engines import availability

warnings.simplefilter("ignore", UserWarning)
PLANNERS = {"classical": ("fast-downward-wastar",), "temporal": ("kairos",)}
SPEC = SuiteSpec(presets=("easy",), cooks=(1, 2), states=1, encodings=("classical", "temporal"),
                 timeout=20, planners=PLANNERS)


def _require_planners() -> None:
    for names in PLANNERS.values():
        for name in names:
            if not availability(name).ok:
                pytest.skip(f"{name} unavailable: {availability(name).reason}")


@pytest.fixture(scope="module")
def suite(tmp_path_factory) -> Path:
    _require_planners()
    out = tmp_path_factory.mktemp("suite") / "set"
    export_suite(SPEC, out)
    return out


def _files(root: Path) -> dict[str, bytes]:
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*"))
            if p.is_file()}


def test_same_arguments_same_bytes(suite, tmp_path):
    again = tmp_path / "again"
    export_suite(SPEC, again)
    assert _files(again) == _files(suite)


def test_the_set_holds_domains_problems_texts_plans_and_manifests(suite):
    files = set(_files(suite))
    for enc in ("classical", "temporal"):
        assert {f"{enc}/domain.pddl", f"{enc}/domain.txt"} <= files
        for name in ("p01", "p02"):
            assert {f"{name}/{enc}.pddl", f"{name}/{enc}.txt", f"{name}/{enc}.plan"} <= files
    top = json.loads((suite / "manifest.json").read_text())
    assert top["instances"] == ["p01", "p02"] and top["arguments"]["cooks"] == [1, 2]
    assert "(define (domain" in (suite / "temporal/domain.pddl").read_text()
    assert "Actions:" in (suite / "classical/domain.txt").read_text()


def test_an_instance_manifest_says_where_the_state_comes_from_and_how_good_plans_can_be(suite):
    m = json.loads((suite / "p02/manifest.json").read_text())
    assert (m["preset"], m["n_agents"], m["seed"], m["sample"]) == ("easy", 2, 0, 0)
    assert m["step"] > 0 and "random joint actions" in m["reached"]
    assert [o["id"] for o in m["orders"]] == m["goal_orders"]
    ref = m["encodings"]["classical"]["reference"]
    assert ref["planner"] == "fast-downward-wastar" and ref["engine"] == "fast-downward"
    assert ref["cost"] >= m["bound"]["cost"] > 0
    assert "Plan valid" in ref["validated"]
    temporal = m["encodings"]["temporal"]["reference"]
    assert temporal["planner"] == "kairos" and temporal["makespan"] >= m["bound"]["makespan"]
    assert load_instance(suite / "p02").state.t == m["step"]
    text = (suite / "p02/classical.txt").read_text()
    assert "cook 1" in text and "Goal:" in text


def test_a_faithful_reference_plan_checks_valid(suite, capsys):
    assert main(["check-plan", str(suite / "p01"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["verdict"] == "valid" and out["replayed"] and out["served"]
    assert main(["check-plan", str(suite / "p01"), "--encoding", "temporal"]) == 0


def test_a_plan_walking_a_cook_through_another_is_realised_with_waits(suite, capsys):
    # wastar's plan for two cooks walks cook 0 past the cell cook 1 stands on: the model
    # ignores cooks on the way, the strict replay detours; the judge (the manifest's, the
    # league's) lets cook 1 step aside and the kitchen reaches the goal
    ref = json.loads((suite / "p02/manifest.json").read_text())["encodings"]["classical"]
    assert ref["reference"]["faithful"] is True and ref["reference"]["waits"] > 0
    assert main(["check-plan", str(suite / "p02"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["verdict"] == "valid" and out["realised"].startswith("realised, the kitchen")
    assert out["divergence"].startswith("at plan step ") and "cook 0 walks from the floor at" \
        in out["divergence"]


def test_a_plan_missing_a_step_is_invalid(suite, tmp_path, capsys):
    lines = (suite / "p01/classical.plan").read_text().splitlines()
    bad = tmp_path / "bad.plan"
    bad.write_text("\n".join(lines[:4] + lines[5:]) + "\n")
    assert main(["check-plan", str(suite / "p01"), "--plan", str(bad), "--json"]) == 4
    out = json.loads(capsys.readouterr().out)
    assert out["verdict"] == "invalid" and "INVALID" in out["validation"]


def test_a_garbage_plan_is_invalid_and_names_the_line(suite, tmp_path, capsys):
    bad = tmp_path / "garbage.plan"
    first = (suite / "p01/classical.plan").read_text().splitlines()[1]  # after the comment
    bad.write_text(f"{first}\n{{'__import__': 'os'}}\n")
    assert main(["check-plan", str(suite / "p01"), "--plan", str(bad), "--json"]) == 4
    out = json.loads(capsys.readouterr().out)
    assert "garbage.plan, line 2: " in out["error"] and "is not a plan step" in out["error"]


def test_domain_problem_and_plan_files_are_validated_without_a_replay(suite, capsys):
    args = ["check-plan", "--domain", str(suite / "temporal/domain.pddl"), "--problem",
            str(suite / "p01/temporal.pddl"), "--plan", str(suite / "p01/temporal.plan"), "--json"]
    assert main(args) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["verdict"] == "valid" and out["replayed"] is False and out["makespan"] > 0


def test_an_edited_problem_is_refused(suite, tmp_path, capsys):
    import shutil

    copy = tmp_path / "set"
    shutil.copytree(suite, copy)
    problem = copy / "p01/classical.pddl"
    problem.write_text(problem.read_text().replace("(free ", "(vacant ", 1))
    assert main(["check-plan", str(copy / "p01")]) == 2
    assert "does not match" in capsys.readouterr().err


def test_a_folder_that_is_no_instance_is_refused(suite, tmp_path):
    with pytest.raises(ConfigError, match="no manifest.json"):
        load_instance(tmp_path)
    with pytest.raises(ConfigError, match="a whole set"):
        load_instance(suite)


def test_a_set_is_never_written_over_another(suite):
    with pytest.raises(ConfigError, match="not empty"):
        export_suite(SPEC, suite)


def test_a_bad_plan_path_for_an_instance_is_bad_input(suite, tmp_path, capsys):
    assert main(["check-plan", str(suite / "p01"), "--plan", str(tmp_path)]) == 2
    assert "is a directory" in capsys.readouterr().err


@pytest.mark.parametrize("encoding", ["classical", "temporal"])
def test_a_bom_and_crlf_plan_is_the_same_plan(suite, tmp_path, capsys, encoding):
    text = (suite / f"p01/{encoding}.plan").read_text()
    windows = tmp_path / "windows.plan"
    windows.write_bytes(b"\xef\xbb\xbf" + text.replace("\n", "\r\n").encode())
    assert main(["check-plan", str(suite / "p01"), "--encoding", encoding,
                 "--plan", str(windows), "--json"]) == 0
    assert '"verdict": "valid"' in capsys.readouterr().out


def test_a_readable_file_that_is_no_plan_still_exits_4(suite, tmp_path):
    not_a_plan = tmp_path / "bad.plan"
    not_a_plan.write_text("(fly a0 to the moon)\n")
    assert main(["check-plan", str(suite / "p01"), "--plan", str(not_a_plan)]) == 4


def test_a_missing_reference_plan_is_a_damaged_set_not_an_invalid_plan(suite, tmp_path, capsys):
    import shutil

    copy = tmp_path / "set"
    shutil.copytree(suite, copy)
    (copy / "p01" / "classical.plan").unlink()
    assert main(["check-plan", str(copy / "p01"), "--encoding", "classical"]) == 2
    assert "not there" in capsys.readouterr().err
