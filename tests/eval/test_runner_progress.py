"""The sweep's progress bar: an ETA from measured times per agent, and what a long
episode is doing."""

from __future__ import annotations

import pytest

from ocplus_plan.eval.episode import EpisodeSpec
from ocplus_plan.eval.progress import LONG_EPISODE_S, EtaModel, Running, clock, running_text


def _spec(agent: str, seed: int = 0, preset: str = "easy") -> EpisodeSpec:
    return EpisodeSpec(preset, "m", None, 1, agent, seed, 200)


def test_eta_uses_each_agents_own_episode_time():
    eta = EtaModel()
    eta.add(_spec("greedy"), 1.0)
    eta.add(_spec("planner:kairos"), 100.0)
    pending = [_spec("greedy", s) for s in range(1, 5)] + [_spec("planner:kairos", 1)]
    # one worker: 4 greedy episodes of 1 s and one planner episode of 100 s
    assert eta.remaining(pending, [], 1, now=0.0) == pytest.approx(104.0)
    # a flat average over all episodes (50.5 s) would have said 252.5 s
    # two workers share the greedy episodes, then one takes the planner's
    assert eta.remaining(pending, [], 2, now=0.0) == pytest.approx(102.0)


def test_eta_prefers_the_same_preset_and_falls_back_to_the_agent_then_to_all():
    eta = EtaModel()
    eta.add(_spec("a", preset="easy"), 2.0)
    eta.add(_spec("a", preset="hard"), 10.0)
    eta.add(_spec("b", preset="easy"), 4.0)
    assert eta.expected(_spec("a", preset="hard")) == 10.0
    assert eta.expected(_spec("a", preset="medium")) == 6.0  # the agent's mean
    assert eta.expected(_spec("c")) == pytest.approx(16.0 / 3)  # every episode's mean
    assert EtaModel().expected(_spec("a")) is None


def test_eta_counts_what_running_episodes_still_need():
    eta = EtaModel()
    eta.add(_spec("p"), 60.0)
    running = [Running(_spec("p", 1), started=0.0)]
    assert eta.remaining([], running, 2, now=45.0) == pytest.approx(15.0)
    assert eta.remaining([], running, 2, now=90.0) == 0.0  # overdue: no negative time
    assert EtaModel().remaining([_spec("p")], [], 1, now=0.0) is None  # nothing measured


def test_a_long_episode_shows_its_step_planner_calls_and_time():
    r = Running(_spec("planner:kairos", 3, "hard"), started=0.0, step=57, planner_calls=4,
                planner_s=61.24)
    text = running_text(r, now=65.0)
    assert text == "planner:kairos hard s3: step 57/200, 4 planner call(s) 61.2 s (1:05)"
    assert running_text(r, now=LONG_EPISODE_S / 2) == "planner:kairos hard s3"


def test_clock():
    assert clock(5) == "0:05" and clock(75) == "1:15" and clock(3725) == "1:02:05"
