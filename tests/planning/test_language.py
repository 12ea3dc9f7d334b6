"""The model in English: generated from the model, complete, and about this kitchen."""

from __future__ import annotations

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.planning import compile
from ocplus_plan.planning.language import (
    ACTION_WORDS,
    FACT_WORDS,
    action_template,
    check_complete,
    describe_domain,
    describe_problem,
    fact_words,
    kitchen_words,
    object_words,
    step_words,
)
from ocplus_plan.planning.model import ENCODINGS, GRANULARITIES, build_domain
from ocplus_plan.sim import make_rules, new_state

VARIANTS = [(e, g, False) for e in ENCODINGS for g in GRANULARITIES] + [
    ("temporal", "stations", True)]


@pytest.fixture(scope="module")
def medium():
    return compile(new_state(make_rules("medium", n_agents=2), 0), encoding="temporal")


def test_every_fluent_of_the_model_has_words():
    assert check_complete() == []


@pytest.mark.parametrize("encoding, granularity, switches", VARIANTS)
def test_every_action_of_every_domain_has_words(encoding, granularity, switches):
    dom = build_domain(encoding, granularity, 3, switches)
    for name, action in dom.actions.items():
        template = action_template(name)
        assert not template.endswith("{_args}"), name
        params = {p.name for p in action.parameters}
        used = {f for f in params if "{" + f + "}" in template}
        assert used, name  # the template speaks about this action's own parameters


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_a_domain_text_describes_every_action_with_its_conditions(encoding):
    text = describe_domain(encoding)
    dom = build_domain(encoding, "stations")
    for name, action in dom.actions.items():
        params = ", ".join(f"{p.name} ({p.type})" for p in action.parameters)
        assert f"\n{name}({params})\n" in text
    assert "needs" in text and ("takes" in text if encoding == "classical" else "lasts" in text)
    assert describe_domain(encoding) == text


def test_a_problem_text_names_every_object_and_goal(medium):
    text = describe_problem(medium)
    for obj in medium.problem.all_objects:
        assert f"- {obj.name}: {object_words(medium, obj.name)}" in text
    for order in medium.goal_orders:
        assert f"- serve o{order} (order {order}): a plate of" in text
    assert "- a0 stands at s_" in text and "cook 1" in text


def test_facts_and_objects_in_words(medium):
    assert fact_words("holding", ["a0", "tomato0"]) == "a0 holds tomato0"
    assert fact_words("dist", ["s_1_1", "s_1_2"], 3) == "walking from s_1_1 to s_1_2 takes 3 steps"
    assert object_words(medium, "a1") == "cook 1"
    board = next(n for n in medium.names.cells if n.startswith("board_"))
    r, c = medium.names.cells[board]
    assert object_words(medium, board) == f"the cutting board at (row {r}, col {c})"
    assert set(FACT_WORDS) >= set(build_domain("classical").fluents)
    assert "move" in ACTION_WORDS


def test_a_plan_step_in_words(medium):
    board = next(n for n in medium.names.cells if n.startswith("board_"))
    words = step_words(medium, "chop", ["a1", "tomato0", board, "s_1_2"])
    assert words.startswith("cook 1 chops tomato0 on the cutting board at (row ")
    assert words.endswith("(standing at the floor at (row 1, col 2))")


def test_a_mismatch_message_in_kitchen_words(medium):
    text = kitchen_words("tomato0: model says [('cell', (1, 2))], simulator says ('hand', 0); "
                         "a0: model at [(1, 1)]", medium)
    assert text == ("tomato0: model says [on the cell at (row 1, col 2)], simulator says held "
                    "by cook 0; cook 0: model at [(row 1, col 1)]")


@pytest.fixture(scope="module")
def sampled():
    """A state some steps into an episode (cooks standing on spots, nothing in progress)."""
    from ocplus_plan.planning.fidelity import sample_state

    return compile(sample_state(make_rules("medium", n_agents=2), 0, 0), encoding="classical")


def test_a_problem_text_states_no_zero_number_and_no_walk_without_its_link(sampled):
    text = describe_problem(sampled)
    facts = [ln for ln in text.splitlines() if ln.startswith("- ")]
    assert not [ln for ln in facts if " 0 steps" in ln or " 0 more steps" in ln]
    links = {tuple(ln[len("- a cook can walk from "):].split(" to "))
             for ln in facts if ln.startswith("- a cook can walk from ")}
    walks = [ln for ln in facts if ln.startswith("- walking from ")]
    assert walks and links
    for ln in walks:
        start, rest = ln[len("- walking from "):].split(" to ")
        assert (start, rest.split(" takes ")[0]) in links, ln
    assert "every number not listed is 0" in text


def test_symmetry_breaking_facts_stand_apart_with_their_reason(sampled):
    text = describe_problem(sampled)
    start, symmetry = text.split("Symmetry breaking", 1)
    assert "comes before" not in start.split("At the start:")[1]
    assert "nothing here is a fact about the kitchen" in symmetry
    assert "comes before" in symmetry.split("Goal:")[0]


def test_one_step_is_said_in_the_singular():
    assert fact_words("dist", ["s_1_1", "s_1_2"], 1) == "walking from s_1_1 to s_1_2 takes 1 step"


@pytest.mark.parametrize("encoding, granularity, switches", VARIANTS)
def test_predicate_parameters_are_named_after_their_types(encoding, granularity, switches):
    import re

    from ocplus_plan.planning.pddl import domain_text

    text = domain_text(encoding, granularity, switches=switches)
    predicates = text.split("(:predicates", 1)[1].split("(:", 1)[0]
    assert not re.search(r"\?x\d", predicates)
    assert "(holding ?agent - agent ?item - item)" in predicates


def test_the_unusable_actions_of_a_kitchen_can_be_cut_from_its_problem():
    from ocplus_plan.planning.adapt import unusable_actions, without_unusable_actions
    from ocplus_plan.planning.pddl import pddl_texts

    easy = compile(new_state(make_rules("easy"), 0), encoding="classical")
    dropped = unusable_actions(easy.problem)
    assert {"wash", "put_sink", "cook"} <= set(dropped)  # no sink, no pan on easy
    assert "chop" not in dropped and "deliver1" not in dropped
    cut, names = without_unusable_actions(easy.problem)
    assert sorted(dropped) == names and len(cut.actions) == len(easy.problem.actions) - len(names)
    domain, _ = pddl_texts(cut)
    assert "(:action wash" not in domain and "(:action chop" in domain
    hard = compile(new_state(make_rules("hard", n_agents=2), 0), encoding="classical")
    assert "wash" not in unusable_actions(hard.problem)


def test_a_domain_text_can_be_cut_to_some_actions():
    text = describe_domain("classical", only={"chop", "move"})
    assert "\nchop(" in text and "\nmove(" in text and "\nwash(" not in text
