"""Run one function in a killable child process with its own process group.

Planners are run this way because several of them cannot be trusted to stop:
TAMER ignores ``timeout``; Fast Downward, SymK, ENHSP's JVM and the Aries server
are grandchildren that survive their Python parent. The child made here is the
leader of a fresh process group, so every process a planner starts belongs to
that group and one ``killpg`` ends them all, on a timeout, on a crash, and after
a normal finish (the Aries server otherwise lingers).

The child is forked (not spawned), so it inherits the already-built
unified-planning problem without pickling it; only the function's (small,
picklable) return value travels back through a pipe. A watchdog thread in the
child kills the group if the parent dies, so nothing is left behind when the
caller itself is killed.

Two limits stop a child. The *CPU limit* (``cpu_limit``) counts what the IPC counts:
the user + system CPU seconds of the whole process group (each live process's own
time plus the time of its children that it has reaped), sampled by the parent while it
waits; the group is killed when the sum reaches the limit. CPU seconds do not stretch
when the machine is loaded, so a planner gets the same search whatever runs beside it.
The *wall-clock limit* (``hard_limit``) is a safety for a child that waits without
computing (a sleeping script, a server that stopped answering).
"""

from __future__ import annotations

import multiprocessing
import os
import shutil
import signal
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import psutil

#: Outcome kinds of :func:`run_isolated`.
OK, RAISED, TIMEOUT, CRASHED = "ok", "raised", "timeout", "crashed"

_LOG_TAIL_CHARS = 2000


@dataclass
class Outcome:
    """What happened to an isolated call.

    ``kind`` is ``ok`` (``value`` holds the return value), ``raised`` (``value``
    holds ``"ExcType: message"``), ``timeout`` (killed at the CPU or the wall-clock limit: ``limit`` says which) or
    ``crashed`` (died without reporting; ``value`` says how). ``log_tail`` is the
    end of what the child wrote to stdout/stderr, ``pgid`` its process group.
    """

    kind: str
    value: Any
    wall_time: float
    pgid: int
    log_tail: str = ""
    #: CPU seconds of the group at the parent's last sample (None: no CPU limit was set)
    cpu_time: float | None = None
    #: which limit stopped a ``timeout``: "cpu" or "wall" (None otherwise)
    limit: str | None = None


def _watch_parent(parent_pid: int, private: str) -> None:
    """Kill our own process group as soon as the parent is gone, and remove the private
    folder, which the parent can no longer remove (a Ray worker killed mid-episode)."""
    while True:
        if os.getppid() != parent_pid:
            me = os.getpid()
            for pid in group_members(os.getpgid(0)):  # first the others: no new files
                if pid != me:
                    try:
                        os.kill(pid, signal.SIGKILL)
                    except OSError:
                        pass
            shutil.rmtree(private, ignore_errors=True)
            os.killpg(0, signal.SIGKILL)
        time.sleep(0.5)


