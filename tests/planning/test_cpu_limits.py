"""Planner limits in CPU seconds (as the IPC counts them), with a wall-clock safety.

The test engine here burns a given number of CPU seconds in a grandchild process (so
the group's CPU time, not the child's own, is what must be counted) and then returns
the tiny problem's plan. "Beside busy processes" means the planner and two spinning
processes share one core (CPU affinity), so the planner gets about a third of it.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import sys
import time
from collections.abc import Iterator

import pytest

pytest.importorskip("unified_planning")

from unified_planning.engines import Engine, PlanGenerationResult, PlanGenerationResultStatus
from unified_planning.engines.mixins import OneshotPlannerMixin
from unified_planning.model import ProblemKind
from unified_planning.plans import ActionInstance, SequentialPlan
from unified_planning.shortcuts import get_environment

from ocplus_plan.errors import PlannerError
from ocplus_plan.planning import _proc
from ocplus_plan.planning.engines import PlannerConfig, solve, wall_safety

from .test_engines import SleepyEngine, _require, tiny_classical

#: CPU seconds the busy engine burns, by engine name
_BURN = {"test-burn-1": 1.0, "test-burn-forever": 600.0}


def _spin(seconds: float) -> None:
    """Burn ``seconds`` of CPU in a new Python process (a grandchild of the solve call)."""
    import subprocess

    code = ("import time\nt = time.process_time()\n"
            f"while time.process_time() - t < {seconds}:\n    pass\n")
    subprocess.run([sys.executable, "-c", code], check=True)


class BurnEngine(Engine, OneshotPlannerMixin):
    """Test-only engine: burns CPU seconds in a grandchild, then answers with the plan."""

    def __init__(self, **_: object) -> None:
        Engine.__init__(self)
        OneshotPlannerMixin.__init__(self)

    @property
    def name(self) -> str:
        return "test-burn"

    @staticmethod
    def supported_kind() -> ProblemKind:
        return tiny_classical().kind

    @staticmethod
    def supports(problem_kind: ProblemKind) -> bool:
        return problem_kind <= BurnEngine.supported_kind()

    def _solve(self, problem, heuristic=None, timeout=None, output_stream=None):
        _spin(_BURN[os.environ["TEST_BURN_ENGINE"]])
        move = problem.action("move")
        objs = [problem.object(n) for n in ("l0", "l2", "l3")]
        plan = SequentialPlan([ActionInstance(move, (objs[0], objs[1])),
                               ActionInstance(move, (objs[1], objs[2]))])
        return PlanGenerationResult(PlanGenerationResultStatus.SOLVED_SATISFICING, plan,
                                    self.name)


def _config(name: str, cls: type = BurnEngine, timeout: float = 5.0) -> PlannerConfig:
    factory = get_environment().factory
    engine = cls.__name__.lower()
    if engine not in factory.engines:
        factory.add_engine(engine, __name__, cls.__name__)
    return PlannerConfig(name=name, engine=engine, encoding="classical", timeout=timeout,
                         env={"TEST_BURN_ENGINE": name})


def _busy() -> None:
    while True:
        pass


@contextlib.contextmanager
def _one_core_beside(n_busy: int) -> Iterator[None]:
    """This process (and so every planner it starts) and ``n_busy`` spinning processes
    on one core."""
    core = {min(os.sched_getaffinity(0))}
    before = os.sched_getaffinity(0)
    ctx = multiprocessing.get_context("fork")
    busy = [ctx.Process(target=_busy, daemon=True) for _ in range(n_busy)]
    for proc in busy:
        proc.start()
        os.sched_setaffinity(proc.pid, core)
    os.sched_setaffinity(0, core)
    try:
        yield
    finally:
        os.sched_setaffinity(0, before)
        for proc in busy:
            proc.kill()
            proc.join(5)


def test_the_cpu_limit_stops_a_planner_by_the_cpu_seconds_of_its_whole_group() -> None:
    result = solve(tiny_classical(), _config("test-burn-forever"), timeout=1.0)
    assert result.status == "timeout" and result.limit_hit == "cpu", result.reason
    assert "CPU limit of 1 s" in result.reason
    assert result.cpu_time is not None and 1.0 <= result.cpu_time < 2.0  # the grandchild's
    assert result.cpu_limit == 1.0 and not _proc.group_alive(result.pgid)


def test_a_planner_that_waits_without_computing_is_stopped_by_the_wall_safety() -> None:
    config = _config("test-sleepy-cpu", SleepyEngine)
    start = time.monotonic()
    result = solve(tiny_classical(), config, timeout=60, wall_limit=0.5)
    assert result.status == "timeout" and result.limit_hit == "wall", result.reason
    assert time.monotonic() - start < 10 and result.cpu_time is not None
    assert result.cpu_time < 1.0 and not _proc.group_alive(result.pgid)


def test_the_wall_safety_defaults_to_a_multiple_of_the_cpu_limit_plus_slack() -> None:
    result = solve(tiny_classical(), _config("test-burn-1"), timeout=3.0)
    assert result.status == "solved", result.reason
    assert result.wall_limit == wall_safety(3.0) and wall_safety(3.0) > 3 * 3.0
    assert result.cpu_time is not None and result.cpu_time >= 1.0
    assert result.to_dict()["wall_time"] == result.planning_time


@pytest.mark.parametrize("bad", [0, -1, float("nan"), float("inf")])
def test_a_limit_that_is_not_a_positive_number_is_refused(bad: float) -> None:
    with pytest.raises(PlannerError, match="timeout must be a positive number of CPU seconds"):
        solve(tiny_classical(), _config("test-burn-1"), timeout=bad)
    with pytest.raises(PlannerError, match="wall_limit must be a positive"):
        solve(tiny_classical(), _config("test-burn-1"), timeout=1, wall_limit=bad)


def test_the_same_outcome_beside_busy_processes() -> None:
    """A planner that needs 1 CPU second, limited to 2: alone it is done in about a second;
    sharing one core with two spinning processes its wall time stretches past the limit,
    and it still gets its CPU seconds and returns the same plan."""
    config = _config("test-burn-1")
    alone = solve(tiny_classical(), config, timeout=2.0)
    with _one_core_beside(2):
        loaded = solve(tiny_classical(), config, timeout=2.0)
    assert alone.status == loaded.status == "solved", (alone.reason, loaded.reason)
    assert alone.steps == loaded.steps
    assert loaded.cpu_time is not None and loaded.cpu_time < 2.0
    assert loaded.planning_time > 2.0  # a 2 s wall-clock limit would have cut it off


def test_fast_downward_gives_the_same_plan_beside_busy_processes() -> None:
    _require("fast-downward")
    alone = solve(tiny_classical(), "fast-downward", timeout=20)
    with _one_core_beside(2):
        loaded = solve(tiny_classical(), "fast-downward", timeout=20)
    assert alone.status == loaded.status == "solved", (alone.reason, loaded.reason)
    assert alone.steps == loaded.steps and alone.cost == loaded.cost
    assert loaded.cpu_time is not None and loaded.cpu_time < 20
