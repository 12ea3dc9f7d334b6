"""The planner league: every planner on every instance of a set, scored as the IPC scores.

:func:`run_league` runs each planner (registry names, planner YAML paths, ``command:``
binaries) on each instance of an exported set (:mod:`.suite`, ``ocplus export-suite``) in
every encoding the planner takes, through :func:`~ocplus_plan.planning.engines.solve`: one
forked child per run leading its own process group, killed at its CPU seconds (the whole
group's, as the IPC counts them), a memory cap (``RLIMIT_AS``) and a generous wall-clock
safety. Every plan is validated (unified-planning's validator and VAL) and judged in the
kitchen (:func:`~ocplus_plan.planning.fidelity_judge.judge`: collision-free routing, waits
allowed). Each run is one row of ``DIR/runs.jsonl``; :func:`scores` turns the rows into
``DIR/scores.json``:

* statuses kept apart (:data:`ROW_STATUSES`): solved (valid and faithful), unsolvable (a
  proof, or a binary's claim), gave-up (an incomplete search that stopped), cpu-timeout,
  memout, safety-kill (the wall-clock safety), crash, invalid, unfaithful, unsupported;
* per planner and track: coverage (solved instances), the IPC quality score (the sum of
  C*/C, C* the best known value: the instance manifest's, improved by any better valid
  and faithful plan of the league), the IPC 2014 agile score (the sum of 1 for a plan
  within 1 CPU s, 0 past the limit, else 1 - log(T)/log(limit)), and the counts of valid
  and faithful plans. An invalid or unfaithful plan scores 0.

Every plan a run returns is kept in IPC format under ``DIR/plans/`` (the row's
``plan_file``), so it can be validated or judged again without running the planner. A row
already in ``runs.jsonl`` (same planner, instance and encoding) is not run again, so an
interrupted league resumes where it stopped.
"""

from __future__ import annotations

import json
import math
import multiprocessing
from collections.abc import Callable, Iterable
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import ConfigError

#: the statuses of a league row, in table order
ROW_STATUSES = ("solved", "unsolvable", "gave-up", "cpu-timeout", "memout", "safety-kill",
                "crash", "invalid", "unfaithful", "unsupported")
RUNS_FILE, SCORES_FILE, PLOT_FILE = "runs.jsonl", "scores.json", "coverage.png"
#: at most this many rows are read back from a runs file (a hostile file stays bounded)
MAX_ROWS = 200_000


@dataclass(frozen=True)
class LeagueSpec:
    """What :func:`run_league` runs (the ``ocplus league`` options)."""

    suite: Path
    planners: tuple[str, ...]
    cpu_limit: float
    memory_limit: float | None = None
    instances: tuple[str, ...] | None = None
    jobs: int = 1
    #: the wall-clock safety per run (None: the default, 30 x the CPU limit + 60 s)
    wall_limit: float | None = None


@dataclass(frozen=True)
class Cell:
    """One planner on one instance in one encoding."""

    planner: str
    instance: str
    encoding: str

    @property
    def key(self) -> tuple[str, str, str]:
        return (self.planner, self.instance, self.encoding)


# ---------------------------------------------------------------- the set

