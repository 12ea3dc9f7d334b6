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

Neither limit depends on the child's cooperation. The parent samples and kills; as a
backstop the child also runs under ``RLIMIT_CPU`` (a little above the CPU limit: the
kernel ends it with SIGXCPU, then SIGKILL, even when its native code never returns to
Python); and the watchdog that ends the group when the parent dies is a separate
single-threaded process (forked by the child before the planner starts), not a thread
that a planner holding the GIL could starve. The child is a *subreaper*
(``PR_SET_CHILD_SUBREAPER``, Linux): a process that a planner starts in a new session
(``setsid``) and then abandons is re-parented to the child, not to init, so it is still
found among the child's descendants and killed with them.

:func:`reaping` does the same for a whole command (``ocplus solve``, ``ocplus eval``):
what is left of the processes started inside it is killed at its end, and
:func:`sigterm_exits` turns SIGTERM into ``SystemExit(143)`` so that every ``finally``
that kills a process group runs.
"""

from __future__ import annotations

import contextlib
import ctypes
import math
import multiprocessing
import os
import resource
import shutil
import signal
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

import psutil

#: Outcome kinds of :func:`run_isolated`.
OK, RAISED, TIMEOUT, CRASHED = "ok", "raised", "timeout", "crashed"

_LOG_TAIL_CHARS = 2000
#: seconds between two looks of the watchdog process at the child and its caller
WATCH_EVERY_S = 0.25
#: the watchdog remembers the process groups of the child's descendants every this many
#: looks (2 s), for the case where the child dies first and they lose their parent
SNAPSHOT_EVERY = 8
#: the kernel's CPU backstop (RLIMIT_CPU) lies this far above the CPU limit: a tenth of
#: it, at least this many seconds
BACKSTOP_MIN_S = 1.0
#: Linux prctl options
_PR_SET_CHILD_SUBREAPER, _PR_GET_CHILD_SUBREAPER = 36, 37
#: exit status of a command ended by SIGTERM (128 + 15, as a shell reports it)
SIGTERM_EXIT = 128 + signal.SIGTERM
#: wall seconds a command has after SIGTERM to run its own cleanup before it is ended
TERM_GRACE_S = 3.0
#: set once SIGTERM has been handled (see :func:`sigterm_exits`)
_EXITING = threading.Event()


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
    #: every process group of the call (the child's first), all killed before the return
    groups: tuple[int, ...] = ()


def _kill_groups(groups: set[int], own: int) -> None:
    """SIGKILL every group of ``groups`` but ``own`` (no error for one that is gone)."""
    for group in groups - {own}:
        try:
            os.killpg(group, signal.SIGKILL)
        except OSError:
            pass


def _watchdog(child: int, caller: int, private: str) -> None:
    """Body of the watchdog process (never returns): while the child lives and its parent
    is still ``caller``, remember the process groups of the child's descendants; once the
    child is gone or orphaned, kill those groups and the child's own, and remove the
    private folder, which a dead caller can no longer remove."""
    own = os.getpgid(0)
    seen: set[int] = set()
    tick = 0
    try:
        while True:
            try:
                proc = psutil.Process(child)  # one read of /proc/<child>/stat
                if proc.ppid() != caller or proc.status() == psutil.STATUS_ZOMBIE:
                    break
                if tick % SNAPSHOT_EVERY == 0:  # a scan of the process table: rarely,
                    seen |= descendant_groups(child)  # its CPU counts against the limit
            except psutil.Error:
                break
            tick += 1
            time.sleep(WATCH_EVERY_S)
        seen |= descendant_groups(os.getpid()) | descendant_groups(child)
        _kill_groups(seen, own)
        for pid in group_members(own):  # first the others: no new files
            if pid != os.getpid():
                with contextlib.suppress(OSError):
                    os.kill(pid, signal.SIGKILL)
        _kill_groups(descendant_groups(os.getpid()), own)
        shutil.rmtree(private, ignore_errors=True)
    finally:
        os.killpg(own, signal.SIGKILL)
        os._exit(0)


def _start_watchdog(caller: int, private: str) -> None:
    """Fork the watchdog process (same process group) of this child."""
    child = os.getpid()
    pid = os.fork()
    if pid == 0:  # the watchdog: nothing of the child's Python state is used
        try:
            _watchdog(child, caller, private)
        finally:
            os._exit(0)


def _cpu_backstop(cpu_limit: float | None) -> None:
    """Have the kernel stop this process a little after ``cpu_limit`` CPU seconds
    (RLIMIT_CPU: SIGXCPU at the soft limit, SIGKILL at the hard one)."""
    if cpu_limit is None:
        return
    soft = math.ceil(cpu_limit + max(BACKSTOP_MIN_S, 0.1 * cpu_limit))
    try:
        _, hard = resource.getrlimit(resource.RLIMIT_CPU)
        new_hard = soft + 2 if hard == resource.RLIM_INFINITY else min(hard, soft + 2)
        resource.setrlimit(resource.RLIMIT_CPU, (min(soft, new_hard), new_hard))
    except (OSError, ValueError):  # pragma: no cover - a stricter limit is already set
        pass


def _child_main(conn: Any, log_path: str, parent_pid: int,
                fn: Callable[..., Any], args: tuple[Any, ...],
                cpu_limit: float | None = None) -> None:
    os.setpgid(0, 0)
    private = os.path.dirname(log_path)
    _start_watchdog(parent_pid, private)
    set_subreaper(True)
    _cpu_backstop(cpu_limit)
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
    # Stay until the parent kills the group: a process abandoned by a planner (re-parented
    # to this subreaper) is then still a descendant that the parent finds and kills.
    deadline = time.monotonic() + 30.0
    while time.monotonic() < deadline and os.getppid() == parent_pid:
        time.sleep(0.1)


# ---------------------------------------------------------------- whole commands
def set_subreaper(on: bool = True) -> bool:
    """Make this process the subreaper of its descendants (Linux ``prctl``): orphans,
    ``setsid`` ones included, are re-parented to it instead of init. True if it worked."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        return int(libc.prctl(_PR_SET_CHILD_SUBREAPER, int(on), 0, 0, 0)) == 0
    except (OSError, AttributeError):  # pragma: no cover - no libc / no prctl
        return False


