"""``ocplus eval``: run every preset x agent x seed combination and rank the agents.

Writes DIR/results.jsonl (one row per episode: configuration, seed, metrics, timings,
planner statistics), DIR/summary.csv (mean and 95% CI per configuration) and, with
--plots, PNG figures in DIR/plots; prints a leaderboard. Agents: greedy, random, stay,
planner:NAME, ppo[:PATH], llm:MODULE:FUNCTION[:MODE] (a language model, as a callable
prompt -> reply; see agents/llm.py) (planners or policies that are not installed are skipped,
with the reason, in the results). An interrupted run continues with --resume.

Episodes run in worker processes on this machine (--backend local, --jobs N) or as tasks
on a Ray cluster (--backend ray, the `cluster` extra): without --address a Ray instance
is started here; --address auto joins the cluster `ray start` made on this machine,
--address HOST:6379 a remote head node. Both backends write the same rows.

--faults injects faults into every episode (docs/faults.md): KEY:VALUE pairs joined by
commas, e.g. burns:3,switches:40,message-loss:0.3,blocker:moving.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

from ..eval.runner import BACKENDS, EvalConfig, parse_list, parse_seeds, run_eval
from ..execution.faults import FAULT_KEYS, parse_faults
from . import _types
from ._common import (
    add_trust_arg,
    HelpFormatter,
    add_episode_timeout_arg,
    add_jobs_arg,
    add_kitchen_args,
    add_output_args,
    add_plots_arg,
    emit,
    note,
    say,
    sweep_rules,
)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("eval", help="evaluate agents on presets (results, summary, leaderboard)",
                       description=__doc__, formatter_class=HelpFormatter)
    add_sweep_args(p, agents="greedy,random")
    p.set_defaults(func=run)


def add_sweep_args(p: argparse.ArgumentParser, *, agents: str | None) -> None:
    """The options of ``eval`` (and of ``demo``, an evaluation with its own agents)."""
    add_kitchen_args(p, sweep=True)
    p.add_argument("--agents", type=_types.name, default=agents,
                   help="comma-separated agents, e.g. greedy,planner:fast-downward,ppo,random")
    p.add_argument("--partner", default=None, metavar="AGENT",
                   help="the last cook is played by AGENT (idle, random, greedy, ppo:PATH), "
                        "which the evaluated agent does not control (ad-hoc teamwork)")
    add_trust_arg(p)
    h = p.add_argument_group("how to run")
    h.add_argument("--resume", action="store_true",
                   help="continue an interrupted run in --out (only missing episodes run)")
    h.add_argument("--backend", choices=BACKENDS, default="local",
                   help="where episodes run: worker processes here, or Ray tasks "
                        "(the `cluster` extra)")
    add_jobs_arg(h)
    h.add_argument("--address", default=None,
                   help="--backend ray: the cluster to join (auto, or HOST:PORT of the head "
                        "node; None: start a Ray instance on this machine)")
    h.add_argument("--retries", type=_types.whole("--retries", 0, 100), default=2,
                   help="--backend ray: reruns of an episode whose worker or node died")
    add_episode_timeout_arg(h)
    add_plots_arg(h)
    h.add_argument("--faults", type=_types.faults, default=None, metavar="KEY:VALUE,...",
                   help="faults in every episode, e.g. burns:3,switches:40,message-loss:0.3,"
                        "blocker:moving; keys: " + "; ".join(f"{k}:{v}" for k, v in
                                                           FAULT_KEYS.items()))
    h.add_argument("--save-replays", type=_types.seed_selection, default="", metavar="SEEDS",
                   help="save these seeds' episodes as recordings under OUT/replays/ "
                        "(play back with `ocplus replay FILE`)")
    add_output_args(p, out=True, writes="results.jsonl, summary.csv, plots/, replays/")


def run(args: argparse.Namespace) -> int:
    return run_sweep(args, agents=args.agents, out=Path(args.out), plots=args.plots)


def run_sweep(args: argparse.Namespace, *, agents: str, out: Path, plots: bool) -> int:
    """Run the evaluation the options describe and print its outcome."""
    seeds = [args.seed] if args.seed is not None else parse_seeds(args.seeds)
    cfg = EvalConfig(
        presets=parse_list(args.presets, "presets"), agents=parse_list(agents, "agents"),
        seeds=seeds, out=out, horizon=args.horizon, n_agents=args.n_agents, map=args.map,
        jobs=args.jobs, backend=args.backend, address=args.address, retries=args.retries,
        resume=args.resume, episode_timeout=args.episode_timeout, plots=plots,
        quiet=args.quiet, replay_seeds=_replay_seeds(args.save_replays),
        rules=sweep_rules(args),
        faults=str(parse_faults(getattr(args, "faults", ""))),
        partner=getattr(args, "partner", None),
    )
    say(args, f"ocplus {args.command}: presets {', '.join(cfg.presets)}; agents "
              f"{', '.join(cfg.agents)}; {len(seeds)} seed(s); {cfg.horizon} steps; "
              f"{_where(cfg)}{'; faults ' + cfg.faults if cfg.faults else ''}; output {out}")
    t0 = time.monotonic()
    try:
        outcome = run_eval(cfg, echo=lambda message: note(args, message))
    except KeyboardInterrupt:
        note(args, f"\nocplus {args.command}: interrupted; finished episodes are kept in {out}; "
                   f"continue with: ocplus {args.command} ... --out {out} --resume")
        raise
    result: dict[str, Any] = {
        "out": str(out), "episodes_run": outcome.ran, "errors": outcome.errors,
        "configurations_skipped": outcome.skipped, "seconds": round(time.monotonic() - t0, 1),
        "results": str(out / "results.jsonl"), "summary": str(out / "summary.csv"),
        "plots": [str(f) for f in outcome.plots], "leaderboard": outcome.summary,
    }
    if args.json:
        emit(result, args)
        return 0
    print()
    print(outcome.leaderboard)
    print(f"{outcome.ran} episode(s) in {result['seconds']:.0f} s ({outcome.errors} error(s), "
          f"{outcome.skipped} configuration(s) skipped)")
    print(f"results: {result['results']}")
    print(f"summary: {result['summary']}")
    if outcome.plots:
        print(f"plots:   {out / 'plots'}/ ({len(outcome.plots)} PNG files, e.g. "
              f"{out / 'plots' / 'leaderboard.png'})")
    elif plots:
        print("plots:   none (matplotlib is missing: pip install -e '.[plots]', then "
              f"`ocplus report {out} --plots`)")
    else:
        print(f"plots:   none (add --plots, or run `ocplus report {out} --plots`)")
    return 0


def _where(cfg: EvalConfig) -> str:
    """Where the episodes run, for the status line."""
    if cfg.backend == "ray":
        cluster = cfg.address or "a Ray instance on this machine"
        return f"on Ray ({cluster}, {cfg.jobs or 'all'} CPU(s))"
    return f"{cfg.jobs or 1} worker(s)"


def _replay_seeds(text: str) -> list[int]:
    """``--save-replays``: one seed (``3``), a list (``0,4``) or a range (``5-9``)."""
    text = text.strip()
    if not text:
        return []
    return [int(text)] if text.isdigit() else parse_seeds(text)
