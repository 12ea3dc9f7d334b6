"""Planner isolation: hard time limits, process groups, crashes, working directories.

Uses the test-only engines and tiny problems of ``test_engines.py``; every test
checks that no planner process outlives the call.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import psutil
import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.planning import _proc
from ocplus_plan.planning.engines import solve

from .test_engines import (
    LiarEngine,
    SleepyEngine,
    _require,
    _test_config,
    hard_unsolvable,
    tiny_classical,
)

ENGINES_TEST_FILE = Path(__file__).with_name("test_engines.py")


def _live_children() -> set[int]:
    """Live (non-zombie) direct children of this test process."""
    return {child.pid for child in psutil.Process().children()
            if _status(child) not in (psutil.STATUS_ZOMBIE, None)}


def _status(proc: psutil.Process) -> str | None:
    """``proc``'s status, None once it is gone."""
    try:
        return proc.status()
    except psutil.Error:
        return None



# ------------------------------------------------------- time limits, groups

def test_timeout_kills_the_whole_process_group() -> None:
    before = _live_children()
    config = _test_config("test-sleepy", SleepyEngine)
    start = time.monotonic()
    result = solve(tiny_classical(), config, timeout=5, wall_limit=0.5)
    elapsed = time.monotonic() - start
    assert result.status == "timeout" and "wall-clock safety limit" in result.reason
    assert elapsed < 0.5 + 2.0 + 3.0
    assert _proc.group_members(result.pgid) == []  # the shell and both sleeps are gone
    assert _live_children() <= before


def test_real_planner_that_ignores_timeout_is_killed() -> None:
    _require("tamer")
    before = _live_children()
    start = time.monotonic()
    result = solve(hard_unsolvable(), "tamer", timeout=0.5)
    assert result.status == "timeout", (result.status, result.reason)
    assert result.limit_hit == "cpu" and result.cpu_time is not None
    assert time.monotonic() - start < 30.0  # 0.5 CPU s: seconds even on a loaded machine
    assert not _proc.group_alive(result.pgid) and _live_children() <= before


def test_solver_process_killed_by_a_signal_is_status_crashed() -> None:
    def die() -> None:
        os.kill(os.getpid(), 9)

    outcome = _proc.run_isolated(die, (), hard_limit=10)
    assert outcome.kind == _proc.CRASHED and "SIGKILL" in outcome.value
    assert not _proc.group_alive(outcome.pgid)


def test_wrong_plan_from_a_planner_is_status_invalid() -> None:
    result = solve(tiny_classical(), _test_config("test-liar", LiarEngine), timeout=5)
    assert result.status == "invalid" and result.validated is False
    assert "INAPPLICABLE" in result.validation_detail


def test_planner_group_dies_with_the_calling_process(tmp_path: Path) -> None:
    """Kill -9 the Python process that called solve(): the watchdog ends the group."""
    import signal
    import subprocess
    import sys

    script = tmp_path / "caller.py"
    script.write_text(
        "import importlib.util, sys\n"
        f"spec = importlib.util.spec_from_file_location('engines_caller', {str(ENGINES_TEST_FILE)!r})\n"
        "mod = importlib.util.module_from_spec(spec); sys.modules['engines_caller'] = mod\n"
        "spec.loader.exec_module(mod)\n"
        "from ocplus_plan.planning.engines import solve\n"
        "solve(mod.tiny_classical(), mod._test_config('test-sleepy', mod.SleepyEngine),"
        " timeout=120)\n")
    # killed with -9, the caller cannot remove its temporary files: keep them in tmp_path
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    caller = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL, env={**os.environ, "TMPDIR": str(tmp)})
    try:
        deadline, group, pgid = time.monotonic() + 60, [], -1
        while time.monotonic() < deadline and len(group) < 4:  # child, sh and two sleeps
            time.sleep(0.2)
            leaders = _all_children(caller.pid)
            pgid = leaders[0] if leaders else -1
            group = _proc.group_members(pgid) if leaders else []
        assert len(group) >= 4, "the planner process group never started"
        caller.send_signal(signal.SIGKILL)
        caller.wait(10)
        deadline = time.monotonic() + 5
        while _proc.group_alive(pgid) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert not _proc.group_alive(pgid)
    finally:
        caller.kill()


def _all_children(pid: int) -> list[int]:
    """Children of ``pid`` that lead their own process group."""
    leaders = []
    for child in psutil.Process(pid).children():
        try:
            if os.getpgid(child.pid) == child.pid:
                leaders.append(child.pid)
        except OSError:  # ended in between
            continue
    return leaders


def test_planners_write_nothing_into_the_callers_directory(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """FD writes output.sas into its cwd: concurrent solves in one directory used to
    corrupt each other (a crashed translator reported as UNSOLVABLE_PROVEN)."""
    _require("fast-downward")
    monkeypatch.chdir(tmp_path)
    result = solve(tiny_classical(), "fast-downward", timeout=30)
    assert result.status == "solved"
    assert list(tmp_path.iterdir()) == []
