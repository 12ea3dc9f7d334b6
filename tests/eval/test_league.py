"""``ocplus league`` on one small set (easy, 1 and 2 cooks, classical): every status from a
planner binary (tests/eval/league_planner.py), one real planner (Fast Downward), the score
arithmetic by hand, resuming, and the faithfulness judge on a two-cook plan."""

from __future__ import annotations

import json
import math
import sys
import warnings
from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.cli import main
from ocplus_plan.eval import league
from ocplus_plan.eval.suite import SuiteSpec, export_suite, load_instance, replay_plan
from ocplus_plan.planning import fidelity_judge
from ocplus_plan.planning.engines import availability
from ocplus_plan.planning.plan_io import read_plan

warnings.simplefilter("ignore", UserWarning)
SCRIPT = Path(__file__).with_name("league_planner.py")
SPEC = SuiteSpec(presets=("easy",), cooks=(1, 2), states=1, encodings=("classical",),
                 timeout=20, planners={"classical": ("fast-downward-wastar",)})


@pytest.fixture(scope="module")
def suite(tmp_path_factory) -> Path:
    if not availability("fast-downward-wastar").ok:
        pytest.skip(availability("fast-downward-wastar").reason)
    out = tmp_path_factory.mktemp("league") / "set"
    export_suite(SPEC, out)
    return out


def _planner(folder: Path, mode: str, extra: str = "", name: str = "") -> str:
    import yaml

    command = [sys.executable, str(SCRIPT), mode, "{domain}", "{problem}", "{plan}"]
    if extra:
        command.append(extra)
    name = name or f"toy-{mode}"
    path = folder / f"{name}.yaml"
    path.write_text(yaml.safe_dump({"name": name, "command": command,
                                    "encoding": "classical"}), encoding="utf-8")
    return str(path)


def _run(suite: Path, out: Path, planners: list[str], **kw) -> dict[tuple[str, str], dict]:
    spec = league.LeagueSpec(suite, tuple(planners), kw.pop("cpu", 2.0), **kw)
    rows, skipped = league.run_league(spec, out)
    assert not skipped
    return {(Path(r["planner"]).stem, r["instance"]): r for r in rows}


def test_every_status_of_a_planner_binary_is_kept_apart(suite, tmp_path):
    plan = (suite / "p01/classical.plan").read_text(encoding="utf-8")
    (tmp_path / "good.plan").write_text(plan, encoding="utf-8")
    (tmp_path / "short.plan").write_text(plan.strip().splitlines()[0] + "\n", encoding="utf-8")
    planners = [_planner(tmp_path, "copy", str(tmp_path / "good.plan")),
                _planner(tmp_path, "none"), _planner(tmp_path, "spin"),
                _planner(tmp_path, "crash")]
    rows = _run(suite, tmp_path / "out", planners, cpu=1.0, instances=("p01",))
    # the memory hog gets CPU seconds to spare: filling 300 MB on a loaded machine may take
    # most of one CPU second, and the limit it is to meet is the memory one
    rows.update(_run(suite, tmp_path / "out-memory", [_planner(tmp_path, "memory")], cpu=10.0,
                     memory_limit=300.0, instances=("p01",)))
    # a short wall-clock safety only for the planner that waits (a loaded machine slows
    # the others in wall time, never in CPU seconds)
    rows.update(_run(suite, tmp_path / "out-sleep", [_planner(tmp_path, "sleep")], cpu=1.0,
                     instances=("p01",), wall_limit=2.0))
    status = {name: row["status"] for (name, _), row in rows.items()}
    assert status == {"toy-copy": "solved", "toy-none": "unsolvable", "toy-spin": "cpu-timeout",
                      "toy-sleep": "safety-kill", "toy-crash": "crash", "toy-memory": "memout"}
    solved = rows[("toy-copy", "p01")]
    assert solved["valid"] is True and solved["faithful"] is True and solved["value"] > 0
    kept = (tmp_path / "out" / solved["plan_file"]).read_text(encoding="utf-8")
    steps = [line.split(":", 1)[1] for line in kept.splitlines() if not line.startswith(";")]
    assert steps == [line.split(":", 1)[1] for line in plan.splitlines()
                     if line.strip() and not line.startswith(";")]
    assert "plan_file" not in rows[("toy-spin", "p01")]
    assert rows[("toy-spin", "p01")]["cpu_time"] >= 1.0
    invalid = _run(suite, tmp_path / "out2", [_planner(tmp_path, "copy",
                   str(tmp_path / "short.plan"), "toy-short")], instances=("p01",))
    row = invalid[("toy-short", "p01")]
    assert row["status"] == "invalid" and row["valid"] is False and row["faithful"] is None


