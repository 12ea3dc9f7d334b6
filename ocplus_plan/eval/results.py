"""Result files of an evaluation: ``results.jsonl``, ``summary.csv``, the leaderboard.

``results.jsonl`` has one JSON object per episode (or per skipped configuration),
appended and flushed as soon as it is known, so an interrupted run keeps everything
finished so far. Each row has ``key`` (what identifies the episode for ``--resume``),
``status`` (``ok``, ``error`` or ``skipped``), ``reason`` (for the latter two), the
configuration (``preset``, ``map``, ``n_agents``, ``agent``, ``seed``, ``horizon``),
``metrics``, ``timings`` and ``controller`` (the controller's ``info()``); an episode run
with ``--faults`` adds ``faults`` (the text, part of the key) and ``fault_report`` (what
the faults did: burns and switches applied, messages lost, the blocker's moves).
"""

from __future__ import annotations

import contextlib
import csv
import json
import math
import os
import stat
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import ConfigError
from .metrics import controller_metrics

RESULTS_FILE = "results.jsonl"
SUMMARY_FILE = "summary.csv"
CONFIG_FILE = "config.json"
LOCK_FILE = ".ocplus-eval.lock"

#: the configuration fields that, with the seed, identify an episode
GROUP_FIELDS: tuple[str, ...] = ("preset", "map", "n_agents", "agent", "horizon")
#: summary.csv columns reported as mean and 95% confidence half-width
SUMMARY_METRICS: tuple[str, ...] = (
    "dishes_served", "completion_rate", "reward", "reward_trend", "steps_per_order",
    "order_latency_mean", "burns", "wrong_deliveries", "moves_blocked", "replans",
    "planning_time_s", "decision_time_s", "wall_time_s",
)

# two-sided 97.5% quantiles of Student's t for 1..30 degrees of freedom
_T975 = (12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179,
         2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064,
         2.060, 2.056, 2.052, 2.048, 2.045, 2.042)


def episode_key(row: dict[str, Any]) -> str:
    """A stable text key of one episode's configuration and seed (and faults, if any)."""
    parts = [str(row.get(f)) for f in GROUP_FIELDS] + [str(row.get("seed"))]
    if row.get("faults"):
        parts.append(f"faults={row['faults']}")
    return "|".join(parts)


def mean_ci(values: Sequence[float]) -> tuple[float | None, float | None]:
    """Mean and half-width of the 95% confidence interval (Student's t); None when empty."""
    xs = [float(v) for v in values if v is not None]
    n = len(xs)
    if n == 0:
        return None, None
    mean = sum(xs) / n
    if n == 1:
        return mean, 0.0
    sd = math.sqrt(sum((x - mean) ** 2 for x in xs) / (n - 1))
    t = _T975[n - 2] if n - 1 <= len(_T975) else 1.96
    return mean, t * sd / math.sqrt(n)


class ResultsWriter:
    """Appends rows to ``results.jsonl`` (one line each, flushed at once)."""

    def __init__(self, out_dir: Path) -> None:
        self.path = Path(out_dir) / RESULTS_FILE
        self._fh = self.path.open("a", encoding="utf-8")

    def write(self, row: dict[str, Any]) -> None:
        try:
            self._fh.write(json.dumps(row, default=_json_default) + "\n")
            self._fh.flush()
            os.fsync(self._fh.fileno())
        except OSError as exc:  # a full or read-only filesystem: one line, rows kept
            raise ConfigError(f"cannot write {self.path}: {exc.strerror}; free some space "
                              "and continue with --resume") from None

    def close(self) -> None:
        self._fh.close()

    def __enter__(self) -> ResultsWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _json_default(obj: Any) -> Any:
    if hasattr(obj, "item"):  # numpy scalars
        return obj.item()
    if isinstance(obj, (set, frozenset, tuple)):
        return list(obj)
    return str(obj)


#: a row of ``results.jsonl`` longer than this is skipped as bad (real rows are < 20 kB)
MAX_ROW_BYTES = 1 << 20
#: a ``results.jsonl`` larger than this is refused (about 100,000 episodes of rows)
MAX_RESULTS_BYTES = 256 << 20
STATUSES = ("ok", "error", "skipped")
_TEXT = (str,)
_FIELD_TYPES: dict[str, tuple[type, ...]] = {
    "key": _TEXT, "status": _TEXT, "preset": _TEXT, "agent": _TEXT, "map": (str, type(None)),
    "n_agents": (int,), "seed": (int, type(None)), "horizon": (int, type(None)),
}
_OPTIONAL_TYPES: dict[str, tuple[type, ...]] = {
    "reason": _TEXT, "faults": _TEXT, "partner": _TEXT, "map_source": _TEXT,
    "metrics": (dict,), "timings": (dict,), "controller": (dict,), "planner": (dict,),
    "rules": (dict,), "worker": (dict,), "fault_report": (dict,),
}


