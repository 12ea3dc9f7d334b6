"""``ocplus eval``: run every preset x agent x seed combination and rank the agents.

Writes DIR/results.jsonl (one row per episode: configuration, seed, metrics, timings,
planner statistics), DIR/summary.csv (mean and 95% CI per configuration) and, with
--plots, PNG figures in DIR/plots; prints a leaderboard. Agents: greedy, random, stay,
planner:NAME, ppo[:PATH] (planners or policies that are not installed are skipped,
with the reason, in the results). An interrupted run continues with --resume.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ..eval.runner import EvalConfig, parse_list, parse_seeds, run_eval


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("eval", help="evaluate agents on presets (results, summary, leaderboard)",
                       description=__doc__,
                       formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    g = p.add_argument_group("what to run")
    g.add_argument("--presets", default="easy,medium,hard", help="comma-separated presets")
    g.add_argument("--agents", default="greedy,random",
                   help="comma-separated agents, e.g. greedy,planner:fast-downward,ppo,random")
    g.add_argument("--seeds", default="10", help="a count (10 = seeds 0-9), a list or a range")
    g.add_argument("--horizon", type=int, default=200, help="steps per episode")
    g.add_argument("--n-agents", type=int, default=None, help="cooks (None: the preset's)")
    g.add_argument("--map", default=None, help="map name or YAML path (None: the preset's)")
    h = p.add_argument_group("how to run")
    h.add_argument("--out", required=True, type=Path, help="output folder (must not exist unless --resume)")
    h.add_argument("--resume", action="store_true",
                   help="continue an interrupted run in --out (only missing episodes run)")
    h.add_argument("--jobs", type=int, default=1, help="worker processes")
    h.add_argument("--episode-timeout", type=float, default=None,
                   help="seconds before an episode is killed and recorded as an error (None: no limit)")
    h.add_argument("--plots", action="store_true", help="also write PNG figures (plots extra)")
    h.add_argument("--quiet", action="store_true", help="no progress bar")
    h.add_argument("--save-replays", default="", metavar="SEEDS",
                   help="save these seeds' episodes as recordings under OUT/replays/ "
                        "(play back with `ocplus replay FILE`)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    cfg = EvalConfig(
        presets=parse_list(args.presets, "presets"), agents=parse_list(args.agents, "agents"),
        seeds=parse_seeds(args.seeds), out=args.out, horizon=args.horizon,
        n_agents=args.n_agents, map=args.map, jobs=args.jobs, resume=args.resume,
        episode_timeout=args.episode_timeout, plots=args.plots, quiet=args.quiet,
        replay_seeds=_replay_seeds(args.save_replays),
    )
    try:
        outcome = run_eval(cfg)
    except KeyboardInterrupt:
        print(f"\nocplus eval: interrupted; finished episodes are kept in {args.out}; "
              f"continue with: ocplus eval ... --out {args.out} --resume")
        raise
    print()
    print(outcome.leaderboard)
    print(f"results: {outcome.out / 'results.jsonl'} ({outcome.ran} episode(s) run, "
          f"{outcome.errors} error(s), {outcome.skipped} configuration(s) skipped)")
    print(f"summary: {outcome.out / 'summary.csv'}")
    if outcome.plots:
        print(f"plots:   {outcome.plots[0].parent}/ ({len(outcome.plots)} PNG files)")
    return 0


def _replay_seeds(text: str) -> list[int]:
    """``--save-replays``: one seed (``3``), a list (``0,4``) or a range (``5-9``)."""
    text = text.strip()
    if not text:
        return []
    return [int(text)] if text.isdigit() else parse_seeds(text)
