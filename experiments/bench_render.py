"""Rendering costs nothing unless asked: env steps/s per ``render_mode``.

For the hard preset (2 cooks, vector observations) it times ``env.step`` with
``render_mode=None``, with ``render_mode="rgb_array"`` but no ``render()`` call, and
with ``render()`` after every step (rgb frame, and the pygame window under SDL's
dummy driver without the fps throttle), plus the raw simulator transition for
reference. Runs are interleaved (None, rgb, None, rgb, ...) so machine noise hits
every mode alike; the median of ``--runs`` is reported. It also checks, in a fresh
process, that a ``render_mode=None`` run draws no frame (``RgbEncoder.draw`` is
never called) and never imports pygame or the window module.

    python experiments/bench_render.py [--steps 5000] [--runs 5]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time

import numpy as np

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")

PRESET, N_AGENTS = "hard", 2


def make_env(render_mode: str | None):
    from ocplus_plan.env.gym_env import OvercookedPlusEnv

    return OvercookedPlusEnv(PRESET, n_agents=N_AGENTS, mode="vector", render_mode=render_mode)


def time_env(render_mode: str | None, call_render: bool, actions: list, seed: int,
             *, window: bool = False) -> float:
    """Env steps/s; ``window``: draw into the pygame window each step (what
    ``render_mode="human"`` does, minus its ``render_fps`` wait)."""
    env = make_env(render_mode)
    if window:
        from ocplus_plan.render.window import Window

        window = Window("bench")
    env.reset(seed=seed)
    t0 = time.perf_counter()
    for joint in actions:
        _, _, term, trunc, _ = env.step(joint)
        if call_render:
            if window:
                window.show(env.core.state)
            else:
                env.render()
        if term or trunc:
            env.reset()
    rate = len(actions) / (time.perf_counter() - t0)
    env.close()
    if window:
        window.close()
    return rate


def time_sim(actions: list, seed: int) -> float:
    from ocplus_plan.sim import make_rules, new_state, transition

    rules = make_rules(PRESET, n_agents=N_AGENTS)
    state = new_state(rules, seed)
    t0 = time.perf_counter()
    for joint in actions:
        if transition(state, joint).truncated:
            state = new_state(rules, seed)
    return len(actions) / (time.perf_counter() - t0)


def what_a_none_run_touches() -> dict[str, object]:
    """In a fresh process: frames drawn and GUI modules imported by 150 steps + render()."""
    code = ("import sys; from ocplus_plan.render import rgb;"
            "calls = [0]; draw = rgb.RgbEncoder.draw\n"
            "def counted(self, state):\n    calls[0] += 1; return draw(self, state)\n"
            "rgb.RgbEncoder.draw = counted\n"
            "from ocplus_plan.env.gym_env import OvercookedPlusEnv\n"
            f"env = OvercookedPlusEnv({PRESET!r}, n_agents={N_AGENTS}, render_mode=None)\n"
            "env.reset(seed=0); [env.step([0, 4]) for _ in range(150)]; env.render()\n"
            "mods = [m for m in sys.modules if m.split('.')[0] == 'pygame' "
            "or m == 'ocplus_plan.render.window']\n"
            "print(calls[0], ' '.join(mods))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    calls, *mods = out.stdout.split()
    return {"frames_drawn": int(calls), "pygame_or_window_modules": mods}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=5000)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--render-steps", type=int, default=500,
                        help="steps for the modes that draw every step (slower)")
    args = parser.parse_args()
    actions = np.random.default_rng(0).integers(0, 5, size=(args.steps, N_AGENTS)).tolist()
    few = actions[: args.render_steps]
    modes = {
        "sim transition (reference)": lambda run: time_sim(actions, run),
        "env render_mode=None": lambda run: time_env(None, False, actions, run),
        "env render_mode=rgb_array, no render() call": lambda run: time_env(
            "rgb_array", False, actions, run),
        "env rgb_array + render() every step": lambda run: time_env(
            "rgb_array", True, few, run),
        "env + pygame window show() every step (dummy driver, no fps cap)": lambda run: time_env(
            None, True, few, run, window=True),
    }
    rates: dict[str, list[float]] = {name: [] for name in modes}
    for run in range(args.runs):
        for name, fn in modes.items():
            rates[name].append(fn(run))
    base = statistics.median(rates["env render_mode=None"])
    for name, values in rates.items():
        med = statistics.median(values)
        print(json.dumps({
            "bench": "render", "preset": PRESET, "n_agents": N_AGENTS, "mode": name,
            "steps_per_s_median": round(med), "steps_per_s_min": round(min(values)),
            "relative_to_render_none": round(med / base, 3), "runs": args.runs,
            "python": platform.python_version(),
        }))
    print(json.dumps({"bench": "render", "check": "render_mode=None, 150 steps + render()",
                      **what_a_none_run_touches()}))


if __name__ == "__main__":
    main()