@dataclass
class ResultsFile:
    """What :func:`scan_results` found: the trusted rows and the lines it skipped."""

    path: Path
    rows: list[dict[str, Any]] = field(default_factory=list)
    #: (line number, why) of every line skipped as bad; a torn last line is among them
    bad: list[tuple[int, str]] = field(default_factory=list)

    def note(self) -> str | None:
        """One line about the skipped lines, or None when every line was a good row."""
        if not self.bad:
            return None
        shown = "; ".join(f"line {n}: {why}" for n, why in self.bad[:3])
        more = f"; and {len(self.bad) - 3} more" if len(self.bad) > 3 else ""
        return f"{self.path}: skipped {len(self.bad)} bad row(s) ({shown}{more})"


def results_path(path: str | os.PathLike[str]) -> Path:
    """``results.jsonl`` of a folder, or the file itself."""
    p = Path(path)
    return p / RESULTS_FILE if p.is_dir() else p


def row_problem(row: Any) -> str | None:
    """Why a parsed line is not a row this package wrote (None when it is one). The key
    must be the one its own configuration gives, so a row cannot claim another episode."""
    if not isinstance(row, dict):
        return f"a JSON {type(row).__name__}, not an object"
    for name, types in _FIELD_TYPES.items():
        if name not in row:
            return f"no {name!r}"
        value = row[name]
        if not isinstance(value, types) or isinstance(value, bool):
            return f"{name!r} is a {type(value).__name__}"
    for name, types in _OPTIONAL_TYPES.items():
        if name in row and not isinstance(row[name], types):
            return f"{name!r} is a {type(row[name]).__name__}"
    if row["status"] not in STATUSES:
        return f"status {row['status'][:40]!r} is not one of {', '.join(STATUSES)}"
    for section in ("metrics", "planner", "timings"):
        for k, v in (row.get(section) or {}).items():
            if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float))):
                if section != "planner" and k in SUMMARY_METRICS:
                    return f"{section}.{k} is not a number"
    if row["key"] != row_key(row):
        return "its key does not match its preset, map, cooks, agent, horizon and seed"
    return None


def row_key(row: dict[str, Any]) -> str:
    """The key the runner gives a row with these fields (:meth:`EpisodeSpec.row_base`)."""
    return episode_key(row) + "".join(f"|{k}={v}" for k, v in (row.get("rules") or {}).items())


