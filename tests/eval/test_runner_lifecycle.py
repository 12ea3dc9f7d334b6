"""Processes that die with their driver, exceptions of user code as error rows, Ctrl-C
that keeps the rows, and the progress a long episode reports."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import psutil
import pytest

from ocplus_plan.agents import FACTORIES
from ocplus_plan.agents.base import Controller
from ocplus_plan.cli import main
from ocplus_plan.eval.episode import EpisodeSpec
from ocplus_plan.eval.local_backend import run_local
from ocplus_plan.eval.results import read_results
from ocplus_plan.eval.runner import EvalConfig, run_eval

#: the slowest a process may outlive its killed driver
OUTLIVE_LIMIT_S = 2.0

#: a driver in its own process: registers a controller whose episodes sit in a
#: planner-like process group (``planning._proc``) for a minute, then runs the sweep
DRIVER = textwrap.dedent("""
    import sys, time
    from ocplus_plan.agents import FACTORIES
    from ocplus_plan.agents.base import Controller
    from ocplus_plan.cli import main

    class Stuck(Controller):
        def act(self, state):
            if state.t == 2:
                from ocplus_plan.planning import _proc
                _proc.run_isolated(time.sleep, (60,), hard_limit=None)
            time.sleep(float(sys.argv[2]))
            return [4] * len(self.agent_ids)

    FACTORIES["stuck"] = lambda arg, seed: Stuck()
    sys.exit(main(["eval", "--presets", "easy", "--agents", sys.argv[3], "--seeds", "4",
                   "--horizon", "40", "--n-agents", "1", "--jobs", sys.argv[4],
                   "--out", sys.argv[1], "--quiet"]))
""")


def _start_driver(tmp_path: Path, agents: str, jobs: int, sleep: float = 0.0):
    script = tmp_path / "driver.py"
    script.write_text(DRIVER)
    out = tmp_path / "run"
    proc = subprocess.Popen([sys.executable, str(script), str(out), str(sleep), agents,
                             str(jobs)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    return proc, out


def _alive(procs: list[psutil.Process]) -> list[psutil.Process]:
    out = []
    for p in procs:
        try:
            if p.is_running() and p.status() != psutil.STATUS_ZOMBIE:
                out.append(p)
        except psutil.NoSuchProcess:
            pass
    return out


def _wait_for(condition, timeout: float, what: str) -> None:
    end = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > end:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.1)


def test_killing_the_driver_kills_its_workers_and_their_planner_groups(tmp_path):
    driver, _out = _start_driver(tmp_path, "stuck", jobs=2)
    me = psutil.Process(driver.pid)
    try:
        # two workers, each with a planner-like group of its own below it
        _wait_for(lambda: len(me.children(recursive=True)) >= 4, 60, "workers and planners")
        family = me.children(recursive=True)
        assert len({os.getpgid(p.pid) for p in family}) >= 4  # workers and planners: own groups
        driver.send_signal(signal.SIGKILL)
        driver.wait(10)
        killed = time.monotonic()
        _wait_for(lambda: not _alive(family), 10, "the driver's processes to die")
        assert time.monotonic() - killed <= OUTLIVE_LIMIT_S
    finally:
        for p in _alive([me, *me.children(recursive=True)]) if me.is_running() else []:
            p.kill()
        driver.kill()
        driver.communicate()


def test_ctrl_c_stops_the_sweep_keeps_the_rows_and_exits_130(tmp_path):
    """Greedy episodes finish first; SIGINT in the middle of the slow ones."""
    driver, out = _start_driver(tmp_path, "greedy,stuck", jobs=2, sleep=0.05)
    me = psutil.Process(driver.pid)
    try:
        results = out / "results.jsonl"
        _wait_for(lambda: results.exists() and len(read_results(results)) >= 4, 60,
                  "the greedy rows")
        _wait_for(lambda: len(me.children(recursive=True)) >= 2, 30, "the stuck episodes")
        family = me.children(recursive=True)
        driver.send_signal(signal.SIGINT)
        _stdout, stderr = driver.communicate(timeout=30)
        assert driver.returncode == 130, stderr
        assert "interrupted" in stderr and "Traceback" not in stderr
        rows = read_results(results)
        assert len(rows) >= 4 and {r["agent"] for r in rows} >= {"greedy"}
        assert all(json.loads(line) for line in results.read_text().splitlines())
        _wait_for(lambda: not _alive(family), OUTLIVE_LIMIT_S, "the episodes to be killed")
    finally:
        driver.kill()
        driver.communicate()


class _Raises(Controller):
    """Raises ``exc`` at step 3, as a user's model function or planner might."""

    def __init__(self, exc: BaseException) -> None:
        self.exc = exc

    def act(self, state):
        if state.t >= 3:
            raise self.exc
        return [4] * len(self.agent_ids)


