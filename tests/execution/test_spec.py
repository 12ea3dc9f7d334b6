"""The planner spec ``planner:NAME:GRANULARITY:POLICY:OPTIONS``, parsed once."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ocplus_plan.errors import ConfigError
from ocplus_plan.execution.spec import DEFAULT_PLANNER, PlannerSpec


def test_empty_fields_take_the_defaults():
    spec = PlannerSpec.parse("fast-downward")
    assert (spec.name, spec.granularity, spec.policy) == ("fast-downward", "stations", "on_event")
    assert PlannerSpec.parse(None).name == DEFAULT_PLANNER
    assert PlannerSpec.parse("").name == DEFAULT_PLANNER
    assert PlannerSpec.parse("::periodic(5)").policy == "periodic(5)"


def test_the_default_planner_is_a_shipped_cost_aware_entry():
    # the default searches on the compiled costs (walking distances, chop/cook/wash steps):
    # lama-first searches on plan length, and its plans walked 1.8x the optimum on a
    # generated corridor kitchen (docs/executive.md, "The default planner")
    pytest.importorskip("unified_planning")
    from ocplus_plan.planning.engines import get_planner

    config = get_planner(DEFAULT_PLANNER)
    assert config.encoding == "classical"
    assert "lazy_wastar" in config.params["fast_downward_search_config"]


def test_options_become_fields():
    spec = PlannerSpec.parse("fast-downward-bjolp:stations:on_event:one-cook+chain2+no-schedule")
    assert spec.name == "fast-downward-bjolp"
    assert (spec.plan_cooks, spec.chain_orders, spec.schedule_cooks) == ("one", 2, False)
    assert PlannerSpec.parse("kairos:::anticipate").anticipate_switches
    assert PlannerSpec.parse("x:::over-switches").over_switches is True
    assert PlannerSpec.parse("x:::no-over-switches").over_switches is False
    assert PlannerSpec.parse("x").over_switches is None


def test_too_many_fields_is_refused_with_the_form():
    with pytest.raises(ConfigError, match="at most four fields"):
        PlannerSpec.parse("a:b:c:d:e")


def test_an_unknown_option_is_refused_with_the_known_ones():
    with pytest.raises(ConfigError, match="unknown option 'twice'.*chainK"):
        PlannerSpec.parse("fast-downward:stations:on_event:twice")


@given(st.sampled_from(["fast-downward", "kairos"]), st.sampled_from(["stations", "cells"]),
       st.booleans(), st.integers(1, 5), st.booleans(), st.sampled_from([None, True, False]))
def test_spec_text_parses_back_to_the_same_spec(name, gran, one, chain, sched, over):
    spec = PlannerSpec(name, gran, "on_event", plan_cooks="one" if one else "all",
                       chain_orders=chain, schedule_cooks=sched, over_switches=over)
    assert PlannerSpec.parse(spec.spec_text()) == spec


def test_the_runner_checks_a_spec_by_its_name_and_its_options(tmp_path):
    from ocplus_plan.eval.runner import check_agent

    with pytest.raises(ConfigError, match="unknown option"):
        check_agent("planner:fast-downward:stations:on_event:sometimes")


def test_walks_over_switches_by_default_only_for_chained_plans_on_switching_maps():
    from ocplus_plan.execution.spec import walks_over_switches

    assert walks_over_switches(None, 2, dynamic=True)
    assert not walks_over_switches(None, 1, dynamic=True)
    assert not walks_over_switches(None, 2, dynamic=False)
    assert not walks_over_switches(False, 2, dynamic=True)
    assert walks_over_switches(True, 1, dynamic=True)
    assert PlannerSpec.parse("fast-downward:::chain2").over_switches_for(True)
