"""The progress bar of a sweep: episodes done, what the long ones are doing, an honest ETA.

- An episode that has run for more than :data:`LONG_EPISODE_S` shows its step, its planner
  calls and its planner seconds (reported by the worker about once a second), and how
  long it has run, so a bar never sits still without saying why.
- The ETA comes from measured episode times per agent (and preset, once one has
  finished there): what the running episodes still need, then each pending episode's
  expected time on the worker that is free first. Before an agent has finished any
  episode, the mean of all finished episodes stands in for it; before any has finished,
  there is no ETA.
"""

from __future__ import annotations

import heapq
import statistics
import sys
import time
from dataclasses import dataclass, field
from typing import Any

from .episode import EpisodeSpec

#: seconds after which a running episode shows its step and planner statistics
LONG_EPISODE_S = 3.0


@dataclass
class Running:
    """What the bar knows about one running episode."""

    spec: EpisodeSpec
    started: float
    step: int = 0
    planner_calls: int = 0
    planner_s: float = 0.0


@dataclass
class EtaModel:
    """Measured episode times per (agent, preset) and per agent."""

    times: dict[tuple[str, str], list[float]] = field(default_factory=dict)

    def add(self, spec: EpisodeSpec, seconds: float) -> None:
        self.times.setdefault((spec.agent, spec.preset), []).append(float(seconds))

    def expected(self, spec: EpisodeSpec) -> float | None:
        """Seconds ``spec`` is expected to take, or None with nothing measured yet."""
        same = self.times.get((spec.agent, spec.preset))
        if same:
            return statistics.fmean(same)
        agent = [t for (a, _p), ts in self.times.items() if a == spec.agent for t in ts]
        if agent:
            return statistics.fmean(agent)
        every = [t for ts in self.times.values() for t in ts]
        return statistics.fmean(every) if every else None

    def remaining(self, pending: list[EpisodeSpec], running: list[Running], jobs: int,
                  now: float) -> float | None:
        """Seconds until the sweep ends: the running episodes' expected rest, then the
        pending ones in order, each on the worker that is free first (as the backends
        hand them out); None while an episode has no measured time to go by."""
        loads = []
        for r in running:
            e = self.expected(r.spec)
            if e is None:
                return None
            loads.append(max(e - (now - r.started), 0.0))
        loads += [0.0] * max(0, jobs - len(loads))
        heapq.heapify(loads)
        for spec in pending:
            e = self.expected(spec)
            if e is None:
                return None
            heapq.heapreplace(loads, loads[0] + e)
        return max(loads, default=0.0)


def clock(seconds: float) -> str:
    """``75`` -> ``1:15``; ``3725`` -> ``1:02:05``."""
    s = int(round(seconds))
    h, rest = divmod(s, 3600)
    m, s = divmod(rest, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m}:{s:02d}"


def running_text(r: Running, now: float) -> str:
    """One running episode, for the bar: its name, and for a long one what it is doing."""
    name = f"{r.spec.agent} {r.spec.preset} s{r.spec.seed}"
    ran = now - r.started
    if ran < LONG_EPISODE_S:
        return name
    text = f"{name}: step {r.step}/{r.spec.horizon}"
    if r.planner_calls or r.planner_s:
        text += f", {r.planner_calls} planner call(s) {r.planner_s:.1f} s"
    return f"{text} ({clock(ran)})"


class SweepProgress:
    """The bar (tqdm) of one sweep; fed by the runner and the backends."""

    def __init__(self, todo: list[EpisodeSpec], jobs: int, quiet: bool) -> None:
        from tqdm import tqdm  # here, not at the top: importing the evaluation stays light

        self.pending = {id(s): s for s in todo}
        self.running: dict[int, Running] = {}
        self.eta = EtaModel()
        self.jobs = max(1, jobs)
        # redrawn in place on a terminal; in a log, one line every 30 s at most
        self.bar = tqdm(total=len(todo), desc="eval", unit="ep", disable=quiet,
                        dynamic_ncols=True, mininterval=0.1 if sys.stderr.isatty() else 30,
                        bar_format="{desc}: {percentage:3.0f}% {n_fmt}/{total_fmt} |{bar}| "
                                   "{elapsed}{postfix}")
        self._by_key = {s.row_base()["key"]: s for s in todo}
        self._live = sys.stderr.isatty() and not quiet  # in a log, tqdm's own pace

    def started(self, spec: EpisodeSpec) -> None:
        self.pending.pop(id(spec), None)
        self.running[id(spec)] = Running(spec, time.monotonic())

    def heard(self, spec: EpisodeSpec, step: int, calls: int, planner_s: float) -> None:
        r = self.running.get(id(spec))
        if r is None:
            self.started(spec)
            r = self.running[id(spec)]
        r.step, r.planner_calls, r.planner_s = step, calls, planner_s
        self.tick()

    def finished(self, row: dict[str, Any]) -> None:
        spec = self._by_key.get(str(row.get("key")))
        if spec is not None:
            r = self.running.pop(id(spec), None)
            self.pending.pop(id(spec), None)
            took = (row.get("timings") or {}).get("wall_time_s")
            if took is None and r is not None:
                took = time.monotonic() - r.started
            if took is not None and row.get("status") in ("ok", "error"):
                self.eta.add(spec, took)
        self.bar.update(1)
        self.tick()

    def tick(self) -> None:
        now = time.monotonic()
        left = self.eta.remaining(list(self.pending.values()), list(self.running.values()),
                                  self.jobs, now)
        parts = [f"ETA {clock(left)}" if left is not None else "ETA ?"]
        parts += [running_text(r, now) for r in self.running.values()]
        self.bar.set_postfix_str(" | ".join(parts), refresh=self._live)

    def close(self) -> None:
        self.bar.close()


__all__ = ["LONG_EPISODE_S", "EtaModel", "Running", "SweepProgress", "clock", "running_text"]
