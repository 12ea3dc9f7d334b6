"""Does ``ocplus train --engine jax`` learn easy with 1 cook? Train, then evaluate.

    XLA_FLAGS="--xla_cpu_multi_thread_eigen=false intra_op_parallelism_threads=1" \\
      nice -n 10 python experiments/bench_jax_easy.py --variant full --out runs/jax_easy

trains the JAX PPO on easy with 1 cook (64 kitchens, 64-step rollouts, 2 epochs, lr 5e-4,
entropy 0.02, 128x128, order curriculum 0.5; with ``--variant full`` the same run as
``ocplus train --engine jax --preset easy --n-agents 1 --n-kitchens 64 --n-steps 64
--timesteps T --n-epochs 2 --lr 5e-4 --ent-coef 0.02 --hidden 128,128 --order-curriculum
0.5 --restart-after 0.2 --seed S``), then plays the policy with the package's evaluation
(``ocplus eval --preset easy --n-agents 1 --agents ppo:OUT/policy.npz@MODE --seeds N
--horizon 200``, sampled and argmax actions) and appends one JSON line to ``--record``:
command, commit, machine, load, agent-steps, wall and CPU seconds of the training, the
learners started again, and dishes per 200-step episode. The other variants each undo one
of the trainer's fixes, to show what each is worth, or try an option:

* ``shared``: one network for policy and value (no separate critic);
* ``rules-reward``: the rules' reward (subtask payments included), no potential shaping;
* ``in-step``: every kitchen starts its episode at the same step;
* ``uniform-orders``: no order curriculum (orders drawn uniformly while training too);
* ``subtask-start``: the subtask payment paid at first, annealed to 0 over the first half
  (an option, not the default);
* ``subtasks``: the subtask payment paid all along (not annealed);
* ``no-restart``: a learner that serves nothing is never started again
  (``PPOConfig.restart_after`` 0);
* ``no-bonus``: no baseline-free shaping term in the advantages
  (``PPOConfig.shaping_bonus`` 0: the trainer before it);
* ``before``: the trainer as it was: one network, the rules' reward, kitchens in step,
  uniform orders, a constant learning rate.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
VARIANTS = {"full": {}, "shared": {"critic": False},
            "rules-reward": {"shaping": 0.0, "subtask_reward": True},
            "in-step": {"desync": False},
            "uniform-orders": {"order_curriculum": 0.0},
            "subtasks": {"subtask_reward": True},
            "subtask-start": {"subtask_anneal": 0.5},
            "no-restart": {"restart_after": 0.0},
            "no-bonus": {"shaping_bonus": 0.0},
            "before": {"critic": False, "shaping": 0.0, "subtask_reward": True,
                       "desync": False, "lr_final": 1.0, "order_curriculum": 0.0}}


def _commit() -> str:
    return subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                          capture_output=True, text=True).stdout.strip()


def _eval(policy: Path, mode: str, seeds: int, out: Path) -> dict:
    shutil.rmtree(out / f"eval_{mode}", ignore_errors=True)  # this script's own output
    cmd = [str(Path(sys.executable).with_name("ocplus")), "eval", "--preset", "easy",
           "--n-agents", "1", "--agents", f"ppo:{policy}@{mode}", "--seeds", str(seeds),
           "--horizon", "200", "--jobs", "1", "--no-plots", "--quiet", "--json",
           "--out", str(out / f"eval_{mode}")]
    done = subprocess.run(cmd, capture_output=True, text=True, check=True)
    board = json.loads(done.stdout.strip().splitlines()[-1])["leaderboard"][0]
    rows = [json.loads(x) for x in (out / f"eval_{mode}" / "results.jsonl").read_text()
            .splitlines()]
    return {"command": "ocplus " + " ".join(cmd[1:]),
            "dishes_mean": board["dishes_served_mean"],
            "dishes_ci95": round(board["dishes_served_ci95"], 3),
            "dishes_by_seed": [r["stats"]["dishes_served"] for r in rows]}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--variant", choices=sorted(VARIANTS), default="full")
    ap.add_argument("--timesteps", type=int, default=3_000_000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--eval-seeds", type=int, default=20)
    ap.add_argument("--ent-coef", type=float, default=0.02)
    ap.add_argument("--n-kitchens", type=int, default=64)
    ap.add_argument("--order-curriculum", type=float, default=None,
                    help="PPOConfig.order_curriculum (default: the package's)")
    ap.add_argument("--n-steps", type=int, default=64)
    ap.add_argument("--restart-after", type=float, default=None,
                    help="PPOConfig.restart_after (default: the package's)")
    ap.add_argument("--out", type=Path, default=ROOT / "runs" / "jax_easy")
    ap.add_argument("--record", type=Path,
                    default=ROOT / "experiments" / "results" / "bench_jax_easy.jsonl")
    args = ap.parse_args(argv)

    import ocplus_plan
    from ocplus_plan.rl.fast.jax_ppo import PPOConfig, train_to_folder

    env = ocplus_plan.make_jax_env("easy", n_agents=1)
    base = PPOConfig(n_envs=args.n_kitchens, n_steps=args.n_steps, n_epochs=2, hidden=128,
                     lr=5e-4, ent_coef=args.ent_coef)
    if args.order_curriculum is not None:
        base = base._replace(order_curriculum=args.order_curriculum)
    if args.restart_after is not None:
        base = base._replace(restart_after=args.restart_after)
    config = base._replace(n_updates=max(1, args.timesteps // (args.n_kitchens * args.n_steps)),
                           **VARIANTS[args.variant])
    out = (args.out / args.variant
           / f"k{args.n_kitchens}_n{args.n_steps}_ent{args.ent_coef}"
           f"_oc{config.order_curriculum}_ra{config.restart_after}_t{args.timesteps}"
           f"_seed{args.seed}")
    load0 = os.getloadavg()
    cpu0, t0 = time.process_time(), time.perf_counter()
    cli = (f"ocplus train --engine jax --preset easy --n-agents 1 "
           f"--n-kitchens {args.n_kitchens} --n-steps {args.n_steps} "
           f"--timesteps {args.timesteps} --n-epochs 2 --lr 5e-4 --ent-coef {args.ent_coef} "
           f"--hidden 128,128 --order-curriculum {config.order_curriculum} "
           f"--restart-after {config.restart_after} --seed {args.seed} "
           f"--out {out}")
    summary = train_to_folder(env, config, str(out), args.seed,
                              cli if args.variant == "full" else None, stream=sys.stderr)
    cpu, wall = time.process_time() - cpu0, time.perf_counter() - t0
    load1 = os.getloadavg()
    record = {
        "command": "python experiments/bench_jax_easy.py " + " ".join(argv or sys.argv[1:]),
        "same_as": cli if args.variant == "full" else None, "variant": args.variant,
        "config": config._asdict(), "commit": _commit(),
        "machine": f"{platform.machine()}, 2 shared cores",
        "load_1min_before_after": [round(load0[0], 2), round(load1[0], 2)],
        "agent_steps": summary["timesteps"], "train_wall_s": round(wall, 1),
        "train_cpu_s": round(cpu, 1),
        "dishes_in_training_last_update": summary["dishes_per_episode_by_update"][-1],
        "restarts": summary["restarts"],
        "learner_start_update": summary["learner_start_update"],
        "recipes": summary["recipes"],
        "served_by_recipe_last_update": summary["served_by_recipe_by_update"][-1],
        "eval": {mode: _eval(out / "policy.npz", mode, args.eval_seeds, out)
                 for mode in ("sample", "greedy")},
    }
    args.record.parent.mkdir(parents=True, exist_ok=True)
    with args.record.open("a") as f:
        f.write(json.dumps(record) + "\n")
    print(json.dumps({k: record[k] for k in ("variant", "agent_steps", "train_wall_s",
                                             "train_cpu_s")}
                     | {m: record["eval"][m]["dishes_mean"] for m in record["eval"]}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
