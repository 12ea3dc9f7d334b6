"""Train the shipped PPO checkpoints and record how (command, wall time, CPU time).

    .venv/bin/python experiments/train_baselines.py                # all, in order
    .venv/bin/python experiments/train_baselines.py easy_1agent    # just one

Each run is ``ocplus train ... --out experiments/runs/NAME``; its policy is copied to
``experiments/checkpoints/NAME.zip`` and ``NAME.json`` beside it records the exact
command, its wall time and CPU time on this machine, and the training summary;
``NAME.episodes.csv`` keeps the training log (game reward and dishes per episode) for
experiments/plot_learning_curves.py (``experiments/runs/`` itself is git-ignored). The
medium and two-agent runs start from the easy checkpoint (``--init``): the features are
map- and agent-count-independent, so what was learned in the easy kitchen transfers.
"""

from __future__ import annotations

import argparse
import json
import resource
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CKPT = ROOT / "experiments" / "checkpoints"

#: name -> ocplus train arguments (without --out); order matters (--init dependencies)
RUNS: dict[str, list[str]] = {
    "easy_1agent": ["--preset", "easy", "--steps", "400000", "--seed", "0",
                    "--anneal-fraction", "0.8", "--n-epochs", "8", "--ent-coef", "0.02",
                    "--n-kitchens", "8"],
    # starts from the easy run's checkpoint at 160k steps (it serves ~3.6 dishes there)
    "medium_1agent": ["--preset", "medium", "--steps", "600000", "--seed", "0",
                      "--anneal-fraction", "0.8", "--n-epochs", "8", "--ent-coef", "0.02",
                      "--n-kitchens", "8",
                      "--init", "experiments/runs/easy_1agent/checkpoints/step_000160000.zip"],
    "easy_2agent": ["--preset", "easy", "--n-agents", "2", "--steps", "200000", "--seed", "0",
                    "--anneal-fraction", "0.8", "--n-epochs", "8", "--ent-coef", "0.02",
                    "--n-kitchens", "8", "--init", "experiments/checkpoints/easy_1agent.zip"],
}


def ship(name: str, run_dir: Path, wall: float | None = None, cpu: float | None = None) -> dict:
    """Copy a finished run's policy and training log next to the shipped checkpoints and
    write ``NAME.json`` (the exact command from the run's train.json, times, summary)."""
    summary = json.loads((run_dir / "train.json").read_text())
    shutil.copyfile(run_dir / "policy.zip", CKPT / f"{name}.zip")
    shutil.copyfile(run_dir / "episodes.csv", CKPT / f"{name}.episodes.csv")
    record = {
        "checkpoint": f"experiments/checkpoints/{name}.zip",
        "command": summary["command"],
        "wall_time_s": wall if wall is not None else summary["wall_time_s"],
        "cpu_time_s": cpu,
        "machine": "2 cores shared with other jobs (load 5-10 while training); "
                   "torch.set_num_threads(1)",
        "timesteps": summary["timesteps"],
        "steps_per_s": summary["steps_per_s"],
        "dishes_per_episode_last50_in_training": summary["dishes_per_episode_last50"],
        "init": summary["config"]["init"],
        "config": summary["config"],
        "size_bytes": (CKPT / f"{name}.zip").stat().st_size,
    }
    (CKPT / f"{name}.json").write_text(json.dumps(record, indent=2) + "\n")
    return record


def train_one(name: str, python: str) -> dict:
    out = ROOT / "experiments" / "runs" / name
    if out.exists():
        shutil.rmtree(out)
    cmd = [python, "-m", "ocplus_plan.cli", "train", *RUNS[name],
           "--out", str(out.relative_to(ROOT)), "--no-progress"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, cwd=ROOT, check=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return ship(name, out, round(wall, 1), round(cpu, 1))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("names", nargs="*", help=f"runs among {', '.join(RUNS)} (default: all)")
    p.add_argument("--ship", metavar="NAME=DIR", action="append", default=[],
                   help="only copy an already finished run DIR as checkpoint NAME")
    args = p.parse_args()
    CKPT.mkdir(parents=True, exist_ok=True)
    if args.ship:
        for item in args.ship:
            name, _, run_dir = item.partition("=")
            print(json.dumps(ship(name, Path(run_dir))), flush=True)
        return
    unknown = [n for n in args.names if n not in RUNS]
    if unknown:
        p.error(f"unknown run(s) {unknown}; choose among {', '.join(RUNS)}")
    for name in args.names or list(RUNS):
        print(json.dumps(train_one(name, sys.executable)), flush=True)


if __name__ == "__main__":
    main()
