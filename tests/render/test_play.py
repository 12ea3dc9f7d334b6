"""``ocplus play`` without a window: key mapping, scripted play, scoring per mode."""

from __future__ import annotations

import argparse

import pytest

from ocplus_plan.commands.play import PlaySession, build_session, parse_humans
from ocplus_plan.errors import ConfigError
from ocplus_plan.render.window import key_map
from ocplus_plan.sim import Action, make_rules

from .scripted import serve_one_dish_keys


def test_one_human_may_use_wasd_or_arrows_and_a_stay_key():
    keys = key_map(1)
    assert keys["w"] == keys["up"] == (0, Action.UP)
    assert keys["a"] == keys["left"] == (0, Action.LEFT)
    assert keys["s"] == keys["down"] == (0, Action.DOWN)
    assert keys["d"] == keys["right"] == (0, Action.RIGHT)
    assert keys["space"] == keys["return"] == (0, Action.STAY)


def test_two_humans_get_one_keyset_each():
    keys = key_map(2)
    assert keys["w"] == (0, Action.UP) and keys["space"] == (0, Action.STAY)
    assert keys["up"] == (1, Action.UP) and keys["return"] == (1, Action.STAY)
    assert {h for h, _ in keys.values()} == {0, 1}
    with pytest.raises(ConfigError, match="1 or 2"):
        key_map(3)


def test_parse_humans():
    assert parse_humans("0") == (0,)
    assert parse_humans("0,1") == (0, 1)
    assert parse_humans("none") == ()
    for bad in ("x", "0,0", "0,1,2", "-1"):
        with pytest.raises(ConfigError, match="--human"):
            parse_humans(bad)


def test_a_scripted_key_sequence_serves_a_dish_on_easy_open():
    session = PlaySession(make_rules("easy", map="easy_open", n_agents=1), 0, humans=(0,))
    keys = serve_one_dish_keys(session.state)
    for key in keys:
        assert session.press(key)
        assert session.ready(turn_based=True)
        session.step()
    assert session.state.stats["dishes_served"] == 1
    assert session.state.stats["orders_completed"] == 1
    assert session.scores()["team score"] == pytest.approx(200 + 10 - 0.1 * len(keys))


def test_turn_based_waits_for_every_human_and_ignores_other_keys():
    session = PlaySession(make_rules("easy", map="easy_open", n_agents=2), 0, humans=(0, 1))
    assert not session.press("x")
    assert session.press("d") and not session.ready(turn_based=True)
    assert session.ready(turn_based=False)
    assert session.press("left") and session.ready(turn_based=True)
    before = list(session.state.agent_pos)
    session.step()
    assert session.state.agent_pos == [before[0] + 1, before[1] - 1]
    assert session.pending == {}


def test_adversarial_mode_scores_humans_apart_and_reports_the_ai_team():
    rules = make_rules("easy", map="easy_open", n_agents=2, horizon=80)
    session = PlaySession(rules, 1, humans=(1,), agents="greedy", mode="adversarial")
    while not session.finished:
        session.press("space")  # the human only ever stays
        session.step()
    m = session.metrics()
    assert m["scores"]["human score"] == pytest.approx(-0.1 * 80)
    assert m["humans_side"]["dishes_served"] == 0
    ai = m["ai_team"]
    assert ai["agents"] == [0] and ai["dishes_served"] >= 1
    assert ai["dishes_served"] == m["dishes_served"]
    assert ai["reward"] == pytest.approx(m["scores"]["AI team score"])
    assert session.labels()[1] == "you (agent 1)"


def test_coop_mode_has_one_team_score():
    rules = make_rules("easy", map="easy_open", n_agents=2, horizon=50)
    session = PlaySession(rules, 0, humans=(0,), agents="greedy")
    for _ in range(50):
        session.step()
    assert set(session.scores()) == {"team score"}
    assert "ai_team" not in session.metrics()
    with pytest.raises(ConfigError, match="over"):
        session.step()


def test_bad_options_name_the_fix():
    with pytest.raises(ConfigError, match="--n-agents"):
        PlaySession(make_rules("easy", n_agents=1), 0, humans=(1,))
    with pytest.raises(ConfigError, match="coop or adversarial"):
        PlaySession(make_rules("easy"), 0, mode="versus")
    ns = argparse.Namespace(human="0,1", preset="easy", map=None, n_agents=None, fps=4.0,
                            horizon=None, agents="greedy", mode="coop", seed=0, record=None)
    assert build_session(ns).rules.n_agents == 2  # easy_open has room for two cooks only
    ns.human = "0"
    session = build_session(ns)
    assert session.rules.n_agents == 2 and session.ai == (1,)  # an AI cook beside the human
    ns.fps = 0
    with pytest.raises(ConfigError, match="--fps"):
        build_session(ns)
