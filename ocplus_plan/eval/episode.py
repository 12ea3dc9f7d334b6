"""One episode of an evaluation: what it is (:class:`EpisodeSpec`), how it runs
(:func:`evaluate_episode`) and the row it leaves, whichever backend runs it.

The runner (:mod:`.runner`) and both backends (:mod:`.local_backend`, :mod:`.ray_backend`)
import from here; nothing here imports them. An episode never raises for what a user's
controller, model function or planner does: any exception, ``SystemExit`` and
``KeyboardInterrupt`` included, becomes an ``error`` row with what happened so far. Only
a real Ctrl-C of the driver (:func:`interrupt_requested`) is let through, so that it can
stop the sweep.
"""

from __future__ import annotations

import json
import os
import platform
import threading
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import ConfigError, DependencyNotInstalled, OcplusError
from ..sim import make_rules, new_state
from .metrics import EpisodeLog, compute_metrics, controller_metrics
from .results import episode_key

#: set by the driver when the user presses Ctrl-C (SIGINT): a KeyboardInterrupt is then the
#: user's, not a controller's, and stops the sweep instead of becoming an error row
_INTERRUPT = threading.Event()
#: progress callback: (step, planner calls, planner seconds)
Progress = Callable[[int, int, float], None]
#: seconds between two progress reports of one episode
PROGRESS_EVERY_S = 1.0


def interrupt_requested() -> bool:
    """True once the driver has seen Ctrl-C (see :func:`request_interrupt`)."""
    return _INTERRUPT.is_set()


def request_interrupt(on: bool = True) -> None:
    """Mark (or, with ``on=False``, clear) a Ctrl-C of the driver."""
    if on:
        _INTERRUPT.set()
    else:
        _INTERRUPT.clear()


def _is_users(exc: BaseException) -> bool:
    """Whether ``exc`` came from the code under evaluation (and becomes a row)."""
    if isinstance(exc, GeneratorExit):
        return False
    return not (isinstance(exc, KeyboardInterrupt) and interrupt_requested())


@dataclass(frozen=True)
class EpisodeSpec:
    """One episode to run: everything a worker process needs."""

    preset: str
    map: str  # the map's name (for tables)
    map_spec: str | None  # what to pass to make_rules (None: the preset's map)
    n_agents: int  # the cooks (a fault's blocking agent comes on top)
    agent: str
    seed: int
    horizon: int
    replay_path: str | None = None  # where to save this episode's recording, if chosen
    faults: str = ""  # ``--faults`` text (execution.faults.parse_faults); empty: none
    rules: tuple[tuple[str, Any], ...] = ()  # rule overrides (``--rules``), sorted by key
    partner: str | None = None  # the agent that plays the last cook (``--partner``)
    #: why the agent could not even be loaded (its module ended or outran its process when
    #: it was checked): the episode is then an ``error`` row with this reason, not run
    load_error: str = ""

    def row_base(self) -> dict[str, Any]:
        agent = self.agent if self.partner is None else f"{self.agent} +{self.partner}"
        d: dict[str, Any] = {"preset": self.preset, "map": self.map, "n_agents": self.n_agents,
                             "agent": agent, "seed": self.seed, "horizon": self.horizon}
        if self.partner is not None:
            d["partner"] = self.partner
        if self.faults:
            d["faults"] = self.faults
        d["key"] = episode_key(d) + "".join(f"|{k}={v}" for k, v in self.rules)
        if self.rules:
            d["rules"] = dict(self.rules)
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
    backend: str = "local"  # one of runner.BACKENDS
    address: str | None = None  # ray: the cluster to join (None: start one on this machine)
    retries: int = 2  # ray: reruns of an episode whose worker died
    resume: bool = False
    episode_timeout: float | None = None
    plots: bool = False
    quiet: bool = False
    replay_seeds: list[int] = field(default_factory=list)  # episodes to save as replays
    faults: str = ""  # ``--faults`` (execution.faults.parse_faults); empty: none
    extra: dict[str, Any] = field(default_factory=dict)
    rules: dict[str, Any] = field(default_factory=dict)  # rule overrides (``--rules``)
    partner: str | None = None  # the agent that plays the last cook (``--partner``)


# ---------------------------------------------------------------- checking agents
#: agent kinds whose creation runs the user's code (``llm:`` imports the user's module):
#: they are checked in a child process, so an exit, a crash or a loop at import cannot end
#: or hang the sweep
USER_CODE_KINDS = ("llm",)


class AgentLoadFailed(Exception):
    """Loading an agent ended or outran the process that checked it (see
    :func:`check_agent`): its episodes become ``error`` rows with this reason."""


