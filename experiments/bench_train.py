"""PPO training throughput (agent-steps per second of training) and where the time goes.

    .venv/bin/python experiments/bench_train.py                        # before and fast, medium
    .venv/bin/python experiments/bench_train.py --preset hard --n-agents 2 --steps 60000
    .venv/bin/python experiments/bench_train.py --setups fast --n-kitchens 64,256

Each setup builds the model exactly as ``ocplus train`` does (``rl.train.build``), runs
``learn`` for ``--steps`` agent-steps (after one untimed warm-up rollout that compiles the
numba kernels) and splits the wall time into:

* ``sim``: stepping the kitchens and the reward shaping (``step_wait`` minus encoding);
* ``encode``: building observations (the per-kitchen encoder, or the batched engine's
  in-place observation scaled for the network);
* ``forward``: the policy's forward passes while collecting the rollout;
* ``rollout_other``: the rest of collection (SB3's buffer, tensors, GAE, callbacks);
* ``train``: PPO's update (forward again over minibatches, backward, optimiser).

Setups (same network: two 128-unit layers per head unless ``--hidden``):
``before`` is the default trainer on the loop engine (features, 8 kitchens, 128-step
rollouts, 512 minibatch, 8 epochs); ``before_grid`` the same with grid observations;
``after`` the default trainer now (the same settings on the batched engine, which
``TrainConfig`` picks with the ``fast`` extra); ``fast`` the batched engine with grid
observations and larger batches (``--n-kitchens``, ``--fast-*``); ``fast_features`` those
batch settings on the loop engine with features (what the shipped PPO checkpoints
trained with); ``fast_batch_features`` the same on the batched engine; ``lean`` and
``lean_bf16`` those batch settings in the lean loop (``--algo lean``, rl/lean.py, float32
or bfloat16), which keeps its own split (``sim`` + ``encode`` = its ``env``; ``train`` = its
``update``). Prints one JSON line per setup and kitchen count.

    .venv/bin/python experiments/bench_train.py --setups fast_batch_features,lean_bf16 \
        --n-kitchens 256 --fast-n-steps 16 --fast-batch-size 2048 --fast-n-epochs 4

    .venv/bin/python experiments/bench_train.py --before-rev aef8f14 --rounds 3

``--before-rev REV`` instead times two whole ``ocplus train`` runs per round, interleaved so
both see the same machine load: the trainer as it was at commit REV (checked out with
``git worktree add`` into a temporary folder, run by this venv's python with
``PYTHONPATH`` on that tree, with its own defaults: 8 kitchens, 128-step rollouts, 512
minibatch, 8 epochs, features, loop) and today's trainer with the fast settings
(``--n-kitchens`` first value, ``--fast-*``, ``--obs``, ``--engine``, ``--algo``,
``--precision``). Each reads the steps/s its run wrote to train.json; a last line gives
the medians, their ratio and the load average. The worktree is removed afterwards. The lean
loop against the issue-era trainer:

    .venv/bin/python experiments/bench_train.py --before-rev aef8f14 --rounds 3 \
        --algo lean --precision bf16 --n-kitchens 256 --fast-n-steps 16 \
        --fast-batch-size 2048 --fast-n-epochs 4 --after-steps 2000000
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from ocplus_plan.rl.train import TrainConfig, build


def _timed(obj: object, name: str, bucket: dict[str, float], key: str) -> None:
    """Replace ``obj.name`` by a wrapper adding its wall time to ``bucket[key]``."""
    inner = getattr(obj, name)

    def wrapper(*args, **kw):
        t0 = time.perf_counter()
        try:
            return inner(*args, **kw)
        finally:
            bucket[key] += time.perf_counter() - t0

    setattr(obj, name, wrapper)


def measure(config: TrainConfig, steps: int) -> dict:
    from stable_baselines3.common.logger import configure

    model, venv, _, _ = build(config)
    with tempfile.TemporaryDirectory() as tmp:
        model.set_logger(configure(tmp, []))
        warm = venv.num_envs * config.n_steps
        if config.algo == "lean":
            split = _measure_lean(model, venv, config, warm, steps)
        else:
            split = _measure_sb3(model, venv, warm, steps)
    venv.close()
    wall, done = split.pop("wall"), split.pop("done")
    return {
        "preset": config.preset, "n_agents": config.n_agents, "obs": config.obs,
        "engine": config.engine, "algo": config.algo, "precision": config.precision,
        "n_kitchens": config.n_kitchens, "n_steps": config.n_steps,
        "batch_size": config.batch_size, "n_epochs": config.n_epochs,
        "hidden": list(config.hidden), "torch_threads": config.torch_threads,
        "agent_steps": done, "wall_s": round(wall, 2),
        "steps_per_s": round(done / wall, 1),
        "seconds": {k: round(v, 2) for k, v in split.items()},
        "share": {k: round(v / wall, 3) for k, v in split.items()},
        "loadavg_1min": round(os.getloadavg()[0], 2),
    }


def _measure_sb3(model, venv, warm: int, steps: int) -> dict:
    model.learn(warm)  # warm-up: numba compilation, torch allocations
    t = dict.fromkeys(("step_wait", "encode", "forward", "rollout", "train"), 0.0)
    _timed(venv, "step_wait", t, "step_wait")
    _timed(venv, "_encode" if venv.batch is None else "_batch_obs", t, "encode")
    _timed(model.policy, "forward", t, "forward")
    _timed(model, "collect_rollouts", t, "rollout")
    _timed(model, "train", t, "train")
    start = model.num_timesteps
    t0 = time.perf_counter()
    model.learn(steps, reset_num_timesteps=False)
    wall = time.perf_counter() - t0
    return {"sim": t["step_wait"] - t["encode"], "encode": t["encode"], "forward": t["forward"],
            "rollout_other": t["rollout"] - t["step_wait"] - t["forward"], "train": t["train"],
            "wall": wall, "done": model.num_timesteps - start}


def _measure_lean(model, venv, config: TrainConfig, warm: int, steps: int) -> dict:
    """The lean loop keeps its own split (env, forward, rollout_other, update)."""
    from ocplus_plan.rl.lean import LeanPPO

    learner = LeanPPO(model, venv, config.precision, config.seed)
    learner.learn(warm)
    t = {"encode": 0.0}
    _timed(venv, "_encode" if venv.batch is None else "_batch_obs", t, "encode")
    before = dict(learner.seconds)
    start = model.num_timesteps
    t0 = time.perf_counter()
    learner.learn(steps, reset_num_timesteps=False)
    wall = time.perf_counter() - t0
    sec = {k: v - before[k] for k, v in learner.seconds.items()}
    return {"sim": sec["env"] - t["encode"], "encode": t["encode"], "forward": sec["forward"],
            "rollout_other": sec["rollout_other"], "train": sec["update"],
            "wall": wall, "done": model.num_timesteps - start}


SETUPS = ("before", "before_grid", "after", "fast", "fast_features", "fast_batch_features",
          "lean", "lean_bf16")


def cli_rate(tree: Path, argv: list[str]) -> dict:
    """Run ``ocplus train ARGV`` from the source tree ``tree`` (this python, PYTHONPATH on
    the tree) into a temporary folder; its train.json's throughput and wall time."""
    with tempfile.TemporaryDirectory() as out:
        env = {**os.environ, "PYTHONPATH": str(tree)}
        cmd = [sys.executable, "-m", "ocplus_plan.cli", "train", *argv, "--out", out]
        subprocess.run(cmd, cwd=tree, env=env, check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
        summary = json.loads((Path(out) / "train.json").read_text())
    return {"steps_per_s": summary["steps_per_s"], "wall_s": summary["wall_time_s"],
            "agent_steps": summary["timesteps"], "loadavg_1min": round(os.getloadavg()[0], 2)}


def before_after(args: argparse.Namespace) -> None:
    """``--before-rev``: interleaved whole-trainer runs, the trainer at REV vs today's."""
    kitchen = ["--preset", args.preset, "--n-agents", str(args.n_agents), "--seed", "0"]
    before = [*kitchen, "--steps", str(args.before_steps), "--no-progress"]
    after = [*kitchen, "--steps", str(args.after_steps), "--quiet", "--obs", args.obs,
             "--engine", args.engine, "--n-kitchens", args.n_kitchens.split(",")[0],
             "--n-steps", str(args.fast_n_steps), "--batch-size", str(args.fast_batch_size),
             "--n-epochs", str(args.fast_n_epochs), "--torch-threads", str(args.torch_threads),
             "--algo", args.algo, "--precision", args.precision]
    rates: dict[str, list[float]] = {"before": [], "after": []}
    with tempfile.TemporaryDirectory() as tmp:
        tree = Path(tmp) / "before"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(tree),
                        args.before_rev], check=True, capture_output=True)
        try:
            for rnd in range(args.rounds):
                for name, tree_, argv in (("before", tree, before), ("after", ROOT, after)):
                    row = cli_rate(tree_, argv)
                    rates[name].append(row["steps_per_s"])
                    rev = args.before_rev if name == "before" else "HEAD"
                    print(json.dumps({"round": rnd, "trainer": name, "rev": rev,
                                      "args": argv, **row}), flush=True)
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force",
                            str(tree)], check=False, capture_output=True)
    med = {k: statistics.median(v) for k, v in rates.items()}
    print(json.dumps({"summary": "median steps/s", "before_rev": args.before_rev,
                      "before": med["before"], "after": med["after"],
                      "ratio": round(med["after"] / med["before"], 1),
                      "rounds": args.rounds, "uptime_loadavg": os.getloadavg()}), flush=True)


