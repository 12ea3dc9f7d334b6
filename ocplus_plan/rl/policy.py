"""The SB3 checkpoint format and a loaded policy that acts from observations.

Loading one unpickles its ``data`` member, which can run any code: :func:`load_policy`
is reached only with ``--trust-pickled-checkpoint``; the weights-only ``.npz`` of
:mod:`ocplus_plan.rl.weights` is what the package ships and reads by default.

A checkpoint is one stable-baselines3 ``PPO.save`` zip with one extra member,
``ocplus_meta.json`` (SB3's loader ignores members that are not ``.pth``): the
observation kind and size, the preset/map/agents it was trained on, and how it was
trained (command, steps, seed, wall time). :func:`read_meta` reads it without torch.
"""

from __future__ import annotations

import json
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ConfigError, DependencyNotInstalled

META_MEMBER = "ocplus_meta.json"
#: what an SB3 checkpoint's members may declare in all, checked before anything is read
MAX_ZIP_BYTES = 64 << 20
FORMAT = "ocplus-ppo/1"


def require_rl() -> None:
    """Raise :class:`DependencyNotInstalled` naming the ``rl`` extra when torch or SB3 is
    missing; otherwise limit torch to one thread (the machine is shared)."""
    try:
        import stable_baselines3  # noqa: F401
        import torch
    except ImportError as exc:  # pragma: no cover - exercised without the extra
        raise DependencyNotInstalled(
            f"the RL baseline needs torch and stable-baselines3 ({exc.name} is missing); "
            "install the extra: pip install 'ocplus-plan[rl]'"
        ) from exc
    torch.set_num_threads(1)


def write_meta(path: str | Path, meta: dict[str, Any]) -> None:
    """Add (or replace) the metadata member of a saved SB3 zip."""
    path = Path(path)
    with zipfile.ZipFile(path) as zf:
        members = {n: zf.read(n) for n in zf.namelist() if n != META_MEMBER}
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
        for name, data in members.items():
            zf.writestr(name, data)
        zf.writestr(META_MEMBER, json.dumps({"format": FORMAT, **meta}, indent=2))


def read_meta(path: str | Path) -> dict[str, Any]:
    """The metadata of a checkpoint (``ConfigError`` if it is not an ocplus PPO checkpoint)."""
    path = Path(path)
    if not path.is_file():
        raise ConfigError(f"PPO checkpoint {str(path)!r} does not exist; train one with "
                          "`ocplus train` or use one from experiments/checkpoints/")
    try:
        with zipfile.ZipFile(path) as zf:
            declared = sum(i.file_size for i in zf.infolist())
            if declared > MAX_ZIP_BYTES or zf.getinfo(META_MEMBER).file_size > 1 << 16:
                raise ConfigError(f"{str(path)!r}: its members declare {declared} bytes (the "
                                  f"limit is {MAX_ZIP_BYTES}) or its metadata is over 64 KiB")
            meta = json.loads(zf.read(META_MEMBER))
    except (zipfile.BadZipFile, KeyError, ValueError, RecursionError) as exc:
        raise ConfigError(
            f"{str(path)!r} is not an ocplus PPO checkpoint (a zip written by `ocplus train` "
            f"with {META_MEMBER}): {exc}"
        ) from exc
    if meta.get("format") != FORMAT:
        raise ConfigError(f"{str(path)!r}: checkpoint format {meta.get('format')!r}, "
                          f"this version reads {FORMAT!r}")
    return meta


@dataclass
class LoadedPolicy:
    """A PPO policy ready to act: :meth:`probs` and :meth:`act` on observation batches."""

    path: Path
    meta: dict[str, Any]
    model: Any = field(repr=False)

    def probs(self, obs: np.ndarray) -> np.ndarray:
        """``(batch, 5)`` action probabilities."""
        import torch

        with torch.no_grad():
            tensor = torch.as_tensor(np.asarray(obs, np.float32))
            dist = self.model.policy.get_distribution(tensor)
            return dist.distribution.probs.numpy()

    def act(self, obs: np.ndarray, rng: np.random.Generator | None = None) -> list[int]:
        """Greedy actions when ``rng`` is None, else sampled with ``rng`` (never torch's
        global generator, so runs are reproducible)."""
        p = self.probs(obs)
        if rng is None:
            return [int(a) for a in p.argmax(axis=1)]
        u = rng.random(len(p))
        cum = np.cumsum(p, axis=1)
        return [int(min(np.searchsorted(c, x * c[-1], side="right"), 4)) for c, x in zip(cum, u)]


def load_policy(path: str | Path) -> LoadedPolicy:
    """Load a checkpoint written by :func:`ocplus_plan.rl.train.train`."""
    meta = read_meta(path)
    require_rl()
    from stable_baselines3 import PPO

    # schedules are pickled closures: replace them, they are not needed to act
    custom = {"learning_rate": 0.0, "lr_schedule": lambda _: 0.0, "clip_range": lambda _: 0.0}
    model = PPO.load(str(path), device="cpu", custom_objects=custom)
    size = int(model.observation_space.shape[0])
    if size != meta["obs_size"]:
        raise ConfigError(f"{path}: network input {size} != metadata obs_size {meta['obs_size']}")
    return LoadedPolicy(Path(path), meta, model)


__all__ = ["FORMAT", "LoadedPolicy", "load_policy", "read_meta", "require_rl", "write_meta"]
