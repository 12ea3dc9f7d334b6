"""The generalisation protocol's cells, episodes, cross-play pairing and tables."""

from __future__ import annotations

import pytest

from ocplus_plan.errors import ConfigError
from ocplus_plan.eval.generalise import (
    cells, crossplay_pairs, crossplay_table, generalisation_table, markdown, play)


def _row(agent, split, kitchen, dishes, family="open", partner=None, cooks=2, seed=0):
    return {"family": family, "split": split, "kitchen": kitchen, "cooks": cooks, "seed": seed,
            "agent": agent, "partner": partner, "dishes": dishes}


def test_cells_leave_out_families_that_need_more_cooks():
    grid = cells(["open", "split"], ["train", "test"], 2, [1, 2], [0])
    assert {(f, n) for f, _, _, n, _ in grid} == {("open", 1), ("open", 2), ("split", 2)}
    assert len(grid) == 2 * 2 + 2 * 2 * 2
    with pytest.raises(ConfigError, match="unknown families"):
        cells(["nope"], ["test"], 1, [1], [0])


def test_the_table_gives_train_test_gap_ratio_to_greedy_and_kitchens_served():
    rows = [_row("greedy", "test", "k1", 4), _row("greedy", "test", "k2", 4),
            _row("greedy", "train", "t1", 4),
            _row("ppo", "test", "k1", 3), _row("ppo", "test", "k2", 0),
            _row("ppo", "test", "k1", 1, seed=1), _row("ppo", "train", "t1", 2),
            _row("ppo", "test", "k1", 9, partner="greedy")]  # cross-play rows are not counted
    table = {(r["family"], r["agent"]): r for r in generalisation_table(rows)}
    ppo = table[("open", "ppo")]
    assert ppo["test"] == round(4 / 3, 3) and ppo["train"] == 2.0
    assert ppo["gap"] == round((2 - 4 / 3) / 2, 3)
    assert ppo["test_vs_greedy"] == round((4 / 3) / 4, 3)
    assert ppo["test_kitchens_served"] == 0.5  # k1 served, k2 did not
    assert table[("all", "ppo")]["episodes_test"] == 3
    text = markdown(generalisation_table(rows))
    assert text.startswith("| cooks | family | agent | train | test |") and "| - |" not in text


def test_cross_play_pairs_every_agent_with_every_other_and_itself():
    assert crossplay_pairs(["greedy", "gen"]) == [("greedy", "greedy"), ("greedy", "gen"),
                                                  ("gen", "greedy"), ("gen", "gen")]
    with pytest.raises(ConfigError, match="must differ"):
        crossplay_pairs(["a", "a"])
    rows = [_row("gen", "test", "k", 2, partner="greedy"),
            _row("gen", "test", "k", 4, partner="greedy"), _row("gen", "test", "k", 5)]
    assert crossplay_table(rows) == [{"agent": "gen", "partner": "greedy", "dishes": 3.0,
                                      "episodes": 2}]


def test_an_episode_with_a_partner_drives_the_last_cook_with_it():
    seen = []

    def factory(name, seed):
        from ocplus_plan.agents import make_controller

        seen.append(name)
        return make_controller(name, seed)

    row = play(("open", "test", 0, 2, 0), "greedy", "greedy", "medium", horizon=30,
               partner=("stay", "stay"), factory=factory)
    assert seen == ["greedy", "stay"] and row["partner"] == "stay" and row["steps"] == 30
    assert row["kitchen"] == "gen:open:test:0:medium" and row["dishes"] >= 0


def test_skipped_rows_are_left_out_of_both_tables():
    rows = [_row("greedy", "test", "k1", 4), dict(_row("gen", "test", "k1", 0), skipped="none"),
            dict(_row("gen", "test", "k1", 0, partner="greedy"), skipped="none")]
    assert {r["agent"] for r in generalisation_table(rows)} == {"greedy"}
    assert crossplay_table(rows) == []
