"""Weights-only PPO checkpoints: a ``.npz`` of float arrays and a JSON description.

A checkpoint written by ``ocplus train`` (``OUT/policy.npz``) and the shipped ones
(``experiments/checkpoints/*.npz``) hold the policy network's tensors under their
stable-baselines3 names (``mlp_extractor.policy_net.0.weight`` ...) and one member
``ocplus_meta`` (the UTF-8 bytes of a JSON object: ``format``, the observation kind and
size, the kitchen it was trained on, the activation). Nothing in it is code: the file is
read with :func:`read_arrays`, which never unpickles (numpy's ``allow_pickle=False``
rules) and checks every size before it allocates:

* the file is a regular file of at most :data:`MAX_FILE_BYTES`;
* at most :data:`MAX_MEMBERS` members, each a ``.npy`` whose declared size (from the zip
  directory) and whose shape and dtype (from the ``.npy`` header, read before the data)
  are within :data:`MAX_ARRAY_BYTES`, the dtype a plain number type (no objects);
* each member's data is read with a bound of exactly its declared size, so a member whose
  compressed stream expands past it is cut off and refused, never held in memory.

An SB3 ``.zip`` (``PPO.save``) is different: its ``data`` member holds cloudpickled Python
objects, and loading it with stable-baselines3 runs whatever they name. Such a file is
refused unless the user passes ``--trust-pickled-checkpoint`` (or sets
:data:`TRUST_ENV` to ``1``). :func:`convert_sb3` turns one into a ``.npz`` without
unpickling its ``data``: it reads only ``policy.pth`` with ``torch.load(weights_only=True)``
(torch's restricted loader: tensors and plain containers) and ``ocplus_meta.json``::

    python -m ocplus_plan.rl.weights IN.zip OUT.npz
"""

from __future__ import annotations

import io
import json
import os
import pickle
import stat
import sys
import zipfile
import zlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ConfigError

FORMAT = "ocplus-ppo-weights/1"
META = "ocplus_meta"
TRUST_ENV = "OCPLUS_TRUST_PICKLED_CHECKPOINT"
TRUST_FLAG = "--trust-pickled-checkpoint"

MAX_FILE_BYTES = 64 << 20
MAX_MEMBERS = 64
MAX_ARRAY_BYTES = 32 << 20
MAX_TOTAL_BYTES = 64 << 20
MAX_META_BYTES = 64 << 10
MAX_DIMS = 4
_HEADER_BYTES = 4096
_KINDS = "fiub"  # float, signed, unsigned, bool: never objects, strings or void
ACTIVATIONS = ("tanh", "relu")
N_ACTIONS = 5
#: subtask slots a free cook chooses from with ``obs="choice"`` (its actions: a slot, or none)
CHOICE_SLOTS = 6


def n_actions(obs: str) -> int:
    """The actions of a policy trained on observation kind ``obs``: the 5 moves, or with
    ``choice`` one of :data:`CHOICE_SLOTS` subtasks or none."""
    return CHOICE_SLOTS + 1 if obs == "choice" else N_ACTIONS


def pickled_trusted() -> bool:
    """Whether the user allowed pickled (code-running) checkpoints for this run."""
    return os.environ.get(TRUST_ENV) == "1"


def refuse_pickled(path: str | Path) -> ConfigError:
    """The refusal of an SB3 ``.zip`` (or any file that is not a ``.npz``)."""
    return ConfigError(
        f"{str(path)!r} is not a weights-only .npz checkpoint: an SB3 .zip holds pickled "
        f"Python objects that run code when loaded. Convert it with `python -m "
        f"ocplus_plan.rl.weights {path} OUT.npz` (reads only its tensors), or pass "
        f"{TRUST_FLAG} if you trust whoever made it")


def _regular_file(path: Path, limit: int, what: str) -> int:
    try:
        st = path.stat()
    except OSError as exc:
        raise ConfigError(f"{what} {str(path)!r} cannot be read ({exc.strerror})") from None
    if not stat.S_ISREG(st.st_mode):
        raise ConfigError(f"{what} {str(path)!r} is not a regular file")
    if st.st_size > limit:
        raise ConfigError(f"{what} {str(path)!r} is {st.st_size} bytes; the limit is {limit}")
    return st.st_size


