"""Every argument is checked before any work: a bad one exits 2 with one line on stderr that
says what is wrong and what is allowed (no traceback, no allocation sized by the input)."""

from __future__ import annotations

import contextlib
import io
import os
import subprocess
import sys
import tracemalloc
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ocplus_plan import cli
from ocplus_plan.cli import main
from ocplus_plan.commands import _types


def run_cli(argv: list[str]) -> tuple[int, str, str]:
    """``main(argv)`` in this process: exit code, stdout, stderr."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


@pytest.fixture
def no_work(monkeypatch, tmp_path):
    """Commands whose work is replaced by a stub that records it ran: what is tested is
    the parsing and checking of the arguments, in a private working directory."""
    ran: list[str] = []
    build = cli.build_parser

    def stubbed():
        parser = build()
        for action in parser._actions:
            if hasattr(action, "choices") and isinstance(action.choices, dict):
                for name, sub in action.choices.items():
                    sub.set_defaults(func=lambda args, name=name: ran.append(name) or 0)
        return parser

    monkeypatch.setattr(cli, "build_parser", stubbed)
    monkeypatch.chdir(tmp_path)
    return ran


def _one_line_naming(err: str, *words: str) -> None:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    for word in words:
        assert word in lines[0], (word, lines[0])


BAD = [
    # seeds: negative, not a number, empty or reversed ranges, too many
    (["rollout", "--seed", "-1"], "--seed", "0 to"),
    (["eval", "--seed", "-1"], "--seed", "0 to"),
    (["solve", "--seed", "-5"], "--seed", "0 to"),
    (["pddl", "--seed", "-5"], "--seed", "0 to"),
    (["export-suite", "--seed", "-5"], "--seed", "0 to"),
    (["rollout", "--seed", "1.5"], "--seed", "whole number"),
    (["rollout", "--seed", str(2**64)], "--seed", "0 to"),
    (["eval", "--seeds", "5-2"], "--seeds", "low-high"),
    (["eval", "--seeds", "0-10000000000"], "--seeds", "0 to"),
    (["eval", "--seeds", "0-20000000"], "--seeds", "at most"),
    (["eval", "--seeds", "0"], "--seeds", "1 to"),
    (["demo", "--seeds", "-3"], "--seeds", "a count"),
    (["eval", "--seeds", "1,1"], "--seeds", "twice"),
    (["eval", "--seeds", ","], "--seeds", "a count"),
    (["eval", "--seeds", "two"], "--seeds", "whole number"),
    (["eval", "--save-replays", "9-1"], "--save-replays", "low-high"),
    # time limits: negative, zero, nan, inf, words
    (["eval", "--episode-timeout", "-1"], "--episode-timeout", "finite number"),
    (["eval", "--episode-timeout", "nan"], "--episode-timeout", "finite number"),
    (["demo", "--episode-timeout", "inf"], "--episode-timeout", "finite number"),
    (["eval", "--episode-timeout", "0"], "--episode-timeout", "finite number"),
    (["solve", "--timeout", "nan"], "--timeout", "finite number"),
    (["export-suite", "--timeout", "-1"], "--timeout", "finite number"),
    (["train", "--max-wall", "inf"], "--max-wall", "finite number"),
    # the horizon and the random steps before compiling: bounded
    (["rollout", "--horizon", "0"], "--horizon", "1 to 10000"),
    (["rollout", "--horizon", str(10**18)], "--horizon", "1 to 10000"),
    (["eval", "--horizon", "-5"], "--horizon", "1 to 10000"),
    (["solve", "--random-steps", "-1"], "--random-steps", "0 to"),
    (["pddl", "--random-steps", "100000"], "--random-steps", "0 to"),
    # jobs and other counts
    (["eval", "--jobs", "0"], "--jobs", "1 to"),
    (["demo", "--jobs", "-2"], "--jobs", "1 to"),
    (["eval", "--jobs", "many"], "--jobs", "whole number"),
    (["eval", "--retries", "-1"], "--retries", "0 to"),
    (["rollout", "--n-agents", "0"], "--n-agents", "1 to"),
    (["export-suite", "--cooks", "1,0"], "--cooks", "1 to"),
    (["export-suite", "--states", "0"], "--states", "1 to"),
    (["train", "--timesteps", "0"], "--timesteps", "at least 1"),
    (["train", "--gamma", "nan"], "--gamma", "finite number"),
    (["replay", "x.jsonl", "--every", "0"], "--every", "at least 1"),
    (["play", "--fps", "0"], "--fps", "finite number"),
    # names that name nothing
    (["rollout", "--preset", ""], "--preset", "names nothing"),
    (["eval", "--agents", " "], "--agents", "names nothing"),
    # unknown options and conflicting ones
    (["rollout", "--bogus"], "--bogus", "--help"),
    (["eval", "--seed", "1", "--seeds", "3"], "--seeds", "not allowed"),
    (["eval", "--seed", "1", "--seeds", "4-6"], "--seeds", "not allowed"),
]


@pytest.mark.parametrize(("argv", "flag", "allowed"), BAD, ids=lambda v: " ".join(v)
                         if isinstance(v, list) else None)
def test_a_bad_argument_exits_2_with_one_line(argv, flag, allowed, no_work):
    code, out, err = run_cli(argv)
    assert code == 2 and out == "" and no_work == []
    _one_line_naming(err, flag, allowed)


def test_out_naming_a_file_is_refused_before_any_work(tmp_path, no_work):
    (tmp_path / "file").write_text("x")
    for command in ("eval", "demo", "train", "pddl", "export-suite"):
        code, _, err = run_cli([command, "--out", "file"])
        assert code == 2 and no_work == [], command
        _one_line_naming(err, "--out", "is a file", "folder")


def test_out_below_a_file_is_refused(tmp_path, no_work):
    (tmp_path / "file").write_text("x")
    code, _, err = run_cli(["eval", "--out", "file/run"])
    assert code == 2 and no_work == []
    _one_line_naming(err, "--out", "not a folder")


@pytest.mark.skipif(os.geteuid() == 0, reason="root may write into a read-only folder")
def test_out_in_an_unwritable_folder_is_refused(tmp_path, no_work):
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        code, _, err = run_cli(["eval", "--out", "locked/run"])
    finally:
        locked.chmod(0o700)
    assert code == 2 and no_work == []
    _one_line_naming(err, "--out", "cannot make")


def test_an_output_file_where_a_folder_is_is_refused(tmp_path, no_work):
    (tmp_path / "frames").mkdir()
    code, _, err = run_cli(["replay", "x.jsonl", "--gif", "frames"])
    assert code == 2 and no_work == []
    _one_line_naming(err, "--gif", "is a folder")
    code, _, err = run_cli(["play", "--record", "frames"])
    assert code == 2
    _one_line_naming(err, "--record", "is a folder")


def test_good_arguments_reach_the_command(no_work):
    argv = ["eval", "--seeds", "0-9999", "--episode-timeout", "2.5", "--horizon", "10000",
            "--jobs", "2", "--out", "runs/a", "--preset", "easy", "--plots"]
    assert run_cli(argv)[0] == 0 and no_work == ["eval"]


def test_resume_without_out_is_refused(no_work):
    code, _, err = run_cli(["eval", "--resume"])
    assert code == 2 and no_work == []
    _one_line_naming(err, "--resume", "--out")


def test_plots_without_matplotlib_is_refused_before_any_work(no_work, monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "matplotlib" else real(name, *a))
    code, _, err = run_cli(["eval", "--plots"])
    assert code == 3 and no_work == []
    assert "plots" in err and "matplotlib" in err


def test_a_huge_seed_range_is_refused_without_allocating_it(no_work):
    tracemalloc.start()
    try:
        code, _, _ = run_cli(["eval", "--seeds", f"0-{_types.MAX_SEED}"])
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert code == 2 and peak < 20_000_000  # the parser itself; never a list of 4e9 seeds


def test_help_returns_0_and_an_empty_command_line_2(no_work):
    assert run_cli(["--help"])[0] == 0
    assert run_cli(["rollout", "--help"])[0] == 0
    assert run_cli([])[0] == 2


def test_a_bad_argument_in_a_real_process_is_one_line_and_exit_2(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "ocplus_plan.cli", "eval", "--seeds", "5-2"],
                          capture_output=True, text=True, cwd=tmp_path, timeout=120)
    assert proc.returncode == 2 and proc.stdout == ""
    _one_line_naming(proc.stderr, "--seeds", "5-2", "low-high")
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_a_bug_is_not_bad_input(monkeypatch, tmp_path):
    """An unexpected exception is left to the interpreter (traceback, exit 1)."""
    monkeypatch.chdir(tmp_path)
    build = cli.build_parser

    def broken():
        parser = build()
        for action in parser._actions:
            if isinstance(getattr(action, "choices", None), dict):
                action.choices["rollout"].set_defaults(func=lambda args: 1 / 0)
        return parser

    monkeypatch.setattr(cli, "build_parser", broken)
    with pytest.raises(ZeroDivisionError):
        main(["rollout"])


def test_a_closed_pipe_ends_quietly(tmp_path):
    """``ocplus ... | head``: the reader goes away; no traceback, exit 0."""
    proc = subprocess.Popen([sys.executable, "-m", "ocplus_plan.cli", "solve", "--list"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=tmp_path)
    proc.stdout.close()  # before the command has printed anything
    err = proc.stderr.read().decode()
    proc.stderr.close()
    assert proc.wait(timeout=120) == 0, err
    assert "Traceback" not in err and "BrokenPipe" not in err


# -- any argument list: exit 0 or 2, never a traceback; a refusal is one line
FLAGS = ["--seed", "--seeds", "--horizon", "--jobs", "--episode-timeout", "--timeout", "--out",
         "--n-agents", "--cooks", "--preset", "--map", "--random-steps", "--step", "--steps",
         "--timesteps", "--retries", "--states", "--orders", "--fps", "--every", "--gif",
         "--save-replays", "--plots", "--no-plots", "--json", "--quiet", "--resume"]
VALUES = st.one_of(
    st.integers(min_value=-2**70, max_value=2**70).map(str),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.sampled_from(["nan", "-inf", "inf", "1e400", "0-0", "5-2", "0-99999999999", "1,1", ",",
                     "", " ", "-", "--", "file", "file/x", ".", "..", "0x10", "1_000",
                     "\u0663", "easy,hard", "runs/x"]),
    st.text(max_size=12),
)
TOKENS = st.one_of(st.sampled_from(FLAGS), VALUES)


@settings(max_examples=150, deadline=10_000, derandomize=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(command=st.sampled_from(sorted(cli.COMMANDS)), tokens=st.lists(TOKENS, max_size=6))
def test_any_argument_list_ends_in_0_or_2_never_a_traceback(command, tokens, no_work,
                                                             tmp_path):
    (Path.cwd() / "file").write_text("x")
    argv = [command, *tokens]
    code, _, err = run_cli(argv)
    assert code in (0, 2), (argv, code, err)
    if code == 2:
        assert len(err.strip().splitlines()) == 1, (argv, err)
