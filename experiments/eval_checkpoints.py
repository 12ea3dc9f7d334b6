"""Dishes served per 200-step episode by each shipped PPO checkpoint, over 20 seeds.

    .venv/bin/python experiments/eval_checkpoints.py                 # every shipped checkpoint
    .venv/bin/python experiments/eval_checkpoints.py --preset hard --n-agents 2 \
        experiments/checkpoints/medium_1agent.npz                   # a policy on another preset

Prints one JSON line per (checkpoint, preset, mode). Seeds are 0..N-1; the controller
samples with its own seeded generator, so every number here is reproducible.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from ocplus_plan.agents.ppo import PPOAgent
from ocplus_plan.rl.weights import WeightsPolicy
from ocplus_plan.sim import make_rules, new_state, transition


def evaluate(path: Path, preset: str, n_agents: int, seeds: int, mode: str | None,
             horizon: int = 200) -> dict:
    agent = PPOAgent(str(path), seed=0, mode=mode)
    rules = make_rules(preset, n_agents=n_agents, horizon=horizon)
    dishes, rewards = [], []
    t0 = time.perf_counter()
    for seed in range(seeds):
        state = new_state(rules, seed)
        agent.reset(state)
        total = 0.0
        while not state.done:
            total += sum(transition(state, agent.act(state)).rewards)
        dishes.append(state.stats["dishes_served"])
        rewards.append(total)
    return {
        "checkpoint": str(path.relative_to(ROOT) if path.is_relative_to(ROOT) else path),
        "preset": preset, "map": rules.layout.name, "n_agents": n_agents, "mode": agent.mode,
        "seeds": seeds, "horizon": horizon,
        "dishes_mean": round(statistics.mean(dishes), 3),
        "dishes_std": round(statistics.pstdev(dishes), 3),
        "dishes_min": min(dishes), "dishes_max": max(dishes),
        "reward_mean": round(statistics.mean(rewards), 2),
        "dishes_per_seed": dishes,
        "wall_s": round(time.perf_counter() - t0, 2),
    }


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("checkpoints", nargs="*", type=Path,
                   help="checkpoints (default: experiments/checkpoints/*.npz)")
    p.add_argument("--seeds", type=int, default=20)
    p.add_argument("--preset", default=None, help="evaluate on this preset (default: trained one)")
    p.add_argument("--n-agents", type=int, default=None)
    p.add_argument("--modes", default="sample,greedy", help="comma-separated: sample, greedy")
    args = p.parse_args()
    paths = args.checkpoints or sorted((ROOT / "experiments" / "checkpoints").glob("*.npz"))
    for path in paths:
        meta = WeightsPolicy(path).meta
        for mode in args.modes.split(","):
            print(json.dumps(evaluate(path, args.preset or meta["preset"],
                                      args.n_agents or meta["n_agents"], args.seeds,
                                      mode.strip())), flush=True)


if __name__ == "__main__":
    main()
