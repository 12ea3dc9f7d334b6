"""What a language model reads: sizes of the text observation and of the llm controller's
prompts, and what writing them costs per step, per preset.

For each preset (its default map and cooks), random play from seed 0 for ``--steps`` steps:
the mean and largest text observation (characters, cook 0), the mean policy prompt (all
cooks driven by one model), the time to write every cook's text observation (median over
the steps, microseconds of wall clock), and the planner-mode prompt of the initial state
(kitchen words, the domain cut to the actions that can apply, in words and as PDDL,
or one of the two, and the PDDL problem; needs the ``planners`` extra). Characters
divided by 4 is a common rough token estimate. Prints one JSON line per preset.

    python experiments/bench_text.py [--steps 200]
"""

from __future__ import annotations

import argparse
import json
import statistics
import time

import numpy as np

from ocplus_plan.agents.llm import LLMAgent
from ocplus_plan.sim import make_rules, new_state, transition
from ocplus_plan.sim.observe_text import text_observations


def measure(preset: str, steps: int) -> dict:
    rules = make_rules(preset)
    state = new_state(rules, 0)
    rng = np.random.default_rng(0)
    prompts: list[str] = []
    agent = LLMAgent(lambda p: prompts.append(p) or "", log="none")
    agent.reset(state)
    sizes, times = [], []
    for _ in range(steps):
        t0 = time.perf_counter()
        texts = text_observations(state)
        times.append(time.perf_counter() - t0)
        sizes.append(len(texts[0]))
        agent.act(state)
        transition(state, [int(a) for a in rng.integers(0, 5, state.n_agents)])
    row = {"preset": preset, "map": rules.layout.name, "cooks": rules.n_agents, "steps": steps,
           "text_chars_mean": round(statistics.mean(sizes)), "text_chars_max": max(sizes),
           "policy_prompt_chars_mean": round(statistics.mean(len(p) for p in prompts)),
           "us_text_all_cooks_median": round(statistics.median(times) * 1e6, 1)}
    for form in ("both", "english", "pddl"):
        key = "planner_prompt_chars" + ("" if form == "both" else f"_{form}")
        try:
            planner_prompts: list[str] = []
            planner = LLMAgent(lambda p: planner_prompts.append(p) or "", mode="planner",
                               max_orders=1, use_val=False, domain=form)
            planner.reset(new_state(rules, 0))
            planner.act(new_state(rules, 0))
            row[key] = len(planner_prompts[0])
        except ImportError as exc:  # the planning layer needs the planners extra
            row[key] = f"skipped: {exc}"
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=200)
    args = ap.parse_args()
    for preset in ("easy", "medium", "hard"):
        print(json.dumps(measure(preset, args.steps)), flush=True)


if __name__ == "__main__":
    main()
