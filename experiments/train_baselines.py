"""Train the shipped PPO checkpoints and record how (command, wall time, CPU time).

    .venv/bin/python experiments/train_baselines.py                # all, in order
    .venv/bin/python experiments/train_baselines.py easy_1agent    # just one

Each run is ``ocplus train ... --out experiments/runs/NAME``; its weights-only policy is
copied to ``experiments/checkpoints/NAME.npz`` (what ``ppo`` loads; the SB3 ``NAME.zip``
is kept beside it in the source tree, not shipped) and ``NAME.json`` beside it records the exact
command, its wall time and CPU time on this machine, and the training summary;
``NAME.episodes.csv`` keeps the training log (game reward and dishes per episode) for
experiments/plot_learning_curves.py (``experiments/runs/`` itself is git-ignored). The
two-agent run starts from the easy checkpoint (``--init``): the features are map- and
agent-count-independent, so what was learned alone transfers to a shared kitchen. The
medium checkpoint is the end of a three-stage chain (see RUNS). The hard checkpoints and
medium with 2 cooks start by cloning the greedy cook (``--bc greedy``, rl/imitation.py),
then run PPO; their record keeps the imitation rounds and ``experiments/runs/NAME/
bc_policy.npz`` the clone alone (evaluate it with eval_checkpoints.py to compare).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CKPT = ROOT / "experiments" / "checkpoints"

#: the throughput settings measured by experiments/bench_train.py (32 kitchens, 2048-sample
#: minibatches, 4 epochs; the network is unchanged)
FAST = ["--n-kitchens", "32", "--batch-size", "2048", "--n-epochs", "4"]

#: the imitation warm start (rl/imitation.py) and the gentle PPO that follows it
BC = ["--bc", "greedy", "--bc-steps", "60000", "--bc-rounds", "4", "--bc-epochs", "8",
      "--lr", "1e-4", "--ent-coef", "0.003", "--anneal-fraction", "0"]

BC_GRID = [*BC[:2], "--bc-steps", "30000", "--bc-rounds", "3", *BC[6:]]
GRID_FAST = ["--n-kitchens", "128", "--n-steps", "64", "--batch-size", "2048", "--n-epochs", "4"]


def _grid_run(preset: str, n_agents: int, seed: int) -> list[str]:
    """The grid-observation recipe: clone the greedy cook (BC_GRID), then 7 minutes of PPO
    on the batched engine (GRID_FAST)."""
    return ["--preset", preset, "--n-agents", str(n_agents), "--steps", "20000000", "--seed",
            str(seed), "--obs", "grid", "--engine", "batch", *BC_GRID, "--max-wall", "420",
            *GRID_FAST]

#: name -> ocplus train arguments (without --out), in order (later runs --init from earlier
#: ones). Names starting with "_" are intermediate stages: trained, not shipped.
RUNS: dict[str, list[str]] = {
    "easy_1agent": ["--preset", "easy", "--steps", "400000", "--seed", "0",
                    "--anneal-fraction", "0.8", "--n-epochs", "8", "--ent-coef", "0.02",
                    "--n-kitchens", "8"],
    "easy_2agent": ["--preset", "easy", "--n-agents", "2", "--steps", "200000", "--seed", "0",
                    "--init", "experiments/checkpoints/easy_1agent.npz"],
    # medium from scratch: one-ingredient steak orders teach the pan (an easy-trained start
    # never explored the steak), then steak + one vegetable, then the preset's own recipes
    "_medium_stage1": ["--preset", "medium", "--steps", "400000", "--seed", "0",
                       "--curriculum", "medium:steak,medium:steak+tomato/steak+lettuce/steak+onion",
                       "--curriculum-fraction", "0.5", "--ent-coef", "0.03"],
    "_medium_stage2": ["--preset", "medium", "--steps", "300000", "--seed", "2",
                       "--curriculum", "medium:steak+tomato/steak+lettuce/steak+onion",
                       "--curriculum-fraction", "0.3", "--ent-coef", "0.03", "--init",
                       "experiments/runs/_medium_stage1/checkpoints/step_000160000.npz"],
    "_medium_1agent_v1": ["--preset", "medium", "--steps", "300000", "--seed", "3",
                          "--anneal-fraction", "0.5",
                          "--init", "experiments/runs/_medium_stage2/policy.npz"],
    # long runs at the fast settings (bench_train.py), each under a wall budget;
    # each starts from the shipped checkpoint before it (its record is kept as init_record)
    "medium_1agent": ["--preset", "medium", "--steps", "8000000", "--seed", "4",
                      "--anneal-fraction", "0.5", "--max-wall", "720",
                      "--init", "experiments/checkpoints/medium_1agent.npz", *FAST],
    "_medium_2agent_s4": ["--preset", "medium", "--n-agents", "2", "--steps", "8000000",
                          "--seed", "5", "--anneal-fraction", "0.5", "--max-wall", "720",
                          "--init", "experiments/checkpoints/medium_1agent.npz", *FAST],
    # first attempt: straight onto hard from medium_2agent (served 0 in 10M steps)
    "_hard_2agent_try1": ["--preset", "hard", "--n-agents", "2", "--steps", "10000000",
                          "--seed", "6", "--anneal-fraction", "0.6", "--max-wall", "900",
                          "--init", "experiments/checkpoints/medium_2agent.npz", *FAST],
    # second: half the kitchens serve the two-ingredient steak orders medium taught, on
    # the hard map (dirty plates, layout switches), for the first 40 %
    "_hard_2agent_try2": ["--preset", "hard", "--n-agents", "2", "--steps", "6000000",
                    "--seed", "8", "--anneal-fraction", "0.6", "--max-wall", "600",
                    "--curriculum", "hard:steak+tomato/steak+lettuce/steak+onion",
                    "--curriculum-fraction", "0.4",
                    "--init", "experiments/checkpoints/medium_2agent.npz", *FAST],
    # behaviour cloning from the greedy cook (4 DAgger rounds of 60k
    # kitchen steps), then PPO on the true reward only (no shaping: the clone already
    # serves), with a small learning rate and entropy so PPO refines the clone
    "hard_2agent": ["--preset", "hard", "--n-agents", "2", "--steps", "20000000",
                    "--seed", "9", *BC, "--max-wall", "1200", *FAST],
    "medium_2agent": ["--preset", "medium", "--n-agents", "2", "--steps", "20000000",
                      "--seed", "13", *BC, "--max-wall", "600", *FAST],
    # (the hard preset's default is 2 cooks: --n-agents 1 is needed)
    "hard_1agent": ["--preset", "hard", "--n-agents", "1", "--steps", "20000000",
                    "--seed", "10", *BC, "--max-wall", "720", *FAST],
    # the grid (SPEC one-hot) observation on the batched engine, from scratch
    "_medium_1agent_grid_scratch": ["--preset", "medium", "--steps", "5000000", "--seed", "7",
                           "--obs", "grid", "--engine", "batch", "--anneal-fraction", "0.5",
                           "--max-wall", "300", "--n-kitchens", "128", "--n-steps", "64",
                           "--batch-size", "2048", "--n-epochs", "4"],
    # the same imitation recipe on the grid observation (fewer, larger samples: 1,404 and
    # 2,300 values per cook), PPO on the batched engine
    "medium_1agent_grid": ["--preset", "medium", "--steps", "20000000", "--seed", "11",
                           "--obs", "grid", "--engine", "batch", *BC_GRID, "--max-wall", "420",
                           *GRID_FAST],
    "hard_2agent_grid": _grid_run("hard", 2, 12),
    # the same grid recipe on the kitchens that had no grid row
    "easy_1agent_grid": _grid_run("easy", 1, 14),
    "easy_2agent_grid": _grid_run("easy", 2, 15),
    "medium_2agent_grid": _grid_run("medium", 2, 16),
    "hard_1agent_grid": _grid_run("hard", 1, 17),
}
#: runs whose record and training log ship but whose policy stays in experiments/runs/
#: (grid policies are 2-4 MB and map-bound; the package data keeps to the features ones)
RECORD_ONLY = {"medium_1agent_grid", "hard_2agent_grid", "easy_1agent_grid",
               "easy_2agent_grid", "medium_2agent_grid", "hard_1agent_grid"}
#: run -> the intermediate runs it was initialised from, oldest first (recorded as lineage)
LINEAGE: dict[str, list[str]] = {"_medium_1agent_v1": ["_medium_stage1", "_medium_stage2"]}


#: the shipped training logs keep at most this many episodes (package data stays small)
MAX_LOG_ROWS = 4000


def _thin_log(src: Path, dst: Path) -> None:
    """Copy an episodes.csv, keeping every k-th episode so at most MAX_LOG_ROWS remain (a
    learning curve needs no more; the full log stays in experiments/runs/)."""
    lines = src.read_text().splitlines(keepends=True)
    head, rows = lines[:1], lines[1:]
    k = max(1, -(-len(rows) // MAX_LOG_ROWS))
    dst.write_text("".join(head + rows[::k]))


def ship(name: str, run_dir: Path, wall: float | None = None, cpu: float | None = None,
         earlier: list[Path] | None = None) -> dict:
    """Copy a finished run's policy and training log next to the shipped checkpoints and
    write ``NAME.json`` (the exact command from the run's train.json, times, summary).
    ``earlier``: the runs whose checkpoints this one started from (oldest first); their
    commands and wall times are recorded as the lineage."""
    summary = json.loads((run_dir / "train.json").read_text())
    from ocplus_plan.rl.weights import WeightsPolicy

    lineage = []
    chain = [*(earlier or []), run_dir]
    for k, d in enumerate(chain[:-1], start=1):
        s = json.loads((d / "train.json").read_text())
        nxt = json.loads((chain[k] / "train.json").read_text())
        used = WeightsPolicy(nxt["config"]["init"]).meta["train"]["timesteps"]
        log = f"{name}.stage{k}.episodes.csv"
        shutil.copyfile(d / "episodes.csv", CKPT / log)
        lineage.append({"command": s["command"], "wall_time_s": s["wall_time_s"],
                        "timesteps": s["timesteps"], "used_timesteps": used,
                        "episodes": log, "config": s["config"]})
    # a run that starts from a shipped checkpoint keeps that checkpoint's record (read
    # before this run's files replace it when the names are the same)
    init = summary["config"]["init"] or ""
    previous = None
    if init.startswith("experiments/checkpoints/"):
        init_json = ROOT / Path(init).with_suffix(".json")
        previous = json.loads(init_json.read_text()) if init_json.is_file() else None
    shutil.copyfile(run_dir / "policy.zip", CKPT / f"{name}.zip")
    shutil.copyfile(run_dir / "policy.npz", CKPT / f"{name}.npz")
    _thin_log(run_dir / "episodes.csv", CKPT / f"{name}.episodes.csv")
    record = {
        "checkpoint": f"experiments/checkpoints/{name}.npz",
        "command": summary["command"],
        "wall_time_s": wall if wall is not None else summary["wall_time_s"],
        "cpu_time_s": cpu,
        "machine": f"{summary['machine']['cpus']} cores shared with other jobs (1-min load "
                   f"average {os.getloadavg()[0]:.1f} when shipped); torch threads "
                   f"{summary['machine']['torch_threads']}",
        "timesteps": summary["timesteps"],
        "steps_per_s": summary["steps_per_s"],
        "dishes_per_episode_last50_in_training": summary["dishes_per_episode_last50"],
        "init": summary["config"]["init"],
        "imitation": summary.get("imitation"),
        "config": summary["config"],
        "size_bytes": (CKPT / f"{name}.npz").stat().st_size,
    }
    if lineage:
        record["lineage"] = lineage
        record["total_wall_time_s"] = round(
            record["wall_time_s"] + sum(x["wall_time_s"] for x in lineage), 1)
    if previous is not None:
        record["init_record"] = previous
    if name in RECORD_ONLY:
        (CKPT / f"{name}.zip").unlink()
        (CKPT / f"{name}.npz").unlink()
        record["checkpoint"] = str((run_dir / "policy.npz").relative_to(ROOT)) \
            if run_dir.is_relative_to(ROOT) else str(run_dir / "policy.npz")
    (CKPT / f"{name}.json").write_text(json.dumps(record, indent=2) + "\n")
    return record


def train_one(name: str, python: str) -> dict:
    out = ROOT / "experiments" / "runs" / name
    if out.exists():
        shutil.rmtree(out)
    cmd = [python, "-m", "ocplus_plan.cli", "train", *RUNS[name],
           "--out", str(out.relative_to(ROOT)), "--quiet"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, cwd=ROOT, check=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if name.startswith("_"):  # an intermediate stage: keep the run, ship nothing
        return {"run": str(out.relative_to(ROOT)), "wall_time_s": round(wall, 1),
                "cpu_time_s": round(cpu, 1)}
    earlier = [ROOT / "experiments" / "runs" / n for n in LINEAGE.get(name, [])]
    return ship(name, out, round(wall, 1), round(cpu, 1), earlier=earlier)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("names", nargs="*", help=f"runs among {', '.join(RUNS)} (default: all)")
    p.add_argument("--ship", metavar="NAME=DIR[,EARLIER...]", action="append", default=[],
                   help="only copy an already finished run DIR as checkpoint NAME (EARLIER: "
                        "the runs it was initialised from, oldest first)")
    args = p.parse_args()
    CKPT.mkdir(parents=True, exist_ok=True)
    if args.ship:
        for item in args.ship:
            name, _, dirs = item.partition("=")
            *earlier, run_dir = [Path(d) for d in dirs.split(",")][::-1]
            print(json.dumps(ship(name, run_dir, earlier=earlier[::-1])), flush=True)
        return
    unknown = [n for n in args.names if n not in RUNS]
    if unknown:
        p.error(f"unknown run(s) {unknown}; choose among {', '.join(RUNS)}")
    for name in args.names or list(RUNS):
        print(json.dumps(train_one(name, sys.executable)), flush=True)


if __name__ == "__main__":
    main()
