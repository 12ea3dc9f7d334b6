"""Recording files: versioned, every line checked; a bad file is refused (exit 2), never
replayed into a traceback or reported as a determinism mismatch."""

from __future__ import annotations

import gzip
import json
from pathlib import Path

import pytest

from ocplus_plan.cli import main
from ocplus_plan.render.replay import (
    ADDED_AFTER_V1,
    VERSION,
    Recording,
    UnreadableRecording,
    verify,
)
from tests.render.test_replay import record_episode

ROOT = Path(__file__).resolve().parents[2]
SKIP_DIRS = {".venv", ".git", "node_modules", ".hypothesis", ".pytest_cache"}


def shipped_recordings() -> list[Path]:
    """Every recording in the source tree: a ``*.jsonl[.gz]`` whose first line is a header."""
    found = []
    for path in sorted(ROOT.rglob("*.jsonl*")):
        parts = path.relative_to(ROOT).parts
        # hidden folders (.venv, .git, tool scratch) hold no shipped file
        if SKIP_DIRS & set(parts) or any(p.startswith(".") for p in parts) \
                or not path.is_file():
            continue
        opener = gzip.open if path.suffix == ".gz" else open
        with opener(path, "rt", encoding="utf-8") as fh:
            if '"ocplus-replay"' in fh.readline(100_000):
                found.append(path)
    return found


@pytest.fixture(scope="module")
def lines(tmp_path_factory) -> list[str]:
    rec, _ = record_episode("easy", steps=30, seed=3)
    path = rec.save(tmp_path_factory.mktemp("rec") / "r.jsonl")
    return path.read_text().splitlines()


def write(tmp_path: Path, lines: list[str], name: str = "t.jsonl") -> Path:
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n")
    return path


def header_with(lines: list[str], **changes) -> list[str]:
    head = json.loads(lines[0])
    for key, value in changes.items():
        if value is KeyError:
            head.pop(key)
        else:
            head[key] = value
    return [json.dumps(head), *lines[1:]]


