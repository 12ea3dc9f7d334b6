"""Episodes in worker processes on this machine: ``ocplus eval --jobs N`` (``--jobs 1`` too).

One forked process per episode, the leader of its own process group (a controller, a
user's model or a planner that exits, crashes or hangs takes down only its episode,
recorded as an ``error`` row). Nothing outlives the driver:

- each worker asks the kernel for a parent-death signal (``prctl(PR_SET_PDEATHSIG)`` on
  Linux) and, everywhere, watches its parent's pid from a thread; when the driver is
  gone (``kill -9`` included) the worker kills its whole process group, itself included,
  within :data:`WATCH_EVERY_S`;
- the planner process groups a worker starts (``planning._proc``) watch the worker the
  same way, so they follow it;
- the episode timeout is enforced by the driver and, as a backstop, by the worker
  itself (a little later), so it holds even when the driver cannot act;
- when the driver stops early (Ctrl-C, SIGTERM, an exception), it kills every running
  group;
- each worker is a subreaper (``PR_SET_CHILD_SUBREAPER``, Linux): a process the episode
  started in a session of its own (``setsid``) and abandoned is re-parented to the worker
  and killed before the worker reports its row.

Workers report ``("progress", step, planner calls, planner seconds)`` about once a second
and then ``("row", row)`` through a pipe.
"""

from __future__ import annotations

import ctypes
import multiprocessing as mp
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator
from multiprocessing.connection import wait
from typing import Any

from .episode import EpisodeSpec, error_row, evaluate_episode, timeout_reason

#: seconds between two looks of a worker at its parent
WATCH_EVERY_S = 0.2
#: how much later than the driver a worker enforces the episode timeout itself
TIMEOUT_BACKSTOP_S = 5.0
#: Linux prctl option: the signal the kernel sends when the parent dies
_PR_SET_PDEATHSIG = 1

#: progress hook of the driver: (spec, step, planner calls, planner seconds)
OnProgress = Callable[[EpisodeSpec, int, int, float], None]


def _kill_own_group() -> None:
    """SIGKILL this process's group (the worker and whatever it started), then itself."""
    try:
        os.killpg(os.getpgid(0), signal.SIGKILL)
    finally:
        os.kill(os.getpid(), signal.SIGKILL)


def _on_parent_death(*_: Any) -> None:
    _kill_own_group()


def set_parent_death_signal(sig: int = signal.SIGTERM) -> bool:
    """Ask the kernel to send ``sig`` to this process when its parent dies (Linux only);
    True when that worked."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(_PR_SET_PDEATHSIG, int(sig), 0, 0, 0) == 0
    except (OSError, AttributeError):  # pragma: no cover - no libc / no prctl
        return False


def die_with_parent(parent_pid: int, deadline: float | None = None) -> None:
    """Make this process (and its process group) die with ``parent_pid``, and at
    ``deadline`` (``time.monotonic()``) if given: a parent-death signal where the kernel
    offers one, and a thread that watches the parent's pid everywhere."""
    signal.signal(signal.SIGTERM, _on_parent_death)
    set_parent_death_signal(signal.SIGTERM)

    def watch() -> None:
        while True:
            if os.getppid() != parent_pid:
                _kill_own_group()
            if deadline is not None and time.monotonic() > deadline:
                _kill_own_group()
            time.sleep(WATCH_EVERY_S)

    threading.Thread(target=watch, name="die-with-parent", daemon=True).start()
    if os.getppid() != parent_pid:  # the parent died before the signal was armed
        _kill_own_group()


def _worker(conn: Any, spec: EpisodeSpec, driver_pid: int, timeout: float | None) -> None:
    """Entry of a worker process: its own process group, tied to the driver's life."""
    try:
        os.setsid()
    except OSError:  # pragma: no cover
        pass
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the driver's to handle
    deadline = None if timeout is None else time.monotonic() + timeout + TIMEOUT_BACKSTOP_S
    die_with_parent(driver_pid, deadline)

    def progress(step: int, calls: int, planning: float) -> None:
        conn.send(("progress", step, calls, planning))

    from ..planning._proc import kill_new_descendants, set_subreaper

    set_subreaper(True)  # what the episode abandons (setsid'd) stays ours to kill
    try:
        row = evaluate_episode(spec, progress)
    except BaseException as exc:  # pragma: no cover - evaluate_episode keeps almost all
        row = error_row(spec, f"{type(exc).__name__}: {exc}")
    kill_new_descendants(set())  # nothing the episode started outlives it
    conn.send(("row", row))
    conn.close()


def _kill(proc: mp.process.BaseProcess) -> None:
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError, OSError):
        proc.kill()
    proc.join(5)


def run_local(todo: list[EpisodeSpec], jobs: int, episode_timeout: float | None,
              on_start: Callable[[EpisodeSpec], None] | None = None,
              on_progress: OnProgress | None = None,
              on_tick: Callable[[], None] | None = None) -> Iterator[dict[str, Any]]:
    """Run ``todo`` in up to ``jobs`` worker processes; yield each row as it is finished.
    ``on_start``, ``on_progress`` and ``on_tick`` (twice a second) feed a progress bar."""
    methods = mp.get_all_start_methods()
    ctx = mp.get_context("fork" if "fork" in methods else "spawn")
    pending = list(reversed(todo))
    running: dict[Any, tuple[Any, EpisodeSpec, float]] = {}
    me = os.getpid()
    try:
        while pending or running:
            while pending and len(running) < jobs:
                spec = pending.pop()
                recv, send = ctx.Pipe(duplex=False)
                # not daemonic: planner controllers start their own (killable) processes,
                # which daemonic processes may not; the finally below kills what is left
                proc = ctx.Process(target=_worker, args=(send, spec, me, episode_timeout),
                                   daemon=False)
                proc.start()
                send.close()
                running[recv] = (proc, spec, time.monotonic())
                if on_start is not None:
                    on_start(spec)
            for conn in wait(list(running), timeout=0.5):
                row = _receive(conn, running, on_progress)
                if row is not None:
                    yield row
            if episode_timeout is not None:
                yield from _expire(running, episode_timeout)
            if on_tick is not None:
                on_tick()
    finally:
        for conn, (proc, _, _) in running.items():
            _kill(proc)
            conn.close()


def _receive(conn: Any, running: dict[Any, tuple[Any, EpisodeSpec, float]],
             on_progress: OnProgress | None) -> dict[str, Any] | None:
    """One message of a worker: a progress report (None) or its row (the worker is done)."""
    proc, spec, _ = running[conn]
    try:
        message = conn.recv()
    except (EOFError, OSError):
        proc.join(5)
        message = ("row", error_row(spec, f"worker process died (exit code {proc.exitcode}) "
                                          "before reporting; a crash in the controller or "
                                          "planner"))
    if message[0] == "progress":
        if on_progress is not None:
            on_progress(spec, *message[1:])
        return None
    running.pop(conn)
    conn.close()
    proc.join(5)
    return message[1]


def _expire(running: dict[Any, tuple[Any, EpisodeSpec, float]],
            episode_timeout: float) -> Iterator[dict[str, Any]]:
    now = time.monotonic()
    for conn, (proc, spec, started) in list(running.items()):
        if now - started > episode_timeout:
            _kill(proc)
            running.pop(conn)
            conn.close()
            yield error_row(spec, timeout_reason(episode_timeout))


__all__ = ["WATCH_EVERY_S", "die_with_parent", "run_local", "set_parent_death_signal"]
