"""The llm controller with scripted models: replies are parsed, never evaluated; a reply
that cannot be read names its line, the cooks stay and the error is counted."""

from __future__ import annotations

import pytest

from ocplus_plan.agents import make_controller, run_episode
from ocplus_plan.agents.llm import LLMAgent, parse_actions
from ocplus_plan.errors import ConfigError, UnreadableText
from ocplus_plan.sim import make_rules, new_state
from ocplus_plan.sim.codes import Action

R, D, L, U, S = (int(a) for a in Action)


def easy(n_agents: int = 1):
    return new_state(make_rules("easy", n_agents=n_agents), 0)


# ---------------------------------------------------------------- reading replies
def test_a_bare_action_drives_the_only_cook():
    assert parse_actions("Up.", (0,)) == [U]


def test_cook_lines_come_back_in_agent_order():
    assert parse_actions("cook 1: left\n\ncook 0: 4", (0, 1)) == [S, L]


def test_a_markdown_fence_around_the_reply_is_skipped():
    assert parse_actions("```\ncook 0: down\n```", (0,)) == [D]


def test_an_unknown_action_names_its_line():
    with pytest.raises(UnreadableText, match="line 2: 'jump' is not an action") as err:
        parse_actions("\ncook 0: jump", (0,))
    assert err.value.line == 2


def test_an_action_number_out_of_range_is_refused():
    with pytest.raises(UnreadableText, match="line 1: 7 is not an action number"):
        parse_actions("cook 0: 7", (0,))


@pytest.mark.parametrize("cook", ["x", "1.5", "99999999999999999999999"])
def test_a_cook_number_that_is_not_one_is_refused(cook):
    with pytest.raises(UnreadableText, match="is not a cook number"):
        parse_actions(f"cook {cook}: up", (0,))


def test_a_cook_that_is_not_driven_is_refused():
    with pytest.raises(UnreadableText, match="cook 3 is not one of the cooks you drive"):
        parse_actions("cook 3: up", (0, 1))


def test_a_line_of_garbage_is_refused():
    with pytest.raises(UnreadableText, match="line 2: .* is not 'cook N: ACTION'"):
        parse_actions("cook 0: up\nNote: the pan is hot", (0, 1))


def test_python_in_a_reply_is_text_not_code():
    with pytest.raises(UnreadableText, match="line 1"):
        parse_actions("__import__('os').system('echo hi')", (0,))


def test_a_huge_reply_is_refused_unread():
    with pytest.raises(UnreadableText, match="more than the limit of 100") as err:
        parse_actions("up\n" * 60, (0,), max_chars=100)
    assert err.value.line == 34


def test_a_cook_given_twice_is_refused():
    with pytest.raises(UnreadableText, match="line 2: cook 0 already has an action"):
        parse_actions("cook 0: up\ncook 0: down", (0, 1))


def test_a_cook_left_out_is_refused():
    with pytest.raises(UnreadableText, match="no action for cook 1"):
        parse_actions("cook 0: up", (0, 1))


# ---------------------------------------------------------------- the controller
def test_an_unreadable_reply_keeps_the_cook_in_place_and_is_counted():
    state = easy()
    agent = LLMAgent(lambda prompt: "jump")
    start = state.agent_pos[0]
    run_episode(state, agent, steps=3)
    info = agent.info()
    assert state.agent_pos[0] == start and info["reply_errors"] == 3


def test_a_model_that_raises_counts_as_an_error():
    def broken(prompt: str) -> str:
        raise TimeoutError("no answer")

    agent = LLMAgent(broken)
    run_episode(easy(), agent, steps=1)
    assert "the model call failed: TimeoutError" in agent.info()["transcript"][0]["error"]


def test_a_reply_that_is_not_text_counts_as_an_error():
    agent = LLMAgent(lambda prompt: None)
    run_episode(easy(), agent, steps=1)
    assert agent.info()["reply_errors"] == 1


def test_the_prompt_holds_the_text_observation_and_is_logged():
    agent = LLMAgent(lambda prompt: "stay")
    run_episode(easy(), agent, steps=2)
    entry = agent.info()["transcript"][1]
    assert entry["t"] == 1 and "Orders, oldest first" in entry["prompt"]
    assert entry["reply"] == "stay"


def test_the_last_error_is_told_to_the_model():
    prompts = []
    agent = LLMAgent(lambda prompt: prompts.append(prompt) or "cook 9: up")
    run_episode(easy(), agent, steps=2)
    assert "could not be used" not in prompts[0] and "cook 9 is not one of" in prompts[1]


def test_log_errors_keeps_only_the_failed_exchanges():
    replies = iter(["up", "jump", "down"])
    agent = LLMAgent(lambda prompt: next(replies), log="errors")
    run_episode(easy(), agent, steps=3)
    assert [e["reply"] for e in agent.info()["transcript"]] == ["jump"]


def test_a_model_reading_the_action_words_picks_up_the_tomato_beside_it():
    from tests.agents.scripted_models import first_useful

    spec = {"name": "tiny", "game_map": [[1, 3, 6, 1], [1, 0, 0, 7], [1, 1, 1, 5]],
            "agent_spawn_points": [[1, 1]]}
    state = new_state(make_rules("easy", map=spec, n_agents=1, recipes=["tomato"]), 0)
    agent = LLMAgent(first_useful)
    run_episode(state, agent, steps=1)
    assert state.item_name(state.agent_hand[0]) == "tomato0"
    assert agent.info()["transcript"][0]["reply"] == "cook 0: up"


def test_the_factory_imports_the_model_by_path():
    agent = make_controller("llm:tests.agents.scripted_models:always_right")
    state = easy(2)
    run_episode(state, agent, steps=1)
    assert agent.info()["model"] == "always_right" and agent.info()["reply_errors"] == 0


@pytest.mark.parametrize("spec, message", [
    ("llm", "needs the model"),
    ("llm:no_such_module_xyz:ask", "cannot import"),
    ("llm:tests.agents.scripted_models:nothing", "has no attribute"),
    ("llm:tests.agents.scripted_models:re", "not a callable"),
    ("llm:tests.agents.scripted_models:gibberish:dream", "llm mode must be one of"),
    ("llm:os.system('x'):f", "MODULE:FUNCTION"),
])
def test_bad_llm_specs_say_what_to_write(spec, message):
    with pytest.raises(ConfigError, match=message):
        make_controller(spec)


def test_ocplus_eval_runs_a_model_given_by_path_and_keeps_its_transcript(tmp_path, capsys):
    from ocplus_plan.cli import main
    from ocplus_plan.eval.results import read_results

    out = tmp_path / "llm"
    assert main(["eval", "--presets", "easy", "--agents",
                 "llm:tests.agents.scripted_models:gibberish", "--seeds", "1", "--horizon", "3",
                 "--out", str(out), "--quiet"]) == 0
    capsys.readouterr()
    row = read_results(out)[0]
    assert row["status"] == "ok" and row["planner"]["reply_errors"] == 3
    assert len(row["controller"]["transcript"]) == 3