@pytest.mark.parametrize("jobs", [1, 2])
def test_system_exit_and_keyboard_interrupt_of_a_controller_are_error_rows(tmp_path,
                                                                           monkeypatch, jobs):
    monkeypatch.setitem(FACTORIES, "exits", lambda arg, seed: _Raises(SystemExit(3)))
    monkeypatch.setitem(FACTORIES, "interrupts", lambda arg, seed: _Raises(KeyboardInterrupt()))
    out = tmp_path / "run"
    outcome = run_eval(EvalConfig(presets=["easy"], agents=["exits", "interrupts", "greedy"],
                                  seeds=[0, 1], out=out, horizon=30, n_agents=1, jobs=jobs,
                                  quiet=True), echo=lambda *a: None)
    rows = read_results(out)
    assert len(rows) == 6 and outcome.errors == 4
    for r in rows:
        if r["agent"] == "greedy":
            assert r["status"] == "ok"
        else:
            assert r["status"] == "error" and "at step 3" in r["reason"]
            assert r["metrics"]["steps"] == 3
    assert {r["reason"].split(":")[0] for r in rows if r["status"] == "error"} == {
        "SystemExit", "KeyboardInterrupt"}


def test_a_model_function_that_raises_system_exit_is_an_error_row(tmp_path, monkeypatch,
                                                                     capsys):
    (tmp_path / "exiting_model.py").write_text("def ask(prompt):\n    raise SystemExit(3)\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    out = tmp_path / "run"
    code = main(["eval", "--presets", "easy", "--agents", "llm:exiting_model:ask,greedy",
                 "--seeds", "2", "--horizon", "20", "--n-agents", "1", "--out", str(out),
                 "--quiet"])
    assert code == 0, capsys.readouterr().err
    rows = {(r["agent"], r["seed"]): r for r in read_results(out)}
    assert len(rows) == 4
    assert rows[("llm:exiting_model:ask", 0)]["status"] == "error"
    assert "SystemExit" in rows[("llm:exiting_model:ask", 1)]["reason"]
    assert rows[("greedy", 1)]["status"] == "ok"


class _Slow(Controller):
    """Thinks 0.2 s a step, and says so in info() as a planner would."""

    calls = 0

    def act(self, state):
        time.sleep(0.2)
        self.calls += 1
        return [4] * len(self.agent_ids)

    def info(self):
        return {"planner_calls": self.calls, "planning_time": 0.2 * self.calls}


def test_a_long_episode_reports_its_step_and_planner_statistics(monkeypatch):
    monkeypatch.setitem(FACTORIES, "slowpoke", lambda arg, seed: _Slow())
    spec = EpisodeSpec("easy", "easy_open", None, 1, "slowpoke", 0, 15)
    heard = []
    rows = list(run_local([spec], 1, None,
                          on_progress=lambda s, *p: heard.append((s.agent, *p))))
    assert rows[0]["status"] == "ok"
    assert heard, "no progress from a 3 s episode"
    agent, step, calls, planning = heard[-1]
    assert agent == "slowpoke" and 0 < step <= 15 and calls == step
    assert planning == pytest.approx(0.2 * calls)


def test_a_model_module_that_exits_while_loading_is_skipped_with_the_reason(tmp_path,
                                                                             monkeypatch):
    (tmp_path / "exits_on_import.py").write_text("raise SystemExit(2)\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    out = tmp_path / "run"
    outcome = run_eval(EvalConfig(presets=["easy"], agents=["llm:exits_on_import:ask", "greedy"],
                                  seeds=[0], out=out, horizon=20, n_agents=1, quiet=True),
                       echo=lambda *a: None)
    rows = {r["agent"]: r for r in read_results(out)}
    assert rows["llm:exits_on_import:ask"]["status"] == "skipped"
    assert "SystemExit" in rows["llm:exits_on_import:ask"]["reason"]
    assert rows["greedy"]["status"] == "ok" and outcome.skipped == 1
