"""Weights-only checkpoints: bounded reading, no code run, the same actions as SB3."""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

from ocplus_plan.agents import make_controller
from ocplus_plan.agents.ppo import shipped_checkpoint
from ocplus_plan.errors import ConfigError
from ocplus_plan.rl import weights
from ocplus_plan.rl.weights import WeightsPolicy, read_arrays, save_weights
from ocplus_plan.sim import make_rules, new_state, transition
from tests.fuzz.corpus_data import _System
from tests.fuzz.corpus_data import planted_sb3 as plant_sb3

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = ROOT / "experiments" / "checkpoints"
OCPLUS = [sys.executable, "-m", "ocplus_plan.cli"]


def tiny_policy(path: Path, size: int = 6, hidden: int = 4, **meta) -> Path:
    rng = np.random.default_rng(0)
    tensors = {"mlp_extractor.policy_net.0.weight": rng.normal(size=(hidden, size)),
               "mlp_extractor.policy_net.0.bias": rng.normal(size=hidden),
               "action_net.weight": rng.normal(size=(5, hidden)),
               "action_net.bias": rng.normal(size=5)}
    return save_weights(path, tensors, {"obs": "features", "obs_size": size, **meta})


def test_a_written_policy_reads_back_and_acts(tmp_path: Path):
    policy = WeightsPolicy(tiny_policy(tmp_path / "p.npz"))
    p = policy.probs(np.zeros((3, 6), np.float32))
    assert p.shape == (3, 5) and np.allclose(p.sum(axis=1), 1.0, atol=1e-6)
    assert policy.act(np.ones((2, 6))) == policy.act(np.ones((2, 6)))


def test_an_object_array_is_refused_and_never_unpickled(tmp_path: Path):
    marker = tmp_path / "ran"
    evil = np.empty(1, dtype=object)
    evil[0] = _System(f"touch {marker}")
    path = tmp_path / "evil.npz"
    np.savez(path, ocplus_meta=evil)  # numpy pickles object arrays into the .npy
    with pytest.raises(ConfigError, match="not a plain number type"):
        read_arrays(path)
    with pytest.raises(ConfigError, match="not a plain number type"):
        make_controller(f"ppo:{path}")
    assert not marker.exists()


def test_a_header_shape_past_the_limit_is_refused_before_allocating(tmp_path: Path):
    raw = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        raw, {"descr": "<f4", "fortran_order": False, "shape": (1 << 20, 1 << 20)})
    path = tmp_path / "big.npz"
    with zipfile.ZipFile(path, "w") as zf:
        zf.writestr("w.npy", raw.getvalue() + b"\0" * 64)
    with pytest.raises(ConfigError, match="out of bounds|needs"):
        read_arrays(path)


def test_a_member_that_expands_past_its_declared_size_is_cut_off(tmp_path: Path):
    arr = io.BytesIO()
    np.save(arr, np.zeros(1000, np.float32))
    path = tmp_path / "lie.npz"
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("w.npy", arr.getvalue())
    blob = bytearray(path.read_bytes())
    # shrink the declared size in both headers: the reader stops there and refuses
    size = len(arr.getvalue()).to_bytes(4, "little")
    smaller = (len(arr.getvalue()) - 400).to_bytes(4, "little")
    path.write_bytes(bytes(blob).replace(size, smaller))
    with pytest.raises(ConfigError, match="not a readable .npz"):
        read_arrays(path)


@pytest.mark.parametrize("junk", [b"", b"PK\x03\x04garbage", b"x" * 100])
def test_junk_files_are_refused(tmp_path: Path, junk: bytes):
    path = tmp_path / "j.npz"
    path.write_bytes(junk)
    with pytest.raises(ConfigError, match=str(path.name)):
        read_arrays(path)


def test_non_regular_files_and_wrong_shapes_are_refused(tmp_path: Path):
    with pytest.raises(ConfigError, match="not a regular file"):
        read_arrays(tmp_path)
    with pytest.raises(ConfigError, match="not a regular file"):
        read_arrays("/dev/zero")
    with pytest.raises(ConfigError, match="take 7 inputs"):
        WeightsPolicy(tiny_policy(tmp_path / "p.npz", size=6, obs_size=7))


def test_bare_ppo_picks_a_shipped_npz():
    assert shipped_checkpoint("medium", 2).name == "medium_2agent.npz"
    three = shipped_checkpoint("easy", 3)  # no easy checkpoint for 3 cooks: the generalist's
    assert (three.parent.name, three.name) == ("generalist_3agent", "policy.npz")


