"""How engine reports become statuses: an incomplete search that stops is no proof (LPG),
a binary's compiled-in limits are ``unsupported``, running out of memory is ``memout``."""

from __future__ import annotations

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.planning.engines import PlanResult, _from_report, availability, solve


def _status(up_status: str, log: str) -> PlanResult:
    report = {"notes": [], "up_status": up_status, "log": log, "steps": None,
              "temporal": True}
    return _from_report(PlanResult("unavailable", "ocplus-lpg", "lpg"), report, None, True, True)


def test_a_search_that_stops_without_a_plan_gave_up():
    result = _status("UNSOLVABLE_INCOMPLETELY", "search limit exceeded.")
    assert result.status == "gave-up" and "UNSOLVABLE_INCOMPLETELY" in result.reason


def test_a_proof_is_unsolvable():
    assert _status("UNSOLVABLE_PROVEN", "").status == "unsolvable"


def test_lpg_compiled_in_limits_are_unsupported_with_the_limit_named():
    result = _status("INTERNAL_ERROR", "   LPG should be recompiled with a higher value for "
                                       "the parameter MAX_VARS.\n")
    assert result.status == "unsupported" and "MAX_VARS" in result.reason


@pytest.mark.parametrize("log", ["java.lang.OutOfMemoryError: Java heap space",
                                 "terminate called after throwing std::bad_alloc"])
def test_running_out_of_memory_is_memout(log):
    assert _status("INTERNAL_ERROR", log).status == "memout"


def test_lpg_on_the_easy_kitchen_does_not_claim_a_proof():
    if not availability("lpg").ok:
        pytest.skip(availability("lpg").reason)
    from ocplus_plan.planning import compile
    from ocplus_plan.sim import make_rules, new_state

    problem = compile(new_state(make_rules("easy"), 0), encoding="temporal").problem
    assert solve(problem, "lpg", timeout=10).status in ("solved", "gave-up", "timeout")
