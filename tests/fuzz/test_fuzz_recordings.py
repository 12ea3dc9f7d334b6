"""Generated and damaged recordings: each loads and replays, or is refused as "not a
readable recording" (a ConfigError); nothing else escapes."""

from __future__ import annotations

import gzip
import json
import tempfile
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ocplus_plan.errors import ConfigError
from ocplus_plan.render.replay import Recording, verify
from tests.render.test_replay import record_episode
from tests.fuzz import fuzz_settings

FUZZ = fuzz_settings(50)
json_values = st.recursive(
    st.none() | st.booleans() | st.integers(-2**70, 2**70) | st.floats() | st.text(max_size=6),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=6), inner,
                                                                max_size=4),
    max_leaves=10)


@pytest.fixture(scope="module")
def good() -> list[str]:
    rec, _ = record_episode("easy", steps=12, seed=2)
    with tempfile.TemporaryDirectory() as tmp:
        return rec.save(Path(tmp) / "g.jsonl").read_text().splitlines()


def check(data: bytes, suffix: str = ".jsonl") -> None:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"fuzz{suffix}"
        path.write_bytes(data)
        try:
            rec = Recording.load(path)
        except ConfigError as exc:
            assert "\n" not in str(exc)
            return
        verify(rec)  # what loads, replays


@FUZZ
@given(st.data())
def test_a_line_replaced_by_any_json(good, data):
    lines = list(good)
    at = data.draw(st.integers(0, len(lines) - 1))
    lines[at] = json.dumps(data.draw(json_values))
    check("\n".join(lines).encode())


@FUZZ
@given(st.data())
def test_a_header_field_replaced_by_any_json(good, data):
    head = json.loads(good[0])
    section = data.draw(st.sampled_from(["top", "rules", "map"]))
    target = head if section == "top" else head[section]
    key = data.draw(st.sampled_from(sorted(target)) | st.text(max_size=5))
    if data.draw(st.booleans()):
        target[key] = data.draw(json_values)
    else:
        target.pop(key, None)
    check("\n".join([json.dumps(head), *good[1:]]).encode())


@FUZZ
@given(st.data())
def test_lines_dropped_repeated_or_cut(good, data):
    lines = data.draw(st.lists(st.sampled_from(good), max_size=len(good) + 3))
    text = "\n".join(lines)
    text = text[: data.draw(st.integers(0, len(text)))]
    check(text.encode())


@FUZZ
@given(st.data())
def test_gzip_bytes_flipped_or_cut(good, data):
    blob = bytearray(gzip.compress(("\n".join(good) + "\n").encode()))
    for _ in range(data.draw(st.integers(0, 4))):
        at = data.draw(st.integers(0, len(blob) - 1))
        blob[at] ^= data.draw(st.integers(1, 255))
    check(bytes(blob[: data.draw(st.integers(0, len(blob)))]), ".jsonl.gz")