def _release_tracks(manifest: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """A release's tracks (``suites/v1/manifest.json``: name -> its folder, a set, and the
    instances ``scored`` and proven ``unsolvable``); empty for a plain set."""
    tracks = manifest.get("tracks")
    if not isinstance(tracks, dict):
        return {}
    return {str(k): v for k, v in tracks.items()
            if isinstance(v, dict) and isinstance(v.get("folder"), str)
            and "/" not in v["folder"] and ".." not in v["folder"]}


def _listed(suite: Path) -> list[str]:
    try:
        manifest = json.loads((suite / "manifest.json").read_text("utf-8"))
    except (OSError, ValueError) as exc:
        raise ConfigError(f"{suite}/manifest.json cannot be read ({exc}); export the set "
                          "again") from None
    release = _release_tracks(manifest)
    if release:  # a release of several sets: instances are TRACK_FOLDER/pNN
        return [f"{t['folder']}/{n}" for t in release.values()
                for key in ("scored", "unsolvable") for n in t.get(key) or []
                if isinstance(n, str) and "/" not in n]
    listed = manifest.get("instances")
    if not isinstance(listed, list) or not all(isinstance(x, str) for x in listed):
        listed = sorted(p.name for p in suite.iterdir() if (p / "manifest.json").is_file())
    return [n for n in listed if "/" not in n]


def suite_instances(suite: Path, names: Iterable[str] | None = None) -> list[str]:
    """The instance folders of a set (its manifest's list, else every ``pNN/``) or of a
    release of sets (``TRACK/pNN``), or the ``names`` asked for (an unknown one raises
    ConfigError naming those there are)."""
    if not (suite / "manifest.json").is_file():
        raise ConfigError(f"{suite} is not an instance set (no manifest.json); give a folder "
                          "written by `ocplus export-suite`, e.g. suites/v1")
    have = [n for n in _listed(suite) if (suite / n / "manifest.json").is_file()]
    if names is None:
        return have
    wanted = list(names)
    unknown = [n for n in wanted if n not in have]
    if unknown:
        raise ConfigError(f"no instance {', '.join(unknown)} in {suite}; it has "
                          f"{', '.join(have[:8])}{' ...' if len(have) > 8 else ''}")
    return wanted


def _manifest(suite: Path, name: str) -> dict[str, Any]:
    try:
        data = json.loads((suite / name / "manifest.json").read_text("utf-8"))
    except (OSError, ValueError) as exc:
        raise ConfigError(f"{suite / name}/manifest.json cannot be read ({exc})") from None
    if not isinstance(data, dict) or not isinstance(data.get("encodings"), dict):
        raise ConfigError(f"{suite / name}/manifest.json has no 'encodings' mapping; export "
                          "the set again")
    return data


def suite_tracks(suite: Path) -> dict[tuple[str, str], str]:
    """(instance, encoding) -> track label, from the set manifest's ``tracks`` (label ->
    instance names; a label starts with its encoding: ``classical``,
    ``temporal-unsolvable`` ...); empty when the set names none."""
    try:
        manifest = json.loads((suite / "manifest.json").read_text("utf-8"))
    except (OSError, ValueError):
        return {}
    out: dict[tuple[str, str], str] = {}
    for name, track in _release_tracks(manifest).items():
        encoding = str(track.get("encoding") or name.split("-", 1)[0])
        for key, label in (("scored", name), ("unsolvable", f"{name}-unsolvable")):
            out.update({(f"{track['folder']}/{n}", encoding): label
                        for n in track.get(key) or [] if isinstance(n, str)})
    tracks = manifest.get("tracks")
    if out or not isinstance(tracks, dict):
        return out
    for label, names in tracks.items():
        encoding = str(label).split("-", 1)[0]
        if isinstance(names, list):
            out.update({(str(n), encoding): str(label) for n in names})
    return out


def track_of(manifest: dict[str, Any], encoding: str, label: str | None = None) -> str:
    """The track an instance's encoding is scored in: the set's label (``label``) or the
    instance manifest's ``track``, where given; a label that is the bare encoding
    ``classical`` (or none) is split by cooks: classical-1cook, classical-multicook; a
    temporal instance is in temporal."""
    if label and label != "classical":
        return label
    entry = manifest["encodings"].get(encoding) or {}
    for where in (entry, manifest):
        track = where.get("track") if isinstance(where, dict) else None
        if isinstance(track, str) and track:
            return track
        tracks = where.get("tracks") if isinstance(where, dict) else None
        if isinstance(tracks, dict) and isinstance(tracks.get(encoding), str):
            return str(tracks[encoding])
    if encoding == "temporal":
        return "temporal"
    cooks = manifest.get("n_agents", manifest.get("cooks", 1))
    return "classical-1cook" if cooks == 1 else "classical-multicook"


def _number(value: Any) -> float | None:
    if isinstance(value, dict):
        for key in ("value", "cost", "makespan"):
            if key in value:
                return _number(value[key])
        return None
    if isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) \
            and value > 0:
        return float(value)
    return None


def best_known(manifest: dict[str, Any], encoding: str) -> float | None:
    """The manifest's best-known cost (classical) or makespan (temporal): its
    ``best_known`` field where the set has one, else the faithful reference plan's value."""
    entry = manifest["encodings"].get(encoding) or {}
    for key in ("best_known", "best"):
        found = _number(entry.get(key))
        if found is None and isinstance(manifest.get(key), dict):
            found = _number(manifest[key].get(encoding))
        if found is not None:
            return found
    ref = entry.get("reference")
    if isinstance(ref, dict) and ref.get("faithful") is not False:
        return _number(ref.get("makespan" if encoding == "temporal" else "cost"))
    return None


