"""The README's headline table: dishes per episode of planners, the greedy cook, PPO and
random play on the six preset kitchens, regenerated from evaluation result files.

Runs (or resumes: finished episodes are kept) one ``ocplus eval`` per cook count into
``--out`` (``cooks1/``, ``cooks2/``), then prints the markdown table and, with
``--readme``, writes it between the ``<!-- headline:begin -->`` and ``<!-- headline:end -->``
markers of README.md together with the conditions it was measured under (commit, machine,
load, seeds). ``--table-only`` rebuilds the table from the files without new episodes.

    .venv/bin/python experiments/headline.py [--seeds 10] [--out experiments/results/headline]
                                             [--jobs 2] [--readme] [--table-only]
"""

from __future__ import annotations

import argparse
import os
import platform
import subprocess
import sys
from pathlib import Path
from typing import Any

from ocplus_plan.eval.results import read_results, summarise
from ocplus_plan.eval.runner import EvalConfig, run_eval

HERE = Path(__file__).resolve().parent
README = HERE.parent / "README.md"
BEGIN, END = "<!-- headline:begin -->", "<!-- headline:end -->"
#: column label -> agent spec (what ``ocplus eval --agents`` takes)
AGENTS = {
    "default planner": "planner:fast-downward-wastar",
    "fd lama-first": "planner:fast-downward",
    "fd-bjolp one-cook+chain2": "planner:fast-downward-bjolp:stations:on_event:one-cook+chain2",
    "greedy": "greedy",
    "PPO": "ppo",
    "random": "random",
}
PRESETS = ("easy", "medium", "hard")


def run(out: Path, seeds: int, jobs: int, agents: list[str]) -> None:
    for cooks in (1, 2):
        run_eval(EvalConfig(presets=list(PRESETS), agents=agents,
                            seeds=list(range(seeds)), out=out / f"cooks{cooks}",
                            n_agents=cooks, jobs=jobs, resume=True, episode_timeout=900,
                            quiet=True), echo=lambda *a, **k: None)


def table(out: Path, seeds: int) -> str:
    cells: dict[tuple[str, int, str], Any] = {}
    for cooks in (1, 2):
        folder = out / f"cooks{cooks}"
        if not (folder / "results.jsonl").exists():
            continue
        for s in summarise(read_results(folder)):
            cells[(s["preset"], int(s["n_agents"]), str(s["agent"]))] = s
    head = "| kitchen | " + " | ".join(AGENTS) + " |"
    lines = [head, "|" + "---|" * (len(AGENTS) + 1)]
    for preset in PRESETS:
        for cooks in (1, 2):
            row = []
            for agent in AGENTS.values():
                s = cells.get((preset, cooks, agent))
                if s is None or not s["episodes"]:
                    row.append("-" if s is None else f"skipped ({s['reason']})")
                else:
                    n = "" if s["episodes"] == seeds else f" ({s['episodes']} seeds)"
                    row.append(f"{s['dishes_served_mean']:.1f} ± {s['dishes_served_ci95']:.1f}{n}")
            lines.append(f"| {preset}, {cooks} cook{'s' if cooks > 1 else ''} | "
                         + " | ".join(row) + " |")
    return "\n".join(lines) + "\n"


def conditions(seeds: int) -> str:
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True, cwd=HERE).stdout.strip() or "unknown"
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return (f"Dishes per 200-step episode, mean ± 95% interval over seeds 0-{seeds - 1}; "
            f"commit {commit}, {platform.machine()} with {os.cpu_count()} cores, 1-min load "
            f"{load:.1f} when the table was written; `python experiments/headline.py "
            f"--seeds {seeds} --readme` reruns it.\n")


def write_readme(text: str) -> None:
    readme = README.read_text()
    if BEGIN not in readme or END not in readme:
        sys.exit(f"{README}: no {BEGIN} ... {END} block to fill")
    head, rest = readme.split(BEGIN, 1)
    README.write_text(head + BEGIN + "\n" + text + END + rest.split(END, 1)[1])


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", type=Path, default=HERE / "results" / "headline")
    ap.add_argument("--table-only", action="store_true")
    ap.add_argument("--readme", action="store_true")
    ap.add_argument("--skip", default="", help="comma-separated column labels to run no "
                    "episodes for (their finished episodes still count)")
    args = ap.parse_args(argv)
    if not args.table_only:
        skip = {s.strip() for s in args.skip.split(",") if s.strip()}
        run(args.out, args.seeds, args.jobs, [a for k, a in AGENTS.items() if k not in skip])
    text = table(args.out, args.seeds) + "\n" + conditions(args.seeds)
    print(text)
    if args.readme:
        write_readme(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
