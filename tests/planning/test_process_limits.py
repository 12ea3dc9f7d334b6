"""Limits an engine cannot ignore: the kernel's CPU backstop, a watchdog that is a process
(a planner holding the GIL cannot starve it), SIGTERM to ``ocplus solve`` that ends the
command and its engine, and processes a planner abandons in a new session."""

from __future__ import annotations

import multiprocessing
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import psutil

from ocplus_plan.planning import _proc
from ocplus_plan.planning.engines import solve

from .test_command import _config
from .test_engines import tiny_classical

ROOT = Path(__file__).resolve().parents[2]


def _with_cmdline(*argv: str) -> list[psutil.Process]:
    found = []
    for proc in psutil.process_iter(["cmdline"]):
        try:
            if proc.info["cmdline"] == list(argv) and proc.status() != psutil.STATUS_ZOMBIE:
                found.append(proc)
        except psutil.Error:
            continue
    return found


def _gone_within(seconds: float, procs: list[psutil.Process]) -> bool:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        alive = []
        for p in procs:
            try:
                if p.is_running() and p.status() != psutil.STATUS_ZOMBIE:
                    alive.append(p)
            except psutil.NoSuchProcess:
                pass
        if not alive:
            return True
        time.sleep(0.1)
    return False


def _spin_under_backstop() -> None:
    _proc._cpu_backstop(0.0)
    while True:
        pass


def test_the_kernel_stops_a_child_past_its_cpu_limit_without_the_parent():
    child = multiprocessing.get_context("fork").Process(target=_spin_under_backstop)
    child.start()
    child.join(20)
    assert child.exitcode == -signal.SIGXCPU  # RLIMIT_CPU: the 1 s margin


def test_a_planner_binary_that_setsids_a_sleeper_leaves_nothing(tmp_path):
    result = solve(tiny_classical(), _config(tmp_path, "setsid", "321.25", timeout=10))
    assert result.status != "solved" and not _proc.group_alive(result.pgid)
    assert _gone_within(2, _with_cmdline("sleep", "321.25"))
    assert not _with_cmdline("sleep", "321.25")


CALLER = textwrap.dedent("""
    import re, subprocess, sys
    from ocplus_plan.planning import _proc

    def engine():
        subprocess.Popen(["setsid", "sleep", "321.5"])
        re.match(r"(a*)*b", "a" * 40)  # native code that holds the GIL for hours

    print(_proc.run_isolated(engine, (), hard_limit=300, cpu_limit=200))
""")


def test_an_engine_holding_the_gil_dies_within_5_s_of_its_killed_caller(tmp_path):
    script = tmp_path / "caller.py"
    script.write_text(CALLER)
    caller = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 30
        while not _with_cmdline("sleep", "321.5") and time.monotonic() < deadline:
            time.sleep(0.1)
        started = psutil.Process(caller.pid).children(recursive=True)
        assert _with_cmdline("sleep", "321.5"), "the engine never started"
        caller.send_signal(signal.SIGKILL)
        caller.wait(5)
        assert _gone_within(5, started + _with_cmdline("sleep", "321.5"))
    finally:
        caller.kill()


def test_sigterm_ends_solve_and_its_engine_within_5_s(tmp_path):
    _config(tmp_path, "spin", timeout=60)  # toy.yaml
    solver = subprocess.Popen([sys.executable, "-m", "ocplus_plan.cli", "solve", "--preset",
                               "easy", "--planner", str(tmp_path / "toy.yaml"), "--timeout", "60",
                               "--json"], cwd=ROOT, stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE)
    try:
        deadline = time.monotonic() + 30
        spinning: list[psutil.Process] = []
        while not spinning and time.monotonic() < deadline:
            time.sleep(0.1)
            spinning = [p for p in psutil.Process(solver.pid).children(recursive=True)
                        if "spin" in p.cmdline()]
        assert spinning, "the engine never started"
        started = psutil.Process(solver.pid).children(recursive=True)
        t0 = time.monotonic()
        solver.send_signal(signal.SIGTERM)
        assert solver.wait(5) == 143
        assert _gone_within(5 - (time.monotonic() - t0), started)
    finally:
        solver.kill()


LOST_SIGTERM = textwrap.dedent("""
    import os, signal, subprocess, time
    from ocplus_plan.planning._proc import reaping, sigterm_exits

    class Finalized:
        def __del__(self):  # SIGTERM lands here: its exception is printed and lost
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.2)

    with sigterm_exits(), reaping():
        subprocess.Popen(["sleep", "321.125"])
        Finalized()
        time.sleep(60)
""")


def test_a_sigterm_whose_exception_is_lost_still_ends_the_command(tmp_path):
    script = tmp_path / "lost.py"
    script.write_text(LOST_SIGTERM)
    t0 = time.monotonic()
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          timeout=30)
    assert proc.returncode == 143 and "Exception ignored" in proc.stderr
    assert time.monotonic() - t0 < 20
    assert _gone_within(5, _with_cmdline("sleep", "321.125"))
