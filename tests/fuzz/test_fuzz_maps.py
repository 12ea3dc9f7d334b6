"""Generated map files: every one loads or is refused with a MapFormatError, quickly."""

from __future__ import annotations

import tempfile
from pathlib import Path

import yaml
from hypothesis import given
from hypothesis import strategies as st

from ocplus_plan.errors import MapFormatError
from ocplus_plan.sim import load_map
from tests.fuzz import fuzz_settings

FUZZ = fuzz_settings(60)
YAML_CHARS = "[]{}:-,&*!|>#'\"?%@` \t\n\r0123456789abcdefgm_.\ufeff\u00e9\x00"
KEYS = ["name", "description", "dimensions", "game_map", "map", "max_n_agent", "dynamic_map",
        "is_dynamic_map", "switch_map", "map_switch_step", "agent_spawn_points", "other"]

cells = st.integers(-3, 14)
grids = st.lists(st.lists(cells, min_size=0, max_size=9), min_size=0, max_size=9)
values = st.recursive(st.none() | st.booleans() | st.integers(-10, 10**6) | st.text(max_size=8)
                      | grids, lambda inner: st.lists(inner, max_size=4)
                      | st.dictionaries(st.text(max_size=4), inner, max_size=3), max_leaves=12)
documents = st.dictionaries(st.sampled_from(KEYS), values | grids, max_size=8)


def check(data: bytes) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "fuzz.yaml"
        path.write_bytes(data)
        try:
            layout = load_map(path)
        except MapFormatError as exc:
            assert str(path) in str(exc) and "\n" not in str(exc)
        else:
            assert 1 <= layout.rows <= 64 and 1 <= layout.cols <= 64


@FUZZ
@given(st.text(alphabet=YAML_CHARS, max_size=400))
def test_random_yaml_text(text):
    check(text.encode("utf-8", "surrogatepass"))


@FUZZ
@given(st.binary(max_size=600))
def test_random_bytes(data):
    check(data)


@FUZZ
@given(documents)
def test_generated_documents(doc):
    check(yaml.safe_dump(doc).encode())


@FUZZ
@given(documents, st.data())
def test_generated_documents_with_a_cut_or_a_splice(doc, data):
    text = yaml.safe_dump(doc, default_flow_style=data.draw(st.booleans()))
    at = data.draw(st.integers(0, len(text)))
    cut = data.draw(st.integers(0, 20))
    splice = data.draw(st.text(alphabet=YAML_CHARS, max_size=12))
    check((text[:at] + splice + text[at + cut:]).encode("utf-8", "surrogatepass"))


# a valid kitchen (tomato, steak, pan, board) whose ``recipes`` entry is drawn
KITCHEN = {"game_map": [[1, 10, 1, 9, 1, 3, 1], [5, 0, 0, 0, 0, 0, 7],
                        [1, 12, 6, 11, 1, 1, 1]], "agent_spawn_points": [[1, 1]]}
words = st.sampled_from(["tomato", "steak", "onion", "plate", "chopped", "cooked", "raw",
                         "burnt", "ingredients", "reward", "plate", "bowl", ""])
ingredient = st.dictionaries(words | st.integers(-2, 12), words | values, max_size=2)
dish = st.dictionaries(words, st.lists(ingredient | values, max_size=7) | values
                       | st.floats(allow_nan=True) | st.integers(-10**30, 10**30), max_size=4)


@FUZZ
@given(st.lists(dish, max_size=4) | values)
def test_generated_recipes(recipes):
    check(yaml.safe_dump(dict(KITCHEN, recipes=recipes)).encode())
