"""Do engines stop at their limit, does SIGTERM end a command, and is anything left behind?

Four parts, each one JSON line per run in ``--out`` (with the commit, the machine and the
load average), and a summary line per part at the end:

``limits``
    every registered engine (``--engines``, default all) on hard's initial state with 2
    cooks, ``ocplus solve --preset hard --n-agents 2 --seed 4 --timeout 10 --json``:
    alone, then beside ``--busy`` processes that spin on the CPU. Recorded: the status,
    the engine group's CPU seconds as the limit counts them (``cpu_time``), the CPU
    seconds of the whole command (import, compile, engine, validation; from
    ``getrusage``), wall seconds. Target: the engine stops within 12 CPU s.
``sigterm``
    ``--tries`` runs of the same command per engine, each sent SIGTERM at a random moment
    (uniform in 0.5-8 s after the start; seeded by ``--seed``). Target: the command and
    every process it started gone within 5 s. On a loaded machine most of these land
    before the engine starts (importing and compiling take longer), so:
``sigterm-engine``
    the same, with the moment drawn once the engine's process exists: uniform in 0-12 s
    after it appears.
``leftovers``
    runs whose children start a process in a new session (``setsid sleep``): a planner
    binary under ``solve``, an ``llm:`` function under ``eval --jobs 1``, and ``eval``
    killed with SIGTERM mid-episode. Target: 0 processes 5 s after the run ends.
``ray``
    ``eval --backend ray`` killed with ``kill -9`` once Ray's agents are up. Target: none of
    its processes and no ``ocray-*`` folder of it 5 s later.

This script makes itself a subreaper (``PR_SET_CHILD_SUBREAPER``), so whatever a run
leaves behind is re-parented to it and counted. CPU-hungry: run it niced, e.g.::

    nice -n 10 .venv/bin/python experiments/bench_engine_limits.py --tries 5 \\
        --out experiments/results/engine-limits/outcomes.jsonl
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import random
import resource
import signal
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

import psutil

ROOT = Path(__file__).resolve().parents[1]
OCPLUS = [sys.executable, "-m", "ocplus_plan.cli"]
SOLVE = ["solve", "--preset", "hard", "--n-agents", "2", "--seed", "4", "--timeout", "10",
         "--json"]
GRACE_S = 5.0
SETSID_PLANNER = "#!/bin/sh\nsetsid sleep 987.5 &\nexit 0\n"
SETSID_MODEL = textwrap.dedent("""
    import subprocess
    def ask(prompt):
        subprocess.Popen(["setsid", "sleep", "987.5"])
        return "stay"
""")


def _context() -> dict[str, object]:
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                            capture_output=True, text=True).stdout.strip()
    return {"commit": commit, "machine": f"{platform.machine()}, 2 shared cores",
            "load_1min": round(os.getloadavg()[0], 2)}


def _become_subreaper() -> None:
    sys.path.insert(0, str(ROOT))
    from ocplus_plan.planning._proc import set_subreaper

    if not set_subreaper(True):
        raise SystemExit("this benchmark needs Linux (PR_SET_CHILD_SUBREAPER)")


def _left_after(seconds: float, exclude: set[int]) -> list[str]:
    """Our descendants (orphans included) still alive ``seconds`` after a run, reaped."""
    deadline = time.monotonic() + seconds
    while True:
        left = []
        for p in psutil.Process().children(recursive=True):
            try:
                if p.pid in exclude:
                    continue
                if p.status() == psutil.STATUS_ZOMBIE:
                    if p.ppid() == os.getpid():
                        os.waitpid(p.pid, os.WNOHANG)
                    continue
                left.append(f"{p.pid} {' '.join(p.cmdline())[:120]}")
            except (psutil.Error, ChildProcessError):
                continue
        if not left or time.monotonic() >= deadline:
            return left
        time.sleep(0.2)


def _cleanup(exclude: set[int]) -> None:
    for p in psutil.Process().children(recursive=True):
        if p.pid not in exclude:
            try:
                p.kill()
            except psutil.Error:
                pass
    _left_after(1.0, exclude)


def _engine_started(pid: int, limit: float) -> float | None:
    """Wait until the command ``pid`` has a forked child (for ``solve``: the engine's
    isolated child, forked once the problem is compiled); seconds waited, None if the
    command ended first or ``limit`` passed."""
    t0 = time.perf_counter()
    while time.perf_counter() - t0 < limit:
        try:
            command = psutil.Process(pid)
            if command.status() == psutil.STATUS_ZOMBIE:
                return None
            line = command.cmdline()
            kids = command.children()
        except psutil.Error:
            return None
        for kid in kids:  # the engine's child is a fork: the same command
            try:                          # line (a probe the command runs has another)
                if kid.cmdline() == line:
                    return time.perf_counter() - t0
            except psutil.Error:
                continue
        time.sleep(0.05)
    return None


def _run(argv: list[str], env: dict[str, str] | None = None,
         term_after: float | None = None, sig: int = signal.SIGTERM,
         cwd: Path = ROOT, after_engine: bool = False) -> dict[str, object]:
    """Run one command; with ``term_after`` send it ``sig`` then (``after_engine``: that
    long after its first child process appeared). CPU seconds of the command and what it
    waited for, wall seconds, its exit code and JSON output."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.Popen(argv, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=env)
    ended_in = None
    engine_at = _engine_started(proc.pid, 600) if after_engine else 0.0
    if term_after is not None and engine_at is not None:
        try:
            proc.wait(term_after)
        except subprocess.TimeoutExpired:
            proc.send_signal(sig)
            t_sig = time.perf_counter()
            try:
                proc.wait(60)
            except subprocess.TimeoutExpired:
                proc.kill()
            ended_in = round(time.perf_counter() - t_sig, 3)
    out, err = proc.communicate()
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    row: dict[str, object] = {
        "code": proc.returncode, "wall_s": round(wall, 3),
        "command_cpu_s": round(after.ru_utime - before.ru_utime
                               + after.ru_stime - before.ru_stime, 3),
        "stderr_tail": err.strip()[-200:]}
    if ended_in is not None:
        row["ended_s_after_signal"] = ended_in
    if after_engine and engine_at is not None:
        row["engine_started_s"] = round(engine_at, 3)
    try:
        row["json"] = json.loads(out)
    except ValueError:
        pass
    return row