def league_cells(spec: LeagueSpec) -> list[Cell]:
    """Every planner x instance x encoding the planner takes, in run order."""
    from ..planning.engines import get_planner

    configs = [(name, get_planner(name)) for name in spec.planners]
    cells = []
    for instance in suite_instances(spec.suite, spec.instances):
        encodings = _manifest(spec.suite, instance)["encodings"]
        for name, config in configs:
            if config.encoding in encodings:
                cells.append(Cell(name, instance, config.encoding))
    return cells


# ---------------------------------------------------------------- one run

def row_status(result: Any) -> str:
    """A :class:`~ocplus_plan.planning.engines.PlanResult`'s status as a league status
    (before the kitchen's judgement)."""
    status = result.status
    if status == "timeout":
        return "safety-kill" if result.limit_hit == "wall" else "cpu-timeout"
    if status in ("error", "crashed"):
        return "crash"
    return status


def run_cell(spec: LeagueSpec, cell: Cell) -> dict[str, Any]:
    """Run one cell: solve, validate, judge; the row of ``runs.jsonl``."""
    from ..planning.engines import solve
    from ..planning.fidelity_judge import judge
    from ..planning.plan_io import format_plan
    from .suite import load_instance

    instance = load_instance(spec.suite / cell.instance)
    label = suite_tracks(spec.suite).get((cell.instance, cell.encoding))
    compiled = instance.compiled(cell.encoding)
    result = solve(compiled.problem, cell.planner, timeout=spec.cpu_limit,
                   memory_limit=spec.memory_limit, wall_limit=spec.wall_limit)
    value = result.makespan if cell.encoding == "temporal" else result.cost
    row: dict[str, Any] = {
        "planner": cell.planner, "instance": cell.instance, "encoding": cell.encoding,
        "track": track_of(instance.manifest, cell.encoding, label), "status": row_status(result),
        "reason": result.reason[:600], "cpu_time": result.cpu_time,
        "wall_time": round(result.planning_time, 3), "cpu_limit": spec.cpu_limit,
        "memory_limit": spec.memory_limit, "value": value, "plan_length": result.plan_length,
        "valid": None, "faithful": None, "failed_step": None,
        "best_known": best_known(instance.manifest, cell.encoding),
    }
    if result.plan is not None:
        row["valid"] = bool(result.validated) if result.validated is not None else None
        row["plan_text"] = format_plan(result.plan, f"{cell.planner} on {cell.instance}")
    if result.status == "solved" and result.plan is not None:
        verdict = judge(compiled, result.plan, instance.state)
        row["faithful"], row["judge"] = verdict.faithful, verdict.how
        row["waits"] = verdict.waits
        if not verdict.faithful:
            row["status"], row["failed_step"] = "unfaithful", verdict.failed_step
            row["reason"] = (f"step {verdict.failed_step}: " if verdict.failed_step is not None
                             else "") + verdict.reason
    return row


# ---------------------------------------------------------------- the league

def read_rows(path: Path) -> list[dict[str, Any]]:
    """The rows of a runs file (absent: none); a line that is not a row is refused."""
    if not path.is_file():
        return []
    rows = []
    with path.open(encoding="utf-8") as fh:
        for number, line in enumerate(fh, 1):
            if number > MAX_ROWS:
                raise ConfigError(f"{path} has more than {MAX_ROWS} rows; start a new --out")
            if not line.strip():
                continue
            try:
                row = json.loads(line)
            except ValueError:
                raise ConfigError(f"{path}:{number} is not a JSON row; remove the line (an "
                                  "interrupted write) or start a new --out") from None
            if not isinstance(row, dict) or not all(
                    isinstance(row.get(k), str) for k in ("planner", "instance", "encoding")):
                raise ConfigError(f"{path}:{number} is not a league row (planner, instance, "
                                  "encoding); give a new --out")
            rows.append(row)
    return rows