def bench_jax_ppo(preset: str, n_agents: int, kitchens: list[int], n_steps: int,
                  obs_radius: int, runs: int) -> None:
    """``--jax-ppo``: the jitted parameter-shared PPO (rl/fast/jax_ppo.py) on the JAX
    kitchen; agent-steps/s of whole training calls (rollouts and updates), compile apart."""
    import jax

    import ocplus_plan
    from ocplus_plan.rl.fast.jax_ppo import PPOConfig, agent_steps, make_train

    env = ocplus_plan.make_jax_env(preset, n_agents=n_agents, obs_radius=obs_radius)
    for k in kitchens:
        config = PPOConfig(n_envs=k, n_steps=n_steps, n_updates=5)
        train = jax.jit(make_train(env, config))
        t0 = time.perf_counter()
        jax.block_until_ready(train(jax.random.PRNGKey(0)))
        compile_s = time.perf_counter() - t0
        times = []
        for r in range(runs):
            t0 = time.perf_counter()
            _, rewards = jax.block_until_ready(train(jax.random.PRNGKey(r + 1)))
            times.append(time.perf_counter() - t0)
        print(json.dumps({
            "bench": "train", "setup": "jax_ppo", "preset": preset, "n_agents": n_agents,
            "obs_radius": obs_radius, "n_kitchens": k, "n_steps": n_steps,
            "config": config._asdict(), "agent_steps": agent_steps(config, n_agents),
            "agent_steps_per_s_median": round(agent_steps(config, n_agents)
                                              / statistics.median(times)),
            "compile_and_first_s": round(compile_s, 1),
            "mean_team_reward_per_step_last_update": float(rewards[-1]),
            "device": str(jax.devices()[0].device_kind), "jax": jax.__version__,
            "load": " ".join(f"{x:.2f}" for x in os.getloadavg())}), flush=True)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--preset", default="medium")
    p.add_argument("--n-agents", type=int, default=1)
    p.add_argument("--steps", type=int, default=30_000, help="timed agent-steps per setup")
    p.add_argument("--setups", default="before,before_grid,fast_features,fast",
                   help="comma-separated among " + ", ".join(SETUPS))
    p.add_argument("--n-kitchens", default="32,128",
                   help="fast setups: kitchens (comma-separated, one line each)")
    p.add_argument("--fast-n-steps", type=int, default=64)
    p.add_argument("--fast-batch-size", type=int, default=2048)
    p.add_argument("--fast-n-epochs", type=int, default=4)
    p.add_argument("--torch-threads", type=int, default=1)
    p.add_argument("--hidden", default="128,128")
    p.add_argument("--jax-ppo", action="store_true",
                   help="time the jitted JAX PPO instead (--n-kitchens, --fast-n-steps, "
                        "--obs-radius; the jax extra, or jax with CUDA)")
    p.add_argument("--obs-radius", type=int, default=0)
    c = p.add_argument_group("before/after (--before-rev)")
    c.add_argument("--before-rev", default=None, metavar="REV",
                   help="time the trainer at this commit against today's, interleaved")
    c.add_argument("--rounds", type=int, default=3)
    c.add_argument("--before-steps", type=int, default=20_000,
                   help="agent-steps of each run of the trainer at REV")
    c.add_argument("--after-steps", type=int, default=300_000,
                   help="agent-steps of each run of today's trainer")
    c.add_argument("--engine", default="auto", help="today's trainer: --engine")
    c.add_argument("--obs", default="features", help="today's trainer: --obs")
    c.add_argument("--algo", default="sb3", choices=("sb3", "lean"),
                   help="today's trainer: --algo")
    c.add_argument("--precision", default="fp32", choices=("fp32", "bf16"),
                   help="today's trainer: --precision (with --algo lean)")
    args = p.parse_args()
    if args.jax_ppo:
        bench_jax_ppo(args.preset, args.n_agents, [int(k) for k in args.n_kitchens.split(",")],
                      args.fast_n_steps, args.obs_radius, 3)
        return
    if args.before_rev:
        before_after(args)
        return
    hidden = tuple(int(h) for h in args.hidden.split(","))
    base = dict(preset=args.preset, n_agents=args.n_agents, hidden=hidden,
                torch_threads=args.torch_threads)
    for setup in args.setups.split(","):
        if setup in ("before", "before_grid", "after"):
            configs = [TrainConfig(**base, obs="grid" if setup == "before_grid" else "features",
                                   engine="batch" if setup == "after" else "loop")]
        elif setup in ("fast", "fast_features", "fast_batch_features", "lean", "lean_bf16"):
            engine = {"fast": dict(obs="grid", engine="batch"),
                      "fast_features": dict(engine="loop"),
                      "fast_batch_features": dict(engine="batch"),
                      "lean": dict(engine="batch", algo="lean"),
                      "lean_bf16": dict(engine="batch", algo="lean", precision="bf16")}[setup]
            configs = [TrainConfig(**base, **engine, n_kitchens=int(k),
                                   n_steps=args.fast_n_steps, batch_size=args.fast_batch_size,
                                   n_epochs=args.fast_n_epochs)
                       for k in args.n_kitchens.split(",")]
        else:
            p.error(f"unknown setup {setup!r}; choose among {', '.join(SETUPS)}")
        for config in configs:
            print(json.dumps({"setup": setup, **measure(config, args.steps)}), flush=True)


if __name__ == "__main__":
    main()
