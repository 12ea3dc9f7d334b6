"""Planner portfolios (planning/portfolio.py): members in turn within one CPU budget."""

from __future__ import annotations

from dataclasses import dataclass, field

import pytest

from ocplus_plan.errors import PlannerError
from ocplus_plan.planning import portfolio
from ocplus_plan.planning.engines import PlanResult, PlannerConfig, availability, solve


def _config(members: list[dict], name: str = "pf") -> PlannerConfig:
    return PlannerConfig.from_mapping({"name": name, "encoding": "classical",
                                       "portfolio": members})


@dataclass
class _Calls:
    answers: dict[str, tuple[str, float]]
    asked: list[tuple[str, float]] = field(default_factory=list)

    def __call__(self, name: str, budget: float) -> PlanResult:
        self.asked.append((name, round(budget, 6)))
        status, cpu = self.answers[name]
        return PlanResult(status=status, engine=name, planner=name, cpu_time=cpu,
                          planning_time=cpu + 0.5)


def _empty() -> PlanResult:
    return PlanResult(status="timeout", engine="portfolio", planner="pf", wall_limit=99.0)


def test_a_member_that_times_out_passes_its_leftover_budget_to_the_next() -> None:
    cfg = _config([{"planner": "a", "share": 0.3}, {"planner": "b"}])
    calls = _Calls({"a": ("timeout", 3.0), "b": ("solved", 1.0)})
    out = portfolio.run(cfg, 10.0, calls, _empty())
    assert calls.asked == [("a", 3.0), ("b", 7.0)]
    assert (out.status, out.planner, out.cpu_time) == ("solved", "pf", 4.0)
    assert out.notes[:2] == ["a: timeout in 3.00 CPU s of 3.00", "b: solved in 1.00 CPU s of 7.00"]


def test_the_first_plan_wins_and_later_members_are_not_asked() -> None:
    cfg = _config([{"planner": "a", "share": 0.3}, {"planner": "b"}])
    calls = _Calls({"a": ("solved", 1.2), "b": ("solved", 0.1)})
    out = portfolio.run(cfg, 10.0, calls, _empty())
    assert [name for name, _ in calls.asked] == ["a"]
    assert out.status == "solved" and out.engine == "a"


def test_a_proof_of_unsolvability_ends_the_portfolio() -> None:
    cfg = _config([{"planner": "a", "share": 0.5}, {"planner": "b"}])
    calls = _Calls({"a": ("unsolvable", 0.2), "b": ("solved", 0.1)})
    assert portfolio.run(cfg, 10.0, calls, _empty()).status == "unsolvable"
    assert len(calls.asked) == 1


def test_when_no_member_answers_the_result_is_a_cpu_timeout_naming_each_member() -> None:
    cfg = _config([{"planner": "a", "share": 0.5}, {"planner": "b"}])
    calls = _Calls({"a": ("error", 0.1), "b": ("timeout", 9.9)})
    out = portfolio.run(cfg, 10.0, calls, _empty())
    assert (out.status, out.limit_hit, out.wall_limit) == ("timeout", "cpu", 99.0)
    assert "a: error" in out.reason and "b: timeout" in out.reason
    assert out.cpu_time == 10.0


@pytest.mark.parametrize("members, match", [
    ([], "non-empty list"),
    ([{"planner": "a"}, {"planner": "b"}], "needs a 'share'"),
    ([{"planner": "a", "share": 0}, {"planner": "b"}], "fraction in"),
    ([{"planner": "a", "share": 1.5}, {"planner": "b"}], "fraction in"),
    ([{"planner": "a", "weight": 1}], "optionally 'share'"),
    (["fast-downward"], "mapping"),
])
def test_bad_member_lists_name_the_member_and_the_fix(members: list, match: str) -> None:
    with pytest.raises(PlannerError, match=match):
        _config(members)


def test_a_portfolio_takes_no_engine_of_its_own() -> None:
    with pytest.raises(PlannerError, match="no 'engine'"):
        PlannerConfig.from_mapping({"name": "pf", "encoding": "classical", "engine": "x",
                                    "portfolio": [{"planner": "fast-downward"}]})


def test_members_must_share_the_encoding_and_not_nest() -> None:
    pytest.importorskip("unified_planning")
    temporal = _config([{"planner": "kairos"}])
    assert "temporal encoding" in availability(temporal).reason
    nested = _config([{"planner": "fast-downward-portfolio"}])
    assert "itself a portfolio" in availability(nested).reason


def test_an_unknown_member_is_named() -> None:
    with pytest.raises(PlannerError, match="unknown planner 'no-such'"):
        availability(_config([{"planner": "no-such"}]))


def test_the_shipped_portfolio_solves_with_its_optimal_member_first() -> None:
    pytest.importorskip("unified_planning")
    if not availability("fast-downward-portfolio").ok:
        pytest.skip(availability("fast-downward-portfolio").reason)
    from ocplus_plan.planning import compile
    from ocplus_plan.sim import make_rules, new_state

    problem = compile(new_state(make_rules("easy", n_agents=1), 0), max_orders=1).problem
    out = solve(problem, "fast-downward-portfolio", timeout=20)
    assert out.status == "solved" and out.validated
    assert out.planner == "fast-downward-portfolio"
    assert out.notes[0].startswith("fast-downward-bjolp: solved")
    # a first member with almost no CPU time times out; lama-first then solves
    cfg = _config([{"planner": "fast-downward-bjolp", "share": 0.001},
                   {"planner": "fast-downward"}])
    out = solve(problem, cfg, timeout=20)
    assert out.status == "solved" and out.engine == "fast-downward"
    assert out.notes[0].startswith("fast-downward-bjolp: timeout")
