"""Regenerate the README's results table and figures from experiments/paper_comparison.yaml.

Runs (or continues: finished episodes are kept) the evaluation that the YAML file
describes, then writes OUT/results_table.md (the README table: one row per preset and
agent, mean ± 95% CI over seeds), OUT/summary.csv and OUT/plots/*.png, and prints one
JSON line per preset x agent.

    .venv/bin/python experiments/make_results.py [--config FILE] [--out DIR] [--seeds N]
                                                 [--agents a,b] [--table-only]
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
from pathlib import Path
from typing import Any

import yaml

from ocplus_plan.eval.results import leaderboard, read_results, summarise, write_summary
from ocplus_plan.eval.runner import EvalConfig, parse_list, run_eval

HERE = Path(__file__).resolve().parent
KEYS = {"name", "presets", "seeds", "horizon", "jobs", "episode_timeout", "out", "agents"}


def load_config(path: Path) -> dict[str, Any]:
    cfg = yaml.safe_load(path.read_text())
    if not isinstance(cfg, dict) or not isinstance(cfg.get("agents"), dict):
        sys.exit(f"{path}: expected a mapping with an 'agents' mapping (category -> agents)")
    unknown = sorted(set(cfg) - KEYS)
    if unknown:
        sys.exit(f"{path}: unknown key(s) {unknown}; known: {sorted(KEYS)}")
    return cfg


def _cell(s: dict[str, Any], name: str, digits: int = 1, pct: bool = False) -> str:
    mean, ci = s.get(f"{name}_mean"), s.get(f"{name}_ci95")
    if mean is None:
        return "-"
    if pct:
        return f"{mean:.0%} ± {ci or 0:.0%}"
    return f"{mean:.{digits}f} ± {ci or 0:.{digits}f}"


def results_table(summary: list[dict[str, Any]], categories: dict[str, str]) -> str:
    """The README's markdown table, presets in order, agents ranked by dishes served."""
    head = ("| preset | kind | agent | episodes | dishes served | completion | reward "
            "| steps / order | burns | wrong deliveries | planning s / episode |")
    lines = [head, "|" + "---|" * 11]
    order = ["easy", "medium", "hard"]
    def rank(s: dict[str, Any]) -> tuple:
        dishes = s["dishes_served_mean"]
        return (order.index(s["preset"]) if s["preset"] in order else 9, dishes is None,
                -(dishes or 0.0), str(s["agent"]))

    rows = sorted(summary, key=rank)
    for s in rows:
        kind = categories.get(str(s["agent"]), "")
        where = f"{s['preset']} ({s['map']}, {s['n_agents']})"
        if not s["episodes"]:
            what = "skipped" if s["skipped"] else "failed"
            lines.append(f"| {where} | {kind} | {s['agent']} | 0 | {what}: {s['reason']} "
                         "| | | | | | |")
            continue
        lines.append(
            f"| {where} | {kind} | {s['agent']} | {s['episodes']} "
            f"| {_cell(s, 'dishes_served')} | {_cell(s, 'completion_rate', pct=True)} "
            f"| {_cell(s, 'reward', 0)} | {_cell(s, 'steps_per_order')} "
            f"| {_cell(s, 'burns', 2)} | {_cell(s, 'wrong_deliveries', 2)} "
            f"| {_cell(s, 'planning_time_s', 2)} |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--config", type=Path, default=HERE / "paper_comparison.yaml")
    ap.add_argument("--out", type=Path, default=None, help="override the YAML's out")
    ap.add_argument("--seeds", type=int, default=None, help="override the YAML's seeds")
    ap.add_argument("--agents", default=None, help="run only these agents (comma-separated)")
    ap.add_argument("--jobs", type=int, default=None, help="override the YAML's jobs")
    ap.add_argument("--table-only", action="store_true", help="no new episodes, only outputs")
    args = ap.parse_args(argv)

    cfg = load_config(args.config)
    categories = {a: kind for kind, agents in cfg["agents"].items() for a in agents}
    agents = list(categories)
    if args.agents:
        agents = parse_list(args.agents, "agents")
        categories.update({a: categories.get(a, "") for a in agents})
    out = args.out or Path(cfg.get("out", "runs/paper_comparison"))
    if not args.table_only:
        seeds = args.seeds if args.seeds is not None else int(cfg.get("seeds", 10))
        run_eval(EvalConfig(
            presets=list(cfg.get("presets", ["easy", "medium", "hard"])), agents=agents,
            seeds=list(range(seeds)), out=out, horizon=int(cfg.get("horizon", 200)),
            jobs=args.jobs or int(cfg.get("jobs", 1)), resume=True,
            episode_timeout=cfg.get("episode_timeout"), plots=False), echo=print)
    summary = summarise(read_results(out))
    write_summary(summary, out / "summary.csv")
    table = results_table(summary, categories)
    (out / "results_table.md").write_text(table)
    plots = []
    if importlib.util.find_spec("matplotlib") is not None:
        from ocplus_plan.eval.plots import make_plots

        plots = make_plots(out)
    for s in summary:
        print(json.dumps({"experiment": cfg.get("name", "paper_comparison"),
                          "kind": categories.get(str(s["agent"]), ""),
                          **{k: (round(v, 4) if isinstance(v, float) else v)
                             for k, v in s.items()}}))
    print(leaderboard(summary), file=sys.stderr)
    print(f"table: {out / 'results_table.md'}; figures: {len(plots)} in {out / 'plots'}",
          file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
