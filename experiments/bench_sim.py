"""Steps per second of the raw transition, per preset, with random actions; and of the
Gymnasium env (``--only env``). Batched kitchens: ``experiments/bench_batch.py``.

Median of 5 runs of N steps each on one core (actions drawn up front so the
timing is the transition alone; episodes restart with ``new_state`` at the
horizon, which is included). Prints one JSON line per configuration.

Env section: ``OvercookedPlusEnv.step`` (the env class itself, no Gymnasium wrappers)
per observation mode (vector, rgb) for 1 and 2 agents on the hard preset, resets
included (wall clock), plus a profile split in CPU time: the share of the step spent in
the transition, in the observation encoder, and in the env's own bookkeeping (vector
mode also reports the from-scratch encoder's cost, ``us_encoder_scratch_cpu``, next to
the env's incremental one).

    python experiments/bench_sim.py [--steps 50000] [--runs 5] [--only transition|env]
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import time

import numpy as np

from ocplus_plan.sim import make_rules, new_state, transition

CONFIGS = [("easy", 1), ("easy", 2), ("medium", 1), ("medium", 2), ("hard", 2)]


def bench_transition(preset: str, n_agents: int, steps: int, runs: int) -> dict:
    rules = make_rules(preset, n_agents=n_agents)
    actions = np.random.default_rng(0).integers(0, 5, size=(steps, n_agents)).tolist()
    rates = []
    for run in range(runs):
        state = new_state(rules, run)
        t0 = time.perf_counter()
        for joint in actions:
            if transition(state, joint).truncated:
                state = new_state(rules, run)
        rates.append(steps / (time.perf_counter() - t0))
    return {
        "bench": "transition", "preset": preset, "map": rules.layout.name, "n_agents": n_agents,
        "steps": steps, "runs": runs, "steps_per_s_median": round(statistics.median(rates)),
        "steps_per_s_min": round(min(rates)), "python": platform.python_version(),
    }


# ---------------------------------------------------------------- env section
#: (preset, n_agents, mode, obs_radius) of the env benchmark
ENV_CONFIGS = [
    ("hard", 1, "vector", 0), ("hard", 2, "vector", 0), ("hard", 2, "vector", 2),
    ("hard", 1, "rgb", 0), ("hard", 2, "rgb", 0), ("hard", 2, "rgb", 2),
]


def _env_split(env, actions: list, runs: int) -> dict:
    """Where the step goes, in CPU time of this process (so other load on the machine
    inflates nothing but cache misses), best of ``runs``, from three loops over the same
    actions: the simulator step alone (``KitchenCore.step``: transition + messages), the
    same plus the observation encoder, and ``env.step`` itself. The encoder's cost is the
    difference of the first two, measured on a hot state as in real use; the env's own
    bookkeeping (action parsing, info, tuple) is the rest. Vector mode adds a fourth loop
    with the from-scratch ``VectorEncoder.encode`` in place of the env's incremental
    encoder (``us_encoder_scratch_cpu``: what the encoder cost before it was incremental)."""
    core = env.core
    clock = time.process_time

    def loop(observe: bool, scratch: bool = False) -> None:
        env.reset(seed=0)
        for joint in actions:
            result = core.step(*core.split_action(joint))
            if scratch:
                core.vector.encode(core.state, core.received if core.comm else None)
            elif observe:
                core.observe()
            if result.terminated or result.truncated:
                env.reset()

    def steps() -> None:
        env.reset(seed=0)
        for joint in actions:
            _, _, terminated, truncated, _ = env.step(joint)
            if terminated or truncated:
                env.reset()

    # the three loops take turns, so a burst of load on the machine hits them alike
    loops = {"sim": lambda: loop(False), "sim+obs": lambda: loop(True), "step": steps}
    if core.vector is not None:
        loops["sim+scratch"] = lambda: loop(True, scratch=True)
    times: dict[str, list[float]] = {name: [] for name in loops}
    for _ in range(runs):
        for name, fn in loops.items():
            t0 = clock()
            fn()
            times[name].append(clock() - t0)
    best = {name: min(t) / len(actions) * 1e6 for name, t in times.items()}
    env.reset(seed=0)
    step, trans = best["step"], best["sim"]
    enc = max(0.0, best["sim+obs"] - trans)
    split = {"us_step_cpu": round(step, 2), "us_transition_cpu": round(trans, 2),
             "us_encoder_cpu": round(enc, 2), "us_env_cpu": round(max(0.0, step - trans - enc), 2),
             "share_transition": round(trans / step, 3), "share_encoder": round(enc / step, 3),
             "cpu_steps_per_s": round(1e6 / step)}
    if "sim+scratch" in best:
        split["us_encoder_scratch_cpu"] = round(max(0.0, best["sim+scratch"] - trans), 2)
    return split


def bench_env(preset: str, n_agents: int, mode: str, radius: int, steps: int, runs: int) -> dict:
    from ocplus_plan.env.gym_env import OvercookedPlusEnv

    env = OvercookedPlusEnv(preset, n_agents=n_agents, mode=mode, obs_radius=radius)
    actions = np.random.default_rng(0).integers(0, 5, size=(steps, n_agents)).tolist()
    rates = []
    for run in range(runs):
        env.reset(seed=run)
        t0 = time.perf_counter()
        for joint in actions:
            _, _, terminated, truncated, _ = env.step(joint)
            if terminated or truncated:
                env.reset()
        rates.append(steps / (time.perf_counter() - t0))
    obs_shape = env.observation_space[0].shape
    return {
        "bench": "env", "preset": preset, "map": env.rules.layout.name, "n_agents": n_agents,
        "mode": mode, "obs_radius": radius, "obs_shape": list(obs_shape), "steps": steps,
        "runs": runs, "steps_per_s_median": round(statistics.median(rates)),
        "steps_per_s_min": round(min(rates)), "split": _env_split(env, actions, runs),
        "python": platform.python_version(),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=50_000)
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--only", choices=("transition", "env"), default=None,
                    help="run one section (default: all)")
    args = ap.parse_args()
    if args.only in (None, "transition"):
        for preset, n in CONFIGS:
            print(json.dumps(bench_transition(preset, n, args.steps, args.runs)), flush=True)
    if args.only in (None, "env"):
        for preset, n, mode, radius in ENV_CONFIGS:
            steps = args.steps if mode == "vector" else max(1, args.steps // 5)
            print(json.dumps(bench_env(preset, n, mode, radius, steps, args.runs)), flush=True)


if __name__ == "__main__":
    main()
