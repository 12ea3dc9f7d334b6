"""check-plan keeps its exit codes: 2 for a path that is no readable plan file (missing, a
directory, a device, unreadable, huge). The cases that need an exported set (4 for an
invalid plan, a byte-order mark or CRLF plan reads the same) are in test_suite.py."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.cli import main
from ocplus_plan.planning.plan_io import MAX_PLAN_BYTES


def bad_input(argv: list[str], capsys, match: str) -> None:
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("ocplus: error: ") and match in err and "\n" not in err


def files_args(plan: str, tmp_path: Path) -> list[str]:
    """--domain/--problem/--plan arguments; the first two exist (their content is never read
    when the plan path is refused first)."""
    (tmp_path / "d.pddl").write_text("(define (domain d))\n")
    (tmp_path / "p.pddl").write_text("(define (problem p))\n")
    return ["check-plan", "--domain", str(tmp_path / "d.pddl"), "--problem",
            str(tmp_path / "p.pddl"), "--plan", plan]


def test_a_missing_plan_file_is_bad_input(tmp_path, capsys):
    bad_input(files_args(str(tmp_path / "nope.plan"), tmp_path), capsys, "no such file")


def test_a_directory_is_bad_input(tmp_path, capsys):
    bad_input(files_args(str(tmp_path), tmp_path), capsys, "is a directory")


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="no /dev/zero here")
def test_a_device_is_bad_input_and_is_not_read(tmp_path, capsys):
    bad_input(files_args("/dev/zero", tmp_path), capsys, "not a regular file")


def test_a_huge_plan_file_is_bad_input(tmp_path, capsys):
    huge = tmp_path / "huge.plan"
    with huge.open("wb") as fh:
        fh.truncate(MAX_PLAN_BYTES + 1)  # sparse: no disk used
    bad_input(files_args(str(huge), tmp_path), capsys, "a plan file has at most")


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root reads any file")
def test_an_unreadable_plan_file_is_bad_input(tmp_path, capsys):
    locked = tmp_path / "locked.plan"
    locked.write_text("(move a0 s_1_1 s_1_2)\n")
    locked.chmod(0)
    bad_input(files_args(str(locked), tmp_path), capsys, "cannot be read")


def test_a_missing_domain_file_is_bad_input(tmp_path, capsys):
    args = files_args(str(tmp_path / "d.pddl"), tmp_path)
    args[2] = str(tmp_path / "missing.pddl")
    bad_input(args, capsys, "missing.pddl: no such file")
