"""Recordings: compact files that replay to the same state hash; GIF export; the CLI."""

from __future__ import annotations

import gzip
import json

import pytest

from ocplus_plan.agents import make_controller
from ocplus_plan.cli import main
from ocplus_plan.errors import ConfigError
from ocplus_plan.render.replay import Recorder, Recording, export_gif, verify
from ocplus_plan.sim import make_rules, new_state, transition


def record_episode(preset: str = "hard", steps: int = 120, seed: int = 4, **overrides):
    rules = make_rules(preset, horizon=steps, **overrides)
    state = new_state(rules, seed)
    agent = make_controller("greedy", seed)
    agent.reset(state)
    rec = Recorder(rules, seed, meta={"agents": "greedy"})
    while not state.done:
        joint = agent.act(state)
        result = transition(state, joint)
        agent.observe(state, result.events)
        rec.record(joint, result.events)
    return rec.finish(state), state


@pytest.mark.parametrize("name", ["episode.jsonl", "episode.jsonl.gz"])
def test_a_saved_episode_replays_to_the_same_state_hash(tmp_path, name):
    rec, state = record_episode()
    path = rec.save(tmp_path / name)
    loaded = Recording.load(path)
    assert loaded.actions == rec.actions and loaded.seed == 4
    assert loaded.state_hash == state.state_hash()
    check = verify(loaded)
    assert check.ok and check.state_hash == state.state_hash() and check.steps == 120
    assert loaded.event_counts()["delivery"] == state.stats["dishes_served"] >= 1
    assert loaded.map_name == "mapC" and loaded.meta == {"agents": "greedy"}


def test_rule_overrides_and_the_map_travel_with_the_recording(tmp_path):
    rec, state = record_episode("medium", steps=60, cook_time=7, order_time_limit=40,
                                rewards={"correct_delivery": 50.0})
    loaded = Recording.load(rec.save(tmp_path / "r.jsonl"))
    rules = loaded.make_rules()
    assert (rules.cook_time, rules.order_time_limit, rules.rewards.correct_delivery) == (7, 40, 50)
    assert (rules.layout.grid == state.rules.layout.grid).all()
    assert verify(loaded).ok


def test_fixed_orders_travel_with_the_recording(tmp_path):
    rec, state = record_episode("easy", steps=80, fixed_orders=["onion", "tomato"])
    assert state.stats["dishes_served"] >= 1  # the served orders came back
    rules = Recording.load(rec.save(tmp_path / "f.jsonl")).make_rules()
    assert rules.fixed_orders == state.rules.fixed_orders
    assert verify(Recording.load(tmp_path / "f.jsonl")).ok


def test_a_recording_is_compact(tmp_path):
    rec, _ = record_episode(steps=200)
    size = rec.save(tmp_path / "r.jsonl.gz").stat().st_size
    assert size < 4_000, size  # 200 steps of a 2-cook hard episode, map included


def test_a_tampered_recording_does_not_verify(tmp_path):
    rec, _ = record_episode(steps=40)
    rec.actions[5] = [4 - a if a < 4 else 0 for a in rec.actions[5]]
    assert not verify(rec).ok


def test_bad_files_raise_config_error_naming_the_file(tmp_path):
    with pytest.raises(ConfigError, match="does not exist"):
        Recording.load(tmp_path / "missing.jsonl")
    bad = tmp_path / "bad.jsonl"
    bad.write_text('{"hello": 1}\n')
    with pytest.raises(ConfigError, match="bad.jsonl.*header"):
        Recording.load(bad)
    broken = tmp_path / "broken.jsonl.gz"
    broken.write_bytes(b"not gzip at all")
    with pytest.raises(ConfigError, match="broken.jsonl.gz"):
        Recording.load(broken)
    rec, _ = record_episode(steps=5)
    path = rec.save(tmp_path / "r.jsonl")
    lines = path.read_text().splitlines()
    lines[2] = json.dumps({"a": ["up"]})
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ConfigError, match="line 3"):
        Recording.load(path)


def test_gif_export_writes_a_small_animation(tmp_path):
    image = pytest.importorskip("PIL.Image", reason="GIF export needs Pillow (gui extra)")
    rec, _ = record_episode(steps=30)
    out = export_gif(rec, tmp_path / "ep.gif", tile=16, every=2)
    with image.open(out) as gif:
        assert gif.n_frames == 16  # steps 0, 2, ..., 30
        assert gif.size == (9 * 16, 9 * 16)
    assert out.stat().st_size < 1_000_000


def test_replay_command_checks_and_exports(tmp_path, capsys):
    pytest.importorskip("PIL.Image", reason="GIF export needs Pillow (gui extra)")
    rec, state = record_episode(steps=20)
    path = rec.save(tmp_path / "r.jsonl.gz")
    assert main(["replay", str(path), "--check", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["matches_recording"] is True and out["state_hash"] == state.state_hash()
    gif = tmp_path / "r.gif"
    assert main(["replay", str(path), "--gif", str(gif), "--max-frames", "5", "--json"]) == 0
    assert gif.exists() and json.loads(capsys.readouterr().out)["gif"] == str(gif)
    # a recording that no longer reaches its hash exits 1
    with gzip.open(path, "rt") as fh:
        lines = fh.read().splitlines()
    end = json.loads(lines[-1])
    end["state_hash"] = "0" * 64
    lines[-1] = json.dumps(end)
    with gzip.open(path, "wt") as fh:
        fh.write("\n".join(lines) + "\n")
    assert main(["replay", str(path), "--check"]) == 1