def run_league(spec: LeagueSpec, out: Path,
               progress: Callable[[dict[str, Any], int, int], None] | None = None,
               ) -> tuple[list[dict[str, Any]], list[str]]:
    """Run every cell not yet in ``out/runs.jsonl`` (appending its row as it ends);
    returns (every row of the cells asked for, the planners skipped with their reason)."""
    from ..planning.engines import availability, get_planner

    out.mkdir(parents=True, exist_ok=True)
    runs = out / RUNS_FILE
    done = {(r["planner"], r["instance"], r["encoding"]): r for r in read_rows(runs)}
    skipped = []
    ok = set()
    for name in spec.planners:
        found = availability(get_planner(name))
        if found.ok:
            ok.add(name)
        else:
            skipped.append(f"{name}: {found.reason}")
    cells = [c for c in league_cells(spec) if c.planner in ok]
    todo = [c for c in cells if c.key not in done]
    count = 0

    def keep(cell: Cell, row: dict[str, Any]) -> None:
        nonlocal count
        text = row.pop("plan_text", None)
        if text is not None:
            row["plan_file"] = _plan_file(cell)
            (out / row["plan_file"]).parent.mkdir(parents=True, exist_ok=True)
            (out / row["plan_file"]).write_text(text, encoding="utf-8")
        with runs.open("a", encoding="utf-8") as fh:
            fh.write(json.dumps(row, sort_keys=True) + "\n")
        done[cell.key] = row
        count += 1
        if progress:
            progress(row, count, len(todo))

    if spec.jobs <= 1:
        for cell in todo:
            keep(cell, run_cell(spec, cell))
    else:  # worker processes: unified-planning's environment is not thread-safe
        context = multiprocessing.get_context("fork")
        with ProcessPoolExecutor(max_workers=spec.jobs, mp_context=context) as pool:
            futures = {pool.submit(run_cell, spec, cell): cell for cell in todo}
            for future in as_completed(futures):
                keep(futures[future], future.result())
    return [done[c.key] for c in cells if c.key in done], skipped


def _plan_file(cell: Cell) -> str:
    """Where a cell's plan is kept, relative to the league's folder."""
    name = cell.instance.replace("/", "-")
    return f"plans/{cell.planner.replace('/', '-')}/{name}.{cell.encoding}.plan"


# ---------------------------------------------------------------- scores

def agile(cpu: float | None, limit: float) -> float:
    """The IPC 2014 agile score of a plan found in ``cpu`` CPU seconds."""
    if cpu is None or cpu > limit:
        return 0.0
    if cpu <= 1.0 or limit <= 1.0:
        return 1.0
    return 1.0 - math.log(cpu) / math.log(limit)


def suite_best(suite: Path, rows: Iterable[dict[str, Any]]) -> dict[tuple[str, str], float]:
    """Per (instance, encoding) of ``rows``: the set's best-known value now (its manifests).
    A row keeps the best known of when it ran; a set whose references improved since (a
    longer offline search) scores the same rows against the better values."""
    known: dict[tuple[str, str], float] = {}
    for key in sorted({(r["instance"], r["encoding"]) for r in rows}):
        if (suite / key[0] / "manifest.json").is_file():
            found = best_known(_manifest(suite, key[0]), key[1])
            if found is not None:
                known[key] = found
    return known


def best_values(rows: Iterable[dict[str, Any]],
                known: dict[tuple[str, str], float] | None = None,
                ) -> dict[tuple[str, str], float]:
    """Per (instance, encoding): the best known value (the rows' own, and ``known``'s: the
    set's now), improved by the league's solved rows."""
    best: dict[tuple[str, str], float] = {k: v for k, v in (known or {}).items() if v > 0}
    for row in rows:
        key = (row["instance"], row["encoding"])
        for value in (row.get("best_known"),
                      row.get("value") if row.get("status") == "solved" else None):
            if isinstance(value, (int, float)) and value > 0 and (
                    key not in best or value < best[key]):
                best[key] = float(value)
    return best


def scores(rows: list[dict[str, Any]],
           known: dict[tuple[str, str], float] | None = None) -> dict[str, Any]:
    """The league's scores: per planner and track, and per planner over all tracks
    (``known``: best-known values beyond the rows', e.g. :func:`suite_best`)."""
    best = best_values(rows, known)
    table: dict[str, dict[str, dict[str, Any]]] = {}
    for row in rows:
        for track in (row["track"], "all"):
            s = table.setdefault(row["planner"], {}).setdefault(track, _empty())
            _add(s, row, best)
    for tracks in table.values():
        for s in tracks.values():
            s["quality"], s["agile"] = round(s["quality"], 4), round(s["agile"], 4)
    return {"planners": table, "best": {f"{i}/{e}": v for (i, e), v in sorted(best.items())},
            "statuses": list(ROW_STATUSES)}


