from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from ocplus_plan.cli import main


def test_check_map_summarises_a_map(capsys):
    assert main(["check-map", "mapC"]) == 0
    out = capsys.readouterr().out
    assert "9 rows x 9 cols" in out and "pan" in out
    assert "cells that switch" in out and "every station reachable" in out


def test_check_map_reports_unreachable_stations(tmp_path, capsys):
    p = tmp_path / "walled.yaml"
    p.write_text("game_map: [[1, 3, 1, 1, 6, 1], [5, 0, 1, 0, 0, 7], [1, 1, 1, 1, 1, 1]]\n"
                 "agent_spawn_points: [[1, 1]]\n")
    assert main(["check-map", str(p)]) == 0
    assert "UNREACHABLE" in capsys.readouterr().out


def test_check_map_bad_file_exits_2_with_the_error_on_stderr(tmp_path):
    p = tmp_path / "bad.yaml"
    p.write_text("game_map: [[1, 3, 1], [5, 0, 99], [1, 7, 1]]\nagent_spawn_points: [[1, 1]]\n")
    proc = subprocess.run([sys.executable, "-m", "ocplus_plan.cli", "check-map", str(p)],
                          capture_output=True, text=True)
    assert proc.returncode == 2 and proc.stdout == ""
    assert "bad.yaml" in proc.stderr and "row 1, column 2" in proc.stderr and "99" in proc.stderr


def test_rollout_json_has_the_promised_keys_and_is_deterministic(capsys):
    args = ["rollout", "--preset", "hard", "--n-agents", "2", "--steps", "60", "--seed", "3",
            "--json"]
    assert main(args) == 0
    first = json.loads(capsys.readouterr().out)
    for key in ("dishes_served", "orders_completed", "burns", "wrong_deliveries", "reward",
                "items_conserved", "state_hash"):
        assert key in first
    assert first["items_conserved"] is True and first["steps"] == 60
    assert main(args) == 0
    assert json.loads(capsys.readouterr().out)["state_hash"] == first["state_hash"]


def test_unknown_preset_is_exit_2(capsys):
    assert main(["rollout", "--preset", "impossible"]) == 2
    assert "unknown preset" in capsys.readouterr().err


def test_every_help_example_runs(capsys, tmp_path, monkeypatch):
    import shlex

    from ocplus_plan.cli import EXAMPLES
    from ocplus_plan.data import data_files

    # a private directory that looks like a checkout: no shared /tmp path, two runs at once
    # never write to the same place
    (tmp_path / "maps").symlink_to(Path(str(data_files("maps"))), target_is_directory=True)
    monkeypatch.chdir(tmp_path)
    for example in EXAMPLES:
        assert "/tmp" not in example, example
        argv = shlex.split(example)
        assert argv[0] == "ocplus"
        assert main(argv[1:]) == 0, example
    capsys.readouterr()


def test_json_results_and_deprecated_spellings(tmp_path, capsys):
    assert main(["check-map", "mapC", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["switch_every"] == 15
    # --steps (rollout) is the old spelling of --horizon: same result, a note on stderr
    assert main(["rollout", "--preset", "easy", "--steps", "30", "--json"]) == 0
    old = capsys.readouterr()
    assert "deprecated" in old.err and "--horizon" in old.err
    assert main(["rollout", "--preset", "easy", "--horizon", "30", "--json"]) == 0
    new = json.loads(capsys.readouterr().out)
    assert new["steps"] == 30 and new["state_hash"] == json.loads(old.out)["state_hash"]
    out = tmp_path / "ev"
    assert main(["eval", "--preset", "easy", "--agents", "random", "--seed", "3", "--horizon",
                 "20", "--out", str(out), "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["episodes_run"] == 1 and result["leaderboard"][0]["agent"] == "random"
    assert main(["report", str(out), "--no-plots", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["leaderboard"][0]["agent"] == "random"
    import argparse

    from ocplus_plan.commands._common import add_deprecated_alias

    p = argparse.ArgumentParser()
    p.add_argument("--quiet", action="store_true")
    add_deprecated_alias(p, "--no-progress", "--quiet", takes_value=False)
    assert p.parse_args(["--no-progress"]).quiet is True
    assert "deprecated" in capsys.readouterr().err
