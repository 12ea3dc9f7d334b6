"""Reference plans from a portfolio: lama-first, then optimal and cost-aware searches,
each plan replayed in the simulator; a fallback to every registered planner."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.eval.suite import (
    OPTIMAL_PLANNERS,
    REFERENCE_PLANNERS,
    SuiteSpec,
    export_suite,
    reference_plan,
)
from ocplus_plan.planning import compile
from ocplus_plan.planning.engines import availability
from ocplus_plan.sim import make_rules
from ocplus_plan.planning.fidelity import sample_state

warnings.simplefilter("ignore", UserWarning)


def _require(*names: str) -> None:
    for name in names:
        if not availability(name).ok:
            pytest.skip(f"{name} unavailable: {availability(name).reason}")


def _instance(preset: str, cooks: int) -> tuple[object, object]:
    state = sample_state(make_rules(preset, n_agents=cooks), 0, 0, 120)
    return compile(state, encoding="classical", max_orders=1), state


def _ghost(tmp_path: Path) -> str:
    """A planner config whose program does not exist (unavailable: it solves nothing)."""
    path = tmp_path / "ghost.yaml"
    path.write_text("name: ghost\nencoding: classical\n"
                    "command: [./no-such-planner, '{domain}', '{problem}', '{plan}']\n", "utf-8")
    return str(path)


def test_the_classical_portfolio_starts_with_lama_first_then_an_optimal_search():
    assert REFERENCE_PLANNERS["classical"][0] == "fast-downward"
    assert set(REFERENCE_PLANNERS["classical"][1:]) & OPTIMAL_PLANNERS


def test_every_portfolio_plan_is_replayed_and_the_reference_says_if_it_is_optimal():
    _require(*REFERENCE_PLANNERS["classical"])
    compiled, state = _instance("easy", 1)
    plan, info, rows = reference_plan(compiled, state, REFERENCE_PLANNERS["classical"], 20)
    assert plan is not None and [r["planner"] for r in rows] == \
        list(REFERENCE_PLANNERS["classical"])
    solved = {n: e for n, e in info["portfolio"].items() if e["value"] is not None}
    assert solved and all(isinstance(e["faithful"], bool) for e in solved.values())
    optimum = [e["value"] for n, e in solved.items() if n in OPTIMAL_PLANNERS]
    assert info["optimal"] is bool(optimum and info["cost"] == min(optimum))
    assert info["engine"] == "fast-downward" and info["faithful"] in (True, False)
    assert all(r["cpu_time"] is not None for r in rows)


def test_a_faithful_plan_is_preferred_to_a_cheaper_unfaithful_one():
    """Easy with two cooks: the portfolio's reference is a plan the league's judge
    realises in the kitchen."""
    _require(*REFERENCE_PLANNERS["classical"])
    compiled, state = _instance("easy", 2)
    _, info, _ = reference_plan(compiled, state, REFERENCE_PLANNERS["classical"], 20)
    faithful = [n for n, e in info["portfolio"].items() if e["faithful"]]
    assert faithful, info["portfolio"]
    assert info["faithful"] is True and info["planner"] in faithful


def test_when_the_portfolio_solves_nothing_every_registered_planner_is_tried(tmp_path):
    _require("fast-downward")
    compiled, state = _instance("easy", 1)
    plan, info, rows = reference_plan(compiled, state, (_ghost(tmp_path),), 20)
    assert info["portfolio"]["ghost"]["status"] == "unavailable"
    assert plan is not None and info["planner"] == "fast-downward"  # the first that solved
    assert len(rows) == 2


def test_without_the_fallback_an_unsolved_instance_has_no_reference(tmp_path):
    compiled, state = _instance("easy", 1)
    plan, info, rows = reference_plan(compiled, state, (_ghost(tmp_path),), 20,
                                      fallback=False)
    assert plan is None and "planner" not in info and len(rows) == 1
    assert info["tried"] == {"ghost": "unavailable"}


def test_the_manifest_names_the_engine_and_the_portfolio(tmp_path):
    _require(*REFERENCE_PLANNERS["classical"])
    spec = SuiteSpec(presets=("easy",), cooks=(2,), encodings=("classical",), timeout=20)
    export_suite(spec, tmp_path / "set")
    ref = json.loads((tmp_path / "set/p01/manifest.json").read_text())[
        "encodings"]["classical"]["reference"]
    assert ref["planner"] in REFERENCE_PLANNERS["classical"] and ref["engine"]
    assert set(ref["portfolio"]) == set(REFERENCE_PLANNERS["classical"])
    assert isinstance(ref["optimal"], bool) and ref["faithful"] is True
    assert not any("time" in k for e in ref["portfolio"].values() for k in e)  # same bytes


def test_the_reference_is_the_best_plan_the_league_judge_accepts(monkeypatch):
    """The cheaper plan is refused by the judge (its failing step recorded in the
    portfolio); the reference is the dearer one the judge realises, with its waits."""
    from ocplus_plan.eval import suite
    from ocplus_plan.planning import engines

    compiled, state = _instance("easy", 1)
    values = {"cheap": 10.0, "dear": 12.0}

    def solve(problem, name, **kw):
        return engines.PlanResult("solved", name, name, plan=name, cost=values[name],
                                  plan_length=3, validated=True, validation_detail="ok")

    def judge_plan(compiled, plan, state):
        if plan == "cheap":
            return {"faithful": False, "judged": "realised", "waits": 0, "failed_step": 4,
                    "divergence": "the kitchen reported ['wrong_delivery']"}
        return {"faithful": True, "judged": "realised", "waits": 3, "failed_step": None,
                "divergence": None}

    monkeypatch.setattr(engines, "solve", solve)
    monkeypatch.setattr(suite, "judge_plan", judge_plan)
    plan, info, _ = reference_plan(compiled, state, ("cheap", "dear"), 5, fallback=False)
    assert plan == "dear" and info["faithful"] is True and info["waits"] == 3
    assert info["failed_step"] is None and info["cost"] == 12.0
    assert info["portfolio"]["cheap"] == {"status": "solved", "value": 10.0,
                                          "faithful": False, "waits": 0, "failed_step": 4,
                                          "optimal": False}
    # when the judge refuses every plan, the best refused one is kept, with its step
    monkeypatch.setattr(suite, "judge_plan", lambda c, p, s: judge_plan(c, "cheap", s))
    plan, info, _ = reference_plan(compiled, state, ("cheap", "dear"), 5, fallback=False)
    assert plan == "cheap" and info["faithful"] is False and info["failed_step"] == 4
    assert info["divergence"] == "the kitchen reported ['wrong_delivery']"
