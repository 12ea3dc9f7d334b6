"""Episode logs and the metrics computed from them (the paper's section V-C and more).

An :class:`EpisodeLog` is what the evaluation records while an episode runs: per step
the joint action, where every agent stands afterwards, the team reward and the
simulator's events, plus when each order was drawn. :func:`compute_metrics` turns a
log into one flat dict of numbers (and a few small lists for the plots). Everything is
computed from the simulator's own events, so a hand-written log has a known answer.

Definitions:
- ``completion_rate``: orders completed / orders issued (the initial orders plus every
  replacement drawn); orders still open at the end count as not completed.
- ``steps_per_order``: steps / orders completed (``None`` when nothing was served).
- ``order_latency_mean``: mean steps from an order being drawn to its delivery.
- ``reward_trend``: least-squares slope of the cumulative team reward, per 100 steps.
- ``reward_halves``: team reward earned in the first and in the second half of the episode.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

from ..sim.codes import Action

ACTION_NAMES: tuple[str, ...] = tuple(a.name.lower() for a in Action)

#: event kind -> metric counting it
EVENT_COUNTS: dict[str, str] = {
    "delivery": "dishes_served",
    "wrong_delivery": "wrong_deliveries",
    "burnt": "burns",
    "order_expired": "orders_expired",
    "chop_done": "chops",
    "cook_done": "cooks",
    "wash_done": "washes",
    "layout_switch": "layout_switches",
    "move_blocked": "moves_blocked",
    "pickup": "pickups",
    "putdown": "putdowns",
    "plate_add": "plate_adds",
    "trash": "trashed",
}


@dataclass
class EpisodeLog:
    """What happened in one episode, step by step (JSON-able, small)."""

    rows: int
    cols: int
    n_agents: int
    start_pos: list[int]
    #: per step: one action per agent
    actions: list[list[int]] = field(default_factory=list)
    #: per step: flat cell of every agent after the step
    positions: list[list[int]] = field(default_factory=list)
    #: per step: team reward (sum over agents)
    rewards: list[float] = field(default_factory=list)
    #: per step: per-agent rewards
    agent_rewards: list[list[float]] = field(default_factory=list)
    #: per step: (kind, agent, value) of each event
    events: list[list[tuple[str, int, Any]]] = field(default_factory=list)
    #: order id -> step it was drawn
    order_created: dict[int, int] = field(default_factory=dict)
    #: per step: seconds the controller took to choose the joint action
    decision_times: list[float] = field(default_factory=list)

    def record(self, actions: Sequence[int], positions: Sequence[int], rewards: Sequence[float],
               events: Iterable[Any], decision_time: float = 0.0) -> None:
        """Append one step (``events`` are simulator ``Event`` tuples or (kind, agent, value))."""
        self.actions.append([int(a) for a in actions])
        self.positions.append([int(p) for p in positions])
        self.agent_rewards.append([float(r) for r in rewards])
        self.rewards.append(float(sum(rewards)))
        evs = []
        for e in events:
            if hasattr(e, "kind"):
                evs.append((e.kind, int(e.agent), e.value))
            else:
                evs.append((str(e[0]), int(e[1]), e[2] if len(e) > 2 else None))
        self.events.append(evs)
        self.decision_times.append(float(decision_time))

    @property
    def steps(self) -> int:
        return len(self.actions)


def _slope(values: Sequence[float]) -> float:
    n = len(values)
    if n < 2:
        return 0.0
    mx = (n - 1) / 2
    my = sum(values) / n
    num = sum((i - mx) * (v - my) for i, v in enumerate(values))
    den = sum((i - mx) ** 2 for i in range(n))
    return num / den


def visit_heatmaps(log: EpisodeLog) -> list[list[list[int]]]:
    """Per agent, a ``rows x cols`` grid of how many steps it spent on each cell
    (the start cell counts once, then the cell after every step)."""
    maps = [[[0] * log.cols for _ in range(log.rows)] for _ in range(log.n_agents)]
    for frame in [log.start_pos, *log.positions[:-1]] if log.positions else [log.start_pos]:
        for a, f in enumerate(frame):
            r, c = divmod(f, log.cols)
            maps[a][r][c] += 1
    return maps


def action_counts(log: EpisodeLog) -> list[dict[str, int]]:
    """Per agent, how often it chose each action (keys: right, down, left, up, stay)."""
    out = [dict.fromkeys(ACTION_NAMES, 0) for _ in range(log.n_agents)]
    for joint in log.actions:
        for a, act in enumerate(joint):
            out[a][ACTION_NAMES[act]] += 1
    return out


def compute_metrics(log: EpisodeLog) -> dict[str, Any]:
    """All per-episode metrics of a log (see the module docstring for definitions)."""
    counts: Counter = Counter()
    delivered_at: dict[int, int] = {}
    for t, evs in enumerate(log.events):
        for kind, _agent, value in evs:
            if kind in EVENT_COUNTS:
                counts[EVENT_COUNTS[kind]] += 1
            if kind == "delivery" and value is not None:
                delivered_at[int(value)] = t + 1  # the state after step t is at time t + 1
    m: dict[str, Any] = {name: counts.get(name, 0) for name in EVENT_COUNTS.values()}
    steps = log.steps
    done = m["dishes_served"]
    m["steps"] = steps
    m["orders_completed"] = done
    issued = max(len(log.order_created), done)
    m["orders_issued"] = issued
    m["completion_rate"] = done / issued if issued else 0.0
    m["steps_per_order"] = steps / done if done else None
    latencies = [delivered_at[o] - log.order_created[o] for o in delivered_at
                 if o in log.order_created]
    m["order_latency_mean"] = sum(latencies) / len(latencies) if latencies else None
    first = min(delivered_at.values()) if delivered_at else None
    m["first_delivery_step"] = first

    cumulative, total = [], 0.0
    for r in log.rewards:
        total += r
        cumulative.append(round(total, 6))
    m["reward"] = round(total, 6)
    m["reward_per_agent"] = [round(sum(step[a] for step in log.agent_rewards), 6)
                             for a in range(log.n_agents)]
    half = steps // 2
    m["reward_halves"] = [round(sum(log.rewards[:half]), 6), round(sum(log.rewards[half:]), 6)]
    m["reward_trend"] = round(_slope(cumulative) * 100, 6)
    m["reward_curve"] = cumulative

    per_agent = action_counts(log)
    m["actions_per_agent"] = per_agent
    total_actions = Counter()
    for d in per_agent:
        total_actions.update(d)
    n = sum(total_actions.values())
    m["action_fractions"] = {k: (total_actions[k] / n if n else 0.0) for k in ACTION_NAMES}
    m["heatmaps"] = visit_heatmaps(log)
    m["cells_visited"] = [sum(1 for row in h for v in row if v) for h in m["heatmaps"]]
    m["decision_time_s"] = round(sum(log.decision_times), 6)
    m["decision_time_max_s"] = round(max(log.decision_times, default=0.0), 6)
    return m


def controller_metrics(info: dict[str, Any]) -> dict[str, Any]:
    """Planner statistics from ``Controller.info()``, under fixed names.

    Read keys (all optional): ``replans`` (int), ``replans_by_reason`` (reason -> count),
    ``planning_time_s`` or ``planning_time`` (total seconds spent planning),
    ``planning_cpu_s`` (CPU seconds of the planner processes; only when given),
    ``planner_calls`` (int), ``plan_failures`` (int) or ``statuses`` (planner status ->
    count; every status but ``solved*`` counts as a failure), and from a language-model
    controller (``agents.llm``) ``model_calls`` and ``reply_errors`` (replies that could
    not be used). Missing ones are ``0`` / ``{}``; ``replans`` defaults to the sum of ``replans_by_reason``.
    """
    by_reason = info.get("replans_by_reason") or {}
    if not isinstance(by_reason, dict):
        by_reason = {}
    by_reason = {str(k): int(v) for k, v in by_reason.items()}
    replans = info.get("replans", sum(by_reason.values()))
    planning = info.get("planning_time_s", info.get("planning_time", 0.0))
    failures = info.get("plan_failures")
    statuses = info.get("statuses")
    if failures is None and isinstance(statuses, dict):
        failures = sum(int(n) for st, n in statuses.items() if not str(st).startswith("solved"))
    return {
        "replans": int(replans or 0),
        "replans_by_reason": by_reason,
        "planning_time_s": float(planning or 0.0),
        "planner_calls": int(info.get("planner_calls", 0) or 0),
        "plan_failures": int(failures or 0),
        "model_calls": int(info.get("model_calls", 0) or 0),
        "reply_errors": int(info.get("reply_errors", 0) or 0),
        **({"planning_cpu_s": float(info["planning_cpu_s"] or 0.0)}
           if "planning_cpu_s" in info else {}),
    }


#: metrics that are lists / dicts (kept in results.jsonl, left out of summary.csv)
SERIES_KEYS: frozenset[str] = frozenset({
    "reward_per_agent", "reward_halves", "reward_curve", "actions_per_agent", "action_fractions",
    "heatmaps", "cells_visited", "replans_by_reason",
})

__all__ = [
    "ACTION_NAMES",
    "EVENT_COUNTS",
    "EpisodeLog",
    "SERIES_KEYS",
    "action_counts",
    "compute_metrics",
    "controller_metrics",
    "visit_heatmaps",
]
