"""Planner binaries (``command:`` in a planner YAML): isolation, plan files, refusals.

Every planner here is ``command_planner.py`` (next to this file), run by the venv's
Python on the tiny problem of ``test_engines.py`` (l0 -> l3; the best plan is
``(move l0 l2) (move l2 l3)``), except the last test, which drives the executive.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.errors import PlannerError
from ocplus_plan.planning import _proc
from ocplus_plan.planning.engines import PlannerConfig, availability, get_planner, solve

from .test_engines import tiny_classical

SCRIPT = Path(__file__).with_name("command_planner.py")
GOOD_PLAN = "; a comment line\n0: (move l0 l2)\n\n1: (MOVE L2 L3)   ; case does not matter\n"


def _config(tmp_path: Path, mode: str, extra: str = "", timeout: float = 20,
            name: str = "toy", env: dict[str, str] | None = None) -> PlannerConfig:
    """A YAML planner config in ``tmp_path`` that runs the script in ``mode``."""
    import yaml

    command = [sys.executable, str(SCRIPT), mode, "{domain}", "{problem}", "{plan}"]
    if extra:
        command.append(extra)
    path = tmp_path / f"{name}.yaml"
    path.write_text(yaml.safe_dump({"name": name, "command": command, "encoding": "classical",
                                    "timeout": timeout, "env": env or {}}), encoding="utf-8")
    return get_planner(str(path))


def test_a_binary_plan_is_read_validated_and_costed(tmp_path):
    (tmp_path / "plan.txt").write_text(GOOD_PLAN, encoding="utf-8")
    result = solve(tiny_classical(), _config(tmp_path, "copy", "{config_dir}/plan.txt"))
    assert result.status == "solved", result.reason
    assert result.engine == "command" and result.validated is True
    assert result.cost == 3.0 and [s["args"] for s in result.steps] == [["l0", "l2"], ["l2", "l3"]]


def test_the_last_numbered_plan_of_an_anytime_planner_is_read(tmp_path):
    (tmp_path / "plan.txt").write_text(GOOD_PLAN, encoding="utf-8")
    result = solve(tiny_classical(), _config(tmp_path, "numbered", "{config_dir}/plan.txt"))
    assert result.status == "solved", result.reason  # plan.1 is garbage, plan.2 the plan


def test_a_malformed_plan_is_invalid_and_the_reason_names_the_line(tmp_path):
    (tmp_path / "plan.txt").write_text("(move l0 l2)\nrm -rf / ; (move l2 l3)\n", "utf-8")
    result = solve(tiny_classical(), _config(tmp_path, "copy", "{config_dir}/plan.txt"))
    assert result.status == "invalid"
    assert "line 2" in result.reason and "Traceback" not in result.reason


def test_a_plan_that_breaks_a_precondition_is_invalid(tmp_path):
    (tmp_path / "plan.txt").write_text("(move l0 l3)\n", encoding="utf-8")
    result = solve(tiny_classical(), _config(tmp_path, "copy", "{config_dir}/plan.txt"))
    assert result.status == "invalid" and result.validated is False


def test_the_wall_safety_kills_the_planner_and_what_it_started(tmp_path):
    result = solve(tiny_classical(), _config(tmp_path, "sleep", timeout=5), wall_limit=0.5)
    assert result.status == "timeout" and result.limit_hit == "wall"
    assert _proc.group_members(result.pgid) == []  # the script and its `sleep 60` are gone


def test_the_cpu_limit_stops_a_binary_that_computes(tmp_path):
    result = solve(tiny_classical(), _config(tmp_path, "spin", timeout=1))
    assert result.status == "timeout" and result.limit_hit == "cpu", result.reason
    assert result.cpu_time is not None and 1.0 <= result.cpu_time < 2.0
    assert _proc.group_members(result.pgid) == []


def test_paths_reach_the_planner_as_single_arguments_and_no_shell_runs(tmp_path):
    odd = tmp_path / "a b; touch pwned $(touch pwned2)"
    odd.mkdir()
    result = solve(tiny_classical(), _config(odd, "argv", "{config_dir}/argv.txt",
                                             env={"TOY_PLANNER_ENV": "from the yaml"}))
    argv = (odd / "argv.txt").read_text(encoding="utf-8").splitlines()
    assert argv[0] == "argv" and argv[1].endswith("domain.pddl")
    assert argv[4] == f"{odd}/argv.txt" and argv[5] == "from the yaml"
    assert not list(tmp_path.rglob("pwned*")) and not Path("pwned").exists()
    assert result.status == "unsolvable"  # it exited 0 without a plan


def test_a_failing_planner_without_a_plan_is_an_error(tmp_path):
    result = solve(tiny_classical(), _config(tmp_path, "none", "3"))
    assert result.status == "error" and "code 3" in result.reason


@pytest.mark.parametrize("command, message", [
    (["planner", "{domain}", "{problem}"], "plan"),
    (["planner", "{domain}", "{problem}", "{plan}", "{output}"], "unknown placeholder"),
    ([], "empty"),
    ({"run": "x"}, "list of arguments"),
    ("planner '{domain}", "cannot be split"),
])
def test_bad_commands_are_refused_with_the_reason(command, message):
    with pytest.raises(PlannerError, match=message):
        PlannerConfig.from_mapping({"name": "x", "command": command, "encoding": "classical"})


def test_a_command_and_an_engine_together_are_refused():
    with pytest.raises(PlannerError, match="either"):
        PlannerConfig.from_mapping({"name": "x", "engine": "fast-downward", "encoding":
                                    "classical", "command": ["p", "{domain}", "{problem}",
                                                             "{plan}"]})


def test_a_string_command_is_split_without_a_shell():
    config = PlannerConfig.from_mapping({"name": "x", "encoding": "classical",
                                         "command": "planner --fast '{domain}' {problem} {plan}"})
    assert config.command == ("planner", "--fast", "{domain}", "{problem}", "{plan}")


def test_a_missing_program_makes_the_planner_unavailable(tmp_path):
    path = tmp_path / "ghost.yaml"
    path.write_text("name: ghost\nencoding: classical\n"
                    "command: [./no-such-planner, '{domain}', '{problem}', '{plan}']\n", "utf-8")
    config = get_planner(str(path))
    assert config.command[0] == str(tmp_path / "no-such-planner")  # relative to the YAML
    assert not availability(config).ok and "does not exist" in availability(config).reason
    assert solve(tiny_classical(), config).status == "unavailable"


def test_a_missing_config_file_is_a_planner_error(tmp_path):
    with pytest.raises(PlannerError, match="does not exist"):
        get_planner(str(tmp_path / "nope.yaml"))


def test_a_binary_drives_the_executive(tmp_path):
    """planner:PATH.yaml in the controller registry: the binary plans every (re)plan."""
    from ocplus_plan.agents import make_controller, run_episode
    from ocplus_plan.sim import make_rules, new_state

    if not availability("fast-downward").ok:
        pytest.skip("the script solves with fast-downward, which is unavailable here")
    config = _config(tmp_path, "solve", timeout=30)  # CPU seconds: load does not cut it
    agent = make_controller(f"planner:{tmp_path / 'toy.yaml'}")
    state = new_state(make_rules("easy"), 0)
    run_episode(state, agent, steps=50)  # a plan or two (seconds each: the script imports UP)
    assert agent.info()["planner"] == str(tmp_path / "toy.yaml") and config.name == "toy"
    statuses = agent.info()["statuses"]
    # every call solves: the limit is 30 CPU seconds (the script imports UP and runs Fast
    # Downward in about 2), which a loaded machine stretches in wall time but never cuts
    assert set(statuses) == {"solved"}, (statuses, agent.info().get("failure_messages"))
    assert state.stats["orders_completed"] >= 1