def test_a_plan_the_kitchen_refuses_is_unfaithful_with_its_step(suite, tmp_path, monkeypatch):
    plan = (suite / "p01/classical.plan").read_text(encoding="utf-8")
    (tmp_path / "good.plan").write_text(plan, encoding="utf-8")

    def refuse(compiled, plan, state):
        return fidelity_judge.Judgement(False, 3, 7, failed_step=2, reason="cook 1 is stuck")

    monkeypatch.setattr(fidelity_judge, "judge", refuse)
    rows = _run(suite, tmp_path / "out", [_planner(tmp_path, "copy", str(tmp_path / "good.plan"),
                                                    "toy-refused")], instances=("p01",))
    row = rows[("toy-refused", "p01")]
    assert row["status"] == "unfaithful" and row["valid"] is True and row["faithful"] is False
    assert row["failed_step"] == 2 and row["reason"] == "step 2: cook 1 is stuck"
    score = league.scores(list(rows.values()))["planners"][row["planner"]]["all"]
    assert score["coverage"] == 0 and score["quality"] == 0 and score["valid"] == 1


def test_fast_downward_in_the_league_and_resume(suite, tmp_path, capsys):
    if not availability("fast-downward").ok:
        pytest.skip(availability("fast-downward").reason)
    out = tmp_path / "out"
    args = ["league", str(suite), "--planners", "fast-downward", "--cpu-limit", "20",
            "--out", str(out), "--quiet"]
    assert main([*args, "--jobs", "2", "--plots"]) == 0  # two worker processes
    assert (out / league.PLOT_FILE).is_file()
    table = capsys.readouterr().out
    assert "fast-downward" in table and "classical-multicook" in table
    rows = league.read_rows(out / league.RUNS_FILE)
    assert {(r["instance"], r["status"], r["faithful"]) for r in rows} == {
        ("p01", "solved", True), ("p02", "solved", True)}
    assert main(args) == 2  # the folder holds a league: --resume or a new --out
    assert "--resume" in capsys.readouterr().err
    assert main([*args, "--resume", "--json"]) == 0
    score = json.loads(capsys.readouterr().out)
    assert score["planners"]["fast-downward"]["all"]["coverage"] == 2
    assert len(league.read_rows(out / league.RUNS_FILE)) == 2  # nothing ran twice


def test_scores_use_the_sets_best_known_now(tmp_path):
    """A row keeps the best known of when it ran; scored beside the set, a better value
    the set found since (a longer offline search) is the C* of the quality score."""
    folder = tmp_path / "temporal" / "p01"
    folder.mkdir(parents=True)
    (folder / "manifest.json").write_text(json.dumps({"encodings": {"temporal": {
        "reference": {"makespan": 16.0, "faithful": True}}}}), encoding="utf-8")
    row = {"planner": "a", "instance": "temporal/p01", "encoding": "temporal",
           "track": "temporal", "status": "solved", "value": 20.0, "cpu_time": 1.0,
           "cpu_limit": 30.0, "best_known": 20.0, "valid": True, "faithful": True}
    assert league.scores([row])["planners"]["a"]["all"]["quality"] == 1.0
    known = league.suite_best(tmp_path, [row])
    assert known == {("temporal/p01", "temporal"): 16.0}
    assert league.scores([row], known)["planners"]["a"]["all"]["quality"] == 0.8
    league.write_scores([row], tmp_path, tmp_path)
    score = json.loads((tmp_path / league.SCORES_FILE).read_text(encoding="utf-8"))
    assert score["best"] == {"temporal/p01/temporal": 16.0}


def test_scores_by_hand():
    def row(planner, instance, status, value=None, cpu=None, best=None, track="t"):
        return {"planner": planner, "instance": instance, "encoding": "classical",
                "track": track, "status": status, "value": value, "cpu_time": cpu,
                "cpu_limit": 100.0, "best_known": best, "valid": value is not None,
                "faithful": status == "solved" if value is not None else None}

    rows = [row("a", "p1", "solved", 10, 0.5, best=8), row("b", "p1", "solved", 5, 10.0, best=8),
            row("a", "p2", "solved", 20, 100.0), row("b", "p2", "unfaithful", 4, 1.0),
            row("a", "p3", "cpu-timeout", cpu=100.0), row("b", "p3", "invalid", 2, 1.0)]
    score = league.scores(rows)
    assert score["best"] == {"p1/classical": 5.0, "p2/classical": 20.0}
    a, b = score["planners"]["a"]["t"], score["planners"]["b"]["t"]
    # a: p1 5/10, p2 20/20 (the unfaithful 4 of b does not count); agile 1 (0.5 s) + 0 (100 s)
    assert a["coverage"] == 2 and a["quality"] == pytest.approx(1.5) and a["agile"] == 1.0
    # b: p1 5/5; agile 1 - log 10 / log 100 = 0.5; valid 3 (p1, p2, p3), faithful 1
    assert b["coverage"] == 1 and b["quality"] == 1.0 and b["agile"] == pytest.approx(0.5)
    assert b["valid"] == 3 and b["faithful"] == 1
    assert b["statuses"] == {"solved": 1, "unfaithful": 1, "invalid": 1}
    assert league.agile(50.0, 100.0) == pytest.approx(1 - math.log(50) / math.log(100))
    assert league.agile(100.5, 100.0) == 0.0


