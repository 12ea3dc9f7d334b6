"""Run every (preset, agent, seed) combination and write the result files.

:func:`run_eval` is what ``ocplus eval`` calls. It checks the whole configuration
before running anything (an unknown preset, map or agent is a :class:`ConfigError`;
a planner or learned policy that is not installed, or an agent kind that this
installation has not registered yet, becomes a ``skipped`` row with the reason),
then runs the episodes in worker processes, ``jobs`` at a time, ``--jobs 1`` included
(one process per episode: a controller, a user's model or a planner that exits, crashes or
hangs takes down only its episode, which is recorded as an ``error`` row; an ``llm:``
module is first loaded in a child process too, within ``--episode-timeout``, so a module
that exits or loops at import cannot end or hang the sweep either) or, with
``backend="ray"``, as Ray tasks on a cluster
(:mod:`.ray_backend`), and appends each finished episode to ``results.jsonl`` at once.
``resume=True`` reruns only what is missing, whichever backend wrote the rows so far.

One episode (:mod:`.episode`) never stops the sweep: whatever a user's controller, model
or planner raises (``SystemExit`` and ``KeyboardInterrupt`` included) becomes its
``error`` row. Ctrl-C of the driver stops the sweep: the running episodes are killed,
the rows so far stay in ``results.jsonl``, and ``KeyboardInterrupt`` reaches the caller
(``ocplus`` exits 130); SIGTERM does the same and exits 143. Worker processes die with
the driver (:mod:`.local_backend`), and with the local backend the driver is the
subreaper of what the episodes start: a process that left its session (``setsid``) is
killed at the end of the sweep (:func:`~ocplus_plan.planning._proc.reaping`).
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import os
import re
import signal
import threading
from collections.abc import Iterator
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from ..errors import ConfigError
from ..sim import make_rules
from .episode import (
    AgentLoadFailed,
    EpisodeSpec,
    EvalConfig,
    check_agent,
    check_partner,
    error_row,
    evaluate_episode,
    kitchen_unavailable,
    request_interrupt,
    timeout_reason,
)
from .results import (
    CONFIG_FILE,
    LOCK_FILE,
    RESULTS_FILE,
    SUMMARY_FILE,
    ResultsWriter,
    episode_key,
    folder_lock,
    leaderboard,
    read_results,
    repair_torn_tail,
    scan_results,
    summarise,
    write_summary,
)

#: where episodes run: worker processes on this machine, or tasks on a Ray cluster
BACKENDS = ("local", "ray")


@dataclass
class EvalOutcome:
    out: Path
    summary: list[dict[str, Any]]
    leaderboard: str
    ran: int
    skipped: int
    errors: int
    plots: list[Path]


def parse_list(text: str | list[str], what: str) -> list[str]:
    """``"a,b, c"`` -> ``["a", "b", "c"]``; empty is an error naming ``what``."""
    items = text if isinstance(text, list) else str(text).split(",")
    out = [s.strip() for s in items if str(s).strip()]
    if not out:
        raise ConfigError(f"--{what} is empty; give a comma-separated list")
    return out


def parse_seeds(text: str | int | list[int]) -> list[int]:
    """``10`` -> seeds 0..9; ``"3,7,11"`` or ``"5-9"`` -> exactly those seeds."""
    if isinstance(text, int):
        count = text
    elif isinstance(text, list):
        return [int(s) for s in text]
    else:
        s = str(text).strip()
        try:
            if "," in s:
                return [int(x) for x in s.split(",") if x.strip()]
            if "-" in s[1:]:
                a, b = s.split("-", 1)
                return list(range(int(a), int(b) + 1))
            count = int(s)
        except ValueError:
            raise ConfigError(f"--seeds {text!r}: give a count (10), a list (0,4,7) or a "
                              "range (5-9)") from None
    if count < 1:
        raise ConfigError(f"--seeds must be at least 1, got {count}")
    return list(range(count))


# ---------------------------------------------------------------- the whole run
def plan_episodes(cfg: EvalConfig) -> tuple[list[EpisodeSpec], list[dict[str, Any]]]:
    """All episodes of ``cfg`` and the rows of the agents that must be skipped.

    Every preset / map / agent-count combination, every agent name and the faults are
    checked first, so a typo fails in a second, not after an hour."""
    from ..execution.faults import parse_faults

    if cfg.horizon < 1:
        raise ConfigError(f"--horizon must be a positive number of steps, got {cfg.horizon}")
    check_backend(cfg)
    fault = parse_faults(cfg.faults)
    kitchens = []
    for preset in cfg.presets:
        kw: dict[str, Any] = {"horizon": cfg.horizon, **cfg.rules}
        if cfg.n_agents is not None:
            kw["n_agents"] = cfg.n_agents
        rules = make_rules(preset, map=cfg.map, **kw)
        if fault.blocker:
            _check_room_for_blocker(preset, cfg.map, rules.n_agents, kw)
        kitchens.append((preset, rules.layout.name, rules.n_agents))
    skip_reason: dict[str, str | None] = {}
    load_error: dict[str, str] = {}  # agents whose loading ended or outran its process
    for agent in cfg.agents:
        try:
            skip_reason[agent] = check_agent(agent, cfg.episode_timeout)
        except AgentLoadFailed as exc:
            skip_reason[agent], load_error[agent] = None, str(exc)
    check_partner(cfg.partner, [n for _, _, n in kitchens], cfg.episode_timeout)
    episodes, skipped = [], []
    for preset, map_name, n_agents in kitchens:
        for agent in cfg.agents:
            reason = skip_reason[agent] or kitchen_unavailable(
                agent, preset, n_agents, map_name)
            base = EpisodeSpec(preset, map_name, cfg.map, n_agents, agent, -1, cfg.horizon,
                               faults=str(fault), rules=tuple(sorted(cfg.rules.items())),
                               partner=cfg.partner, load_error=load_error.get(agent, ""))
            if reason:
                row = base.row_base()
                row.update(seed=None, status="skipped", reason=reason)
                row["key"] = episode_key(row)
                skipped.append(row)
                continue
            for seed in cfg.seeds:
                spec = dataclasses.replace(base, seed=seed)
                if seed in cfg.replay_seeds:
                    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", spec.row_base()["key"])
                    path = cfg.out / "replays" / f"{name}.jsonl.gz"
                    spec = dataclasses.replace(spec, replay_path=str(path))
                episodes.append(spec)
    return episodes, skipped


def _check_room_for_blocker(preset: str, map_name: str | None, cooks: int,
                            kw: dict[str, Any]) -> None:
    """``blocker:`` drives one agent more than the cooks: the map must have room for it."""
    from ..execution.faults import safe_cells
    from ..sim import new_state

    try:
        rules = make_rules(preset, map=map_name, **{**kw, "n_agents": cooks + 1})
    except ConfigError as exc:
        raise ConfigError(f"--faults blocker:... adds an agent to the {cooks} cook(s) of "
                          f"{preset}, which this map has no room for ({exc}); give fewer "
                          "cooks with --n-agents, or drop blocker") from None
    geo = new_state(rules, 0).geo
    if not all(safe_cells(geo, li) for li in range(len(geo.walkables))):
        raise ConfigError(f"--faults blocker:... on {rules.layout.name}: this map has no floor "
                          "cell where an agent can stand without cutting the kitchen in two or "
                          "blocking the only access to a station; drop blocker for this map")


def check_backend(cfg: EvalConfig) -> None:
    """Refuse a backend setting that cannot work, before anything runs."""
    if cfg.jobs is not None and cfg.jobs < 1:
        raise ConfigError(f"--jobs must be at least 1, got {cfg.jobs}")
    if cfg.backend not in BACKENDS:
        raise ConfigError(f"--backend {cfg.backend!r} is unknown; choose one of "
                          f"{', '.join(BACKENDS)}")
    if cfg.backend == "ray":
        from .ray_backend import import_ray

        import_ray()  # DependencyNotInstalled naming the extra
    elif cfg.address is not None:
        raise ConfigError("--address names a Ray cluster; add --backend ray, or drop --address")
    if cfg.retries < 0:
        raise ConfigError(f"--retries must be 0 or more, got {cfg.retries}")


def prepare_out_dir(out: Path, resume: bool, echo: Any = print) -> set[str]:
    """Check ``out`` (created and locked by :func:`folder_lock`) or, for ``--resume``, read
    it: the keys of the episodes already done. Bad rows are skipped and counted (never
    trusted); a row torn by a killed run is cut off before anything is appended."""
    results = out / RESULTS_FILE
    if not resume and any(p.name != LOCK_FILE for p in out.iterdir()):
        raise ConfigError(
            f"output folder {out} already exists and is not empty; continue that run "
            "with --resume, or choose another --out")
    if not resume or not results.exists():
        return set()
    found = scan_results(results)
    if found.note():
        echo(f"note: {found.note()}")
    repair_torn_tail(results)
    return {r["key"] for r in found.rows if r["status"] in ("ok", "error")}


def run_eval(cfg: EvalConfig, echo: Any = print) -> EvalOutcome:
    """Run (or continue) an evaluation and write results.jsonl, summary.csv and plots."""
    from ..planning._proc import reaping, sigterm_exits

    out = Path(cfg.out)
    # Ray keeps its own worker processes (and may be the caller's): reaped here only locally
    reaper = reaping() if cfg.backend == "local" else contextlib.nullcontext()
    with _sigint_marks_interrupt(), sigterm_exits(), reaper:
        episodes, skipped = plan_episodes(cfg)
        with _backend_session(cfg), folder_lock(out):  # Ray is joined before any file is written
            ran, n_err = _run_and_write(cfg, episodes, skipped, echo)
            summary = summarise(read_results(out))
            write_summary(summary, out / SUMMARY_FILE)
    plots: list[Path] = []
    if cfg.plots:
        from .plots import make_plots

        plots = make_plots(out)
    return EvalOutcome(out, summary, leaderboard(summary), ran, len(skipped), n_err, plots)


def _backend_session(cfg: EvalConfig) -> contextlib.AbstractContextManager[Any]:
    if cfg.backend == "ray":
        from .ray_backend import ray_session

        return ray_session(cfg)
    return contextlib.nullcontext()


def _run_and_write(cfg: EvalConfig, episodes: list[EpisodeSpec], skipped: list[dict[str, Any]],
                   echo: Any) -> tuple[int, int]:
    """Run the episodes that ``out`` does not have yet, appending each row as it comes;
    (episodes run, errors)."""
    from .progress import SweepProgress

    out = Path(cfg.out)
    done = prepare_out_dir(out, cfg.resume, echo)
    config = {k: (str(v) if isinstance(v, Path) else v) for k, v in asdict(cfg).items()}
    try:
        (out / CONFIG_FILE).write_text(json.dumps(config, indent=2) + "\n")
    except OSError as exc:
        raise ConfigError(f"cannot write {out / CONFIG_FILE}: {exc.strerror}") from None
    todo = [e for e in episodes if e.row_base()["key"] not in done]
    if cfg.resume and done:
        echo(f"resuming {out}: {len(episodes) - len(todo)} episode(s) already done, "
             f"{len(todo)} to run")
    for row in skipped:
        echo(f"skipping {row['agent']} on {row['preset']}: {row['reason']}")
    n_err = 0
    with ResultsWriter(out) as writer:
        for row in skipped:
            writer.write(row)
        bar = SweepProgress(todo, cfg.jobs or 1, cfg.quiet)
        try:
            for row in _run_all(todo, cfg, bar):
                row.setdefault("worker", {})["backend"] = cfg.backend
                writer.write(row)
                n_err += row.get("status") == "error"
                bar.finished(row)
        finally:
            bar.close()
    return len(todo), n_err


@contextlib.contextmanager
def _sigint_marks_interrupt() -> Iterator[None]:
    """While the sweep runs, Ctrl-C (SIGINT) is marked as the user's before it raises
    KeyboardInterrupt, so that an episode running in this process lets it through
    instead of recording it as its controller's error."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.getsignal(signal.SIGINT)

    def on_sigint(signum: int, frame: Any) -> None:
        request_interrupt()
        raise KeyboardInterrupt

    request_interrupt(False)
    signal.signal(signal.SIGINT, on_sigint)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        request_interrupt(False)


def _run_all(todo: list[EpisodeSpec], cfg: EvalConfig, bar: Any) -> Iterator[dict[str, Any]]:
    if cfg.backend == "ray":
        from .ray_backend import run_on_ray

        yield from run_on_ray(todo, cfg, on_tick=bar.tick)
        return
    if not hasattr(os, "fork"):  # pragma: no cover - no child processes to isolate in
        for spec in todo:
            bar.started(spec)
            yield evaluate_episode(spec, lambda *p, spec=spec: bar.heard(spec, *p))
        return
    jobs = cfg.jobs or 1
    from .local_backend import run_local

    yield from run_local(todo, jobs, cfg.episode_timeout, on_start=bar.started,
                         on_progress=bar.heard, on_tick=bar.tick)


__all__ = [
    "BACKENDS",
    "EpisodeSpec",
    "EvalConfig",
    "EvalOutcome",
    "check_agent",
    "check_backend",
    "error_row",
    "evaluate_episode",
    "parse_list",
    "parse_seeds",
    "plan_episodes",
    "prepare_out_dir",
    "run_eval",
    "timeout_reason",
]
