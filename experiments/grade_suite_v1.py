"""Grade ``suites/v1``: the first fifth of each track against every working planner at
30 CPU s, the last fifth against the track's strongest configurations at 300 CPU s.

    nice -n 10 .venv/bin/python experiments/grade_suite_v1.py --fifth first
    nice -n 10 .venv/bin/python experiments/grade_suite_v1.py --fifth last --memory-limit 4096

One row per planner x instance goes to ``experiments/results/suite_v1/grade_<fifth>.jsonl``
(appended; a row already there for the same instance state, ``state_hash``, is not run
again, so an interrupted grading resumes; rows of cells since replaced are in
``replaced_cells.jsonl``): status, CPU and wall seconds, value, whether UP's validator and VAL accepted the plan and
whether the league's judge accepted it in the kitchen, the CPU limit, the memory limit and the load average
when the row started. Planner limits are CPU seconds of the planner's process group
(``planning/engines.solve``); ``--memory-limit`` caps the address space of each planner's
process and every process it starts (RLIMIT_AS); a planner that runs out is ``memout``,
which counts as not solved (IPC practice).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
from pathlib import Path

#: planners of the package that solve the easy instances (docs: experiments/results/
#: bench_planners.md); lpg and tamer solve none of them and are graded apart
WORKING = {
    "classical": ("fast-downward", "fast-downward-bjolp", "fast-downward-opt",
                  "fast-downward-wastar", "fast-downward-portfolio", "symk", "enhsp",
                  "pyperplan"),
    "temporal": ("kairos", "kairos-anytime", "aries", "tamerlite"),
}
#: the strongest configurations of each encoding, named: lama-first, weighted A* and ENHSP
#: (classical); Kairos, its anytime mode and TamerLite (temporal)
STRONGEST = {"classical": ("fast-downward", "fast-downward-wastar", "enhsp"),
             "temporal": ("kairos", "kairos-anytime", "tamerlite")}
LIMITS = {"first": 30.0, "last": 300.0}


def fifth(instances: list[str], which: str) -> list[str]:
    """The first or last fifth of a track's scored instances (at least one)."""
    n = max(1, len(instances) // 5)
    return instances[:n] if which == "first" else instances[-n:]


def grade_one(folder: Path, encoding: str, planner: str, cpu: float,
              memory: int | None = None) -> dict[str, object]:
    """Solve one instance with one planner (``memory``: MiB of address space, running out
    is status ``memout``, not solved, as the IPC counts it); validate the plan and judge
    it in the kitchen (the league's judge)."""
    from ocplus_plan.eval.suite import judge_plan, load_instance
    from ocplus_plan.planning.engines import solve

    inst = load_instance(folder)
    compiled = inst.compiled(encoding)
    result = solve(compiled.problem, planner, timeout=cpu, memory_limit=memory)
    value = result.cost if encoding == "classical" else result.makespan
    faithful = None
    if result.solved and result.validated is True:
        faithful = judge_plan(compiled, result.plan, inst.state)["faithful"]
    return {"state_hash": inst.manifest["state_hash"], "status": result.status,
            "cpu_time": result.cpu_time,
            "wall_time": round(result.planning_time, 2), "value": value,
            "valid": result.validated, "faithful": faithful, "reason": result.reason[:160]}


def _grades(results: Path) -> dict[tuple[str, str], list[tuple[str | None, str]]]:
    """(track, instance) -> (state hash or None, "planner status (CPU/limit s)") of every
    graded row."""
    out: dict[tuple[str, str], list[tuple[str | None, str]]] = {}
    for path in sorted(results.glob("grade_*.jsonl")):
        for line in path.read_text(encoding="utf-8").splitlines():
            r = json.loads(line)
            cpu = r["cpu_time"] or 0.0
            out.setdefault((r["track"], r["instance"]), []).append((r.get("state_hash"), (
                f"{r['planner']} {r['status']} ({cpu:.0f}/{r['cpu_limit']:.0f} s)")))
    return out


def table(suite: Path, results: Path) -> str:
    """The docs' table of every track: levers, status, best known, bound, grading rows."""
    manifest = json.loads((suite / "manifest.json").read_text(encoding="utf-8"))
    grades = _grades(results)
    lines = []
    for track, info in manifest["tracks"].items():
        enc = info["encoding"]
        key = "cost" if enc == "classical" else "makespan"
        lines += [f"\n**{track}** ({len(info['scored'])} scored, unsolvable "
                  f"{info['unsolvable'] or 'none'}, dropped {info['dropped'] or 'none'})\n",
                  "| inst | preset, kitchen | cooks | orders | status | best known (by) | "
                  "optimal | faithful | bound | graded |", "|---|---|---|---|---|---|---|---|---|---|"]
        for name in info["scored"] + info["unsolvable"] + info["dropped"]:
            m = json.loads((suite / info["folder"] / name / "manifest.json").read_text())
            e = m["encodings"][enc]
            ref = e["reference"]
            rows = [text for h, text in grades.get((track, name), [])
                    if h in (None, m["state_hash"])]  # rows of this instance's state
            best = f"{ref.get(key)} ({ref.get('planner')})" if ref.get("planner") else "-"
            lines.append(f"| {name} | {m['preset']}, {m['layout']} | {m['n_agents']} | "
                         f"{len(m['goal_orders'])} | {e['status']} | {best} | "
                         f"{ref.get('optimal', '-')} | {ref.get('faithful', '-')} | "
                         f"{m['bound'][key]} | {'; '.join(rows)} |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--suite", default="suites/v1")
    ap.add_argument("--fifth", choices=("first", "last"))
    ap.add_argument("--table", action="store_true", help="print the docs' table and stop")
    ap.add_argument("--planners", default=None, help="comma-separated (default: all working "
                    "planners for the first fifth, the strongest for the last)")
    ap.add_argument("--tracks", default=None)
    ap.add_argument("--instances", default=None, help="comma-separated, e.g. p17,p18")
    ap.add_argument("--cpu-limit", type=float, default=None)
    ap.add_argument("--memory-limit", type=int, default=None, help="MiB")
    ap.add_argument("--out", default="experiments/results/suite_v1")
    args = ap.parse_args(argv)
    if args.table or not args.fifth:
        print(table(Path(args.suite), Path(args.out)))
        return 0
    cpu = args.cpu_limit or LIMITS[args.fifth]
    suite = Path(args.suite)
    manifest = json.loads((suite / "manifest.json").read_text(encoding="utf-8"))
    out = Path(args.out) / f"grade_{args.fifth}.jsonl"
    out.parent.mkdir(parents=True, exist_ok=True)
    done = set()
    if out.is_file():
        for line in out.read_text(encoding="utf-8").splitlines():
            r = json.loads(line)
            done.add((r["track"], r["instance"], r["planner"], r["cpu_limit"],
                      r.get("state_hash")))
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True, check=False).stdout.strip()
    for track, info in manifest["tracks"].items():
        if args.tracks and track not in args.tracks.split(","):
            continue
        enc = info["encoding"]
        names = fifth(info["scored"], args.fifth)
        if args.instances:
            names = [n for n in names if n in args.instances.split(",")]
        pool = STRONGEST if args.fifth == "last" else WORKING
        planners = args.planners.split(",") if args.planners else list(pool[enc])
        for name in names:
            digest = json.loads((suite / info["folder"] / name / "manifest.json").read_text(
                encoding="utf-8"))["state_hash"]
            for planner in planners:
                if {(track, name, planner, cpu, h) for h in (digest, None)} & done:
                    continue  # a row without a hash predates them: the instance is unchanged
                row = {"track": track, "instance": name, "planner": planner,
                       "cpu_limit": cpu, "memory_limit_mib": args.memory_limit,
                       "load": round(os.getloadavg()[0], 2), "commit": commit,
                       "machine": f"{platform.machine()}, {os.cpu_count()} shared cores"}
                row.update(grade_one(suite / info["folder"] / name, enc, planner, cpu,
                                     args.memory_limit))
                with out.open("a", encoding="utf-8") as f:
                    f.write(json.dumps(row, sort_keys=True) + "\n")
                print(f"{track} {name} {planner}: {row['status']} {row['cpu_time']} CPU s "
                      f"value {row['value']} valid {row['valid']} faithful {row['faithful']}",
                      flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