def _child_main(conn: Any, log_path: str, parent_pid: int,
                fn: Callable[..., Any], args: tuple[Any, ...]) -> None:
    os.setpgid(0, 0)
    private = os.path.dirname(log_path)
    threading.Thread(target=_watch_parent, args=(parent_pid, private), daemon=True).start()
    # Temporary files of the child and of the planners it starts (UP's PDDL folders, Aries'
    # server log, which it never deletes) go to the private folder the parent removes,
    # even when the group is killed at the time limit.
    tempfile.tempdir = private
    os.environ["TMPDIR"] = private
    # Planners print a lot (and some print from native code): send fds 1 and 2 to a file.
    log_fd = os.open(log_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    sys.stdout.flush()
    sys.stderr.flush()
    os.dup2(log_fd, 1)
    os.dup2(log_fd, 2)
    try:
        result = (OK, fn(*args))
    except BaseException as exc:  # noqa: BLE001 - everything must be reported, not lost
        result = (RAISED, f"{type(exc).__name__}: {exc}")
    try:
        conn.send(result)
    except Exception as exc:  # noqa: BLE001 - an unpicklable value is a bug in the caller
        conn.send((RAISED, f"result could not be sent back: {type(exc).__name__}: {exc}"))
    conn.close()


def group_alive(pgid: int) -> bool:
    """True if any process of group ``pgid`` still exists (zombies excluded)."""
    return bool(group_members(pgid))


def _group_processes(pgid: int) -> list[psutil.Process]:
    """The processes (zombies included) whose process group is ``pgid``.

    psutil has no process-group field, so each candidate is asked with ``os.getpgid``;
    a process that ends while we look is simply not in the answer."""
    found = []
    for proc in psutil.process_iter():
        try:
            if os.getpgid(proc.pid) == pgid:
                found.append(proc)
        except OSError:  # gone (ProcessLookupError) or not ours to ask
            continue
    return found


def group_members(pgid: int) -> list[int]:
    """PIDs of the live (non-zombie) processes whose process group is ``pgid``."""
    live = []
    for proc in _group_processes(pgid):
        try:
            if proc.status() != psutil.STATUS_ZOMBIE:
                live.append(proc.pid)
        except psutil.Error:  # ended in between
            continue
    return live


def group_cpu_seconds(pgid: int, exclude: tuple[int, ...] = ()) -> float:
    """CPU seconds (user + system) used so far by the processes of group ``pgid``,
    zombies included, except ``exclude``: for planner servers nobody waits for."""
    total = 0.0
    for proc in _group_processes(pgid):
        if proc.pid in exclude:
            continue
        try:
            times = proc.cpu_times()
        except psutil.Error:  # reaped in between: its time went to its parent's children
            continue
        total += times.user + times.system
    return total


def group_tree_cpu_seconds(pgid: int) -> float:
    """CPU seconds (user + system) of group ``pgid`` as a whole: every member's own time
    plus the time of the children it has reaped (which were members too, so nothing is
    counted twice). This is the number :func:`run_isolated`'s CPU limit compares."""
    total = 0.0
    for proc in _group_processes(pgid):
        try:
            times = proc.cpu_times()
        except psutil.Error:  # reaped in between: its time went to its parent's children
            continue
        total += times.user + times.system + times.children_user + times.children_system
    return total


def kill_group(pgid: int, wait: float = 2.0) -> bool:
    """SIGKILL every process in group ``pgid``; wait until gone. True if none is left."""
    deadline = time.monotonic() + wait
    while True:
        try:
            os.killpg(pgid, signal.SIGKILL)
        except ProcessLookupError:
            return True
        except PermissionError:  # the pgid was recycled by someone else's group
            return True
        if not group_alive(pgid):
            return True
        if time.monotonic() > deadline:
            return False
        time.sleep(0.02)


def run_isolated(fn: Callable[..., Any], args: tuple[Any, ...],
                 hard_limit: float | None, cpu_limit: float | None = None) -> Outcome:
    """Call ``fn(*args)`` in a forked child that leads its own process group.

    The child is killed (with its whole group) once the group has used ``cpu_limit`` CPU
    seconds (None: no CPU limit), or after ``hard_limit`` seconds of wall time (None: no
    limit), whichever comes first. Whatever happens, the group is killed before this
    returns, so no planner process outlives the call.
    """
    if sys.platform == "win32":  # pragma: no cover - the project targets Linux
        raise OSError("isolated planner runs need fork and process groups (Linux/macOS)")
    # one private folder for the child's log and temporary files, removed whatever happens
    with tempfile.TemporaryDirectory(prefix="ocplus-planner-") as private:
        return _run_child(fn, args, hard_limit, cpu_limit,
                          os.path.join(private, "child.log"))


def _run_child(fn: Callable[..., Any], args: tuple[Any, ...], hard_limit: float | None,
               cpu_limit: float | None, log_path: str) -> Outcome:
    ctx = multiprocessing.get_context("fork")
    recv, send = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=_child_main, args=(send, log_path, os.getpid(), fn, args),
                       daemon=False)
    start = time.perf_counter()
    proc.start()
    send.close()
    pgid = proc.pid
    try:
        os.setpgid(pgid, pgid)  # also done by the child: whoever runs first wins the race
    except OSError:
        pass
    try:
        kind, value, used, limit = _wait(recv, proc, pgid, start, hard_limit, cpu_limit)
        wall = time.perf_counter() - start
    finally:
        kill_group(pgid)
        proc.join(2.0)
        recv.close()
    return Outcome(kind, value, wall, pgid, _read_tail(log_path), used, limit)


def _wait(recv: Any, proc: Any, pgid: int, start: float, hard_limit: float | None,
          cpu_limit: float | None) -> tuple[str, Any, float | None, str | None]:
    """Wait for the child's report, sampling the group's CPU seconds when a CPU limit is
    set: (kind, value, CPU seconds at the last sample, the limit that stopped it)."""
    deadline = float("inf") if hard_limit is None else start + hard_limit
    used: float | None = None if cpu_limit is None else 0.0
    cores = max(1, os.cpu_count() or 1)
    while True:
        left = deadline - time.perf_counter()
        wait: float | None = None if left == float("inf") else max(0.0, left)
        if cpu_limit is not None and used is not None:
            # the group cannot use more than `cores` CPU seconds per second: sample no later
            # than the earliest moment it could reach the limit (at least every 0.25 s)
            step = min(0.25, max(0.02, (cpu_limit - used) / cores))
            wait = step if wait is None else min(wait, step)
        if recv.poll(wait):
            try:
                kind, value = recv.recv()
            except EOFError:
                proc.join(1.0)
                kind, value = CRASHED, _death_reason(proc.exitcode)
            return kind, value, used, None
        if cpu_limit is not None:
            used = group_tree_cpu_seconds(pgid)
            if used >= cpu_limit:
                return (TIMEOUT, f"stopped at the CPU limit of {cpu_limit:g} s "
                        f"({used:.2f} CPU s used in {time.perf_counter() - start:.2f} s)",
                        used, "cpu")
        if time.perf_counter() >= deadline:
            return (TIMEOUT, f"killed at the wall-clock safety limit of {hard_limit:g} s"
                    + ("" if used is None else f" ({used:.2f} CPU s used)"), used, "wall")


def _death_reason(exitcode: int | None) -> str:
    if exitcode is None:
        return "the planner process stopped answering"
    if exitcode < 0:
        try:
            name = signal.Signals(-exitcode).name
        except ValueError:
            name = str(-exitcode)
        hint = " (out of memory?)" if -exitcode == signal.SIGKILL else ""
        return f"the planner process was killed by {name}{hint}"
    return f"the planner process exited with code {exitcode} without a result"


def _read_tail(path: str) -> str:
    try:
        with open(path, "rb") as fh:
            fh.seek(0, os.SEEK_END)
            fh.seek(max(0, fh.tell() - _LOG_TAIL_CHARS * 4))
            return fh.read().decode("utf-8", errors="replace")[-_LOG_TAIL_CHARS:]
    except OSError:
        return ""
