"""Episodes in worker processes on this machine: ``ocplus eval --jobs N`` (``--jobs 1`` too).

``jobs`` forked worker processes, each the leader of its own process group, each running
one episode after another (the modules, maps and planner set-up it loaded stay warm, as
in one process): a controller, a user's model or a planner that exits, crashes or hangs
takes down only its episode, recorded as an ``error`` row, and the worker is replaced by
a fresh one for the next. Nothing outlives the driver:

- each worker asks the kernel for a parent-death signal (``prctl(PR_SET_PDEATHSIG)`` on
  Linux) and, everywhere, watches its parent's pid from a thread; when the driver is
  gone (``kill -9`` included) the worker kills its whole process group, itself included,
  within :data:`WATCH_EVERY_S`;
- the planner process groups a worker starts (``planning._proc``) watch the worker the
  same way, so they follow it;
- the episode timeout is enforced by the driver (it kills the worker's group) and, as a
  backstop, by the worker itself (a little later), so it holds even when the driver
  cannot act;
- when the driver stops early (Ctrl-C, SIGTERM, an exception), it kills every running
  group;
- each worker is a subreaper (``PR_SET_CHILD_SUBREAPER``, Linux): a process the episode
  started in a session of its own (``setsid``) and abandoned is re-parented to the worker
  and killed before the worker reports its row.

The driver sends a worker an episode (its :class:`~.episode.EpisodeSpec`; None: stop)
through a pipe; the worker reports ``("progress", step, planner calls, planner seconds)``
about once a second and then ``("row", row)``.
"""

from __future__ import annotations

import contextlib
import ctypes
import multiprocessing as mp
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
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


def die_with_parent(parent_pid: int, deadline: float | list[float | None] | None = None) -> None:
    """Make this process (and its process group) die with ``parent_pid``, and at
    ``deadline`` (``time.monotonic()``) if given: a parent-death signal where the kernel
    offers one, and a thread that watches the parent's pid everywhere. ``deadline`` may be
    a one-item list that the caller changes (a worker that runs one episode after another)."""
    signal.signal(signal.SIGTERM, _on_parent_death)
    set_parent_death_signal(signal.SIGTERM)
    box = deadline if isinstance(deadline, list) else [deadline]

    def watch() -> None:
        while True:
            if os.getppid() != parent_pid:
                _kill_own_group()
            due = box[0]
            if due is not None and time.monotonic() > due:
                _kill_own_group()
            time.sleep(WATCH_EVERY_S)

    threading.Thread(target=watch, name="die-with-parent", daemon=True).start()
    if os.getppid() != parent_pid:  # the parent died before the signal was armed
        _kill_own_group()


def _worker(conn: Any, driver_pid: int, timeout: float | None) -> None:
    """Entry of a worker process: its own process group, tied to the driver's life; runs
    the episodes the driver sends, one at a time, until it is sent None."""
    try:
        os.setsid()
    except OSError:  # pragma: no cover
        pass
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the driver's to handle
    deadline: list[float | None] = [None]
    die_with_parent(driver_pid, deadline)
    from ..planning._proc import kill_new_descendants, set_subreaper

    set_subreaper(True)  # what an episode abandons (setsid'd) stays ours to kill

    def progress(step: int, calls: int, planning: float) -> None:
        conn.send(("progress", step, calls, planning))

    while True:
        try:
            spec = conn.recv()
        except (EOFError, OSError):
            break
        if spec is None:
            break
        if timeout is not None:
            deadline[0] = time.monotonic() + timeout + TIMEOUT_BACKSTOP_S
        try:
            row = evaluate_episode(spec, progress)
        except BaseException as exc:  # pragma: no cover - evaluate_episode keeps almost all
            row = error_row(spec, f"{type(exc).__name__}: {exc}")
        kill_new_descendants(set())  # nothing the episode started outlives it
        deadline[0] = None
        conn.send(("row", row))
    conn.close()


def _kill(proc: mp.process.BaseProcess) -> None:
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError, OSError):
        proc.kill()
    proc.join(5)