def check_agent(spec: str, load_timeout: float | None = None) -> str | None:
    """None if ``spec`` can run here; the reason when it must be skipped.

    Raises :class:`ConfigError` / :class:`PlannerError` for names that are simply wrong.
    An agent whose creation runs the user's code (:data:`USER_CODE_KINDS`) is created in a
    child process, stopped after ``load_timeout`` seconds (None: no limit): when that
    process dies (``os._exit``, a crash) or runs out of time, :class:`AgentLoadFailed`.
    """
    if spec.partition(":")[0] in USER_CODE_KINDS and hasattr(os, "fork"):
        return _check_in_child(spec, load_timeout)
    return _check_here(spec)


def _check_here(spec: str) -> str | None:
    from ..agents import FACTORIES, make_controller

    kind, _, arg = spec.partition(":")
    if kind == "planner":  # ``planner:`` (and ``planner``): the default planner
        from ..execution.spec import PlannerSpec

        reason = _planner_unavailable(PlannerSpec.parse(arg).name)
        if reason:
            return reason
    if kind not in FACTORIES:
        make_controller(spec)  # raises the ConfigError listing the known agents
    try:
        make_controller(spec, 0)
    except DependencyNotInstalled as exc:
        return str(exc)
    except OcplusError:
        raise
    except BaseException as exc:  # a controller that cannot even be built is reported
        if not _is_users(exc):
            raise
        return f"could not be created: {type(exc).__name__}: {exc}"
    return None


def _check_reporting(spec: str) -> tuple[str, str | None]:
    """In the child: ("ok", skip reason) or ("bad", the message of a wrong name)."""
    try:
        return "ok", _check_here(spec)
    except OcplusError as exc:
        return "bad", str(exc)


def _check_in_child(spec: str, load_timeout: float | None) -> str | None:
    from ..planning import _proc

    outcome = _proc.run_isolated(_check_reporting, (spec,), hard_limit=load_timeout)
    if outcome.kind == _proc.OK:
        verdict, text = outcome.value
        if verdict == "bad":
            raise ConfigError(str(text))
        return text  # type: ignore[no-any-return]
    if outcome.kind == _proc.TIMEOUT:
        raise AgentLoadFailed(f"loading agent {spec} did not finish within "
                              f"{load_timeout:g} s (--episode-timeout); its process was killed")
    what = str(outcome.value).replace("the planner process", "its process")
    raise AgentLoadFailed(f"loading agent {spec} failed: {what}")


def check_partner(partner: str | None, cooks: list[int],
                  load_timeout: float | None = None) -> None:
    """``--partner``: a known agent that runs here, and kitchens with a cook to spare."""
    if partner is None:
        return
    from ..agents.base import PARTNER_ALIASES

    try:
        reason = check_agent(PARTNER_ALIASES.get(partner, partner), load_timeout)
    except AgentLoadFailed as exc:
        raise ConfigError(f"--partner {partner}: {exc}") from None
    if reason:
        raise ConfigError(f"--partner {partner}: {reason}")
    if min(cooks) < 2:
        raise ConfigError(f"--partner plays the last cook beside the agent's: every kitchen "
                          f"needs at least 2 cooks, one has {min(cooks)} (raise --n-agents)")


def kitchen_unavailable(spec: str, preset: str, n_agents: int,
                        map_name: str | None = None) -> str | None:
    """The reason an agent that runs here cannot play this kitchen (a bare ``ppo`` with no
    shipped checkpoint for the kitchen and cook count), or None."""
    kind, _, arg = spec.partition(":")
    if kind != "ppo":
        return None
    from ..agents.ppo import missing_checkpoint

    return missing_checkpoint(arg or None, preset, n_agents, map_name)


def _planner_unavailable(name: str) -> str | None:
    try:
        from ..planning import engines
    except ImportError as exc:
        return f"the planning layer cannot be imported ({exc})"
    engines.get_planner(name)  # unknown name: PlannerError listing the known ones
    av = engines.availability(name)
    return None if av.ok else f"planner {name!r} is not available: {av.reason}"


# ---------------------------------------------------------------- one episode
def _drivers(spec: EpisodeSpec, controller: Any, fault: Any) -> Any:
    """The team of an episode: the controller drives the cooks (but the last, with a
    partner: ``agents.base.with_partner``); a fault's blocker the extra agent. Message loss
    is wired into a planner controller's executive."""
    from ..agents import with_partner

    if fault.message_loss and hasattr(controller, "executive"):
        from ..execution.faults import MessageLoss

        controller.executive.deliver_plan = MessageLoss(fault.message_loss, spec.seed)
    team = with_partner(controller, spec.partner, spec.n_agents, spec.seed)
    if not fault.blocker:
        return team
    from ..execution.faults import BlockingAgent

    blocker = BlockingAgent(seed=spec.seed)
    drivers = team if isinstance(team, list) else [(controller, range(spec.n_agents))]
    return [*drivers, (blocker, [spec.n_agents])]


