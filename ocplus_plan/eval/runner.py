"""Run every (preset, agent, seed) combination and write the result files.

:func:`run_eval` is what ``ocplus eval`` calls. It checks the whole configuration
before running anything (an unknown preset, map or agent is a :class:`ConfigError`;
a planner or learned policy that is not installed, or an agent kind that this
installation has not registered yet, becomes a ``skipped`` row with the reason),
then runs the episodes, in worker processes with ``jobs > 1`` (one process per
episode: a planner that crashes or hangs takes down only its episode, which is
recorded as an ``error`` row) or, with ``backend="ray"``, as Ray tasks on a cluster
(:mod:`.ray_backend`), and appends each finished episode to ``results.jsonl`` at once.
``resume=True`` reruns only what is missing, whichever backend wrote the rows so far.
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import multiprocessing as mp
import os
import platform
import re
import signal
import sys
import time
import traceback
from dataclasses import asdict, dataclass, field
from multiprocessing.connection import wait
from pathlib import Path
from typing import Any

from ..errors import ConfigError, DependencyNotInstalled, OcplusError
from ..sim import make_rules, new_state
from .metrics import EpisodeLog, compute_metrics, controller_metrics
from .results import (
    CONFIG_FILE,
    RESULTS_FILE,
    SUMMARY_FILE,
    ResultsWriter,
    episode_key,
    leaderboard,
    read_results,
    summarise,
    write_summary,
)

#: agent kinds that other parts of the project register when installed; until then an
#: evaluation skips them (with the reason) instead of failing
PENDING_KINDS: dict[str, str] = {
    "planner": "the planner-backed controller (ocplus_plan/execution)",
    "ppo": "the PPO policy (the `rl` extra: pip install -e '.[rl]')",
}

#: where episodes run: worker processes on this machine, or tasks on a Ray cluster
BACKENDS = ("local", "ray")


@dataclass(frozen=True)
class EpisodeSpec:
    """One episode to run: everything a worker process needs."""

    preset: str
    map: str  # the map's name (for tables)
    map_spec: str | None  # what to pass to make_rules (None: the preset's map)
    n_agents: int
    agent: str
    seed: int
    horizon: int
    replay_path: str | None = None  # where to save this episode's recording, if chosen
    partner: str | None = None  # the agent that plays the last cook (--partner)

    def row_base(self) -> dict[str, Any]:
        agent = self.agent if self.partner is None else f"{self.agent} +{self.partner}"
        d = {"preset": self.preset, "map": self.map, "n_agents": self.n_agents,
             "agent": agent, "seed": self.seed, "horizon": self.horizon}
        if self.partner is not None:
            d["partner"] = self.partner
        d["key"] = episode_key(d)
        if self.map_spec is not None:
            d["map_source"] = str(self.map_spec)
        return d


@dataclass
class EvalConfig:
    """Everything ``ocplus eval`` takes."""

    presets: list[str]
    agents: list[str]
    seeds: list[int]
    out: Path
    horizon: int = 200
    n_agents: int | None = None
    map: str | None = None
    jobs: int | None = None  # local: worker processes (None: 1); ray: episodes in flight
    backend: str = "local"  # one of BACKENDS
    address: str | None = None  # ray: the cluster to join (None: start one on this machine)
    retries: int = 2  # ray: reruns of an episode whose worker died
    resume: bool = False
    episode_timeout: float | None = None
    plots: bool = False
    quiet: bool = False
    replay_seeds: list[int] = field(default_factory=list)  # episodes to save as replays
    partner: str | None = None  # the agent that plays the last cook (--partner)
    extra: dict[str, Any] = field(default_factory=dict)


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


# ---------------------------------------------------------------- checking agents
def check_agent(spec: str) -> str | None:
    """None if ``spec`` can run here; the reason when it must be skipped.

    Raises :class:`ConfigError` / :class:`PlannerError` for names that are simply wrong.
    """
    from ..agents import FACTORIES, make_controller

    kind, _, arg = spec.partition(":")
    if kind == "planner":
        if not arg:
            raise ConfigError("agent 'planner' needs a planner name: planner:NAME "
                              "(e.g. planner:fast-downward)")
        from ..execution.spec import PlannerSpec

        reason = _planner_unavailable(PlannerSpec.parse(arg).name)
        if reason:
            return reason
    if kind not in FACTORIES:
        if kind in PENDING_KINDS:
            return (f"agent kind {kind!r} is not registered in this installation: "
                    f"{PENDING_KINDS[kind]} is not available yet")
        make_controller(spec)  # raises the ConfigError listing the known agents
    try:
        make_controller(spec, 0)
    except DependencyNotInstalled as exc:
        return str(exc)
    except OcplusError:
        raise
    except Exception as exc:  # a controller that cannot even be built is reported, not fatal
        return f"could not be created: {type(exc).__name__}: {exc}"
    return None


def check_partner(partner: str | None, cooks: list[int]) -> None:
    """``--partner``: a known agent that runs here, and kitchens with a cook to spare."""
    if partner is None:
        return
    from ..agents.base import PARTNER_ALIASES

    reason = check_agent(PARTNER_ALIASES.get(partner, partner))
    if reason:
        raise ConfigError(f"--partner {partner}: {reason}")
    if min(cooks) < 2:
        raise ConfigError(f"--partner plays the last cook beside the agent's: every kitchen "
                          f"needs at least 2 cooks, one has {min(cooks)} (raise --n-agents)")


def _kitchen_unavailable(spec: str, preset: str, n_agents: int) -> str | None:
    """The reason an agent that runs here cannot play this kitchen (a bare ``ppo`` with no
    shipped checkpoint for the preset and cook count), or None."""
    kind, _, arg = spec.partition(":")
    if kind != "ppo":
        return None
    from ..agents.ppo import missing_checkpoint

    return missing_checkpoint(arg or None, preset, n_agents)


def _planner_unavailable(name: str) -> str | None:
    try:
        from ..planning import engines
    except ImportError as exc:
        return f"the planning layer cannot be imported ({exc})"
    engines.get_planner(name)  # unknown name: PlannerError listing the known ones
    av = engines.availability(name)
    return None if av.ok else f"planner {name!r} is not available: {av.reason}"


# ---------------------------------------------------------------- one episode
def evaluate_episode(spec: EpisodeSpec) -> dict[str, Any]:
    """Run one episode and return its results row (never raises for controller failures)."""
    from ..agents import Episode, make_controller
    from ..agents.base import with_partner

    row = spec.row_base()
    row["worker"] = {"node": platform.node(), "pid": os.getpid()}
    t_start = time.perf_counter()
    kw: dict[str, Any] = {"horizon": spec.horizon, "n_agents": spec.n_agents}
    rules = make_rules(spec.preset, map=spec.map_spec, **kw)
    state = new_state(rules, spec.seed)
    log = EpisodeLog(state.geo.rows, state.geo.cols, state.n_agents, list(state.agent_pos))
    for o in state.orders:
        log.order_created.setdefault(o.order_id, o.created)
    controller = None
    recorder = None
    if spec.replay_path is not None:
        from ..render.replay import Recorder  # numpy only: no window, no pygame

        recorder = Recorder(rules, spec.seed, meta={"agent": spec.agent, "key": row["key"]})
    status, reason = "ok", ""

    def record(episode: Episode, result: Any) -> None:
        if recorder is not None:
            recorder.record(episode.joint, result.events)
        log.record(episode.joint, state.agent_pos, result.rewards, result.events,
                   episode.decision_time)
        for o in state.orders:
            log.order_created.setdefault(o.order_id, o.created)

    try:
        controller = make_controller(spec.agent, spec.seed)
        Episode(state, with_partner(controller, spec.partner, state.n_agents, spec.seed)
                ).run(on_step=record)
    except DependencyNotInstalled as exc:
        status, reason = "skipped", str(exc)
    except Exception as exc:  # the controller (or its planner process) failed: keep going
        status = "error"
        reason = f"{type(exc).__name__}: {exc} (at step {state.t})"
        row["traceback"] = traceback.format_exc(limit=6)
    if recorder is not None:
        row["replay"] = str(recorder.save(spec.replay_path, state))
    info: dict[str, Any] = {}
    if controller is not None:
        try:
            info = dict(controller.info())
        except Exception as exc:  # pragma: no cover - a broken info() must not lose the row
            info = {"info_error": f"{type(exc).__name__}: {exc}"}
    row.update(status=status, reason=reason, metrics=compute_metrics(log),
               stats=dict(state.stats), planner=controller_metrics(info),
               controller=json.loads(json.dumps(info, default=str)),
               timings={"wall_time_s": round(time.perf_counter() - t_start, 4),
                        "decision_time_s": round(sum(log.decision_times), 4)})
    return row


def _worker(conn: Any, spec: EpisodeSpec) -> None:
    """Entry of a worker process: its own process group, so a timeout kills its children."""
    try:
        os.setsid()
    except OSError:  # pragma: no cover
        pass
    try:
        row = evaluate_episode(spec)
    except BaseException as exc:  # pragma: no cover - reported by the parent
        row = error_row(spec, f"{type(exc).__name__}: {exc}")
    conn.send(row)
    conn.close()


def error_row(spec: EpisodeSpec, reason: str) -> dict[str, Any]:
    """The row of an episode that produced none itself (its process died or timed out)."""
    return {**spec.row_base(), "status": "error", "reason": reason}


def timeout_reason(episode_timeout: float | None) -> str:
    return (f"episode timed out after {episode_timeout:g} s (--episode-timeout); "
            "its processes were killed")


def _kill(proc: mp.Process) -> None:
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError, OSError):
        proc.kill()
    proc.join(5)


# ---------------------------------------------------------------- the whole run
def plan_episodes(cfg: EvalConfig) -> tuple[list[EpisodeSpec], list[dict[str, Any]]]:
    """All episodes of ``cfg`` and the rows of the agents that must be skipped.

    Every preset / map / agent-count combination and every agent name is checked first,
    so a typo fails in a second, not after an hour."""
    if cfg.horizon < 1:
        raise ConfigError(f"--horizon must be a positive number of steps, got {cfg.horizon}")
    check_backend(cfg)
    kitchens = []
    for preset in cfg.presets:
        kw: dict[str, Any] = {"horizon": cfg.horizon}
        if cfg.n_agents is not None:
            kw["n_agents"] = cfg.n_agents
        rules = make_rules(preset, map=cfg.map, **kw)
        kitchens.append((preset, rules.layout.name, rules.n_agents))
    skip_reason = {agent: check_agent(agent) for agent in cfg.agents}
    check_partner(cfg.partner, [n for _, _, n in kitchens])
    episodes, skipped = [], []
    for preset, map_name, n_agents in kitchens:
        for agent in cfg.agents:
            reason = skip_reason[agent] or _kitchen_unavailable(agent, preset, n_agents)
            if reason:
                base = EpisodeSpec(preset, map_name, cfg.map, n_agents, agent, -1, cfg.horizon,
                                   partner=cfg.partner)
                row = base.row_base()
                row.update(seed=None, status="skipped", reason=reason)
                row["key"] = episode_key(row)
                skipped.append(row)
                continue
            for seed in cfg.seeds:
                spec = EpisodeSpec(preset, map_name, cfg.map, n_agents, agent, seed, cfg.horizon,
                                   partner=cfg.partner)
                if seed in cfg.replay_seeds:
                    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", spec.row_base()["key"])
                    path = cfg.out / "replays" / f"{name}.jsonl.gz"
                    spec = dataclasses.replace(spec, replay_path=str(path))
                episodes.append(spec)
    return episodes, skipped


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


def prepare_out_dir(out: Path, resume: bool) -> set[str]:
    """Create ``out`` (or check it for ``--resume``); the keys of the episodes already done."""
    results = out / RESULTS_FILE
    if out.exists() and not resume:
        if any(out.iterdir()):
            raise ConfigError(
                f"output folder {out} already exists and is not empty; continue that run "
                "with --resume, or choose another --out")
    out.mkdir(parents=True, exist_ok=True)
    if not resume or not results.exists():
        return set()
    rows = read_results(results)
    _drop_partial_last_line(results)
    return {r["key"] for r in rows if r.get("status") in ("ok", "error") and "key" in r}


def _drop_partial_last_line(path: Path) -> None:
    """Cut a row that a killed run left half-written, so appended rows start on a new line."""
    data = path.read_bytes()
    if not data or data.endswith(b"\n"):
        return
    cut = data.rfind(b"\n") + 1
    try:
        json.loads(data[cut:])
        path.write_bytes(data + b"\n")  # complete row, only the newline is missing
    except ValueError:
        path.write_bytes(data[:cut])


def run_eval(cfg: EvalConfig, echo: Any = print) -> EvalOutcome:
    """Run (or continue) an evaluation and write results.jsonl, summary.csv and plots."""
    out = Path(cfg.out)
    episodes, skipped = plan_episodes(cfg)
    with _backend_session(cfg):  # a Ray cluster is joined before any file is written
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
    out = Path(cfg.out)
    done = prepare_out_dir(out, cfg.resume)
    config = {k: (str(v) if isinstance(v, Path) else v) for k, v in asdict(cfg).items()}
    (out / CONFIG_FILE).write_text(json.dumps(config, indent=2) + "\n")
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
        from tqdm import tqdm  # here, not at the top: importing the evaluation stays light

        # redrawn in place on a terminal; in a log, one line every 30 s at most
        bar = tqdm(total=len(todo), desc="eval", unit="ep", disable=cfg.quiet,
                   dynamic_ncols=True, mininterval=0.1 if sys.stderr.isatty() else 30)
        try:
            for row in _run_all(todo, cfg):
                row.setdefault("worker", {})["backend"] = cfg.backend
                writer.write(row)
                n_err += row.get("status") == "error"
                bar.set_postfix_str(f"{row['agent']} {row['preset']} s{row['seed']}")
                bar.update(1)
        finally:
            bar.close()
    return len(todo), n_err


def _run_all(todo: list[EpisodeSpec], cfg: EvalConfig):  # -> Iterator[dict]
    if cfg.backend == "ray":
        from .ray_backend import run_on_ray

        yield from run_on_ray(todo, cfg)
        return
    jobs = cfg.jobs or 1
    if jobs <= 1 and cfg.episode_timeout is None:
        for spec in todo:
            yield evaluate_episode(spec)
        return
    methods = mp.get_all_start_methods()
    ctx = mp.get_context("fork" if "fork" in methods else "spawn")
    pending = list(reversed(todo))
    running: dict[Any, tuple[mp.Process, EpisodeSpec, float]] = {}
    try:
        while pending or running:
            while pending and len(running) < jobs:
                spec = pending.pop()
                recv, send = ctx.Pipe(duplex=False)
                # not daemonic: planner controllers start their own (killable) processes,
                # which daemonic processes may not; the finally below kills what is left
                proc = ctx.Process(target=_worker, args=(send, spec), daemon=False)
                proc.start()
                send.close()
                running[recv] = (proc, spec, time.monotonic())
            for conn in wait(list(running), timeout=0.5):
                proc, spec, _ = running.pop(conn)
                try:
                    row = conn.recv()
                except (EOFError, OSError):
                    proc.join(5)
                    row = error_row(spec, f"worker process died (exit code {proc.exitcode}) "
                                          "before reporting; a crash in the controller or planner")
                conn.close()
                proc.join(5)
                yield row
            if cfg.episode_timeout is not None:
                now = time.monotonic()
                for conn, (proc, spec, started) in list(running.items()):
                    if now - started > cfg.episode_timeout:
                        _kill(proc)
                        running.pop(conn)
                        conn.close()
                        yield error_row(spec, timeout_reason(cfg.episode_timeout))
    finally:
        for conn, (proc, _, _) in running.items():
            _kill(proc)
            conn.close()


__all__ = [
    "BACKENDS",
    "EpisodeSpec",
    "EvalConfig",
    "EvalOutcome",
    "PENDING_KINDS",
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