def _read_member(zf: zipfile.ZipFile, info: zipfile.ZipInfo) -> np.ndarray:
    with zf.open(info) as f:
        version = np.lib.format.read_magic(f)
        if version == (1, 0):
            shape, fortran, dtype = np.lib.format.read_array_header_1_0(
                f, max_header_size=_HEADER_BYTES)
        elif version == (2, 0):
            shape, fortran, dtype = np.lib.format.read_array_header_2_0(
                f, max_header_size=_HEADER_BYTES)
        else:
            raise ValueError(f"npy format version {version} is not read")
        if dtype.hasobject or dtype.kind not in _KINDS or dtype.fields is not None:
            raise ValueError(f"dtype {dtype} is not a plain number type")
        if len(shape) > MAX_DIMS or any(not 0 <= n <= MAX_ARRAY_BYTES for n in shape):
            raise ValueError(f"shape {shape} is out of bounds")
        count = int(np.prod(shape, dtype=np.int64)) if shape else 1
        nbytes = count * dtype.itemsize
        if nbytes > MAX_ARRAY_BYTES or nbytes > info.file_size:
            raise ValueError(f"shape {shape} of {dtype} needs {nbytes} bytes; the member "
                             f"declares {info.file_size} (limit {MAX_ARRAY_BYTES})")
        data = f.read(nbytes)
        if len(data) != nbytes or f.read(1):
            raise ValueError("the data does not match its header's shape")
    arr = np.frombuffer(data, dtype=dtype)
    return arr.reshape(shape, order="F" if fortran else "C")


def read_arrays(path: str | Path, what: str = "checkpoint") -> dict[str, np.ndarray]:
    """The arrays of a ``.npz`` file, read within the limits above (``ConfigError``
    naming the file and the fault otherwise). Nothing is unpickled."""
    path = Path(path)
    _regular_file(path, MAX_FILE_BYTES, what)
    out: dict[str, np.ndarray] = {}
    try:
        with zipfile.ZipFile(path) as zf:
            infos = zf.infolist()
            if len(infos) > MAX_MEMBERS:
                raise ValueError(f"{len(infos)} members; the limit is {MAX_MEMBERS}")
            total = sum(i.file_size for i in infos)
            if total > MAX_TOTAL_BYTES:
                raise ValueError(f"members declare {total} bytes; the limit is {MAX_TOTAL_BYTES}")
            for info in infos:
                if not info.filename.endswith(".npy") or info.filename.startswith("/"):
                    raise ValueError(f"member {info.filename[:80]!r} is not a .npy array")
                if info.compress_type not in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED):
                    raise ValueError(f"member {info.filename[:80]!r}: compression "
                                     f"{info.compress_type} is not read")
                try:
                    out[info.filename[:-4]] = _read_member(zf, info)
                except ValueError as exc:
                    raise ValueError(f"member {info.filename[:80]!r}: {exc}") from None
    except (zipfile.BadZipFile, zlib.error, EOFError, OSError, ValueError,
            NotImplementedError, RuntimeError) as exc:
        raise ConfigError(f"{what} {str(path)!r} is not a readable .npz: {exc}") from None
    return out


