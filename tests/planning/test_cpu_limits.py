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


def _spin_in_own_session() -> None:
    """Start a spinning grandchild in a session of its own (as unified-planning starts
    Fast Downward) and wait for it."""
    import subprocess

    subprocess.run([sys.executable, "-c", "while True: pass"], start_new_session=True,
                   check=False)


def test_a_planner_in_a_session_of_its_own_is_counted_and_killed() -> None:
    outcome = _proc.run_isolated(_spin_in_own_session, (), hard_limit=120, cpu_limit=1.0)
    assert outcome.kind == _proc.TIMEOUT and outcome.limit == "cpu", outcome.value
    assert len(outcome.groups) == 2 and outcome.groups[0] == outcome.pgid
    assert not any(_proc.group_alive(g) for g in outcome.groups)


def test_fast_downwards_search_is_stopped_at_the_cpu_limit() -> None:
    """BJOLP on medium with two cooks needs far more than 2 CPU seconds; Fast Downward runs
    in a session of its own, whose CPU seconds count."""
    _require("fast-downward-bjolp")
    from ocplus_plan.planning import compile
    from ocplus_plan.sim import make_rules, new_state

    problem = compile(new_state(make_rules("medium", n_agents=2), 0), max_orders=1).problem
    result = solve(problem, "fast-downward-bjolp", timeout=2.0)
    assert result.status == "timeout" and result.limit_hit == "cpu", result.reason
    assert result.cpu_time is not None and 2.0 <= result.cpu_time < 4.0
    assert result.planning_time < wall_safety(2.0)


def test_the_planner_agent_sums_the_cpu_seconds_of_its_calls_for_the_eval_rows() -> None:
    _require("fast-downward")
    from ocplus_plan.agents import run_episode
    from ocplus_plan.agents.planner import PlannerAgent
    from ocplus_plan.eval.metrics import controller_metrics
    from ocplus_plan.sim import make_rules, new_state

    agent = PlannerAgent("fast-downward", timeout=20)
    run_episode(new_state(make_rules("easy"), 0), [(agent, [0])], None, 3)
    info = agent.info()
    assert info["planner_calls"] >= 1 and 0 < info["planning_cpu_s"] < 20 * info["planner_calls"]
    assert controller_metrics(info)["planning_cpu_s"] == info["planning_cpu_s"]
