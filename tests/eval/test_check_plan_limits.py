"""check-plan within limits: PDDL file sizes, plan lengths, CPU seconds, JSON nesting."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.cli import main
from ocplus_plan.eval.check import MAX_PDDL_BYTES, MAX_PLAN_ACTIONS
from ocplus_plan.eval.suite import MAX_JSON_DEPTH, read_json

ROOT = Path(__file__).resolve().parents[2]


def bad_input(argv: list[str], capsys, match: str) -> None:
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("ocplus: error: ") and match in err and "\n" not in err


def _args(tmp_path: Path, domain: Path, problem: Path, plan: Path) -> list[str]:
    return ["check-plan", "--domain", str(domain), "--problem", str(problem),
            "--plan", str(plan), "--no-val"]


def test_a_problem_over_the_limit_is_refused_unread(tmp_path, capsys):
    huge = tmp_path / "p.pddl"
    with huge.open("wb") as fh:
        fh.truncate(MAX_PDDL_BYTES + 1)
    plan = tmp_path / "x.plan"
    plan.write_text("")
    bad_input(_args(tmp_path, ROOT / "domains" / "classical_cells.pddl", huge, plan), capsys,
              "a PDDL domain or problem file has at most")


def test_a_plan_of_too_many_actions_is_refused_before_parsing(tmp_path, capsys):
    problem = tmp_path / "p.pddl"
    problem.write_text("(define (problem p) (:domain ocplus_classical_cells-domain))\n")
    plan = tmp_path / "long.plan"
    plan.write_text("(noop a0)\n" * (MAX_PLAN_ACTIONS + 1))
    bad_input(_args(tmp_path, ROOT / "domains" / "classical_cells.pddl", problem, plan),
              capsys, f"at most {MAX_PLAN_ACTIONS} actions")


def test_a_problem_that_takes_too_long_stops_at_the_cpu_limit(tmp_path, capsys):
    objects = " ".join(f"s{i}" for i in range(60_000))
    problem = tmp_path / "p.pddl"
    problem.write_text("(define (problem p) (:domain ocplus_classical_cells-domain)\n"
                       f" (:objects {objects} - spot)\n (:init)\n (:goal (and)))\n")
    plan = tmp_path / "x.plan"
    plan.write_text("")
    bad_input(_args(tmp_path, ROOT / "domains" / "classical_cells.pddl", problem, plan)
              + ["--cpu-limit", "0.5"], capsys, "ocplus: error: the check used more than 0.5 CPU seconds")


def test_instance_json_is_read_within_depth_and_size(tmp_path, capsys):
    deep = tmp_path / "state.json"
    deep.write_text("[" * 100_000 + "]" * 100_000)
    with pytest.raises(ValueError, match=f"nested 100000 deep; the limit is {MAX_JSON_DEPTH}"):
        read_json(deep)
    ok = tmp_path / "ok.json"
    ok.write_text(json.dumps({"a": [{"b": "[[[[\\\"]]"}]}))
    assert read_json(ok) == {"a": [{"b": "[[[[\\\"]]"}]}
    with pytest.raises(ValueError, match="over 10 bytes"):
        read_json(ok, limit=10)
    instance = tmp_path / "p01"
    instance.mkdir()
    (instance / "manifest.json").write_text("{\"a\":" * 100_000 + "1" + "}" * 100_000)
    bad_input(["check-plan", str(instance)], capsys, "nested 100000 deep")
