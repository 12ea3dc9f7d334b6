"""Run ``ocplus`` argument lists under an address-space and a time limit, one forked child
each, and report how each ended.

``python -m tests.fuzz.limited`` reads a JSON list of argument lists on stdin and writes one
JSON line per list: ``{"argv", "code", "stderr", "seconds", "cpu_seconds", "killed",
"vm_peak_mb", "max_rss_mb"}`` (``vm_peak_mb``: the child's largest address space). The command line
interface is imported once, before the forks, so a case costs milliseconds, not an
interpreter start. In the child, ``RLIMIT_AS`` caps the address space (a bigger allocation
fails with MemoryError, which would end in a traceback) and ``SIGALRM`` ends it after the
time limit (``killed``). An exception that escapes ``main`` prints its traceback to stderr
and exits 1, as the installed ``ocplus`` script would.
"""

from __future__ import annotations

import json
import os
import resource
import signal
import sys
import tempfile
import time
import traceback

#: the address space a hostile input may use (bytes)
ADDRESS_SPACE = 600 * 1024 * 1024
#: the wall time a hostile input may take (seconds)
SECONDS = 20


def _vm_peak_kb() -> int:
    """The largest address space this process has had (kB; 0 where /proc has no answer)."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmPeak:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return 0


def _child(argv: list[str], err_fd: int, peak_fd: int) -> None:
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)
    os.dup2(err_fd, 2)
    resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE, ADDRESS_SPACE))
    signal.alarm(SECONDS)
    code = 1
    try:
        from ocplus_plan.cli import main

        code = main(argv)
    except SystemExit as exc:  # argparse's exit 2
        code = exc.code if isinstance(exc.code, int) else 1
    except BaseException:  # noqa: BLE001 - the point is to see it
        traceback.print_exc()
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
        os.write(peak_fd, str(_vm_peak_kb()).encode())
        os._exit(code)


def run(argv: list[str]) -> dict[str, object]:
    """One argument list in a forked child under the limits; how it ended."""
    with tempfile.TemporaryFile() as err, tempfile.TemporaryFile() as peak:
        start = time.monotonic()
        pid = os.fork()
        if pid == 0:
            _child(argv, err.fileno(), peak.fileno())
        _, status, usage = os.wait4(pid, 0)
        seconds = time.monotonic() - start
        err.seek(0)
        stderr = err.read(20_000).decode("utf-8", "replace")
        peak.seek(0)
        vm_peak_kb = int(peak.read() or 0)
    killed = os.WIFSIGNALED(status)
    code = -os.WTERMSIG(status) if killed else os.WEXITSTATUS(status)
    return {"argv": argv, "code": code, "stderr": stderr, "seconds": round(seconds, 3),
            "cpu_seconds": round(usage.ru_utime + usage.ru_stime, 3), "killed": killed,
            "vm_peak_mb": round(vm_peak_kb / 1024, 1),
            "max_rss_mb": round(usage.ru_maxrss / 1024, 1)}


def main() -> None:
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    import ocplus_plan.cli  # noqa: F401 - imported once, shared by every fork
    import ocplus_plan.render.replay  # noqa: F401

    for argv in json.load(sys.stdin):
        print(json.dumps(run(argv)), flush=True)


if __name__ == "__main__":
    main()
