"""``ocplus solve``: the planner limits it takes and the times it reports."""

from __future__ import annotations

import json
import time

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.cli import main
from ocplus_plan.commands import solve as solve_command
from ocplus_plan.planning.engines import availability, wall_safety


def _require(name: str) -> None:
    if not availability(name).ok:
        pytest.skip(f"{name} unavailable: {availability(name).reason}")


def test_solve_reports_cpu_and_wall_time_and_both_limits(capsys):
    _require("fast-downward")
    code = main(["solve", "--preset", "easy", "--orders", "1", "--timeout", "20", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["status"] == "solved", out["reason"]
    assert out["cpu_limit"] == 20 and out["wall_limit"] == wall_safety(20)
    assert 0 < out["cpu_time"] < 20 and out["wall_time"] == out["planning_time"] > 0


def test_the_wall_safety_is_an_option(capsys):
    _require("fast-downward")
    assert main(["solve", "--preset", "easy", "--orders", "1", "--timeout", "20",
                 "--wall-limit", "300", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["wall_limit"] == 300


@pytest.mark.parametrize("option, value", [("--timeout", "0"), ("--timeout", "nan"),
                                           ("--wall-limit", "-1"), ("--wall-limit", "inf")])
def test_a_limit_that_is_not_a_positive_number_exits_2(option, value, capsys):
    assert main(["solve", "--preset", "easy", option, value]) == 2
    assert option in capsys.readouterr().err


def test_compile_time_leaves_out_the_import_of_unified_planning(monkeypatch, capsys, tmp_path):
    """The one-off import is reported apart (here made slow on purpose)."""
    real = solve_command.import_planning

    def slow_import() -> None:
        time.sleep(3.0)
        real()

    monkeypatch.setattr(solve_command, "import_planning", slow_import)
    assert main(["pddl", "--preset", "easy", "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["import_time_s"] >= 3.0 and out["compile_time_s"] < 3.0