def _fault_report(fault: Any, schedule: Any, team: Any, info: dict[str, Any]) -> dict[str, Any]:
    """What the faults did in an episode (for results.jsonl)."""
    done = [kind for _t, kind in (schedule.applied if schedule is not None else [])]
    report: dict[str, Any] = {"burns": done.count("burn"), "switches": done.count("switch")}
    if fault.message_loss:
        report["messages_lost"] = info.get("messages_lost")  # None: the agent takes no plans
    if fault.blocker and isinstance(team, list):
        report.update(team[1][0].info())
    return report


def evaluate_episode(spec: EpisodeSpec, progress: Progress | None = None) -> dict[str, Any]:
    """Run one episode and return its results row (never raises for controller failures).

    ``progress`` (if given) hears the step, planner calls and planner seconds about once a
    second."""
    from ..agents import Episode, make_controller
    from ..execution.faults import parse_faults
    from ..execution.stall import StallWatch

    fault = parse_faults(spec.faults)
    row = spec.row_base()
    row["worker"] = {"node": platform.node(), "pid": os.getpid()}
    if spec.load_error:
        return {**row, "status": "error", "reason": spec.load_error}
    t_start = time.perf_counter()
    rules = make_rules(spec.preset, map=spec.map_spec, horizon=spec.horizon,
                       n_agents=spec.n_agents + (1 if fault.blocker else 0), **dict(spec.rules))
    state = new_state(rules, spec.seed)
    schedule = fault.schedule(spec.horizon) if fault else None
    log = EpisodeLog(state.geo.rows, state.geo.cols, state.n_agents, list(state.agent_pos))
    for o in state.orders:
        log.order_created.setdefault(o.order_id, o.created)
    stalls = StallWatch(state)  # stretches with no progress toward any order, any agent
    controller: Any = None
    team: Any = None
    recorder = None
    if spec.replay_path is not None:
        from ..render.replay import Recorder  # numpy only: no window, no pygame

        recorder = Recorder(rules, spec.seed, meta={"agent": spec.agent, "key": row["key"]})
    status, reason = "ok", ""
    last_report = [time.monotonic()]

    def record(episode: Any, result: Any) -> None:
        if recorder is not None:
            recorder.record(episode.joint, result.events)
        log.record(episode.joint, state.agent_pos, result.rewards, result.events,
                   episode.decision_time)
        stalls.update(state)
        for o in state.orders:
            log.order_created.setdefault(o.order_id, o.created)
        now = time.monotonic()
        if progress is not None and now - last_report[0] >= PROGRESS_EVERY_S:
            last_report[0] = now
            m = controller_metrics(dict(controller.info()))
            progress(state.t, m["planner_calls"], m["planning_time_s"])

    try:
        controller = make_controller(spec.agent, spec.seed)
        team = _drivers(spec, controller, fault)
        Episode(state, team, schedule).run(on_step=record)
    except DependencyNotInstalled as exc:
        status, reason = "skipped", str(exc)
    except BaseException as exc:  # the controller, its model or its planner failed: go on
        if not _is_users(exc):
            raise
        status = "error"
        reason = f"{type(exc).__name__}: {exc} (at step {state.t})"
        row["traceback"] = traceback.format_exc(limit=6)
    _finish_row(row, spec, state, log, controller, recorder, t_start)
    row.update(status=status, reason=reason, **stalls.info())
    if fault:
        row["fault_report"] = _fault_report(fault, schedule, team, row["controller"])
    return row


def _finish_row(row: dict[str, Any], spec: EpisodeSpec, state: Any, log: EpisodeLog,
                controller: Any, recorder: Any, t_start: float) -> None:
    if recorder is not None:
        row["replay"] = str(recorder.save(spec.replay_path, state))
    info: dict[str, Any] = {}
    if controller is not None:
        try:
            info = dict(controller.info())
        except Exception as exc:  # pragma: no cover - a broken info() must not lose the row
            info = {"info_error": f"{type(exc).__name__}: {exc}"}
    row.update(metrics=compute_metrics(log), stats=dict(state.stats),
               planner=controller_metrics(info),
               controller=json.loads(json.dumps(info, default=str)),
               timings={"wall_time_s": round(time.perf_counter() - t_start, 4),
                        "decision_time_s": round(sum(log.decision_times), 4)})


def error_row(spec: EpisodeSpec, reason: str) -> dict[str, Any]:
    """The row of an episode that produced none itself (its process died or timed out)."""
    return {**spec.row_base(), "status": "error", "reason": reason}


def timeout_reason(episode_timeout: float | None) -> str:
    return (f"episode timed out after {episode_timeout:g} s (--episode-timeout); "
            "its processes were killed")


__all__ = [
    "USER_CODE_KINDS",
    "AgentLoadFailed",
    "EpisodeSpec",
    "EvalConfig",
    "Progress",
    "check_agent",
    "check_partner",
    "error_row",
    "evaluate_episode",
    "interrupt_requested",
    "kitchen_unavailable",
    "request_interrupt",
    "timeout_reason",
]