@dataclass
class _Slot:
    """A worker process and the episode it runs (None: idle)."""

    proc: Any
    conn: Any
    spec: EpisodeSpec | None = None
    started: float = 0.0


def run_local(todo: list[EpisodeSpec], jobs: int, episode_timeout: float | None,
              on_start: Callable[[EpisodeSpec], None] | None = None,
              on_progress: OnProgress | None = None,
              on_tick: Callable[[], None] | None = None) -> Iterator[dict[str, Any]]:
    """Run ``todo`` in up to ``jobs`` worker processes; yield each row as it is finished.
    A worker runs one episode after another; one that dies or runs out of time is
    replaced by a fresh one. ``on_start``, ``on_progress`` and ``on_tick`` (twice a
    second) feed a progress bar."""
    methods = mp.get_all_start_methods()
    ctx = mp.get_context("fork" if "fork" in methods else "spawn")
    pending = list(reversed(todo))
    slots: list[_Slot] = []
    me = os.getpid()
    try:
        while pending or any(s.spec is not None for s in slots):
            for slot in [s for s in slots if s.spec is None]:
                if not pending:
                    break
                _hand(slot, pending.pop(), on_start)
            while pending and len(slots) < jobs:
                # not daemonic: planner controllers start their own (killable) processes,
                # which daemonic processes may not; the finally below kills what is left
                mine, theirs = ctx.Pipe(duplex=True)
                proc = ctx.Process(target=_worker, args=(theirs, me, episode_timeout),
                                   daemon=False)
                proc.start()
                theirs.close()
                slots.append(_Slot(proc, mine))
                _hand(slots[-1], pending.pop(), on_start)
            busy = {s.conn: s for s in slots if s.spec is not None}
            for conn in wait(list(busy), timeout=0.5):
                row = _receive(busy[conn], slots, on_progress)
                if row is not None:
                    yield row
            if episode_timeout is not None:
                yield from _expire(slots, episode_timeout)
            if on_tick is not None:
                on_tick()
    finally:
        for slot in slots:
            if slot.spec is None:  # idle: asked to stop, killed if it does not
                with contextlib.suppress(OSError, ValueError):
                    slot.conn.send(None)
                slot.proc.join(1.0)
            _kill(slot.proc)
            slot.conn.close()


def _hand(slot: _Slot, spec: EpisodeSpec, on_start: Callable[[EpisodeSpec], None] | None) -> None:
    slot.conn.send(spec)
    slot.spec, slot.started = spec, time.monotonic()
    if on_start is not None:
        on_start(spec)


def _drop(slot: _Slot, slots: list[_Slot]) -> None:
    """Forget a worker that died or was killed (its episode is over)."""
    _kill(slot.proc)
    slot.conn.close()
    slots.remove(slot)


def _receive(slot: _Slot, slots: list[_Slot],
             on_progress: OnProgress | None) -> dict[str, Any] | None:
    """One message of a worker: a progress report (None) or its row (the episode is done)."""
    spec = slot.spec
    assert spec is not None
    try:
        message = slot.conn.recv()
    except (EOFError, OSError):
        slot.proc.join(5)
        code = slot.proc.exitcode
        _drop(slot, slots)
        return error_row(spec, f"worker process died (exit code {code}) before reporting; "
                               "a crash in the controller or planner")
    if message[0] == "progress":
        if on_progress is not None:
            on_progress(spec, *message[1:])
        return None
    slot.spec = None
    return message[1]  # type: ignore[no-any-return]


def _expire(slots: list[_Slot], episode_timeout: float) -> Iterator[dict[str, Any]]:
    now = time.monotonic()
    for slot in list(slots):
        if slot.spec is not None and now - slot.started > episode_timeout:
            spec = slot.spec
            _drop(slot, slots)
            yield error_row(spec, timeout_reason(episode_timeout))


__all__ = ["WATCH_EVERY_S", "die_with_parent", "run_local", "set_parent_death_signal"]
