"""Sweep wall time on the local backend and on Ray, with 1 and 2 workers, same sweep.

Runs one small evaluation (default: greedy and planner:fast-downward on the easy preset,
seeds 0-5, 200 steps) four times: ``--backend local --jobs 1``, ``--jobs 2``, then
``--backend ray --jobs 1`` and ``--jobs 2`` (a Ray instance started on this machine with
that many CPUs, its start and stop included in the time, as a user of ``ocplus eval``
pays them). Prints one JSON line per run (wall time, the episodes' own wall times added
up, speed-up over local with one worker, whether every episode's outcome equals the
first run's) and a last line with what the runs predict for a cluster: the sweep's work
divided over the workers plus Ray's fixed cost.

    python experiments/bench_sweep.py [--agents greedy,planner:fast-downward]
                                      [--presets easy] [--seeds 6] [--horizon 200]

Result folders go to a temporary directory that is removed at the end.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import tempfile
import time
from pathlib import Path

from ocplus_plan.eval.results import read_results
from ocplus_plan.eval.runner import EvalConfig, parse_list, parse_seeds, run_eval

RUNS = [("local", 1), ("local", 2), ("ray", 1), ("ray", 2)]


def outcome_digest(rows: list[dict]) -> str:
    """One hash of every episode's outcome (timing metrics left out), in key order."""
    parts = []
    for row in sorted(rows, key=lambda r: r["key"]):
        metrics = {k: v for k, v in row["metrics"].items() if not k.startswith("decision_time")}
        parts.append(json.dumps([row["key"], row["status"], metrics], sort_keys=True))
    return hashlib.sha256("\n".join(parts).encode()).hexdigest()[:16]


def run_once(args: argparse.Namespace, backend: str, jobs: int, folder: Path) -> dict:
    cfg = EvalConfig(presets=parse_list(args.presets, "presets"),
                     agents=parse_list(args.agents, "agents"), seeds=parse_seeds(args.seeds),
                     out=folder / f"{backend}-{jobs}", horizon=args.horizon, jobs=jobs,
                     backend=backend, quiet=True)
    load_before = os.getloadavg()[0]
    t0 = time.perf_counter()
    outcome = run_eval(cfg, echo=lambda *_: None)
    wall = time.perf_counter() - t0
    rows = [r for r in read_results(cfg.out) if r.get("status") in ("ok", "error")]
    episode_s = sum(r["timings"]["wall_time_s"] for r in rows if "timings" in r)
    return {"backend": backend, "workers": jobs, "episodes": outcome.ran,
            "errors": outcome.errors, "wall_s": round(wall, 2),
            "episode_wall_sum_s": round(episode_s, 2), "outcomes": outcome_digest(rows),
            "load_avg_1min": [round(load_before, 2), round(os.getloadavg()[0], 2)]}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--agents", default="greedy,planner:fast-downward")
    p.add_argument("--presets", default="easy")
    p.add_argument("--seeds", default="6")
    p.add_argument("--horizon", type=int, default=200)
    args = p.parse_args()
    results = []
    with tempfile.TemporaryDirectory(prefix="bench-sweep-") as folder:
        for backend, jobs in RUNS:
            row = run_once(args, backend, jobs, Path(folder))
            base = results[0] if results else row
            row["speedup_vs_local_1"] = round(base["wall_s"] / row["wall_s"], 2)
            row["same_outcomes_as_first_run"] = row["outcomes"] == base["outcomes"]
            results.append(row)
            print(json.dumps(row), flush=True)
    work = results[0]["wall_s"]  # one worker, no Ray: the sweep's serial cost
    by = {(r["backend"], r["workers"]): r["wall_s"] for r in results}
    # Ray's fixed cost (start, first workers, stop), estimated from 1 worker against local
    ray_fixed = max(0.0, by[("ray", 1)] - work)
    per_episode = work / max(1, results[0]["episodes"])
    print(json.dumps({
        "model": "wall(N workers) ~ ray_fixed_s + episodes * per_episode_s / N "
                 "(while episodes >> N)",
        "per_episode_s": round(per_episode, 2), "ray_fixed_s": round(ray_fixed, 2),
        "predicted_ray_2_s": round(ray_fixed + work / 2, 2), "measured_ray_2_s": by[("ray", 2)],
    }))


if __name__ == "__main__":
    main()