def test_two_cooks_walking_through_each_other_are_realised_with_a_wait(suite):
    # the reference (weighted A*) plan for two cooks walks cook 0 over the cell cook 1
    # stands on: the strict replay calls it unfaithful, the judge lets cook 1 step aside
    instance = load_instance(suite / "p02")
    compiled = instance.compiled("classical")
    plan = read_plan(suite / "p02/classical.plan", compiled.problem)
    assert not replay_plan(compiled, plan, instance.state).ok
    verdict = fidelity_judge.judge(compiled, plan, instance.state)
    assert verdict.faithful, verdict.reason
    assert verdict.waits > 0 and set(compiled.goal_orders) <= set(verdict.served)
    # the export records the league judge's verdict, not the strict replay's
    ref = json.loads((suite / "p02/manifest.json").read_text())[
        "encodings"]["classical"]["reference"]
    assert ref["faithful"] is True and ref["judged"] == "realised"
    assert ref["waits"] == verdict.waits and ref["failed_step"] is None
    assert ref["divergence"] is None
    assert ref["portfolio"]["fast-downward-wastar"]["waits"] == verdict.waits


def test_bad_input_is_refused_in_one_line(suite, tmp_path, capsys):
    assert main(["league", str(suite), "--planners", "no-such", "--cpu-limit", "1",
                 "--out", str(tmp_path / "o")]) == 2
    assert "unknown planner" in capsys.readouterr().err
    assert main(["league", str(suite), "--planners", "fast-downward", "--cpu-limit", "1",
                 "--instances", "p09", "--out", str(tmp_path / "o")]) == 2
    assert "no instance p09" in capsys.readouterr().err
    assert main(["league", str(tmp_path), "--planners", "fast-downward", "--cpu-limit", "1",
                 "--out", str(tmp_path / "o")]) == 2


def test_the_judge_refuses_a_plan_with_the_step_it_cannot_realise(suite):
    instance = load_instance(suite / "p02")
    compiled = instance.compiled("classical")
    lines = [line for line in (suite / "p02/classical.plan").read_text().splitlines()
             if line.strip() and not line.startswith(";")]
    first_move = next(i for i, line in enumerate(lines) if "(move " in line)
    # without its first move, the step after it acts from a cell the model's cook is not on
    plan = read_plan_text(lines[:first_move] + lines[first_move + 1:], compiled.problem)
    verdict = fidelity_judge.judge(compiled, plan, instance.state)
    assert not verdict.faithful and verdict.failed_step == first_move
    assert verdict.reason == "not applicable in the model"


def read_plan_text(lines, problem):
    from ocplus_plan.planning.plan_io import parse_plan

    return parse_plan("\n".join(lines) + "\n", problem)


def test_a_release_of_sets_is_read_by_its_tracks(tmp_path):
    (tmp_path / "manifest.json").write_text(json.dumps({"tracks": {"temporal": {
        "folder": "t", "encoding": "temporal", "scored": ["p01"], "unsolvable": ["p02"]},
        "bad": {"folder": "../x", "scored": ["p01"]}}}))
    for name in ("p01", "p02"):
        (tmp_path / "t" / name).mkdir(parents=True)
        (tmp_path / "t" / name / "manifest.json").write_text('{"encodings": {"temporal": {}}}')
    assert league.suite_instances(tmp_path) == ["t/p01", "t/p02"]
    assert league.suite_tracks(tmp_path) == {("t/p01", "temporal"): "temporal",
                                             ("t/p02", "temporal"): "temporal-unsolvable"}
    row = {"planner": "a", "instance": "t/p02", "encoding": "temporal",
           "track": "temporal-unsolvable", "status": "unsolvable", "cpu_time": 1.0,
           "cpu_limit": 10.0}
    assert league.scores([row])["planners"]["a"]["temporal-unsolvable"]["coverage"] == 1
