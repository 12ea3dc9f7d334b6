"""Retention under faults: dishes with a fault over dishes without, same seeds, per agent.

For every preset, agent and fault (``ocplus eval --faults`` texts) one evaluation runs the
same seeds as the fault-free one (``ocplus_plan.eval.runner.run_eval``, local worker
processes, an episode timeout). It writes two kinds of JSON lines to ``--out``:

- ``{"episode": ...}``: one per episode: preset, agent, faults, seed, status, dishes, burns
  and switches applied, messages lost, the blocker's moves and unsafe steps, wall time and
  planner calls;
- ``{"summary": true, ...}``: one per (preset, agent, fault): dishes with the fault, dishes
  without (summed over the seeds where both episodes finished), their ratio, and for
  burns the dishes lost against the burns applied (per episode: ``lost <= burns``?).

Example (the numbers in docs/faults.md)::

    .venv/bin/python experiments/bench_faults.py --presets medium,hard --n-agents 1 \\
        --agents greedy,planner:fast-downward --seeds 0-5 --jobs 2 \\
        --out experiments/results/faults/retention-medium-hard-1cook-s0-5.jsonl

Result folders of the evaluations go to a temporary directory that is removed at the end.
``python experiments/bench_faults.py --table FILE...`` prints the table of docs/faults.md
from result files.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ocplus_plan.eval.results import read_results  # noqa: E402
from ocplus_plan.eval.runner import EvalConfig, parse_list, parse_seeds, run_eval  # noqa: E402

FAULTS = ["", "burns:3", "switches:40", "message-loss:0.3", "blocker:moving"]


def episode_line(row: dict) -> dict:
    report = row.get("fault_report") or {}
    metrics = row.get("metrics") or {}
    return {"episode": True, "preset": row["preset"], "agent": row["agent"],
            "n_agents": row["n_agents"], "faults": row.get("faults", ""), "seed": row["seed"],
            "status": row["status"], "reason": row.get("reason", "")[:200],
            "dishes": metrics.get("dishes_served"), "burnt": metrics.get("burns"),
            "burns_applied": report.get("burns", 0), "switches_applied": report.get("switches", 0),
            "messages_lost": report.get("messages_lost"),
            "blocker_moves": report.get("blocker_moves"),
            "blocker_unsafe_steps": report.get("blocker_unsafe_steps"),
            "planner_calls": (row.get("planner") or {}).get("planner_calls"),
            "wall_time_s": (row.get("timings") or {}).get("wall_time_s")}


def retention(lines: list[dict]) -> list[dict]:
    """One line per (preset, agent, fault) against the fault-free episodes, same seeds."""
    ok = {(e["preset"], e["agent"], e["faults"], e["seed"]): e for e in lines
          if e["status"] == "ok"}
    out = []
    groups = sorted({(p, a, f) for (p, a, f, _s) in ok if f})
    for preset, agent, fault in groups:
        pairs = [(ok[(preset, agent, "", s)], e) for (p, a, f, s), e in sorted(ok.items())
                 if (p, a, f) == (preset, agent, fault) and (preset, agent, "", s) in ok]
        base = sum(b["dishes"] for b, _ in pairs)
        with_fault = sum(e["dishes"] for _, e in pairs)
        line = {"summary": True, "preset": preset, "agent": agent, "faults": fault,
                "seeds": [e["seed"] for _, e in pairs], "dishes_without": base,
                "dishes_with": with_fault,
                "retention": round(with_fault / base, 3) if base else None}
        if fault.startswith("burns"):
            line["burns_applied"] = sum(e["burns_applied"] for _, e in pairs)
            line["dishes_lost"] = base - with_fault
            line["episodes_losing_more_than_burnt"] = sum(
                (b["dishes"] - e["dishes"]) > e["burns_applied"] for b, e in pairs)
        if fault.startswith("switches"):
            line["switches_applied"] = sum(e["switches_applied"] for _, e in pairs)
        if fault.startswith("blocker"):
            line["blocker_unsafe_steps"] = sum(e["blocker_unsafe_steps"] or 0 for _, e in pairs)
        out.append(line)
    return out


def table(paths: list[str]) -> list[str]:
    """Markdown rows of docs/faults.md from the summary lines of earlier ``--out`` files."""
    rows = ["| preset, cooks | agent | fault | dishes without -> with | retention | notes |",
            "|---|---|---|---|---|---|"]
    for path in paths:
        lines = [json.loads(line) for line in Path(path).read_text().splitlines()]
        meta = next((d for d in lines if d.get("meta")), {})
        cooks = {d["preset"]: d["n_agents"] for d in lines if d.get("episode")}
        timeouts: dict[tuple, int] = {}
        for d in lines:
            if d.get("episode") and d["status"] != "ok":
                key = (d["preset"], d["agent"], d["faults"])
                timeouts[key] = timeouts.get(key, 0) + 1
        for d in lines:
            if not d.get("summary"):
                continue
            notes = []
            if "burns_applied" in d:
                notes.append(f"{d['burns_applied']} burns applied, {d['dishes_lost']} dishes "
                             f"lost; episodes losing more than they burnt: "
                             f"{d['episodes_losing_more_than_burnt']}")
            if "switches_applied" in d:
                notes.append(f"{d['switches_applied']} extra switches applied")
            if "blocker_unsafe_steps" in d:
                notes.append(f"{d['blocker_unsafe_steps']} blocker steps on unsafe cells "
                             "(from its spawn)")
            n_out = timeouts.get((d["preset"], d["agent"], d["faults"]), 0)
            if n_out:
                notes.append(f"{n_out} episode(s) timed out, left out")
            ratio = "-" if d["retention"] is None else f"{d['retention']:.2f}"
            rows.append(f"| {d['preset']} {cooks.get(d['preset'], '?')} | {d['agent']} | "
                        f"{d['faults']} | {d['dishes_without']} -> {d['dishes_with']} | "
                        f"{ratio} | {'; '.join(notes)} (commit {meta.get('commit', '?')}) |")
    return rows


def main(argv: list[str] | None = None) -> int:
    given = sys.argv[1:] if argv is None else argv
    if given[:1] == ["--table"]:
        print("\n".join(table(given[1:])))
        return 0
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--presets", default="medium,hard")
    p.add_argument("--agents", default="greedy,planner:fast-downward")
    p.add_argument("--n-agents", type=int, default=1, help="cooks (a blocker comes on top)")
    p.add_argument("--seeds", default="0-5")
    p.add_argument("--faults", default=";".join(FAULTS[1:]),
                   help="fault texts joined by ';' (the fault-free run is always added)")
    p.add_argument("--horizon", type=int, default=200)
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--episode-timeout", type=float, default=600.0)
    p.add_argument("--out", required=True, help="JSON lines file to write")
    args = p.parse_args(argv)
    faults = [""] + [f for f in args.faults.split(";") if f.strip()]
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True, check=False).stdout.strip()
    lines: list[dict] = []
    with tempfile.TemporaryDirectory(prefix="bench-faults-") as tmp:
        for i, fault in enumerate(faults):
            out = Path(tmp) / f"run{i}"
            cfg = EvalConfig(presets=parse_list(args.presets, "presets"),
                             agents=parse_list(args.agents, "agents"),
                             seeds=parse_seeds(args.seeds), out=out, horizon=args.horizon,
                             n_agents=args.n_agents, jobs=args.jobs,
                             episode_timeout=args.episode_timeout, quiet=True, faults=fault)
            run_eval(cfg, echo=lambda *a: None)
            for row in read_results(out):
                if row["status"] != "skipped":
                    lines.append(episode_line(row))
                    print(json.dumps(lines[-1]), flush=True)
    results = retention(lines)
    with open(args.out, "w", encoding="utf-8") as fh:
        fh.write(json.dumps({"meta": True, "commit": commit, "argv": sys.argv[1:]}) + "\n")
        for line in lines + results:
            fh.write(json.dumps(line) + "\n")
    for line in results:
        print(json.dumps(line))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
