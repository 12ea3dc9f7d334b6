"""A trainer's checkpoint as weights only: ``policy.npz`` + ``train.json``, the format
:mod:`ocplus_plan.rl.npz_policy` plays with numpy alone (``np.load`` without pickle: a
checkpoint in this form cannot run code when it is loaded).

The SB3 network of ``ocplus train`` (two tanh layers for the actor, a separate critic) is
written as ``w0 b0 w1 b1`` (the actor's layers) and ``w2 b2`` (its action logits, with a
last column of zeros where :mod:`.npz_policy` reads a value: the critic is not needed to
play). ``train.json`` holds the observation kind, radius and size, the cooks and the
record of the training run, so :class:`~ocplus_plan.rl.npz_policy.NpzPolicy` encodes each
cook as the policy was trained. The exported policy gives the same action probabilities
(``tests/rl/test_generalist.py``).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ConfigError
from .policy import load_policy


def export_npz(checkpoint: str | Path, out_dir: str | Path, extra: dict[str, Any] | None = None,
               ) -> Path:
    """Write ``checkpoint`` (a ``policy.zip`` of ``ocplus train``) as ``out_dir/policy.npz``
    and ``out_dir/train.json``; returns the ``.npz`` path."""
    policy = load_policy(checkpoint)
    state = {k: v.detach().cpu().numpy().astype(np.float32)
             for k, v in policy.model.policy.state_dict().items()}
    layers = sorted({int(k.split(".")[2]) for k in state
                     if k.startswith("mlp_extractor.policy_net.") and k.endswith(".weight")})
    if len(layers) != 2 or any(k.startswith("features_extractor.") and "weight" in k
                               for k in state):
        raise ConfigError(f"{str(checkpoint)!r}: the weights-only format holds two hidden "
                          f"layers and a flat input; this policy has {len(layers)} layers")
    w = {}
    for i, layer in enumerate(layers):
        w[f"w{i}"] = state[f"mlp_extractor.policy_net.{layer}.weight"].T
        w[f"b{i}"] = state[f"mlp_extractor.policy_net.{layer}.bias"]
    head, bias = state["action_net.weight"].T, state["action_net.bias"]
    w["w2"] = np.concatenate([head, np.zeros((head.shape[0], 1), np.float32)], axis=1)
    w["b2"] = np.concatenate([bias, np.zeros(1, np.float32)])
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    np.savez(out / "policy.npz", **{k: np.ascontiguousarray(v) for k, v in w.items()})
    meta = policy.meta
    record = {k: meta.get(k) for k in ("obs", "obs_radius", "obs_size", "n_agents", "map",
                                        "maps", "kitchens", "preset", "act")}
    record.update({"engine": "sb3", "exported_from": Path(checkpoint).name,
                   "train": meta.get("train"), **(extra or {})})
    (out / "train.json").write_text(json.dumps(record, indent=2) + "\n")
    return out / "policy.npz"


__all__ = ["export_npz"]
