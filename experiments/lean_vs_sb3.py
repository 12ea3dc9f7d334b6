"""Does the lean PPO loop learn as well as the SB3 trainer with the same steps?

    .venv/bin/python experiments/lean_vs_sb3.py                      # easy, 1 cook, 2M steps
    .venv/bin/python experiments/lean_vs_sb3.py --steps 1000000 --seeds 0 --trainers sb3,lean

For each trainer and training seed, one ``ocplus train`` run from scratch (the same kitchen,
steps, shaping and learning rate; only the loop and its batch settings differ, see
TRAINERS) into ``experiments/runs/lean_vs_sb3/``, one after the other, then the policy's
dishes per 200-step episode over 20 evaluation seeds (experiments/eval_checkpoints.py,
sampled actions). Prints one JSON line per run and a last line per trainer with the means
over training seeds (easy from scratch takes off at a seed-dependent moment, so one
seed per trainer says little).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "experiments"))

from eval_checkpoints import evaluate

#: trainer -> its ocplus train options. sb3 is the setting the session-5 checkpoints
#: trained with (FAST in train_baselines.py: 32 kitchens x 128 steps, 2048-sample
#: minibatches, 4 epochs); the lean ones run the same PPO over 256 kitchens x 16 steps
#: (the same 4,096 samples per update), in bfloat16, with 4, 3 or 2 epochs.
TRAINERS: dict[str, list[str]] = {
    "sb3": ["--n-kitchens", "32", "--n-steps", "128", "--batch-size", "2048",
            "--n-epochs", "4"],
    "lean": ["--algo", "lean", "--precision", "bf16", "--n-kitchens", "256", "--n-steps", "16",
             "--batch-size", "2048", "--n-epochs", "4"],
    "lean_2epochs": ["--algo", "lean", "--precision", "bf16", "--n-kitchens", "256",
                     "--n-steps", "16", "--batch-size", "2048", "--n-epochs", "2"],
    "lean_3epochs": ["--algo", "lean", "--precision", "bf16", "--n-kitchens", "256",
                     "--n-steps", "16", "--batch-size", "2048", "--n-epochs", "3"],
}


def run(trainer: str, preset: str, n_agents: int, steps: int, seed: int, eval_seeds: int,
        ) -> dict:
    out = ROOT / "experiments" / "runs" / "lean_vs_sb3" / f"{preset}_{n_agents}_{trainer}_{seed}"
    cmd = [sys.executable, "-m", "ocplus_plan.cli", "train", "--preset", preset,
           "--n-agents", str(n_agents), "--steps", str(steps), "--seed", str(seed),
           *TRAINERS[trainer], "--out", str(out), "--quiet"]
    subprocess.run(cmd, cwd=ROOT, check=True, stdout=subprocess.DEVNULL)
    summary = json.loads((out / "train.json").read_text())
    scored = evaluate(out / "policy.npz", preset, n_agents, eval_seeds, "sample")
    return {"trainer": trainer, "seed": seed, "preset": preset, "n_agents": n_agents,
            "command": summary["command"], "timesteps": summary["timesteps"],
            "wall_time_s": summary["wall_time_s"], "steps_per_s": summary["steps_per_s"],
            "dishes_last50_in_training": summary["dishes_per_episode_last50"],
            "eval_dishes_mean": scored["dishes_mean"], "eval_dishes_std": scored["dishes_std"],
            "eval_seeds": eval_seeds, "loadavg_1min": round(os.getloadavg()[0], 2)}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--preset", default="easy")
    p.add_argument("--n-agents", type=int, default=1)
    p.add_argument("--steps", type=int, default=2_000_000)
    p.add_argument("--seeds", default="0,1,2", help="training seeds, comma-separated")
    p.add_argument("--eval-seeds", type=int, default=20)
    p.add_argument("--trainers", default=",".join(TRAINERS),
                   help="comma-separated among " + ", ".join(TRAINERS))
    args = p.parse_args()
    trainers = args.trainers.split(",")
    unknown = [t for t in trainers if t not in TRAINERS]
    if unknown:
        p.error(f"unknown trainer(s) {unknown}; choose among {', '.join(TRAINERS)}")
    rows: dict[str, list[dict]] = {t: [] for t in trainers}
    for seed in (int(s) for s in args.seeds.split(",")):
        for trainer in trainers:
            row = run(trainer, args.preset, args.n_agents, args.steps, seed, args.eval_seeds)
            rows[trainer].append(row)
            print(json.dumps(row), flush=True)
    for trainer, got in rows.items():
        dishes = [r["eval_dishes_mean"] for r in got]
        print(json.dumps({
            "summary": trainer, "preset": args.preset, "n_agents": args.n_agents,
            "steps": args.steps, "seeds": [r["seed"] for r in got],
            "eval_dishes_per_seed": dishes,
            "eval_dishes_mean_over_seeds": round(statistics.mean(dishes), 2),
            "steps_per_s_median": statistics.median(r["steps_per_s"] for r in got),
            "wall_time_s_median": statistics.median(r["wall_time_s"] for r in got),
        }), flush=True)


if __name__ == "__main__":
    main()