def _busy(n: int) -> list[subprocess.Popen[bytes]]:
    return [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(n)]


def part_limits(engines: list[str], busy: int, emit) -> None:
    for phase, n_busy in (("alone", 0), (f"beside {busy} busy", busy)):
        spinners = _busy(n_busy)
        keep = {p.pid for p in spinners}
        try:
            for engine in engines:
                row = _run([*OCPLUS, *SOLVE, "--planner", engine])
                result = row.pop("json", {}) or {}
                row.update(part="limits", phase=phase, engine=engine,
                           status=result.get("status"), cpu_time=result.get("cpu_time"),
                           limit_hit=result.get("limit_hit"),
                           engine_wall_s=result.get("wall_time"))
                row["left_after_5s"] = _left_after(GRACE_S, keep)
                _cleanup(keep)
                emit(row)
        finally:
            for p in spinners:
                p.kill()
                p.wait()


def part_sigterm(engines: list[str], tries: int, rng: random.Random, emit) -> None:
    for engine in engines:
        for k in range(tries):
            at = round(rng.uniform(0.5, 8.0), 2)
            row = _run([*OCPLUS, *SOLVE, "--planner", engine], term_after=at)
            row.pop("json", None)
            row.update(part="sigterm", engine=engine, attempt=k, signal_at_s=at)
            row["left_after_5s"] = _left_after(GRACE_S, set())
            _cleanup(set())
            emit(row)


def part_sigterm_engine(engines: list[str], tries: int, rng: random.Random, emit) -> None:
    for engine in engines:
        for k in range(tries):
            at = round(rng.uniform(0.0, 12.0), 2)
            row = _run([*OCPLUS, *SOLVE, "--planner", engine], term_after=at,
                       after_engine=True)
            result = row.pop("json", None) or {}
            row.update(part="sigterm-engine", engine=engine, attempt=k,
                       signal_after_engine_start_s=at, status=result.get("status"))
            row["left_after_5s"] = _left_after(GRACE_S, set())
            _cleanup(set())
            emit(row)


def part_leftovers(emit) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        script = work / "setsid_planner.sh"
        script.write_text(SETSID_PLANNER)
        script.chmod(0o755)
        (work / "setsid_planner.yaml").write_text(
            f"name: setsid-planner\ncommand: [{str(script)!r}, '{{domain}}', '{{problem}}',"
            " '{plan}']\nencoding: classical\n")
        (work / "setsid_model.py").write_text(SETSID_MODEL)
        env = {**os.environ, "PYTHONPATH": f"{tmp}:{ROOT}"}
        runs = {
            "solve, planner binary runs setsid sleep": (
                [*OCPLUS, "solve", "--preset", "easy", "--planner",
                 str(work / "setsid_planner.yaml"), "--json"], None),
            "eval --jobs 1, llm: function runs setsid sleep": (
                [*OCPLUS, "eval", "--presets", "easy", "--agents", "llm:setsid_model:ask",
                 "--seeds", "2", "--horizon", "5", "--n-agents", "1", "--jobs", "1",
                 "--quiet", "--out", str(work / "run1")], None),
            "eval --jobs 1 planner:tamer on hard, SIGTERM at 6 s": (
                [*OCPLUS, "eval", "--presets", "hard", "--agents", "planner:tamer",
                 "--seeds", "1", "--horizon", "50", "--jobs", "1", "--quiet", "--out",
                 str(work / "run2")], 6.0),
            "eval --jobs 2 planner:fast-downward on hard, SIGINT at 6 s": (
                [*OCPLUS, "eval", "--presets", "hard", "--agents", "planner:fast-downward",
                 "--seeds", "2", "--horizon", "50", "--jobs", "2", "--quiet", "--out",
                 str(work / "run3")], 6.0),
        }
        for name, (argv, term_after) in runs.items():
            sig = signal.SIGINT if "SIGINT" in name else signal.SIGTERM
            row = _run(argv, env=env, term_after=term_after, sig=sig, cwd=work)
            row.pop("json", None)
            row.update(part="leftovers", run=name)
            row["left_after_5s"] = _left_after(GRACE_S, set())
            _cleanup(set())
            emit(row)


