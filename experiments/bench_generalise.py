"""The generalisation protocol: greedy, the default planner (``--planner``) and each learned
baseline on train- and test-split generated kitchens of every family, 1-3 cooks, and a
cross-play table (every agent beside every other as the two cooks of a test kitchen).

    .venv/bin/python experiments/bench_generalise.py --kitchens-per-family 10 --seeds 3 \\
        --learned generalist=ppo --out experiments/results/generalise/grid.jsonl
    .venv/bin/python experiments/bench_generalise.py --table experiments/results/generalise/grid.jsonl

``--learned LABEL=AGENT`` names a learned baseline (``ppo``: the shipped generalist for
each cook count; ``ppo:PATH``: a checkpoint, ``.zip`` or weights-only ``.npz``); repeat it
for several. The first line of ``--out`` records the command, commit, machine and load;
then one JSON line per episode (eval/generalise.py's rows). ``--table`` prints the
generalisation table (dishes per family and cook count, train against test, each agent's
ratio to greedy on test, the share of test kitchens it served in) and the cross-play table
as Markdown. Planner calls are limited in CPU seconds (``--timeout``).
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import os
import resource
import platform
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from ocplus_plan.eval.generalise import (  # noqa: E402
    cells, crossplay_pairs, crossplay_table, generalisation_table, markdown, play)
from ocplus_plan.errors import OcplusError  # noqa: E402
from ocplus_plan.sim.generate import FAMILIES  # noqa: E402

PLANNER = "planner:fast-downward-wastar"


def _factory(timeout: float):
    from ocplus_plan.agents import make_controller
    from ocplus_plan.agents.planner import make_planner_agent

    def make(name: str, seed: int):
        if name.startswith("planner:"):
            return make_planner_agent(name.partition(":")[2], seed, timeout=timeout)
        return make_controller(name, seed)
    return make


def run(args: argparse.Namespace) -> list[dict]:
    agents = [("greedy", "greedy")]
    for spec in args.learned:
        label, sep, agent = spec.partition("=")
        if not sep or not label or not agent:
            raise SystemExit(f"--learned {spec!r}: write LABEL=AGENT, e.g. generalist=ppo")
        agents.append((agent, label))
    if args.planner:
        agents.append((args.planner_spec, "planner"))
    seeds = list(range(args.seeds))
    grid = cells(args.families, ["train", "test"], args.kitchens_per_family, args.cooks, seeds)
    rows = []
    out = args.out.open("a") if args.out else None
    if out:
        out.write(json.dumps({"header": True, "command": " ".join(sys.argv),
                              "commit": _commit(), "machine": "x86_64, 2 shared cores",
                              "python": platform.python_version(),
                              "load_1min": round(os.getloadavg()[0], 2),
                              "started": time.strftime("%Y-%m-%d %H:%M:%S UTC",
                                                       time.gmtime())}) + "\n")
    jobs = [(c, a, lab, None) for c in grid for a, lab in agents
            if not (lab == "planner" and c[1] == "train" and not args.planner_train)]
    pair_cells = cells(args.families, ["test"], args.crossplay_kitchens, [2], seeds)
    labels = {lab: a for a, lab in agents if lab != "planner"}
    for first, second in crossplay_pairs(list(labels)):
        jobs += [(c, labels[first], first, (labels[second], second)) for c in pair_cells]
    work = [(job, args.preset, args.horizon, args.timeout) for job in jobs]
    pool = multiprocessing.get_context("fork").Pool(args.jobs) if args.jobs > 1 else None
    results = pool.imap(_play, work, chunksize=4) if pool else map(_play, work)
    t0 = time.time()
    for i, row in enumerate(results):
        rows.append(row)
        if out:
            out.write(json.dumps(row) + "\n")
            out.flush()
        if (i + 1) % 200 == 0:
            print(f"{i + 1}/{len(jobs)} episodes, {time.time() - t0:.0f} s",
                  file=sys.stderr, flush=True)
    if pool:
        pool.close()
        pool.join()
    if out:
        cpu = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(
            resource.RUSAGE_CHILDREN)
        out.write(json.dumps({"header": True, "finished": time.strftime(
            "%Y-%m-%d %H:%M:%S UTC", time.gmtime()), "episodes": len(rows),
            "cpu_s": round(sum(r.ru_utime + r.ru_stime for r in cpu), 1),
            "load_1min": round(os.getloadavg()[0], 2)}) + "\n")
    return rows


def _play(work: tuple) -> dict:
    (cell, agent, label, partner), preset, horizon, timeout = work
    try:
        return play(cell, agent, label, preset, horizon, partner, _factory(timeout))
    except OcplusError as exc:  # e.g. a bare ppo with no generalist for this cook count
        family, split, index, cooks, seed = cell
        return {"family": family, "split": split, "index": index, "cooks": cooks,
                "seed": seed, "agent": label, "partner": partner[1] if partner else None,
                "skipped": str(exc)}


def _commit() -> str:
    return subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                          capture_output=True, text=True).stdout.strip()


def tables(paths: list[Path]) -> str:
    cells, headers = {}, []
    for path in paths:  # one row per episode: a cell played in several files counts once
        for line in path.read_text().splitlines():
            r = json.loads(line)
            if r.get("header"):
                headers.append(r)
            else:
                cells[(r["family"], r["split"], r["index"], r["cooks"], r["seed"], r["agent"],
                       r.get("partner"))] = r
    rows = list(cells.values())
    text = [f"conditions: {json.dumps(h)}" for h in headers]
    text += ["", "generalisation (mean dishes per episode):", "",
             markdown(generalisation_table(rows)), "cross-play (2 cooks, test kitchens; "
             "agent drives cook 0, partner cook 1):", "", markdown(crossplay_table(rows))]
    return "\n".join(text)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--families", nargs="+", default=list(FAMILIES), choices=FAMILIES)
    p.add_argument("--kitchens-per-family", type=int, default=10,
                   help="kitchens 0..N-1 of each split and family")
    p.add_argument("--cooks", type=int, nargs="+", default=[1, 2, 3])
    p.add_argument("--seeds", type=int, default=3, help="seeds 0..N-1")
    p.add_argument("--horizon", type=int, default=200)
    p.add_argument("--preset", default="medium", help="stations and recipes")
    p.add_argument("--learned", action="append", default=[], metavar="LABEL=AGENT",
                   help="a learned baseline, e.g. generalist=ppo or clone=ppo:runs/x/policy.zip")
    p.add_argument("--planner", action="store_const", const=PLANNER, default=None,
                   help=f"also play the default planner ({PLANNER}; ~10 CPU s an episode)")
    p.add_argument("--planner-spec", default=PLANNER, help=argparse.SUPPRESS)
    p.add_argument("--planner-train", action="store_true",
                   help="the planner plays train kitchens too (by default test only)")
    p.add_argument("--timeout", type=float, default=10.0, help="CPU seconds per planner call")
    p.add_argument("--crossplay-kitchens", type=int, default=10,
                   help="test kitchens per family for the cross-play table (0: none)")
    p.add_argument("--jobs", type=int, default=1, help="worker processes")
    p.add_argument("--out", type=Path, default=None, help="append the JSON lines here")
    p.add_argument("--table", type=Path, nargs="+", default=None,
                   help="print the tables of these --out files and stop")
    args = p.parse_args(argv)
    if args.table:
        print(tables(args.table))
        return 0
    if args.planner:
        args.planner_spec = args.planner
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
    rows = run(args)
    print(markdown(generalisation_table(rows)))
    print(markdown(crossplay_table(rows)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
