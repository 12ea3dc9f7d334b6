"""Limits that hold everywhere: ``--rules`` within the recordings' limits, ASCII digits,
no empty list items, generated seeds within the maximum, one-line write errors."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from ocplus_plan.cli import main
from ocplus_plan.commands import _types
from ocplus_plan.commands._common import parse_rule_overrides
from ocplus_plan.errors import ConfigError
from ocplus_plan.render import replay
from ocplus_plan.sim.rules import MAX_ORDERS, MAX_RULE_INT, RULE_LIMITS, make_rules


def _one_line_error(capsys: pytest.CaptureFixture, code: int, *needles: str) -> str:
    assert code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    for needle in needles:
        assert needle in err[0]
    return err[0]


@pytest.mark.parametrize("item, needle", [
    (f"n_orders={MAX_ORDERS + 1}", f"from 1 to {MAX_ORDERS}"),
    ("n_orders=100000000", f"from 1 to {MAX_ORDERS}"),
    (f"burn_time={MAX_RULE_INT + 1}", f"from 1 to {MAX_RULE_INT}"),
    (f"order_time_limit={10**30}", "integer or None"),
    ("cook_time=３", "ASCII digits"),
    ("cook_time=1_0", "ASCII digits"),
])
def test_rules_beyond_the_recording_limits_are_refused_when_parsed(item: str, needle: str):
    with pytest.raises(ConfigError, match=needle):
        parse_rule_overrides([item])


def test_the_rules_and_the_recordings_share_one_table():
    for name, (lo, hi) in RULE_LIMITS.items():
        check, what = replay._RULE_CHECKS[name]
        assert check(lo) and check(hi) and not check(lo - 1) and not check(hi + 1), name
        assert f"from {lo} to {hi}" in what
    with pytest.raises(ConfigError, match="n_orders"):
        make_rules("easy", n_orders=MAX_ORDERS + 1)
    rules = make_rules("easy", n_orders=MAX_ORDERS, burn_time=MAX_RULE_INT)
    assert rules.n_orders == MAX_ORDERS  # the largest values are still playable rules


def test_rollout_with_a_huge_n_orders_is_one_line(capsys):
    code = main(["rollout", "--rules", "n_orders=100000000", "--horizon", "3"])
    _one_line_error(capsys, code, "n_orders")


def test_eval_with_a_huge_burn_time_writes_nothing(tmp_path: Path, capsys):
    out = tmp_path / "run"
    code = main(["eval", "--agents", "greedy", "--presets", "easy", "--seed", "0",
                 "--rules", f"burn_time={2**40}", "--save-replays", "0", "--out", str(out)])
    _one_line_error(capsys, code, "burn_time")
    assert not (out / "replays").exists()


@pytest.mark.parametrize("text", ["３", "１２", "٣", "1_000", "+", ""])
def test_whole_numbers_are_ascii_digits(text: str):
    with pytest.raises(Exception, match="not a whole number"):
        _types.seed(text)


@pytest.mark.parametrize("argv, needle", [
    (["--faults", ""], "empty item"),
    (["--faults", ",,,"], "empty item"),
    (["--faults", "burns:3,"], "empty item"),
    (["--faults", "burns:３"], "ASCII"),
    (["--agents", "greedy,,greedy"], "empty item"),
    (["--presets", "easy,"], "empty item"),
])
def test_empty_and_non_ascii_list_items_are_refused(tmp_path: Path, capsys, argv, needle):
    code = main(["eval", *argv, "--seed", "0", "--out", str(tmp_path / "o")])
    _one_line_error(capsys, code, needle)


def test_generated_seeds_stay_within_the_maximum(tmp_path: Path, capsys):
    code = main(["generate", "--family", "open", "--no-prove", "--seed", str(_types.MAX_SEED),
                 "--n", "5", "--out", str(tmp_path / "g")])
    _one_line_error(capsys, code, "past the largest seed")
    assert not (tmp_path / "g").exists()


def test_generate_into_proc_is_one_line(capsys):
    code = main(["generate", "--family", "open", "--no-prove", "--out", "/proc/ocplus-x"])
    _one_line_error(capsys, code, "/proc/ocplus-x")


def test_the_pkg_resources_warning_is_filtered_by_the_planning_package():
    script = (
        "import warnings, ocplus_plan.planning\n"
        "with warnings.catch_warnings(record=True) as seen:\n"
        "    for c in (UserWarning, DeprecationWarning):\n"
        "        warnings.warn('pkg_resources is deprecated as an API. See https://setuptools"
        ".pypa.io/en/latest/pkg_resources.html', c)\n"
        "print(len(seen))\n")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=120)
    assert done.stdout.strip() == "0" and done.stderr == ""