def refused_by_the_cli(path: Path, capsys, match: str) -> None:
    assert main(["replay", str(path), "--check", "--json"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"ocplus: error: not a readable recording: {path}: ")
    assert match in err and "\n" not in err and "Traceback" not in err


@pytest.mark.parametrize("path", shipped_recordings(), ids=lambda p: str(p.relative_to(ROOT)))
def test_every_shipped_recording_replays(path, capsys):
    assert main(["replay", str(path), "--check", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["matches_recording"] is True


def test_the_shipped_recordings_are_found():
    assert ROOT / "docs/figures/hard_greedy.jsonl.gz" in shipped_recordings()


def test_a_version_1_file_gets_the_fields_added_since(tmp_path, lines):
    head = json.loads(lines[0])
    head["version"] = 1
    for key in ADDED_AFTER_V1:
        head["rules"].pop(key)
    rec = Recording.load(write(tmp_path, [json.dumps(head), *lines[1:]]))
    assert all(rec.rules[k] == v for k, v in ADDED_AFTER_V1.items()) and verify(rec).ok


def test_a_new_file_is_written_at_the_current_version(lines):
    assert json.loads(lines[0])["version"] == VERSION == 2


def test_a_version_2_file_must_hold_every_rule_field(tmp_path, lines):
    head = json.loads(lines[0])
    head["rules"].pop("fixed_orders")
    with pytest.raises(UnreadableRecording, match=r"rule parameters missing \['fixed_orders'\]"):
        Recording.load(write(tmp_path, [json.dumps(head), *lines[1:]]))


@pytest.mark.parametrize("cut", [1, 5])
def test_a_truncated_file_is_a_bad_file_not_a_mismatch(tmp_path, lines, capsys, cut):
    refused_by_the_cli(write(tmp_path, lines[:-cut]), capsys, "no end line")


def test_a_file_cut_inside_a_line_is_refused(tmp_path, lines, capsys):
    path = tmp_path / "cut.jsonl"
    path.write_text("\n".join(lines)[:-15])
    refused_by_the_cli(path, capsys, "is not JSON")


def test_a_truncated_gzip_file_is_refused(tmp_path, lines, capsys):
    data = gzip.compress(("\n".join(lines) + "\n").encode())
    path = tmp_path / "cut.jsonl.gz"
    path.write_bytes(data[: len(data) // 2])
    refused_by_the_cli(path, capsys, "damaged or truncated")


def test_flipped_gzip_bytes_are_refused(tmp_path, lines, capsys):
    data = bytearray(gzip.compress(("\n".join(lines) + "\n").encode()))
    for k in range(20, 40):
        data[k] ^= 0xFF
    path = tmp_path / "flip.jsonl.gz"
    path.write_bytes(bytes(data))
    refused_by_the_cli(path, capsys, "")


def test_a_line_that_is_a_number_is_refused(tmp_path, lines, capsys):
    refused_by_the_cli(write(tmp_path, [lines[0], "5", *lines[1:]]), capsys, "line 2 is not a step")


def test_a_missing_header_key_is_refused(tmp_path, lines, capsys):
    refused_by_the_cli(write(tmp_path, header_with(lines, rules=KeyError)), capsys,
                       "header keys missing ['rules']")


@pytest.mark.parametrize("seed", [-1, "4", 2.5, True, 2**70])
def test_a_bad_seed_is_refused(tmp_path, lines, capsys, seed):
    refused_by_the_cli(write(tmp_path, header_with(lines, seed=seed)), capsys, "header 'seed'")


def test_a_wrong_rule_type_is_refused(tmp_path, lines, capsys):
    head = json.loads(lines[0])
    head["rules"]["horizon"] = "30"
    refused_by_the_cli(write(tmp_path, [json.dumps(head), *lines[1:]]), capsys,
                       "rule parameter 'horizon' must be an integer")


def test_deep_nesting_is_refused(tmp_path, lines, capsys):
    deep = "[" * 100_000 + "]" * 100_000
    refused_by_the_cli(write(tmp_path, [lines[0], '{"a": ' + deep + "}", *lines[1:]]), capsys,
                       "line 2 is nested too deeply")


def test_an_action_out_of_range_is_refused(tmp_path, lines, capsys):
    refused_by_the_cli(write(tmp_path, [lines[0], '{"a": [9]}', *lines[1:]]), capsys,
                       "line 2: 'a' must list 1 action numbers from 0 to 4")


def test_a_newer_version_is_refused(tmp_path, lines, capsys):
    refused_by_the_cli(write(tmp_path, header_with(lines, version=VERSION + 1)), capsys,
                       f"reads versions 1 to {VERSION}")


def test_lines_after_the_end_are_refused(tmp_path, lines, capsys):
    refused_by_the_cli(write(tmp_path, [*lines, lines[1]]), capsys, "1 lines after the end line")


def test_an_end_line_with_a_wrong_count_is_refused(tmp_path, lines, capsys):
    end = json.loads(lines[-1])
    end["steps"] += 1
    refused_by_the_cli(write(tmp_path, [*lines[:-1], json.dumps(end)]), capsys,
                       "the end line counts 31 steps but the file holds 30")


def test_a_map_that_does_not_load_is_refused(tmp_path, lines, capsys):
    refused_by_the_cli(write(tmp_path, header_with(lines, map={"game_map": [[9]]})), capsys,
                       "its rules cannot be rebuilt")


def test_metadata_never_overrides_the_verdict(tmp_path, lines, capsys):
    head = json.loads(lines[0])
    head["meta"] = {"matches_recording": "yes"}
    actions = [json.loads(x) for x in lines[1:-1]]
    actions[3]["a"] = [(actions[3]["a"][0] + 1) % 4]
    path = write(tmp_path, [json.dumps(head), *map(json.dumps, actions), lines[-1]])
    assert main(["replay", str(path), "--check", "--json"]) == 1
    assert json.loads(capsys.readouterr().out)["matches_recording"] is False


def test_a_huge_order_count_is_refused_before_the_replay_starts(tmp_path, lines, capsys):
    head = json.loads(lines[0])
    head["rules"]["n_orders"] = 10**9
    refused_by_the_cli(write(tmp_path, [json.dumps(head), *lines[1:]]), capsys,
                       "rule parameter 'n_orders' must be an integer from 1 to 1000")


def test_the_reader_checks_every_rule_field_the_writer_writes():
    from ocplus_plan.render.replay import _RULE_CHECKS, rules_to_dict
    from ocplus_plan.sim import make_rules

    # a field added to Rules needs a check here, a version bump and a default for older files
    assert set(rules_to_dict(make_rules("hard"))) == set(_RULE_CHECKS)