def part_ray(emit) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        before = set(Path("/tmp").glob("ocray-*"))
        argv = [*OCPLUS, "eval", "--backend", "ray", "--jobs", "1", "--presets", "easy",
                "--agents", "greedy", "--seeds", "50", "--horizon", "200", "--quiet",
                "--out", str(Path(tmp) / "run")]
        proc = subprocess.Popen(argv, cwd=tmp, stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)
        deadline = time.monotonic() + 120
        agents_up = False
        while time.monotonic() < deadline and proc.poll() is None and not agents_up:
            time.sleep(0.5)
            names = [p.name() for p in psutil.Process().children(recursive=True)]
            agents_up = any("RuntimeEnvAgent" in n or "DashboardAgent" in n for n in names) \
                and any(n.startswith("ray::") and "Agent" not in n for n in names)
        seen = [f"{p.pid} {p.name()}" for p in psutil.Process().children(recursive=True)]
        proc.kill()
        proc.wait()
        left = _left_after(GRACE_S, set())
        folders = sorted(str(f) for f in set(Path("/tmp").glob("ocray-*")) - before)
        _cleanup(set())
        emit({"part": "ray", "run": "eval --backend ray, kill -9 of the driver",
              "agents_were_up": agents_up, "processes_before_kill": len(seen),
              "left_after_5s": left, "folders_left_after_5s": folders})


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--parts", default="limits,sigterm,sigterm-engine,leftovers,ray")
    parser.add_argument("--engines", default="", help="comma-separated (default: all)")
    parser.add_argument("--tries", type=int, default=5, help="SIGTERM tries per engine")
    parser.add_argument("--busy", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path,
                        default=ROOT / "experiments/results/engine-limits/outcomes.jsonl")
    args = parser.parse_args()
    _become_subreaper()
    from ocplus_plan.planning.engines import planner_names

    engines = [e for e in args.engines.split(",") if e] or planner_names()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    rows: list[dict[str, object]] = []

    def emit(row: dict[str, object]) -> None:
        row.update(_context())
        rows.append(row)
        with args.out.open("a") as fh:
            fh.write(json.dumps(row) + "\n")
        print(json.dumps(row)[:300], flush=True)

    parts = args.parts.split(",")
    if "limits" in parts:
        part_limits(engines, args.busy, emit)
    if "sigterm" in parts:
        part_sigterm(engines, args.tries, random.Random(args.seed), emit)
    if "sigterm-engine" in parts:
        part_sigterm_engine(engines, args.tries, random.Random(args.seed), emit)
    if "leftovers" in parts:
        part_leftovers(emit)
    if "ray" in parts:
        part_ray(emit)
    _summary(rows)


def _summary(rows: list[dict[str, object]]) -> None:
    lim = [r for r in rows if r["part"] == "limits"]
    if lim:
        worst = max((r.get("cpu_time") or 0.0) for r in lim)
        over = [f"{r['engine']} ({r['phase']})" for r in lim if (r.get("cpu_time") or 0) > 12]
        print(json.dumps({"summary": "limits", "runs": len(lim), "max_engine_cpu_s": worst,
                          "over_12_cpu_s": over,
                          "max_command_cpu_s": max(r["command_cpu_s"] for r in lim),
                          "with_leftovers": sum(bool(r["left_after_5s"]) for r in lim)}))
    for name in ("sigterm", "sigterm-engine"):
        _summary_sigterm(name, [r for r in rows if r["part"] == name])
    for part in ("leftovers", "ray"):
        some = [r for r in rows if r["part"] == part]
        if some:
            print(json.dumps({"summary": part, "runs": len(some),
                              "with_leftovers": sum(bool(r["left_after_5s"])
                                                    or bool(r.get("folders_left_after_5s"))
                                                    for r in some)}))


def _summary_sigterm(name: str, term: list[dict[str, object]]) -> None:
    if term:
        signalled = [r for r in term if "ended_s_after_signal" in r]
        print(json.dumps({
            "summary": name, "tries": len(term), "signalled": len(signalled),
            "max_end_s": max((r["ended_s_after_signal"] for r in signalled), default=None),
            "over_5_s": sum(r["ended_s_after_signal"] > 5 for r in signalled),
            "with_leftovers": sum(bool(r["left_after_5s"]) for r in term)}))


if __name__ == "__main__":
    main()