def test_an_sb3_zip_is_refused_without_the_flag(tmp_path: Path, monkeypatch):
    monkeypatch.delenv(weights.TRUST_ENV, raising=False)
    with pytest.raises(ConfigError, match="trust-pickled-checkpoint"):
        make_controller(f"ppo:{SHIPPED / 'easy_1agent.zip'}")


@pytest.mark.parametrize("argv", [
    ["eval", "--agents", "ppo:EVIL", "--presets", "easy", "--seed", "0", "--horizon", "3"],
    ["eval", "--agents", "greedy", "--partner", "ppo:EVIL", "--presets", "easy",
     "--n-agents", "2", "--seed", "0", "--horizon", "3"],
    ["rollout", "--agents", "ppo:EVIL", "--horizon", "3"],
    ["train", "--init", "EVIL", "--timesteps", "64"],
])
def test_a_planted_checkpoint_does_nothing(tmp_path: Path, argv: list[str]):
    marker = tmp_path / "ran"
    evil = str(plant_sb3(tmp_path / "evil.zip", marker))
    argv = [a.replace("EVIL", evil) for a in argv]
    if argv[0] in ("eval", "train"):
        argv += ["--out", str(tmp_path / "out")]
    env = {k: v for k, v in os.environ.items() if k != weights.TRUST_ENV}
    done = subprocess.run(OCPLUS + argv, capture_output=True, text=True, timeout=120,
                          cwd=tmp_path, env=env)
    assert done.returncode == 2, done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and "trust-pickled" in done.stderr
    assert not marker.exists()


def test_converted_shipped_policies_act_as_the_sb3_ones(monkeypatch):
    pytest.importorskip("stable_baselines3", reason="the rl extra is not installed")
    from ocplus_plan.rl.policy import load_policy
    from ocplus_plan.rl.obs import make_encoder

    monkeypatch.setenv(weights.TRUST_ENV, "1")
    for name in ("easy_1agent", "hard_2agent"):
        sb3 = load_policy(SHIPPED / f"{name}.zip")
        npz = WeightsPolicy(SHIPPED / f"{name}.npz")
        assert npz.meta["obs_size"] == sb3.meta["obs_size"]
        rules = make_rules(sb3.meta["preset"], n_agents=sb3.meta["n_agents"])
        enc = make_encoder(sb3.meta["obs"], rules, 0)
        state, rng = new_state(rules, 3), np.random.default_rng(0)
        rows = []
        for _ in range(60):  # observations of a real episode, random joint actions
            rows.append(enc.encode_all(state, list(range(rules.n_agents))))
            transition(state, [int(a) for a in rng.integers(0, 5, rules.n_agents)])
        obs = np.concatenate(rows)
        assert np.allclose(npz.probs(obs), sb3.probs(obs), atol=1e-5)
        assert npz.act(obs) == sb3.act(obs)
        assert npz.act(obs, np.random.default_rng(7)) == sb3.act(obs, np.random.default_rng(7))


def test_convert_reads_only_the_tensors(tmp_path: Path):
    pytest.importorskip("torch", reason="the rl extra is not installed")
    marker = tmp_path / "ran"
    out = weights.convert_sb3(plant_sb3(tmp_path / "evil.zip", marker), tmp_path / "w.npz")
    assert not marker.exists()
    assert WeightsPolicy(out).meta["preset"] == "easy"


def test_the_flag_loads_an_sb3_zip_within_its_declared_sizes(tmp_path: Path):
    pytest.importorskip("stable_baselines3", reason="the rl extra is not installed")
    env = {k: v for k, v in os.environ.items() if k != weights.TRUST_ENV}
    argv = ["rollout", "--agents", f"ppo:{SHIPPED / 'easy_1agent.zip'}@greedy", "--horizon",
            "20", "--json", "--trust-pickled-checkpoint"]
    done = subprocess.run(OCPLUS + argv, capture_output=True, text=True, timeout=300,
                          cwd=tmp_path, env=env)
    assert done.returncode == 0, done.stderr
    npz = subprocess.run(OCPLUS + [a.replace(".zip", ".npz") for a in argv[:-1]],
                         capture_output=True, text=True, timeout=300, cwd=tmp_path, env=env)
    same = ("state_hash", "dishes_served", "reward")
    zipped, weighed = json.loads(done.stdout), json.loads(npz.stdout)
    assert {k: zipped[k] for k in same} == {k: weighed[k] for k in same}
    with zipfile.ZipFile(tmp_path / "big.zip", "w", zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("ocplus_meta.json", json.dumps({"format": "ocplus-ppo/1"}))
        zf.writestr("data", b"\0" * (65 << 20))
    from ocplus_plan.rl.policy import read_meta

    with pytest.raises(ConfigError, match="declare"):
        read_meta(tmp_path / "big.zip")
