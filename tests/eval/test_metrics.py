"""Metrics on hand-made episode logs with known answers, and against the simulator's stats."""

from __future__ import annotations

import math

import pytest

from ocplus_plan.eval.metrics import EpisodeLog, compute_metrics, controller_metrics
from ocplus_plan.eval.results import mean_ci, summarise


def _log() -> EpisodeLog:
    """2 cooks on a 2x3 grid, 4 steps: a wrong delivery, a delivery of order 0, a burn."""
    log = EpisodeLog(rows=2, cols=3, n_agents=2, start_pos=[0, 5])
    log.order_created.update({0: 0, 1: 0})
    log.record([0, 2], [1, 4], [-0.1, -0.1], [("move_blocked", 1, "occupied")], 0.01)
    log.record([4, 3], [1, 1], [-5.1, -0.1], [("wrong_delivery", 0, None)], 0.02)
    log.record([1, 4], [4, 1], [199.9, -0.1], [("delivery", 0, 0), ("order_new", -1, 2)], 0.03)
    log.order_created[2] = 3  # drawn when order 0 was served, after step index 2
    log.record([4, 4], [4, 1], [-2.1, -0.1], [("burnt", 0, None), ("chop_done", 1, None)], 0.04)
    return log


def test_counts_rates_and_efficiency():
    m = compute_metrics(_log())
    assert m["steps"] == 4
    assert m["dishes_served"] == m["orders_completed"] == 1
    assert m["wrong_deliveries"] == 1 and m["burns"] == 1 and m["chops"] == 1
    assert m["moves_blocked"] == 1
    assert m["orders_issued"] == 3
    assert m["completion_rate"] == pytest.approx(1 / 3)
    assert m["steps_per_order"] == 4
    # order 0 drawn at t=0, served in step index 2, i.e. the state at t=3
    assert m["order_latency_mean"] == 3 and m["first_delivery_step"] == 3


def test_rewards_curve_halves_and_trend():
    m = compute_metrics(_log())
    team = [-0.2, -5.2, 199.8, -2.2]
    assert m["reward"] == pytest.approx(sum(team))
    assert m["reward_per_agent"] == pytest.approx([-0.1 - 5.1 + 199.9 - 2.1, -0.4])
    assert m["reward_curve"] == pytest.approx([-0.2, -5.4, 194.4, 192.2])
    assert m["reward_halves"] == pytest.approx([-5.4, 197.6])
    # least-squares slope of the cumulative curve over x = 0..3, per 100 steps
    xs, ys = [0, 1, 2, 3], [-0.2, -5.4, 194.4, 192.2]
    mx, my = 1.5, sum(ys) / 4
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    assert m["reward_trend"] == pytest.approx(slope * 100)


def test_action_distribution_and_heatmaps():
    m = compute_metrics(_log())
    assert m["actions_per_agent"][0] == {"right": 1, "down": 1, "left": 0, "up": 0, "stay": 2}
    assert m["actions_per_agent"][1] == {"right": 0, "down": 0, "left": 1, "up": 1, "stay": 2}
    assert m["action_fractions"]["stay"] == pytest.approx(0.5)
    assert sum(m["action_fractions"].values()) == pytest.approx(1.0)
    # cook 0 stands on cells 0, 1, 1, 4 and cook 1 on 5, 4, 1, 1 (the position after the
    # last step is not a visit: one count per step)
    assert m["heatmaps"][0] == [[1, 2, 0], [0, 1, 0]]
    assert m["heatmaps"][1] == [[0, 2, 0], [0, 1, 1]]
    assert sum(map(sum, m["heatmaps"][0])) == 4
    assert m["cells_visited"] == [3, 3]
    assert m["decision_time_s"] == pytest.approx(0.1) and m["decision_time_max_s"] == 0.04


def test_empty_episode_has_no_division_by_zero():
    m = compute_metrics(EpisodeLog(rows=1, cols=2, n_agents=1, start_pos=[0]))
    assert m["steps"] == 0 and m["completion_rate"] == 0.0
    assert m["steps_per_order"] is None and m["order_latency_mean"] is None
    assert m["reward_trend"] == 0.0


def test_controller_metrics_reads_planner_statistics_and_aliases():
    info = {"replans_by_reason": {"initial": 1, "deviation": 3}, "planning_time": 1.5,
            "planner_calls": 4, "statuses": {"solved": 3, "timeout": 1}}
    assert controller_metrics(info) == {
        "replans": 4, "replans_by_reason": {"initial": 1, "deviation": 3},
        "planning_time_s": 1.5, "planner_calls": 4, "plan_failures": 1, "model_calls": 0,
        "reply_errors": 0}
    assert controller_metrics({})["replans"] == 0
    assert controller_metrics({"replans": 7, "planning_time_s": 2.0})["planning_time_s"] == 2.0


def test_controller_metrics_counts_a_language_models_unusable_replies():
    m = controller_metrics({"model_calls": 12, "reply_errors": 5})
    assert (m["model_calls"], m["reply_errors"]) == (12, 5)


def test_mean_ci_uses_student_t():
    mean, ci = mean_ci([1.0, 2.0, 3.0])
    assert mean == 2.0 and ci == pytest.approx(4.303 / math.sqrt(3))
    assert mean_ci([5.0]) == (5.0, 0.0)
    assert mean_ci([]) == (None, None)


def test_summary_groups_and_ignores_failed_rows():
    def row(agent, seed, dishes, status="ok"):
        return {"preset": "easy", "map": "m", "n_agents": 1, "agent": agent, "horizon": 10,
                "seed": seed, "status": status, "reason": "boom" if status != "ok" else "",
                "metrics": {"dishes_served": dishes}}
    rows = [row("a", 0, 2), row("a", 1, 4), row("b", 0, 1), row("b", 1, 0, "error")]
    summary = {s["agent"]: s for s in summarise(rows)}
    assert summary["a"]["episodes"] == 2 and summary["a"]["dishes_served_mean"] == 3.0
    assert summary["b"]["episodes"] == 1 and summary["b"]["errors"] == 1
    assert summary["b"]["reason"] == "boom"
    assert [s["agent"] for s in summarise(rows)] == ["a", "b"]  # ranked by dishes


def test_metrics_from_events_agree_with_simulator_stats():
    from ocplus_plan.eval.runner import EpisodeSpec, evaluate_episode

    row = evaluate_episode(EpisodeSpec("medium", "medium_kitchen", None, 2, "greedy", 1, 120))
    m, stats = row["metrics"], row["stats"]
    assert row["status"] == "ok" and m["steps"] == 120
    for key in ("dishes_served", "orders_completed", "burns", "wrong_deliveries", "chops",
                "cooks", "washes", "layout_switches", "orders_expired"):
        assert m[key] == stats[key], key
    assert m["dishes_served"] >= 1
