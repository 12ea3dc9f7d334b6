"""End-to-end evaluation: worker processes, result files, resume, bad input, failures."""

from __future__ import annotations

import json
import os
from types import SimpleNamespace

import pytest

from ocplus_plan.agents import FACTORIES
from ocplus_plan.agents.base import Controller
from ocplus_plan.cli import main
from ocplus_plan.errors import ConfigError, DependencyNotInstalled
from ocplus_plan.eval import runner
from ocplus_plan.eval.results import read_results
from ocplus_plan.eval.runner import EvalConfig, parse_seeds, run_eval


def _cfg(out, **kw) -> EvalConfig:
    base = dict(presets=["easy"], agents=["greedy", "random"], seeds=[0, 1], out=out,
                horizon=80, n_agents=2, jobs=2, quiet=True)
    base.update(kw)
    return EvalConfig(**base)


class _Crashing(Controller):
    """Fails at step 5, as a planner process that dies would."""

    def act(self, state):
        if state.t >= 5:
            raise RuntimeError("planner process exited with code -11")
        return [4] * len(self.agent_ids)


class _Dying(Controller):
    """Kills its whole process, as a segfault in native planner code would."""

    def act(self, state):
        os._exit(7)


def test_two_agents_two_seeds_end_to_end_in_worker_processes(tmp_path):
    out = tmp_path / "run"
    outcome = run_eval(_cfg(out), echo=lambda *a: None)
    rows = read_results(out)
    assert len(rows) == 4 and all(r["status"] == "ok" for r in rows)
    assert {(r["agent"], r["seed"]) for r in rows} == {(a, s) for a in ("greedy", "random")
                                                       for s in (0, 1)}
    for r in rows:
        assert r["metrics"]["steps"] == 80 and r["n_agents"] == 2 and r["map"] == "easy_open"
        assert r["timings"]["wall_time_s"] > 0 and "planner" in r and "controller" in r
        assert len(r["metrics"]["heatmaps"]) == 2
    by_agent = {s["agent"]: s for s in outcome.summary}
    assert by_agent["greedy"]["dishes_served_mean"] > by_agent["random"]["dishes_served_mean"]
    assert by_agent["greedy"]["episodes"] == 2
    csv_text = (out / "summary.csv").read_text()
    assert csv_text.startswith("preset,map,n_agents,agent,horizon,episodes")
    assert len(csv_text.strip().splitlines()) == 3
    assert "greedy" in outcome.leaderboard and "±" in outcome.leaderboard
    assert json.loads((out / "config.json").read_text())["agents"] == ["greedy", "random"]


def test_existing_folder_is_an_error_and_resume_continues(tmp_path):
    out = tmp_path / "run"
    cfg = _cfg(out, jobs=1)
    run_eval(cfg, echo=lambda *a: None)
    with pytest.raises(ConfigError, match="already exists.*--resume"):
        run_eval(cfg, echo=lambda *a: None)
    # simulate an interrupted run: the last row is lost, half of another is written
    lines = (out / "results.jsonl").read_text().splitlines()
    (out / "results.jsonl").write_text("\n".join(lines[:-1]) + "\n" + lines[-1][:30])
    outcome = run_eval(_cfg(out, jobs=1, resume=True), echo=lambda *a: None)
    assert outcome.ran == 1
    rows = read_results(out)
    assert len({r["key"] for r in rows}) == 4
    again = run_eval(_cfg(out, jobs=1, resume=True, seeds=[0, 1, 2]), echo=lambda *a: None)
    assert again.ran == 2  # only the new seed, for both agents


def test_bad_names_fail_before_anything_runs(tmp_path):
    with pytest.raises(ConfigError, match="unknown agent 'gredy'"):
        run_eval(_cfg(tmp_path / "a", agents=["gredy"]))
    with pytest.raises(ConfigError, match="unknown preset 'medum'"):
        run_eval(_cfg(tmp_path / "b", presets=["medum"]))
    with pytest.raises(ConfigError, match="at most"):
        run_eval(_cfg(tmp_path / "c", n_agents=5))
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()


