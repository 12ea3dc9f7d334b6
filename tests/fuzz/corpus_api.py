"""Hostile values through the Python API, third group: env actions and sizes, the JAX
kitchen's actions, a checkpoint read directly. Each case runs in a forked child under the
limits of :mod:`tests.fuzz.limited` (600 MB of address space, 20 s) and must raise the
package's own error (an ``OcplusError``) whose message is one readable line.

    python -m tests.fuzz.corpus_api      # one JSON line per case
"""

from __future__ import annotations

import json
import os
import resource
import signal
import tempfile
import time
from collections.abc import Callable

from tests.fuzz.limited import ADDRESS_SPACE, SECONDS


def _gym_step(action: object) -> None:
    import gymnasium as gym

    env = gym.make("OvercookedPlus-v0", preset="easy", n_agents=1)
    env.reset(seed=0)
    env.step(action)


def _single_step(action: object) -> None:
    import gymnasium as gym

    env = gym.make("OvercookedPlusSingle-v0", preset="easy", n_agents=2)
    env.reset(seed=0)
    env.step(action)


def _gym_make(**kw: object) -> None:
    import gymnasium as gym

    gym.make("OvercookedPlus-v0", **kw)


def _vec_make(num_envs: int) -> None:
    import gymnasium as gym

    gym.make_vec("OvercookedPlus-v0", num_envs=num_envs, vectorization_mode="vector_entry_point")


def _jax_step(action: object, checked: bool) -> None:
    import jax

    import ocplus_plan

    env = ocplus_plan.make_jax_env("easy", n_agents=1, checked=checked)
    _, state = env.reset(jax.random.PRNGKey(0))
    env.step(jax.random.PRNGKey(1), state, {"agent_0": action})


def _weights(header_shape: tuple[int, ...]) -> None:
    import io
    import zipfile

    import numpy as np

    from ocplus_plan.rl.weights import WeightsPolicy

    raw = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        raw, {"descr": "<f4", "fortran_order": False, "shape": header_shape})
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "w.npz")
        with zipfile.ZipFile(path, "w") as zf:
            zf.writestr("ocplus_meta.npy", raw.getvalue() + b"\0" * 16)
        WeightsPolicy(path)


CASES: dict[str, Callable[[], None]] = {
    "gym_float_action": lambda: _gym_step([1.7]),
    "gym_nan_action": lambda: _gym_step([float("nan")]),
    "gym_huge_action": lambda: _gym_step([2**63]),
    "gym_single_float_action": lambda: _single_step(1.7),
    "gym_obs_radius_huge": lambda: _gym_make(obs_radius=10**6),
    "vec_num_envs_huge": lambda: _vec_make(10**7),
    "jax_float_action": lambda: _jax_step(1.7, False),
    "jax_nan_action": lambda: _jax_step(float("nan"), False),
    "jax_checked_action_5": lambda: _jax_step(5, True),
    "jax_checked_action_max": lambda: _jax_step(2**31 - 1, True),
    "weights_terabyte_header": lambda: _weights((1 << 20, 1 << 20)),
}
NEEDS = {name: "jax" for name in CASES if name.startswith("jax_")}


#: cases run without the address-space limit: XLA's CPU client reserves more than 600 MB
#: of address space to start at all, whatever the input (its peak is recorded instead)
UNLIMITED_ADDRESS_SPACE = {name for name in CASES if name.startswith("jax_")}


def _vm_peak_mb() -> float:
    from tests.fuzz.limited import _vm_peak_kb

    return round(_vm_peak_kb() / 1024, 1)


def _child(name: str, out_fd: int) -> None:
    if name not in UNLIMITED_ADDRESS_SPACE:
        resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE, ADDRESS_SPACE))
    signal.alarm(SECONDS)
    result = {"error": None, "message": ""}
    try:
        CASES[name]()
    except BaseException as exc:  # noqa: BLE001 - the point is to see it
        from ocplus_plan.errors import OcplusError

        result = {"error": type(exc).__name__, "package_error": isinstance(exc, OcplusError),
                  "message": str(exc)}
    result["vm_peak_mb"] = _vm_peak_mb()
    result["address_space_limited"] = name not in UNLIMITED_ADDRESS_SPACE
    os.write(out_fd, json.dumps(result).encode())
    os._exit(0)


def run(name: str) -> dict[str, object]:
    """One case in a forked child under the limits; what it raised."""
    with tempfile.TemporaryFile() as out:
        start = time.monotonic()
        pid = os.fork()
        if pid == 0:
            _child(name, out.fileno())
        _, status, usage = os.wait4(pid, 0)
        out.seek(0)
        raw = out.read()
    result = json.loads(raw) if raw else {"error": None, "message": ""}
    return {"case": name, **result, "killed": os.WIFSIGNALED(status),
            "seconds": round(time.monotonic() - start, 3),
            "cpu_seconds": round(usage.ru_utime + usage.ru_stime, 3),
            "max_rss_mb": round(usage.ru_maxrss / 1024, 1)}


def available(name: str) -> bool:
    import importlib.util

    return name not in NEEDS or importlib.util.find_spec(NEEDS[name]) is not None


def main() -> None:
    import gymnasium  # noqa: F401 - imported once, shared by every fork

    import ocplus_plan  # noqa: F401

    for name in CASES:
        if available(name):
            print(json.dumps(run(name)), flush=True)


if __name__ == "__main__":
    main()
