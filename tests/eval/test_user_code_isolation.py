"""User code that exits, crashes, loops at import or leaves a process behind, with
``--jobs 1``: each becomes an ``error`` row, the sweep goes on and writes its summary,
and nothing it started is left."""

from __future__ import annotations

import time
from pathlib import Path

import psutil
import pytest

from ocplus_plan.cli import main
from ocplus_plan.eval.results import SUMMARY_FILE, read_results

MODELS = {
    "exits_model": "import os\ndef ask(prompt):\n    os._exit(7)\n",
    "segfault_model": "import ctypes\ndef ask(prompt):\n    ctypes.string_at(0)\n",
    "loops_on_import": "while True:\n    pass\ndef ask(prompt):\n    return 'stay'\n",
    "exits_on_import": "import os\nos._exit(5)\n",
    "setsid_model": ("import subprocess\nSTARTED = []\ndef ask(prompt):\n"
                     "    if not STARTED:\n"
                     "        STARTED.append(subprocess.Popen(['setsid', 'sleep', '321.5']))\n"
                     "    return 'stay'\n"),
}


@pytest.fixture()
def models(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    for name, text in MODELS.items():
        (tmp_path / f"{name}.py").write_text(text)
    monkeypatch.syspath_prepend(str(tmp_path))
    return tmp_path


def _eval(out: Path, agents: str, *extra: str) -> int:
    return main(["eval", "--presets", "easy", "--agents", agents, "--seeds", "2",
                 "--horizon", "10", "--n-agents", "1", "--jobs", "1", "--out", str(out),
                 "--quiet", *extra])


def _sleepers() -> list[psutil.Process]:
    found = []
    for proc in psutil.process_iter(["cmdline"]):
        if proc.info["cmdline"] == ["sleep", "321.5"]:
            found.append(proc)
    return found


@pytest.mark.parametrize("model", ["exits_model"])  # a segfault: tests/fuzz/processes.py
def test_a_model_that_ends_its_process_is_an_error_row_with_jobs_1(models, tmp_path, model,
                                                                   capsys):
    out = tmp_path / "run"
    assert _eval(out, f"llm:{model}:ask,greedy") == 0, capsys.readouterr().err
    rows = {(r["agent"], r["seed"]): r for r in read_results(out)}
    assert len(rows) == 4
    for seed in (0, 1):
        row = rows[(f"llm:{model}:ask", seed)]
        assert row["status"] == "error" and "worker process died" in row["reason"]
        assert rows[("greedy", seed)]["status"] == "ok"
    assert (out / SUMMARY_FILE).is_file()


def test_a_module_that_loops_at_import_is_bounded_by_the_episode_timeout(models, tmp_path):
    out = tmp_path / "run"
    start = time.monotonic()
    assert _eval(out, "llm:loops_on_import:ask,greedy", "--episode-timeout", "2") == 0
    assert time.monotonic() - start < 20
    rows = {(r["agent"], r["seed"]): r for r in read_results(out)}
    looping = [rows[("llm:loops_on_import:ask", s)] for s in (0, 1)]
    assert all(r["status"] == "error" and "did not finish within 2 s" in r["reason"]
               for r in looping)
    assert rows[("greedy", 0)]["status"] == "ok" and (out / SUMMARY_FILE).is_file()


def test_a_module_that_exits_at_import_is_an_error_row(models, tmp_path):
    out = tmp_path / "run"
    assert _eval(out, "llm:exits_on_import:ask") == 0
    rows = read_results(out)
    assert [r["status"] for r in rows] == ["error", "error"]
    assert "exited with code 5" in rows[0]["reason"]


def test_a_process_a_model_starts_in_a_new_session_is_killed(models, tmp_path):
    out = tmp_path / "run"
    assert _eval(out, "llm:setsid_model:ask") == 0
    assert [r["status"] for r in read_results(out)] == ["ok", "ok"]
    deadline = time.monotonic() + 5
    while _sleepers() and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not _sleepers()