def test_planner_with_no_name_is_the_default_planner(monkeypatch):
    pytest.importorskip("ocplus_plan.planning.engines")
    from ocplus_plan.agents import make_controller, with_partner
    from ocplus_plan.eval.runner import check_agent, check_partner
    from ocplus_plan.execution.spec import DEFAULT_PLANNER
    from ocplus_plan.planning import engines

    asked = []
    monkeypatch.setattr(engines, "availability", 
                        lambda name: asked.append(name) or SimpleNamespace(ok=False, reason="gone"))
    for spec in ("planner:", "planner", "planner:::", "planner::stations"):
        assert "gone" in check_agent(spec)  # skipped for the default planner's reason
        assert make_controller(spec).planner_name == DEFAULT_PLANNER
    assert set(asked) == {DEFAULT_PLANNER}
    with pytest.raises(ConfigError, match="--partner planner:"):
        check_partner("planner:", [2])
    team = with_partner(make_controller("greedy"), "planner:", 2)
    assert team[1][0].planner_name == DEFAULT_PLANNER


def test_unknown_planner_name_is_an_error(tmp_path):
    pytest.importorskip("ocplus_plan.planning.engines")
    from ocplus_plan.errors import PlannerError

    with pytest.raises(PlannerError, match="no-such-planner"):
        run_eval(_cfg(tmp_path / "p", agents=["planner:no-such-planner"]))


def test_a_planner_spec_with_options_is_checked_by_its_planner_name(tmp_path, monkeypatch):
    """planner:NAME:GRAN:POLICY:OPTIONS (the README's fourth field): the availability check
    looks the planner up by NAME, not by the whole spec."""
    engines = pytest.importorskip("ocplus_plan.planning.engines")
    asked = []
    monkeypatch.setattr(engines, "availability", lambda name: asked.append(name) or
                        engines.Availability(False, "not installed here"))
    spec = "planner:fast-downward-bjolp:stations:on_event:one-cook+chain2"
    out = tmp_path / "opts"
    run_eval(_cfg(out, agents=[spec], seeds=[0]), echo=lambda *a: None)
    assert asked == ["fast-downward-bjolp"]
    assert [r["status"] for r in read_results(out)] == ["skipped"]


def test_an_agent_whose_dependency_is_missing_is_skipped_with_its_reason(tmp_path,
                                                                         monkeypatch):
    def factory(arg, seed):
        raise DependencyNotInstalled("the `future` extra is not installed: pip install -e "
                                     "'.[future]'")

    monkeypatch.setitem(FACTORIES, "futurekind", factory)
    messages = []
    outcome = run_eval(_cfg(tmp_path / "s", agents=["greedy", "futurekind:x"], seeds=[0]),
                       echo=messages.append)
    rows = read_results(tmp_path / "s")
    skipped = [r for r in rows if r["status"] == "skipped"]
    assert len(skipped) == 1 and "[future]" in skipped[0]["reason"]
    assert any("skipping futurekind:x" in m for m in messages)
    assert "futurekind:x" in outcome.leaderboard and "skipped" in outcome.leaderboard


def test_the_runner_and_its_ray_backend_import_no_cycle():
    import ast
    from pathlib import Path

    def imports(module: str) -> set[str]:
        tree = ast.parse(Path(runner.__file__).with_name(f"{module}.py").read_text())
        return {node.module for node in ast.walk(tree)
                if isinstance(node, ast.ImportFrom) and node.level == 1 and node.module}

    assert "runner" not in imports("ray_backend") and "runner" not in imports("local_backend")
    assert not {"runner", "ray_backend", "local_backend"} & imports("episode")
    assert not hasattr(runner, "PENDING_KINDS")


def test_crashing_and_dying_controllers_become_error_rows(tmp_path, monkeypatch):
    monkeypatch.setitem(FACTORIES, "crashy", lambda arg, seed: _Crashing())
    monkeypatch.setitem(FACTORIES, "dying", lambda arg, seed: _Dying())
    out = tmp_path / "e"
    outcome = run_eval(_cfg(out, agents=["crashy", "dying", "greedy"], seeds=[0]),
                       echo=lambda *a: None)
    rows = {r["agent"]: r for r in read_results(out)}
    assert rows["crashy"]["status"] == "error"
    assert "exited with code -11" in rows["crashy"]["reason"] and "step 5" in rows["crashy"]["reason"]
    assert rows["crashy"]["metrics"]["steps"] == 5  # what happened before the crash is kept
    assert rows["dying"]["status"] == "error" and "died" in rows["dying"]["reason"]
    assert rows["greedy"]["status"] == "ok"
    assert outcome.errors == 2 and "failed" in outcome.leaderboard


