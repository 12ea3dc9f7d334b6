"""Reading ``results.jsonl`` that may be damaged or forged: bounded, validated, locked."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from ocplus_plan.cli import main
from ocplus_plan.errors import ConfigError
from ocplus_plan.eval import results
from ocplus_plan.eval.results import (
    folder_lock,
    read_results,
    repair_torn_tail,
    row_key,
    scan_results,
)
from ocplus_plan.eval.runner import EvalConfig, run_eval


def _row(seed: int = 0, **kw) -> dict:
    row = {"preset": "easy", "map": "easy_open", "n_agents": 1, "agent": "greedy",
           "seed": seed, "horizon": 20, "status": "ok",
           "metrics": {"dishes_served": 1, "reward": 5.0}}
    row.update(kw)
    row["key"] = row_key(row)
    return row


def _write(path: Path, *lines: str | bytes) -> Path:
    path.write_bytes(b"".join(x if isinstance(x, bytes) else x.encode() for x in lines))
    return path


def _cfg(out: Path, **kw) -> EvalConfig:
    base = dict(presets=["easy"], agents=["greedy"], seeds=[0, 1], out=out, horizon=20,
                n_agents=1, jobs=1, quiet=True)
    base.update(kw)
    return EvalConfig(**base)


GOOD = json.dumps(_row(0)) + "\n"


@pytest.mark.parametrize("bad, why", [
    ("[1, 2]\n", "a JSON list"),
    ('"text"\n', "a JSON str"),
    (json.dumps({**_row(1), "agent": ["greedy"]}) + "\n", "'agent' is a list"),
    (json.dumps({**_row(1), "status": "won"}) + "\n", "status"),
    (json.dumps({**_row(1), "metrics": {"reward": "lots"}}) + "\n", "metrics.reward"),
    (b"\xff\xfe\x00binary\n", "not UTF-8"),
    ("[" * 100_000 + "]" * 100_000 + "\n", "nested too deeply"),
    ("{not json\n", "not JSON"),
    ("x" * (results.MAX_ROW_BYTES + 10) + "\n", "longer than"),
])
def test_a_bad_row_is_skipped_and_counted_with_its_line(tmp_path: Path, bad: str, why: str):
    path = _write(tmp_path / "results.jsonl", GOOD, bad, json.dumps(_row(2)) + "\n")
    found = scan_results(path)
    assert [r["seed"] for r in found.rows] == [0, 2]
    assert len(found.bad) == 1 and found.bad[0][0] == 2 and why in found.bad[0][1]
    assert "line 2" in found.note()


def test_a_forged_row_whose_key_matches_but_fields_differ_is_not_trusted(tmp_path: Path):
    forged = {**_row(0), "horizon": 99999, "preset": "hard"}  # key still says easy, 20
    path = _write(tmp_path / "results.jsonl", json.dumps(forged) + "\n")
    found = scan_results(path)
    assert found.rows == [] and "key does not match" in found.bad[0][1]


@pytest.mark.parametrize("kind", ["dir", "fifo", "device", "missing", "huge"])
def test_only_a_regular_file_within_the_limit_is_read(tmp_path: Path, kind: str,
                                                      monkeypatch: pytest.MonkeyPatch):
    path = tmp_path / "results.jsonl"
    if kind == "dir":
        path.mkdir()
    elif kind == "fifo":
        os.mkfifo(path)  # no writer: a blocking open would hang
    elif kind == "device":
        path.symlink_to("/dev/full")
    elif kind == "huge":
        _write(path, GOOD * 4)
        monkeypatch.setattr(results, "MAX_RESULTS_BYTES", len(GOOD) * 2)
    with pytest.raises(ConfigError, match="not a regular file|does not exist|the limit"):
        read_results(path)


def test_a_torn_last_line_is_cut_and_a_whole_one_gets_its_newline(tmp_path: Path):
    path = _write(tmp_path / "results.jsonl", GOOD, GOOD[:25])
    assert repair_torn_tail(path) and path.read_text() == GOOD
    assert not repair_torn_tail(path)
    _write(path, GOOD, GOOD.rstrip("\n"))
    assert repair_torn_tail(path) and path.read_text() == GOOD * 2
    _write(path, "x" * (results.MAX_ROW_BYTES * 2))  # torn and longer than any row
    assert repair_torn_tail(path) and path.read_bytes() == b""


def test_resume_after_garbage_runs_the_rest_and_report_reads_it(tmp_path: Path, capsys):
    out = tmp_path / "run"
    run_eval(_cfg(out, seeds=[0]), echo=lambda *a: None)
    with (out / "results.jsonl").open("a") as fh:
        fh.write("garbage in the middle\n\x00\x01 torn")
    notes: list[str] = []
    outcome = run_eval(_cfg(out, resume=True), echo=notes.append)
    assert outcome.ran == 1 and any("skipped 2 bad row(s) (line 2" in n for n in notes)
    text = (out / "results.jsonl").read_text()
    assert text.endswith("}\n") and "torn" not in text
    assert {r["seed"] for r in read_results(out)} == {0, 1}
    assert main(["report", str(out), "--json"]) == 0
    assert "skipped 1 bad row(s)" in capsys.readouterr().err


def test_report_refuses_a_folder_that_is_not_results(tmp_path: Path, capsys):
    (tmp_path / "results.jsonl").mkdir()
    assert main(["report", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "not a regular file" in err[0]


def test_a_second_run_on_a_locked_folder_is_refused(tmp_path: Path):
    out = tmp_path / "run"
    with folder_lock(out):
        with pytest.raises(ConfigError, match="being written by another run"):
            run_eval(_cfg(out), echo=lambda *a: None)
        with pytest.raises(ConfigError, match="being written by another run"):
            run_eval(_cfg(out, resume=True), echo=lambda *a: None)
    assert not (out / results.LOCK_FILE).exists()
    assert run_eval(_cfg(out), echo=lambda *a: None).ran == 2  # free again


def test_a_full_filesystem_is_one_line(tmp_path: Path):
    writer = results.ResultsWriter(tmp_path)
    writer._fh.close()
    writer._fh = open("/dev/full", "w")  # every write fails with ENOSPC
    with pytest.raises(ConfigError, match="cannot write .*No space left"):
        writer.write(_row(0))