def is_subreaper() -> bool:
    """Whether this process is a subreaper (False where that cannot be known)."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        flag = ctypes.c_int(0)
        if libc.prctl(_PR_GET_CHILD_SUBREAPER, ctypes.byref(flag), 0, 0, 0) != 0:
            return False
        return bool(flag.value)
    except (OSError, AttributeError):  # pragma: no cover
        return False


def kill_new_descendants(before: set[int], wait: float = 3.0) -> list[int]:
    """SIGKILL the descendants of this process that are not in ``before`` (with their
    process groups, but never this process's own group), reap those that became its
    children, and return their pids."""
    me = os.getpid()
    own = os.getpgid(0)
    try:
        found = [p for p in psutil.Process(me).children(recursive=True) if p.pid not in before]
    except psutil.Error:  # pragma: no cover
        return []
    killed = []
    for proc in found:
        with contextlib.suppress(OSError):
            group = os.getpgid(proc.pid)
            if group != own:
                os.killpg(group, signal.SIGKILL)
            os.kill(proc.pid, signal.SIGKILL)
            killed.append(proc.pid)
    deadline = time.monotonic() + wait
    for proc in found:
        while time.monotonic() < deadline:
            try:
                if proc.ppid() == me:
                    os.waitpid(proc.pid, os.WNOHANG)
                if proc.status() == psutil.STATUS_ZOMBIE and proc.ppid() != me:
                    break
            except (psutil.Error, ChildProcessError):
                break
            time.sleep(0.02)
    return killed


@contextlib.contextmanager
def reaping() -> Iterator[None]:
    """Run a command's body as the subreaper of what it starts (where the kernel offers
    one); whatever of it is still alive at the end, ``setsid`` orphans included, is
    killed. Processes that existed before are left alone."""
    was = is_subreaper()
    became = was or set_subreaper(True)
    try:
        before = {p.pid for p in psutil.Process().children(recursive=True)}
    except psutil.Error:  # pragma: no cover
        before = set()
    try:
        yield
    finally:
        if became:
            kill_new_descendants(before)
        if became and not was:
            set_subreaper(False)


def _exit_later(grace: float) -> None:
    """In ``grace`` seconds, unless the process has ended by then: SIGKILL all its
    descendants (with their process groups) and exit 143. The exception a signal handler
    raises is lost when the signal lands in a finalizer or a callback (Python prints
    "Exception ignored in ..." and goes on); this thread ends the command anyway."""
    if _EXITING.is_set():
        return
    _EXITING.set()

    def later() -> None:
        time.sleep(grace)
        with contextlib.suppress(Exception):
            kill_new_descendants(set(), wait=1.0)
        os._exit(SIGTERM_EXIT)

    threading.Thread(target=later, name="sigterm-exit", daemon=True).start()


@contextlib.contextmanager
def sigterm_exits() -> Iterator[None]:
    """While inside, SIGTERM raises ``SystemExit(143)`` in the main thread, so that the
    ``finally`` blocks that kill process groups run (by default SIGTERM ends Python at
    once and leaves them behind); once they have, the process exits with 143 at once,
    without the interpreter's teardown. Should the exception be lost, or the cleanup take
    more than :data:`TERM_GRACE_S`, a thread kills every descendant and exits 143.
    Elsewhere than the main thread: nothing changes."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def on_sigterm(signum: int, frame: Any) -> None:
        _exit_later(TERM_GRACE_S)
        raise SystemExit(SIGTERM_EXIT)

    previous = signal.signal(signal.SIGTERM, on_sigterm)
    try:
        yield
    except SystemExit as exc:
        if exc.code != SIGTERM_EXIT:
            raise
        # the cleanup inside has run: end now, without the interpreter's teardown (a
        # second or more of CPU with the planners loaded; seconds of wall on a busy machine)
        with contextlib.suppress(Exception):
            sys.stdout.flush()
            sys.stderr.flush()
        os._exit(SIGTERM_EXIT)
    finally:
        signal.signal(signal.SIGTERM, previous)


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
    counted twice)."""
    return tree_cpu_seconds(pgid, {pgid})


def tree_cpu_seconds(leader: int, groups: set[int]) -> float:
    """CPU seconds (user + system) of the process groups in ``groups``, after adding to
    it the groups of every live descendant of ``leader``: the number
    :func:`run_isolated`'s CPU limit compares.

    unified-planning starts the planners it runs as programs (Fast Downward, SymK, ENHSP,
    LPG) in a session of their own, so their processes leave the child's group; they are
    still its descendants, and their groups are followed (and killed) too. Each member's
    own time is counted with the time of the children it has reaped (members too, so
    nothing is counted twice); one pass over the process table."""
    members: list[tuple[psutil.Process, int]] = []
    kids: dict[int, list[int]] = {}
    pgids: dict[int, int] = {}
    for proc in psutil.process_iter(["ppid"]):
        try:
            pgid = os.getpgid(proc.pid)
        except OSError:  # gone (ProcessLookupError) or not ours to ask
            continue
        pgids[proc.pid] = pgid
        kids.setdefault(proc.info["ppid"], []).append(proc.pid)
        members.append((proc, pgid))
    todo = list(kids.get(leader, ()))
    while todo:
        pid = todo.pop()
        groups.add(pgids[pid])
        todo.extend(kids.get(pid, ()))
    total = 0.0
    for proc, pgid in members:
        if pgid not in groups:
            continue
        try:
            times = proc.cpu_times()
        except psutil.Error:  # reaped in between: its time went to its parent's children
            continue
        total += times.user + times.system + times.children_user + times.children_system
    return total


def descendant_groups(pid: int) -> set[int]:
    """The process groups of the live descendants of ``pid`` (its own excluded)."""
    out = set()
    try:
        children = psutil.Process(pid).children(recursive=True)
    except psutil.Error:
        return out
    for child in children:
        try:
            out.add(os.getpgid(child.pid))
        except OSError:
            continue
    return out


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
    proc = ctx.Process(target=_child_main,
                       args=(send, log_path, os.getpid(), fn, args, cpu_limit), daemon=False)
    start = time.perf_counter()
    proc.start()
    send.close()
    pgid = proc.pid
    try:
        os.setpgid(pgid, pgid)  # also done by the child: whoever runs first wins the race
    except OSError:
        pass
    groups = {pgid}  # the child's group and those of the planners it starts (see above)
    try:
        kind, value, used, limit = _wait(recv, proc, groups, start, hard_limit, cpu_limit)
        wall = time.perf_counter() - start
    finally:
        groups |= descendant_groups(pgid)
        for group in sorted(groups - {pgid}):  # the planners first, then the child
            kill_group(group)
        kill_group(pgid)
        proc.join(2.0)
        recv.close()
    return Outcome(kind, value, wall, pgid, _read_tail(log_path), used, limit,
                   (pgid, *sorted(groups - {pgid})))


def _wait(recv: Any, proc: Any, groups: set[int], start: float, hard_limit: float | None,
          cpu_limit: float | None) -> tuple[str, Any, float | None, str | None]:
    """Wait for the child's report, sampling the CPU seconds of its process tree's groups
    (``groups`` grows as planners start in groups of their own) when a CPU limit is set:
    (kind, value, CPU seconds at the last sample, the limit that stopped it)."""
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
                if cpu_limit is not None and proc.exitcode == -signal.SIGXCPU:
                    return (TIMEOUT, "stopped by the kernel's CPU backstop (RLIMIT_CPU) "
                            f"past the CPU limit of {cpu_limit:g} s", used, "cpu")
                kind, value = CRASHED, _death_reason(proc.exitcode)
            return kind, value, used, None
        if cpu_limit is not None:
            used = tree_cpu_seconds(proc.pid, groups)
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
