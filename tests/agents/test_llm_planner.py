"""The llm controller as a planner: the model's plan is read, validated and run by the
executive like any planner's; a plan that cannot be read or is invalid is refused."""

from __future__ import annotations

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.agents import run_episode
from ocplus_plan.agents.llm import LLMAgent
from ocplus_plan.sim import make_rules, new_state
from tests.planning.test_plan_text import PLAN, TINY

TEMPORAL_PLAN = """0.000: (pick a0 tomato0 tomato_0_1 s_1_1) [1.000]
1.001: (move a0 s_1_1 s_1_2) [1.000]
2.002: (put_board a0 tomato0 board_0_2 s_1_2) [1.000]
3.003: (chop a0 tomato0 board_0_2 s_1_2) [3.000]
6.004: (move a0 s_1_2 s_1_1) [1.000]
7.005: (pick a0 plate0 plate_1_0 s_1_1) [1.000]
8.006: (move a0 s_1_1 s_1_2) [1.000]
9.007: (plate_take a0 tomato0 board_0_2 s_1_2 plate0 k_tomato c_empty c_tomato) [1.000]
10.008: (deliver1 a0 plate0 c_tomato c_empty o0 o_none delivery_1_3 s_1_2 plate_1_0 tomato0 tomato_0_1) [1.000]
"""


def tiny():
    return new_state(make_rules("easy", map=TINY, n_agents=1, recipes=["tomato"]), 0)


def scripted(*replies: str):
    """A model that answers with these replies in turn, then with an empty plan."""
    queue = list(replies)
    return lambda prompt: queue.pop(0) if queue else ""


@pytest.mark.parametrize("encoding, reply", [("classical", PLAN), ("temporal", TEMPORAL_PLAN)])
def test_the_models_plan_is_executed_and_serves_the_order(encoding, reply):
    agent = LLMAgent(scripted(reply), mode="planner", encoding=encoding, max_orders=1,
                     use_val=False, policy="never")
    summary = run_episode(tiny(), agent, steps=14)
    assert summary["dishes_served"] == 1 and agent.info()["statuses"]["solved"] >= 1


def test_the_prompt_holds_the_kitchen_and_the_pddl_problem():
    prompts = []
    agent = LLMAgent(lambda p: prompts.append(p) or PLAN, mode="planner", max_orders=1,
                     use_val=False)
    run_episode(tiny(), agent, steps=1)
    assert "Orders, oldest first" in prompts[0] and "(:objects" in prompts[0]


def test_a_plan_with_an_unknown_action_is_refused_and_counted():
    agent = LLMAgent(scripted("(teleport a0 s_1_2)"), mode="planner", max_orders=1)
    state = tiny()
    start = state.agent_pos[0]
    run_episode(state, agent, steps=1)
    info = agent.info()
    assert info["statuses"] == {"unreadable": 1} and info["reply_errors"] == 1
    assert state.agent_pos[0] == start and "unknown action 'teleport'" in \
        info["transcript"][0]["error"]


def test_a_plan_the_validator_rejects_is_refused():
    agent = LLMAgent(scripted("(move a0 s_1_1 s_1_2)"), mode="planner", max_orders=1)
    run_episode(tiny(), agent, steps=1)
    info = agent.info()
    assert info["statuses"] == {"invalid": 1}
    assert "not valid for the problem" in info["transcript"][0]["error"]


def prompts_of(domain: str, preset: str = "easy") -> str:
    seen: list[str] = []
    agent = LLMAgent(lambda p: seen.append(p) or "", mode="planner", max_orders=1,
                     use_val=False, domain=domain)
    state = new_state(make_rules(preset), 0)
    agent.reset(state)
    agent.act(state)
    return seen[0]


def test_the_planner_prompt_gives_the_domain_in_words_and_cut_to_the_kitchen():
    prompt = prompts_of("both")
    assert "The actions a plan can use here:" in prompt and "Domain:\n(define" in prompt
    assert "(:action wash" not in prompt and "(:action cook" not in prompt  # easy: no sink, pan
    assert "(:action chop" in prompt and "\nchop(" in prompt  # in PDDL and in words


@pytest.mark.parametrize("domain, words, pddl", [("english", True, False), ("pddl", False, True)])
def test_the_planner_prompt_can_give_the_domain_one_way(domain, words, pddl):
    prompt = prompts_of(domain)
    assert ("The actions a plan can use here:" in prompt) is words
    assert ("Domain:\n(define" in prompt) is pddl
    assert "Problem:\n(define" in prompt


def test_an_unknown_domain_form_is_refused():
    from ocplus_plan.errors import ConfigError

    with pytest.raises(ConfigError, match="both, english, pddl"):
        LLMAgent(lambda p: "", mode="planner", domain="latex")