def _empty() -> dict[str, Any]:
    return {"instances": 0, "coverage": 0, "quality": 0.0, "agile": 0.0, "valid": 0,
            "faithful": 0, "statuses": {}}


def _add(s: dict[str, Any], row: dict[str, Any], best: dict[tuple[str, str], float]) -> None:
    s["instances"] += 1
    s["statuses"][row["status"]] = s["statuses"].get(row["status"], 0) + 1
    s["valid"] += row.get("valid") is True
    s["faithful"] += row.get("faithful") is True
    if row["status"] == "unsolvable" and "unsolvable" in row["track"]:
        s["coverage"] += 1  # the unsolvability track: a proof is what counts
    if row["status"] != "solved":
        return
    s["coverage"] += 1
    value = row.get("value")
    star = best.get((row["instance"], row["encoding"]))
    if isinstance(value, (int, float)) and value > 0 and star:
        s["quality"] += min(1.0, star / value)
    elif value == 0:
        s["quality"] += 1.0
    s["agile"] += agile(row.get("cpu_time"), float(row.get("cpu_limit") or 0.0))


def table_text(score: dict[str, Any]) -> str:
    """The league table: one line per planner and track."""
    head = (f"{'planner':<28} {'track':<20} {'n':>3} {'cov':>4} {'quality':>8} "
            f"{'agile':>7} {'valid':>5} {'faithf':>6}  statuses")
    lines = [head, "-" * len(head)]
    for planner in sorted(score["planners"]):
        for track, s in sorted(score["planners"][planner].items(),
                               key=lambda kv: (kv[0] == "all", kv[0])):
            statuses = " ".join(f"{k}={v}" for k, v in sorted(s["statuses"].items()))
            lines.append(f"{planner:<28} {track:<20} {s['instances']:>3} {s['coverage']:>4} "
                         f"{s['quality']:>8.2f} {s['agile']:>7.2f} {s['valid']:>5} "
                         f"{s['faithful']:>6}  {statuses}")
    return "\n".join(lines)


def write_scores(rows: list[dict[str, Any]], out: Path,
                 suite: Path | None = None) -> dict[str, Any]:
    """Write ``out/scores.json`` and return it (``suite``: score against its best known
    values now as well)."""
    score = scores(rows, suite_best(suite, rows) if suite is not None else None)
    (out / SCORES_FILE).write_text(json.dumps(score, indent=1, sort_keys=True) + "\n",
                                   encoding="utf-8")
    return score


def plot_coverage(rows: list[dict[str, Any]], out: Path) -> Path:
    """``out/coverage.png``: solved instances against CPU seconds, one line per planner
    (matplotlib: the ``plots`` extra)."""
    from .plots import _pyplot, _save

    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.5))
    limit = max((float(r.get("cpu_limit") or 1.0) for r in rows), default=1.0)
    for planner in sorted({r["planner"] for r in rows}):
        times = sorted(max(float(r.get("cpu_time") or 0.0), 1e-3) for r in rows
                       if r["planner"] == planner and r["status"] == "solved")
        xs = [1e-3, *times, limit]
        ys = [0, *range(1, len(times) + 1), len(times)]
        ax.step(xs, ys, where="post", label=planner)
    ax.set_xscale("log")
    ax.yaxis.get_major_locator().set_params(integer=True)
    ax.set_xlabel("CPU seconds")
    ax.set_ylabel("instances solved (valid and faithful)")
    ax.set_title("coverage against CPU time")
    ax.legend(fontsize=7, loc="upper left")
    return _save(plt, fig, out / PLOT_FILE)


__all__ = ["PLOT_FILE", "ROW_STATUSES", "RUNS_FILE", "SCORES_FILE", "Cell", "LeagueSpec",
           "agile", "best_known", "best_values", "league_cells", "plot_coverage", "read_rows",
           "row_status", "run_cell", "suite_tracks", "run_league", "scores", "suite_instances", "table_text",
           "track_of", "write_scores"]