def _open_regular(p: Path) -> int:
    """A read-only descriptor of ``p``, which must be a regular file within the limit
    (opened without blocking, so a FIFO is refused, never waited on)."""
    try:
        fd = os.open(p, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_NOCTTY", 0))
    except FileNotFoundError:
        raise ConfigError(f"no results found: {p} does not exist; run `ocplus eval --out DIR` "
                          "first or point at a folder that holds results.jsonl") from None
    except OSError as exc:
        raise ConfigError(f"cannot read {p}: {exc.strerror}") from None
    st = os.fstat(fd)
    why = None if stat.S_ISREG(st.st_mode) else "is not a regular file"
    if why is None and st.st_size > MAX_RESULTS_BYTES:
        why = f"is {st.st_size} bytes; the limit is {MAX_RESULTS_BYTES}"
    if why:
        os.close(fd)
        raise ConfigError(f"{p} {why}; point at a folder written by `ocplus eval --out DIR`")
    return fd


def scan_results(path: str | os.PathLike[str]) -> ResultsFile:
    """Read a ``results.jsonl`` (a folder holding one, or the file itself) within the limits
    above. Every line that is not a valid row (not UTF-8, not JSON, nested too deep, too
    long, not an object, fields of the wrong type, a key that its fields do not give) is
    skipped and counted with its line number; none is fatal."""
    p = results_path(path)
    found = ResultsFile(p)
    with os.fdopen(_open_regular(p), "rb") as fh:
        for number, raw, long in _lines(fh):
            if long:
                found.bad.append((number, f"longer than {MAX_ROW_BYTES} bytes"))
                continue
            if not raw.strip():
                continue
            try:
                row = json.loads(raw.decode("utf-8"))
            except UnicodeDecodeError:
                found.bad.append((number, "not UTF-8"))
                continue
            except RecursionError:
                found.bad.append((number, "nested too deeply"))
                continue
            except ValueError as exc:
                found.bad.append((number, f"not JSON ({str(exc)[:60]})"))
                continue
            problem = row_problem(row)
            if problem:
                found.bad.append((number, problem))
            else:
                found.rows.append(row)
    return found


def _lines(fh: Any) -> Iterator[tuple[int, bytes, bool]]:
    """(line number, bytes, too long) for each line; a long line is not kept in memory."""
    number = 0
    while True:
        raw = fh.readline(MAX_ROW_BYTES + 1)
        if not raw:
            return
        number += 1
        long = len(raw) > MAX_ROW_BYTES
        while long and not raw.endswith(b"\n"):
            raw = fh.readline(MAX_ROW_BYTES + 1)
            if not raw:
                break
        yield number, (b"" if long else raw), long


def read_results(path: str | os.PathLike[str]) -> list[dict[str, Any]]:
    """The trusted rows of a ``results.jsonl`` (see :func:`scan_results`)."""
    return scan_results(path).rows


def repair_torn_tail(path: Path) -> bool:
    """Before appending: a last line without its newline (a run killed mid-write) is cut
    off, or, when it is a whole row, given its newline. True if the file was changed.
    Reads at most one row's length back from the end."""
    with open(path, "r+b") as fh:
        size = fh.seek(0, os.SEEK_END)
        if size == 0:
            return False
        fh.seek(size - 1)
        if fh.read(1) == b"\n":
            return False
        start = max(0, size - MAX_ROW_BYTES - 1)
        fh.seek(start)
        tail = fh.read()
        cut = tail.rfind(b"\n")
        keep = start + cut + 1 if cut >= 0 else (0 if start == 0 else None)
        if keep is None:  # a torn line longer than a row: find where it started
            keep = _last_newline_before(fh, start) + 1
        last = tail[keep - start:] if keep >= start else b""
        try:
            whole = row_problem(json.loads(last.decode("utf-8"))) is None
        except (ValueError, RecursionError):
            whole = False
        if whole:
            fh.write(b"\n")
        else:
            fh.truncate(keep)
        return True


def _last_newline_before(fh: Any, end: int) -> int:
    """The offset of the last newline before ``end`` (-1 when there is none)."""
    while end > 0:
        start = max(0, end - (1 << 16))
        fh.seek(start)
        chunk = fh.read(end - start)
        i = chunk.rfind(b"\n")
        if i >= 0:
            return start + i
        end = start
    return -1


@contextlib.contextmanager
def folder_lock(out: Path) -> Iterator[None]:
    """Hold ``out/.ocplus-eval.lock`` (``flock``) while a run writes ``out``; a second run
    on the same folder is refused at once. The kernel drops the lock when the holder
    dies, whatever killed it."""
    import fcntl

    out.mkdir(parents=True, exist_ok=True)
    lock = out / LOCK_FILE
    fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise ConfigError(f"output folder {out} is being written by another run (it "
                              f"holds {lock}); wait for it to end or choose another "
                              "--out") from None
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        try:
            yield
        finally:
            with contextlib.suppress(OSError):
                lock.unlink()
    finally:
        os.close(fd)


def latest_rows(rows: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
    """One row per key, the last one written (a resumed run may redo an episode)."""
    by_key: dict[str, dict[str, Any]] = {}
    for row in rows:
        if isinstance(row.get("controller"), dict):  # re-derive: the raw info is the source
            row["planner"] = controller_metrics(row["controller"])
        by_key[row.get("key") or episode_key(row)] = row
    return list(by_key.values())


def summarise(rows: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
    """One summary per (preset, map, n_agents, agent, horizon): counts, means and 95% CIs."""
    groups: dict[tuple, list[dict[str, Any]]] = {}
    for row in latest_rows(rows):
        gkey = tuple(row.get(f) for f in GROUP_FIELDS) + (row.get("faults") or "",)
        groups.setdefault(gkey, []).append(row)
    out = []
    for gkey, members in groups.items():
        ok = [r for r in members if r.get("status") == "ok"]
        s: dict[str, Any] = dict(zip(GROUP_FIELDS, gkey))
        if gkey[-1]:
            s["faults"] = gkey[-1]
        s["episodes"] = len(ok)
        s["errors"] = sum(1 for r in members if r.get("status") == "error")
        s["skipped"] = sum(1 for r in members if r.get("status") == "skipped")
        reasons = sorted({r.get("reason", "") for r in members if r.get("status") != "ok"})
        s["reason"] = "; ".join(x for x in reasons if x)
        for name in SUMMARY_METRICS:
            vals = [_metric(r, name) for r in ok]
            mean, ci = mean_ci([v for v in vals if v is not None])
            s[f"{name}_mean"] = mean
            s[f"{name}_ci95"] = ci
        out.append(s)
    out.sort(key=lambda s: (str(s["preset"]), s["dishes_served_mean"] is None,
                            -(s["dishes_served_mean"] or 0.0), str(s["agent"]),
                            s.get("faults", "")))
    return out


def _metric(row: dict[str, Any], name: str) -> float | None:
    for section in ("metrics", "planner", "timings"):
        d = row.get(section) or {}
        if name in d:
            v = d[name]
            return None if v is None else float(v)
    return None


def write_summary(summary: list[dict[str, Any]], path: str | os.PathLike[str]) -> Path:
    """Write the summaries as CSV (numbers rounded to 4 decimals)."""
    p = Path(path)
    fields = list(GROUP_FIELDS) + (["faults"] if any("faults" in s for s in summary) else [])
    fields += ["episodes", "errors", "skipped"]
    fields += [f"{m}_{s}" for m in SUMMARY_METRICS for s in ("mean", "ci95")] + ["reason"]
    try:
        with p.open("w", newline="", encoding="utf-8") as fh:
            w = csv.DictWriter(fh, fieldnames=fields)
            w.writeheader()
            for s in summary:
                w.writerow({k: (round(v, 4) if isinstance(v, float) else v)
                            for k, v in s.items() if k in fields})
    except OSError as exc:
        raise ConfigError(f"cannot write {p}: {exc.strerror}") from None
    return p


def _fmt(mean: float | None, ci: float | None, digits: int = 1) -> str:
    if mean is None:
        return "-"
    return f"{mean:.{digits}f} ± {ci or 0:.{digits}f}"


def _label(s: dict[str, Any]) -> str:
    """The agent's name in the leaderboard, with its faults if any."""
    return str(s["agent"]) + (f" [{s['faults']}]" if s.get("faults") else "")


def leaderboard(summary: list[dict[str, Any]]) -> str:
    """A terminal table per preset: agents ranked by dishes served (mean ± 95% CI)."""
    lines = []
    header = (f"  {'#':>2} {'agent':28s} {'n':>3} {'dishes':>13} {'completion':>11} "
              f"{'reward':>17} {'steps/order':>13} {'burns':>6} {'wrong':>6} {'think s':>8}")
    presets = sorted({str(s["preset"]) for s in summary},
                     key=lambda p: (["easy", "medium", "hard"] + [p]).index(p))
    for preset in presets:
        rows = [s for s in summary if str(s["preset"]) == preset]
        maps = sorted({f"{s['map']}, {s['n_agents']} agent(s)" for s in rows})
        lines.append(f"{preset}  ({'; '.join(maps)})")
        lines.append(header)
        rank = 0
        for s in rows:
            if not s["episodes"]:
                continue
            rank += 1
            comp = s["completion_rate_mean"]
            plan = s["planning_time_s_mean"] or s["decision_time_s_mean"] or 0.0
            err = f"  ({s['errors']} error(s))" if s["errors"] else ""
            lines.append(
                f"  {rank:>2} {_label(s):28s} {s['episodes']:>3} "
                f"{_fmt(s['dishes_served_mean'], s['dishes_served_ci95']):>13} "
                f"{(f'{comp:.0%}' if comp is not None else '-'):>11} "
                f"{_fmt(s['reward_mean'], s['reward_ci95']):>17} "
                f"{_fmt(s['steps_per_order_mean'], s['steps_per_order_ci95']):>13} "
                f"{s['burns_mean'] or 0:>6.2f} {s['wrong_deliveries_mean'] or 0:>6.2f} "
                f"{plan:>8.2f}{err}")
        for s in rows:
            if not s["episodes"]:
                what = "skipped" if s["skipped"] else "failed"
                lines.append(f"   - {_label(s):28s} {what}: {s['reason']}")
        lines.append("")
    return "\n".join(lines).rstrip() + "\n"


__all__ = [
    "CONFIG_FILE",
    "GROUP_FIELDS",
    "LOCK_FILE",
    "MAX_RESULTS_BYTES",
    "MAX_ROW_BYTES",
    "ResultsFile",
    "RESULTS_FILE",
    "ResultsWriter",
    "SUMMARY_FILE",
    "SUMMARY_METRICS",
    "episode_key",
    "latest_rows",
    "leaderboard",
    "mean_ci",
    "folder_lock",
    "read_results",
    "repair_torn_tail",
    "row_problem",
    "scan_results",
    "summarise",
    "write_summary",
]
