"""experiments/bench_planners.py: every solve row carries the plan's quality beside the
plan bound, and ``--table`` turns saved rows into the README table."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "experiments" / "bench_planners.py"


def _bench():
    spec = importlib.util.spec_from_file_location("bench_planners", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_rows_carry_value_bound_and_ratio_and_the_table_reads_them(tmp_path, capsys) -> None:
    pytest.importorskip("unified_planning")
    from ocplus_plan.planning.engines import available_planners

    bench = _bench()
    # an unknown-to-this-machine planner still gives a row (status 'unavailable')
    names = (available_planners("classical")[:1] or ["pyperplan"])
    assert bench.main(["--presets", "easy", "--agents", "1", "--planners", ",".join(names),
                       "--timeout", "20", "--compile-runs", "1", "--seed", "0,4"]) == 0
    rows = [json.loads(line) for line in capsys.readouterr().out.splitlines() if line]
    solves = [r for r in rows if r["bench"] == "solve"]
    assert {r["seed"] for r in solves} == {0, 4} and len(solves) == 2
    for r in solves:
        assert r["bound"] == r["bound_cost"] > 0 and r["quality"] == "cost"
        if r["status"] == "solved":
            assert r["value"] == r["cost"] >= r["bound"]
            assert r["ratio"] == pytest.approx(r["value"] / r["bound"], abs=1e-3)
        else:
            assert r["value"] is None and r["ratio"] is None
    saved = tmp_path / "rows.jsonl"
    saved.write_text("\n".join(json.dumps(r) for r in rows))
    assert bench.main(["--table", "--from", str(saved)]) == 0
    table = capsys.readouterr().out
    assert "| lower bound: cost |" in table and f"| {names[0]} (classical) |" in table
    assert "easy 1a" in table


def test_a_single_seed_cell_shows_value_ratio_and_time() -> None:
    bench = _bench()
    row = {"bench": "solve", "preset": "easy", "n_agents": 1, "seed": 0, "encoding": "temporal",
           "planner": "kairos", "status": "solved", "quality": "makespan", "cost": 17,
           "makespan": 20.016, "value": 20.016, "bound": 16, "ratio": 1.251,
           "validated": True, "planning_time_s": 0.42, "bound_cost": 14, "bound_makespan": 16}
    table = bench.table([row, dict(row, status="timeout", planner="tamer", value=None,
                                   ratio=None, planning_time_s=12.0)])
    assert "| kairos (temporal) | makespan 20.016 = 1.25x bound, 0.4 s |" in table
    assert "| tamer (temporal) | timeout (12.0 s) |" in table
    assert "| lower bound: makespan | 16 |" in table


def test_a_several_seed_cell_lists_each_seed_and_the_mean_ratio() -> None:
    bench = _bench()
    solved = {"bench": "solve", "preset": "easy", "n_agents": 1, "seed": 0,
              "encoding": "classical", "planner": "fast-downward", "status": "solved",
              "quality": "cost", "cost": 20, "makespan": None, "value": 20, "bound": 16,
              "ratio": 1.25, "validated": True, "planning_time_s": 0.5, "bound_cost": 16,
              "bound_makespan": 16}
    missed = dict(solved, seed=4, status="timeout", value=None, ratio=None, planning_time_s=30.0)
    table = bench.table([missed, solved])
    assert "| fast-downward (classical) | cost 20/- = 1.25x bound (mean), 1/2 solved, 0.5 s |" \
        in table
    assert "| lower bound: cost | 16 / 16 |" in table
