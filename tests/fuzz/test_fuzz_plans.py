"""Generated plan texts and files: each reads as a plan or is refused as UnreadableText."""

from __future__ import annotations

import tempfile
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

pytest.importorskip("unified_planning")

from ocplus_plan.errors import UnreadableText
from ocplus_plan.planning import compile
from ocplus_plan.planning.plan_io import parse_plan, read_plan
from ocplus_plan.sim import make_rules, new_state
from tests.fuzz import fuzz_settings

FUZZ = fuzz_settings(60)
PUNCT = ["(", ")", ":", ";", "[", "]", " ", "\n", "\r\n", "\ufeff", "0.5", "1e999", "-1", "nan",
         "3", "\x00", "\u00e9"]


@pytest.fixture(scope="module", params=["classical", "temporal"])
def problem(request):
    return compile(new_state(make_rules("easy"), 0), encoding=request.param).problem


def words(problem) -> list[str]:
    return [a.name for a in problem.actions] + [o.name for o in problem.all_objects][:40]


@FUZZ
@given(st.data())
def test_token_soup(problem, data):
    tokens = data.draw(st.lists(st.sampled_from(PUNCT + words(problem)), max_size=60))
    try:
        parse_plan(" ".join(tokens), problem, "fuzz.plan")
    except UnreadableText as exc:
        assert str(exc).startswith("fuzz.plan")


@FUZZ
@given(st.binary(max_size=400))
def test_random_bytes_in_a_file(problem, data):
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "fuzz.plan"
        path.write_bytes(data)
        try:
            read_plan(path, problem)
        except UnreadableText as exc:
            assert str(path) in str(exc)