def _meta(path: Path, arrays: Mapping[str, np.ndarray]) -> dict[str, Any]:
    raw = arrays.get(META)
    if raw is None or raw.dtype != np.uint8 or raw.ndim != 1 or raw.size > MAX_META_BYTES:
        raise ConfigError(f"checkpoint {str(path)!r} has no {META} member (bytes of a JSON "
                          "object); write one with `ocplus train` or convert an SB3 zip")
    try:
        meta = json.loads(raw.tobytes().decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise ConfigError(f"checkpoint {str(path)!r}: {META} is not JSON ({exc})") from None
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        got = meta.get("format") if isinstance(meta, dict) else type(meta).__name__
        raise ConfigError(f"checkpoint {str(path)!r}: format {got!r}, this version reads "
                          f"{FORMAT!r}")
    for key in ("obs", "obs_size", "activation"):
        if key not in meta:
            raise ConfigError(f"checkpoint {str(path)!r}: {META} lacks {key!r}")
    if not isinstance(meta["obs_size"], int) or not 0 < meta["obs_size"] <= 1 << 20:
        raise ConfigError(f"checkpoint {str(path)!r}: obs_size {meta['obs_size']!r} is not "
                          "a positive integer")
    if meta["activation"] not in ACTIVATIONS:
        raise ConfigError(f"checkpoint {str(path)!r}: activation {meta['activation']!r}; "
                          f"known: {', '.join(ACTIVATIONS)}")
    return meta


def _layers(path: Path, arrays: Mapping[str, np.ndarray], size: int, actions: int
            ) -> list[tuple]:
    """The policy's (weight, bias) pairs, shapes chained from ``size`` to ``actions``."""
    names = sorted((int(k.split(".")[2]), k.rsplit(".", 1)[0]) for k in arrays
                   if k.startswith("mlp_extractor.policy_net.") and k.endswith(".weight")
                   and k.split(".")[2].isdigit())
    layers = []
    for base in [n for _, n in names] + ["action_net"]:
        w, b = arrays.get(f"{base}.weight"), arrays.get(f"{base}.bias")
        if w is None or b is None or w.ndim != 2 or b.shape != (w.shape[0],) \
                or w.shape[1] != size:
            raise ConfigError(f"checkpoint {str(path)!r}: layer {base} is missing or does not "
                              f"take {size} inputs")
        layers.append((np.asarray(w, np.float32).T.copy(), np.asarray(b, np.float32)))
        size = w.shape[0]
    if size != actions:
        raise ConfigError(f"checkpoint {str(path)!r}: {size} action logits, expected "
                          f"{actions}")
    return layers


class WeightsPolicy:
    """A loaded weights-only checkpoint: :meth:`probs` and :meth:`act` on observation
    batches, with numpy alone (the same numbers as the SB3 policy it came from)."""

    def __init__(self, path: str | Path, arrays: Mapping[str, np.ndarray] | None = None):
        self.path = Path(path)
        arrays = read_arrays(self.path) if arrays is None else arrays
        self.meta = _meta(self.path, arrays)
        self.layers = _layers(self.path, arrays, self.meta["obs_size"],
                              n_actions(self.meta["obs"]))
        self.tensors = {k: v for k, v in arrays.items() if k != META}
        self._act = np.tanh if self.meta["activation"] == "tanh" else \
            (lambda h: np.maximum(h, 0.0))

    def probs(self, obs: np.ndarray) -> np.ndarray:
        """``(batch, actions)`` action probabilities."""
        h = np.asarray(obs, np.float32)
        for w, b in self.layers[:-1]:
            h = self._act(h @ w + b)
        w, b = self.layers[-1]
        logits = h @ w + b
        e = np.exp(logits - logits.max(axis=1, keepdims=True))
        return e / e.sum(axis=1, keepdims=True)

    def act(self, obs: np.ndarray, rng: np.random.Generator | None = None) -> list[int]:
        """Greedy actions when ``rng`` is None, else sampled with ``rng`` (the draw of
        :class:`~ocplus_plan.rl.policy.LoadedPolicy`)."""
        p = self.probs(obs)
        if rng is None:
            return [int(a) for a in p.argmax(axis=1)]
        u = rng.random(len(p))
        cum = np.cumsum(p, axis=1)
        return [int(min(np.searchsorted(c, x * c[-1], side="right"), len(c) - 1))
                for c, x in zip(cum, u)]


def save_weights(path: str | Path, tensors: Mapping[str, Any], meta: Mapping[str, Any]) -> Path:
    """Write ``tensors`` (name -> array or torch tensor) and ``meta`` as a weights file."""
    path = Path(path)
    arrays = {k: np.asarray(v.detach().cpu().numpy() if hasattr(v, "detach") else v,
                            np.float32) for k, v in tensors.items()}
    record = {"format": FORMAT, "activation": "tanh", **meta}
    arrays[META] = np.frombuffer(json.dumps(record).encode(), np.uint8)
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **arrays)
    path.write_bytes(buffer.getvalue())
    return path


def convert_sb3(zip_path: str | Path, out: str | Path) -> Path:
    """Write the weights of an ``ocplus train`` SB3 zip as a ``.npz``. Only ``policy.pth``
    (``torch.load(weights_only=True)``) and ``ocplus_meta.json`` are read; the pickled
    ``data`` member is never opened."""
    from .policy import META_MEMBER, require_rl

    zip_path = Path(zip_path)
    _regular_file(zip_path, MAX_FILE_BYTES, "checkpoint")
    require_rl()
    import torch

    try:
        with zipfile.ZipFile(zip_path) as zf:
            infos = {i.filename: i for i in zf.infolist()}
            for name in ("policy.pth", META_MEMBER):
                if name not in infos or infos[name].file_size > MAX_TOTAL_BYTES:
                    raise ValueError(f"member {name} is missing or over {MAX_TOTAL_BYTES} bytes")
            meta = json.loads(zf.read(META_MEMBER))
            tensors = torch.load(io.BytesIO(zf.read("policy.pth")), map_location="cpu",
                                 weights_only=True)
    except (zipfile.BadZipFile, zlib.error, OSError, ValueError, RuntimeError,
            RecursionError, pickle.UnpicklingError) as exc:
        raise ConfigError(f"{str(zip_path)!r} is not a convertible SB3 checkpoint: {exc}") \
            from None
    if not isinstance(meta, dict) or not isinstance(tensors, dict):
        raise ConfigError(f"{str(zip_path)!r}: unexpected metadata or policy contents")
    meta = {k: v for k, v in meta.items() if k != "format"}
    return save_weights(out, tensors, meta)


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 2 or not args[1].endswith(".npz"):
        print("usage: python -m ocplus_plan.rl.weights IN.zip OUT.npz", file=sys.stderr)
        return 2
    try:
        WeightsPolicy(convert_sb3(args[0], args[1]))
    except ConfigError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(args[1])
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())


__all__ = ["FORMAT", "MAX_ARRAY_BYTES", "META", "MAX_FILE_BYTES", "TRUST_ENV", "TRUST_FLAG",
           "WeightsPolicy", "convert_sb3", "pickled_trusted",
           "read_arrays", "refuse_pickled", "save_weights"]
