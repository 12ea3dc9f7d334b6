"""Episodes as Ray tasks: ``ocplus eval --backend ray [--address ADDR]``.

A sweep that outgrows one machine runs on a Ray cluster (the ``cluster`` extra). Each
episode is one Ray task; inside the task the episode runs in a forked child that leads
its own process group (:func:`~ocplus_plan.planning._proc.run_isolated`), exactly as with
the local backend, so ``--episode-timeout`` kills the episode and every planner process
it started, and a crashing planner becomes an ``error`` row without costing the worker.

What Ray adds is the cluster and fault tolerance: a Ray worker (or node) that dies in the
middle of an episode has that episode run again, up to ``retries`` more times, by Ray
itself (``max_retries``); an episode that keeps killing its worker becomes an ``error``
row with Ray's reason. Rows come back as episodes finish (``ray.wait``) and the runner
writes each at once, so a driver that dies loses only the episodes in flight, which are
at most as many as the cluster has CPUs (or ``--jobs``).

Without ``--address`` a private Ray instance is started on this machine (``--jobs``
CPUs, default all) and stopped at the end, even when the driver is killed (``kill -9``):
a small cleaner process, forked before Ray starts and in a session of its own, waits for
the driver; if the driver dies with the instance's folder still there, the cleaner kills
every process of that instance (those whose command line names the folder: GCS, raylet,
monitors; and their descendants: workers, the dashboard and runtime-env agents) and
removes the folder, then exits. Since the raylet may die first and orphan its agents
(whose command lines name nothing), the cleaner also remembers, once a second, the
driver's descendants, and kills those too. After a normal end it exits at once; ``--address auto`` joins the cluster started
with ``ray start`` on this machine, ``--address HOST:6379`` a remote head node. A Ray
instance that the caller already started (``ray.init`` in a notebook or a test) is
used as it is and left running.
"""

from __future__ import annotations

import contextlib
import functools
import logging
import os
import shutil
import signal
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from ..errors import ConfigError, DependencyNotInstalled
from .episode import (
    EpisodeSpec,
    EvalConfig,
    check_agent,
    error_row,
    evaluate_episode,
    timeout_reason,
)

#: the pip extra that brings Ray
EXTRA = "cluster"
#: prefix of the private folder of a Ray instance started here
TEMP_PREFIX = "ocray-"
#: the longest folder that can hold that private folder: Ray's deepest socket path,
#: ``<folder>/ocray-XXXXXXXX/session_<date>_<time>_<micros>_<pid>/sockets/plasma_store``,
#: must stay within the 107 bytes of an AF_UNIX path
MAX_BASE_CHARS = 30


def short_temp_base() -> Path:
    """A folder, short enough for Ray's socket paths, to make Ray's private folder in: the
    temporary directory when its path is short (Linux: /tmp), else /tmp (macOS' TMPDIR is
    about 50 characters). :class:`ConfigError` if neither works."""
    for candidate in (tempfile.gettempdir(), "/tmp"):
        if len(candidate) <= MAX_BASE_CHARS and os.path.isdir(candidate) \
                and os.access(candidate, os.W_OK | os.X_OK):
            return Path(candidate)
    raise ConfigError(
        f"Ray needs a temporary folder with a path of at most {MAX_BASE_CHARS} characters "
        f"(its socket paths are limited to 107 bytes); {tempfile.gettempdir()!r} is longer and "
        "/tmp is not writable: set TMPDIR to a short writable folder")


def private_temp_dir() -> str:
    """A new private folder for a Ray instance's session files, short whatever TMPDIR is;
    the caller removes it."""
    return tempfile.mkdtemp(prefix=TEMP_PREFIX, dir=short_temp_base())


def import_ray() -> Any:
    """The ``ray`` module, or :class:`DependencyNotInstalled` naming the extra."""
    try:
        import ray
    except ImportError as exc:
        raise DependencyNotInstalled(
            f"--backend ray needs Ray, which is not installed ({exc}): "
            f"pip install -e '.[{EXTRA}]' (or pip install 'ocplus-plan[{EXTRA}]'), "
            "or use --backend local") from exc
    return ray


