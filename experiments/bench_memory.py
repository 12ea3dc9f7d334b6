"""Bytes held per kitchen by the Gymnasium vector env and per single env instance.

``make_vec``: ``gymnasium.make_vec("OvercookedPlus-v0", num_envs=N,
vectorization_mode="vector_entry_point", preset, n_agents, obs_radius)``, reset, then 5
steps of random actions. ``single``: ``k`` instances of ``gymnasium.make("OvercookedPlus-v0",
...)``, each reset and stepped 5 times. Every measurement runs in a fresh interpreter, after
a warm-up instance of the same configuration was built, stepped and dropped (imports and
numba's compiled kernels are then not counted; the encoder's tables are, since the warm-up
instance held the only reference to them). What is counted is what ``tracemalloc`` sees
held at the end (numpy reports its buffers to it): the env with its engine, observations,
spaces and tables.

One JSON line per measurement, with the parts: ``sim_arrays`` (the engine's per-kitchen
arrays), ``observation_space`` (the arrays its Boxes hold) and ``encoder_tables``
(the encoder's arrays, shared or not).

    python experiments/bench_memory.py --label after \\
        --out experiments/results/memory/make_vec_hard_2cooks.jsonl
    # the code before: an exported tree first on the path, site-packages after it (-S
    # skips the .pth files, so an editable install of the checkout does not take over)
    git archive a61827f ocplus_plan | tar -x -C /tmp/base
    git archive a61827f maps | tar -x -C /tmp/base/ocplus_plan/data   # its package data
    PYTHONPATH=/tmp/base:$VENV/lib/python3.11/site-packages python -S \
        experiments/bench_memory.py --label before --code-commit a61827f
    python experiments/bench_memory.py \\
        --summary experiments/results/memory/make_vec_hard_2cooks.jsonl
"""

from __future__ import annotations

import argparse
import gc
import json
import os
import platform
import subprocess
import sys
import tracemalloc
from pathlib import Path
from typing import Any

import numpy as np

KITCHENS = (1, 256, 1024, 4096)
RADII = (0, 2)
SINGLES = (1, 16)


def _owned_bytes(arrays: list[np.ndarray]) -> int:
    """Bytes of the distinct buffers behind ``arrays`` (views count their owner once)."""
    seen: dict[int, int] = {}
    for a in arrays:
        while isinstance(a.base, np.ndarray):
            a = a.base
        seen[id(a)] = a.nbytes
    return sum(seen.values())


def _space_arrays(space: Any) -> list[np.ndarray]:
    boxes = list(getattr(space, "spaces", [space]))
    return [v for box in boxes for v in vars(box).values() if isinstance(v, np.ndarray)]


def _encoder_arrays(enc: Any) -> list[np.ndarray]:
    return [v for v in vars(enc).values() if isinstance(v, np.ndarray)]


def _kwargs(args: argparse.Namespace, radius: int) -> dict[str, Any]:
    return dict(preset=args.preset, n_agents=args.n_agents, obs_radius=radius)


def _make_vec(n: int, kw: dict[str, Any]) -> Any:
    import gymnasium as gym

    import ocplus_plan.env  # noqa: F401  (registers the ids)

    venv = gym.make_vec("OvercookedPlus-v0", num_envs=n,
                        vectorization_mode="vector_entry_point", **kw)
    venv.reset(seed=0)
    acts = np.random.default_rng(0).integers(0, 5, size=(5, n, kw["n_agents"]))
    for a in acts:
        venv.step(a)
    return venv


def _singles(k: int, kw: dict[str, Any]) -> list[Any]:
    import gymnasium as gym

    import ocplus_plan.env  # noqa: F401  (registers the ids)

    envs = []
    for i in range(k):
        env = gym.make("OvercookedPlus-v0", **kw)
        env.reset(seed=i)
        for _ in range(5):
            env.step([0] * kw["n_agents"])
        envs.append(env)
    return envs


def measure_one(what: str, n: int, kw: dict[str, Any]) -> dict[str, Any]:
    """Build, reset and step ``n`` kitchens (``make_vec``) or ``n`` single envs; bytes held."""
    build = _make_vec if what == "make_vec" else _singles
    warm = build(1, kw)  # imports, numba's kernels, Gymnasium's registry
    del warm
    gc.collect()
    tracemalloc.start()
    held_obj = build(n, kw)
    gc.collect()
    current, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    row: dict[str, Any] = {"held_bytes": current, "peak_bytes": peak,
                           "bytes_per_kitchen": round(current / n)}
    if what == "make_vec":
        venv = held_obj
        row["sim_arrays_per_kitchen"] = round(sum(a.nbytes for a in venv.sim.arrays) / n)
        row["observation_space_bytes"] = _owned_bytes(_space_arrays(venv.observation_space))
        row["encoder_table_bytes"] = _owned_bytes(_encoder_arrays(venv.sim.encoder))
    else:
        encs = [env.unwrapped.core.vector for env in held_obj]
        row["encoder_table_bytes"] = _owned_bytes([a for e in encs for a in _encoder_arrays(e)])
    return row


