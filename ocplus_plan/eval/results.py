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

import csv
import json
import math
import os
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

from ..errors import ConfigError
from .metrics import controller_metrics

RESULTS_FILE = "results.jsonl"
SUMMARY_FILE = "summary.csv"
CONFIG_FILE = "config.json"

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
        self._fh.write(json.dumps(row, default=_json_default) + "\n")
        self._fh.flush()
        os.fsync(self._fh.fileno())

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


def read_results(path: str | os.PathLike[str]) -> list[dict[str, Any]]:
    """Rows of a ``results.jsonl`` (a folder holding one, or the file itself).

    A truncated last line (a run killed mid-write) is ignored; any other broken line is
    a :class:`ConfigError` naming the line.
    """
    p = Path(path)
    if p.is_dir():
        p = p / RESULTS_FILE
    if not p.exists():
        raise ConfigError(f"no results found: {p} does not exist; run `ocplus eval --out DIR` "
                          "first or point at a folder that holds results.jsonl")
    rows = []
    lines = p.read_text(encoding="utf-8").splitlines()
    for i, line in enumerate(lines):
        if not line.strip():
            continue
        try:
            rows.append(json.loads(line))
        except json.JSONDecodeError as exc:
            if i == len(lines) - 1:
                break  # interrupted while writing the last row: it will be rerun
            raise ConfigError(f"{p}: line {i + 1} is not valid JSON ({exc}); "
                              "remove that line and run with --resume to redo it") from None
    return rows


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
    with p.open("w", newline="", encoding="utf-8") as fh:
        w = csv.DictWriter(fh, fieldnames=fields)
        w.writeheader()
        for s in summary:
            w.writerow({k: (round(v, 4) if isinstance(v, float) else v) for k, v in s.items()
                        if k in fields})
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
    "RESULTS_FILE",
    "ResultsWriter",
    "SUMMARY_FILE",
    "SUMMARY_METRICS",
    "episode_key",
    "latest_rows",
    "leaderboard",
    "mean_ci",
    "read_results",
    "summarise",
    "write_summary",
]