def test_episode_timeout_kills_the_episode(tmp_path, monkeypatch):
    class _Slow(Controller):
        def act(self, state):
            import time

            time.sleep(10)
            return [4] * len(self.agent_ids)

    monkeypatch.setitem(FACTORIES, "slow", lambda arg, seed: _Slow())
    out = tmp_path / "t"
    run_eval(_cfg(out, agents=["slow"], seeds=[0], jobs=1, episode_timeout=1.0),
             echo=lambda *a: None)
    (row,) = read_results(out)
    assert row["status"] == "error" and "timed out" in row["reason"]


def test_seed_parsing():
    assert parse_seeds("3") == [0, 1, 2]
    assert parse_seeds("4,9") == [4, 9]
    assert parse_seeds("5-7") == [5, 6, 7]
    with pytest.raises(ConfigError, match="--seeds"):
        parse_seeds("many")


def test_cli_eval_prints_leaderboard_and_refuses_existing_folder(tmp_path, capsys):
    out = tmp_path / "cli"
    args = ["eval", "--presets", "easy", "--agents", "greedy", "--seeds", "1", "--horizon", "40",
            "--out", str(out), "--quiet"]
    assert main(args) == 0
    text = capsys.readouterr().out
    assert "easy" in text and "greedy" in text and "results.jsonl" in text
    assert main(args) == 2
    assert "already exists" in capsys.readouterr().err
    assert main(["report", str(out), "--no-plots"]) == 0
    assert "greedy" in capsys.readouterr().out
    assert main(["report", str(tmp_path / "nothing")]) == 2


def test_importing_the_evaluation_loads_no_heavy_package():
    import subprocess
    import sys

    code = ("import sys, ocplus_plan.eval, ocplus_plan.commands.eval; "
            "print(' '.join(sorted(sys.modules)))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    roots = {m.split(".")[0] for m in out.stdout.split()}
    assert not roots & {"matplotlib", "unified_planning", "torch", "pygame", "tqdm"}


def test_planner_that_is_not_installed_is_skipped_with_the_reason(tmp_path, monkeypatch):
    engines = pytest.importorskip("ocplus_plan.planning.engines")
    monkeypatch.setattr(engines, "availability", lambda name: engines.Availability(
        False, "Python package 'up_fast_downward' is not installed; install the planners extra"))
    out = tmp_path / "np"
    outcome = run_eval(_cfg(out, agents=["greedy", "planner:fast-downward"], seeds=[0]),
                       echo=lambda *a: None)
    rows = {r["agent"]: r for r in read_results(out)}
    assert rows["planner:fast-downward"]["status"] == "skipped"
    assert "up_fast_downward" in rows["planner:fast-downward"]["reason"]
    assert rows["greedy"]["status"] == "ok" and outcome.skipped == 1


def test_chosen_episodes_are_saved_as_replays_that_verify(tmp_path, capsys):
    from ocplus_plan.render.replay import Recording, verify

    out = tmp_path / "run"
    assert main(["eval", "--presets", "easy", "--agents", "greedy", "--seeds", "2",
                 "--horizon", "60", "--quiet", "--out", str(out), "--save-replays", "1"]) == 0
    capsys.readouterr()
    rows = {r["seed"]: r for r in read_results(out)}
    assert "replay" not in rows[0] and rows[1]["replay"].endswith(".jsonl.gz")
    rec = Recording.load(rows[1]["replay"])
    assert len(rec.actions) == 60 and verify(rec).ok
    assert rec.stats["dishes_served"] == rows[1]["stats"]["dishes_served"]


def test_planner_agents_can_plan_inside_worker_processes(tmp_path):
    """Regression: daemonic workers may not start the planner's own process, so every
    planner call failed (status error) when the evaluation ran with --jobs 2."""
    from ocplus_plan.planning import engines

    av = engines.availability("fast-downward")
    if not av.ok:
        pytest.skip(f"fast-downward not available: {av.reason}")
    out = tmp_path / "run"
    run_eval(_cfg(out, agents=["planner:fast-downward"], seeds=[0], n_agents=1, horizon=40,
                  jobs=2), echo=lambda *a: None)
    (row,) = read_results(out)
    assert row["status"] == "ok" and row["controller"]["statuses"].get("solved", 0) >= 1
    assert "error" not in row["controller"]["statuses"]