def _git_commit() -> str:
    """The commit checked out here, ``+dirty`` when the package differs from it."""
    try:
        def git(*a: str) -> str:
            return subprocess.run(["git", *a], capture_output=True, text=True,
                                  check=True).stdout.strip()
        dirty = git("status", "--porcelain", "--", "ocplus_plan")
        return git("rev-parse", "--short", "HEAD") + ("+dirty" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def summary(path: Path) -> str:
    """A markdown table of a results file: bytes per kitchen at each size, per label, and
    the marginal bytes of one more kitchen (from the smallest to the largest batch)."""
    rows = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    vec = [r for r in rows if r["what"] == "make_vec"]
    sizes = sorted({r["n_kitchens"] for r in vec})
    out = ["| code | obs_radius | " + " | ".join(f"{n:,} kitchens" for n in sizes)
           + " | one more kitchen |", "|---" * (len(sizes) + 3) + "|"]
    for label, radius in sorted({(r["label"], r["obs_radius"]) for r in vec}):
        got = {r["n_kitchens"]: r for r in vec if (r["label"], r["obs_radius"]) == (label, radius)}
        lo, hi = got[min(got)], got[max(got)]
        slope = (hi["held_bytes"] - lo["held_bytes"]) / max(1, hi["n_kitchens"] - lo["n_kitchens"])
        cells = [f"{got[n]['bytes_per_kitchen']:,}" if n in got else "-" for n in sizes]
        out.append(f"| {label} ({lo['commit']}) | {radius} | " + " | ".join(cells)
                   + f" | {round(slope):,} |")
    singles = [r for r in rows if r["what"] == "single"]
    if singles:
        out += ["", "| code | obs_radius | single envs | bytes per env | encoder tables |",
                "|---|---|---|---|---|"]
        for r in sorted(singles, key=lambda r: (r["label"], r["obs_radius"], r["n_envs"])):
            out.append(f"| {r['label']} ({r['commit']}) | {r['obs_radius']} | {r['n_envs']} | "
                       f"{r['bytes_per_kitchen']:,} | {r['encoder_table_bytes']:,} |")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--preset", default="hard")
    ap.add_argument("--n-agents", type=int, default=2)
    ap.add_argument("--kitchens", type=int, nargs="+", default=list(KITCHENS))
    ap.add_argument("--singles", type=int, nargs="+", default=list(SINGLES))
    ap.add_argument("--radius", type=int, nargs="+", default=list(RADII))
    ap.add_argument("--label", default="", help="what code this measures (before, after)")
    ap.add_argument("--code-commit", default=None, help="the commit of the code measured")
    ap.add_argument("--out", type=Path, default=None, help="append the JSON lines here")
    ap.add_argument("--summary", type=Path, default=None,
                    help="print the markdown table of a results file and stop")
    ap.add_argument("--one", nargs=3, metavar=("WHAT", "N", "RADIUS"), help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.summary:
        print(summary(args.summary))
        return
    if args.one:
        what, n, radius = args.one[0], int(args.one[1]), int(args.one[2])
        print(json.dumps(measure_one(what, n, _kwargs(args, radius))))
        return
    import ocplus_plan

    commit = args.code_commit or _git_commit()
    jobs = [("make_vec", n, r) for r in args.radius for n in args.kitchens]
    jobs += [("single", k, r) for r in args.radius for k in args.singles]
    for what, n, radius in jobs:
        site = ["-S"] if sys.flags.no_site else []  # keeps a PYTHONPATH tree first
        cmd = [sys.executable, *site, __file__, "--preset", args.preset, "--n-agents",
               str(args.n_agents), "--one", what, str(n), str(radius)]
        out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
        row = {"bench": "memory", "what": what, "label": args.label, "preset": args.preset,
               "n_agents": args.n_agents, "obs_radius": radius,
               ("n_kitchens" if what == "make_vec" else "n_envs"): n,
               **json.loads(out.strip().splitlines()[-1]),
               "code": os.path.dirname(ocplus_plan.__file__), "commit": commit,
               "load": " ".join(f"{x:.2f}" for x in os.getloadavg()),
               "numpy": np.__version__, "python": platform.python_version(),
               "machine": "the shared 2-core machine, under the load given",
               "command": "python " + " ".join([Path(__file__).name, *(argv or sys.argv[1:])])}
        line = json.dumps(row)
        print(line, flush=True)
        if args.out:
            args.out.parent.mkdir(parents=True, exist_ok=True)
            with args.out.open("a") as fh:
                fh.write(line + "\n")


if __name__ == "__main__":
    main()