def ray_episode(spec: EpisodeSpec, episode_timeout: float | None) -> dict[str, Any]:
    """The body of one Ray task: the episode in an isolated, killable process group."""
    import ray

    from ..planning import _proc

    _warm_up(spec.agent)
    outcome = _proc.run_isolated(evaluate_episode, (spec,), hard_limit=episode_timeout)
    if outcome.kind == _proc.OK:
        row = outcome.value
    elif outcome.kind == _proc.TIMEOUT:
        row = error_row(spec, timeout_reason(episode_timeout))
    else:  # the episode's process crashed or raised outside the controller
        row = error_row(spec, f"the episode's process failed: {outcome.value}")
    row.setdefault("worker", {})["node_id"] = ray.get_runtime_context().get_node_id()
    return row


@functools.cache
def _warm_up(agent: str) -> None:
    """Import what ``agent``'s episodes need, once per Ray worker, before the first fork.

    The local backend's episode processes are forked from the driver, which has loaded
    the agent's modules (unified-planning, the planner plug-ins) while checking it; a Ray
    worker starts cold, and each forked episode would load them again and throw them away
    (measured: ~1.6 s of a 2 s fast-downward episode). Checking the agent here loads them
    into the worker, which Ray reuses for later tasks."""
    check_agent(agent)


@contextlib.contextmanager
def ray_session(cfg: EvalConfig) -> Iterator[Any]:
    """Join the cluster at ``cfg.address`` (or start a Ray instance here) for the sweep;
    leave it at the end. A Ray that the caller started already is used and left running.
    A cluster that cannot be joined is a :class:`ConfigError` saying what to check."""
    ray = import_ray()
    if ray.is_initialized():
        yield ray
        return
    # a Ray instance started here keeps its session files (sockets, logs) in a folder of
    # its own that goes with it; a short path: Ray's socket paths must stay under 108 bytes
    private = private_temp_dir() if cfg.address is None else None
    cleaner = None if private is None else start_cleaner(private)
    try:
        try:
            ray.init(address=cfg.address, num_cpus=cfg.jobs if cfg.address is None else None,
                     include_dashboard=False, log_to_driver=False,
                     logging_level=logging.WARNING, _temp_dir=private)
        except (ConnectionError, ray.exceptions.RayError) as exc:
            raise ConfigError(
                f"could not join the Ray cluster at {cfg.address or 'this machine'}: "
                f"{_first_line(exc)}. Check that `ray start --head` runs there and that the "
                "address is HOST:PORT of its GCS (6379 unless --port said otherwise); with "
                "token authentication set RAY_AUTH_MODE=token here and give this machine the "
                "cluster's token (~/.ray/auth_token or RAY_AUTH_TOKEN)") from exc
        try:
            yield ray
        finally:
            ray.shutdown()
    finally:
        if private is not None:
            shutil.rmtree(private, ignore_errors=True)
        if cleaner is not None:
            stop_cleaner(cleaner)


#: seconds between two looks of the cleaner at the driver
CLEANER_EVERY_S = 0.25


def start_cleaner(private: str) -> int | None:
    """Fork the cleaner of the Ray instance whose folder is ``private`` (see the module
    doc); its pid, or None where processes cannot be forked."""
    if not hasattr(os, "fork"):  # pragma: no cover - Linux and macOS fork
        return None
    driver = os.getpid()
    pid = os.fork()
    if pid != 0:
        return pid
    try:  # the cleaner: a group kill of the driver's session must not reach it
        os.setsid()
        devnull = os.open(os.devnull, os.O_RDWR)
        for fd in (0, 1, 2):
            os.dup2(devnull, fd)
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        seen: set[tuple[int, float]] = set()
        tick = 0
        while os.getppid() == driver and os.path.isdir(private):
            if tick % 4 == 0:  # Ray's processes start in the first seconds: remember them
                seen |= _descendants(driver)
            tick += 1
            time.sleep(CLEANER_EVERY_S)
        if os.path.isdir(private):  # the driver died without stopping its instance
            kill_instance(private, seen)
            shutil.rmtree(private, ignore_errors=True)
    finally:
        os._exit(0)


