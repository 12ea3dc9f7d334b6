"""`ocplus demo`: a small real evaluation that prints the leaderboard and where the plots are."""

from __future__ import annotations

from ocplus_plan.agents import FACTORIES
from ocplus_plan.cli import main
from ocplus_plan.commands import demo
from ocplus_plan.errors import DependencyNotInstalled


def test_demo_runs_three_presets_and_reports_skipped_agents(tmp_path, capsys, monkeypatch):
    # the planners are exercised by their own tests; here a kind whose extra is missing
    # stands in for a planner that is missing, to check that the demo skips it with the reason
    def missing(arg, seed):
        raise DependencyNotInstalled("laterkind is not registered: its extra is missing")

    monkeypatch.setitem(FACTORIES, "laterkind", missing)
    monkeypatch.setattr(demo, "DEMO_AGENTS", ["greedy", "laterkind:x", "random"])
    out = tmp_path / "demo"
    assert main(["demo", "--out", str(out), "--seeds", "2", "--horizon", "60", "--jobs", "2"]) == 0
    text = capsys.readouterr().out
    for preset in ("easy", "medium", "hard"):
        assert f"\n{preset}  (" in text or text.startswith(f"{preset}  (")
    assert "greedy" in text and "random" in text
    assert "laterkind:x" in text and "not registered" in text
    assert str(out / "results.jsonl") in text and "plots:" in text
    assert (out / "summary.csv").exists()