def _descendants(pid: int) -> set[tuple[int, float]]:
    """(pid, start time) of each descendant of ``pid`` but the calling process."""
    import psutil

    out = set()
    try:
        for proc in psutil.Process(pid).children(recursive=True):
            if proc.pid != os.getpid():
                out.add((proc.pid, proc.create_time()))
    except psutil.Error:
        pass
    return out


def stop_cleaner(pid: int) -> None:
    """End the cleaner after a normal end of the session (its folder is gone)."""
    with contextlib.suppress(OSError):
        os.kill(pid, signal.SIGKILL)
    with contextlib.suppress(OSError):
        os.waitpid(pid, 0)


def kill_instance(private: str, known: set[tuple[int, float]] = frozenset()) -> list[int]:
    """SIGKILL every process of the Ray instance whose folder is ``private``: those whose
    command line names it, and all their descendants (Ray renames its workers and agents,
    ``ray::IDLE``, so they are found as the raylet's children), and the processes of
    ``known`` ((pid, start time) pairs, seen earlier as the driver's descendants: once the
    raylet is gone its agents are orphans that name nothing); their pids."""
    import psutil

    found: dict[int, psutil.Process] = {}
    for pid, started in known:
        with contextlib.suppress(psutil.Error):
            proc = psutil.Process(pid)
            if proc.create_time() == started:  # not a recycled pid
                found[pid] = proc
    for proc in psutil.process_iter(["cmdline"]):
        try:
            if any(private in arg for arg in proc.info["cmdline"] or ()):
                found[proc.pid] = proc
                found.update({c.pid: c for c in proc.children(recursive=True)})
        except psutil.Error:
            continue
    found.pop(os.getpid(), None)
    for proc in found.values():
        with contextlib.suppress(psutil.Error):
            proc.kill()
    psutil.wait_procs(list(found.values()), timeout=3)
    return sorted(found)


def run_on_ray(todo: list[EpisodeSpec], cfg: EvalConfig,
               on_tick: Callable[[], None] | None = None) -> Iterator[dict[str, Any]]:
    """Run ``todo`` as Ray tasks on the Ray that :func:`ray_session` opened; yield each
    episode's row as soon as it is finished (``on_tick`` about once a second, for the
    progress bar)."""
    import ray

    in_flight_limit = cfg.jobs or max(1, int(ray.cluster_resources().get("CPU", 1)))
    task = ray.remote(ray_episode).options(num_cpus=1, max_retries=cfg.retries,
                                           retry_exceptions=False, name="ocplus-episode")
    pending = list(reversed(todo))
    running: dict[Any, EpisodeSpec] = {}
    try:
        while pending or running:
            while pending and len(running) < in_flight_limit:
                spec = pending.pop()
                running[task.remote(spec, cfg.episode_timeout)] = spec
            finished, _ = ray.wait(list(running), num_returns=1, timeout=1.0)
            if on_tick is not None:
                on_tick()
            for ref in finished:
                spec = running.pop(ref)
                try:
                    row = ray.get(ref)
                except ray.exceptions.RayError as exc:  # failed for good, retries spent
                    row = error_row(spec, _failure_reason(exc, cfg.retries))
                yield row
    finally:
        for ref in running:  # the driver stops early (Ctrl-C): no orphan episodes
            ray.cancel(ref, force=True)


def _failure_reason(exc: BaseException, retries: int) -> str:
    """Ray's reason for a task that failed for good, on one line."""
    return (f"the Ray task failed after {retries + 1} attempt(s) (--retries {retries}): "
            f"{type(exc).__name__}: {_first_line(exc)}")


def _first_line(exc: BaseException) -> str:
    return (str(exc).strip().splitlines() or [""])[0]


__all__ = ["EXTRA", "TEMP_PREFIX", "import_ray", "kill_instance", "private_temp_dir",
           "ray_episode", "ray_session", "run_on_ray", "short_temp_base", "start_cleaner",
           "stop_cleaner"]
