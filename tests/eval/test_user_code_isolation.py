"""User code that ends its process, with ``--jobs 1``: an ``error`` row, the sweep goes
on and writes its summary. A segfault, a loop at import and processes left in a new
session: the hostile-process corpus (tests/fuzz/processes.py)."""

from __future__ import annotations

from pathlib import Path

import pytest

from ocplus_plan.cli import main
from ocplus_plan.eval.results import SUMMARY_FILE, read_results

MODELS = {
    "exits_model": "import os\ndef ask(prompt):\n    os._exit(7)\n",
    "exits_on_import": "import os\nos._exit(5)\n",
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


def test_a_model_that_ends_its_process_is_an_error_row_with_jobs_1(models, tmp_path, capsys):
    out = tmp_path / "run"
    assert _eval(out, "llm:exits_model:ask,greedy") == 0, capsys.readouterr().err
    rows = {(r["agent"], r["seed"]): r for r in read_results(out)}
    assert len(rows) == 4
    for seed in (0, 1):
        row = rows[("llm:exits_model:ask", seed)]
        assert row["status"] == "error" and "worker process died" in row["reason"]
        assert rows[("greedy", seed)]["status"] == "ok"
    assert (out / SUMMARY_FILE).is_file()


def test_a_module_that_exits_at_import_is_an_error_row(models, tmp_path):
    out = tmp_path / "run"
    assert _eval(out, "llm:exits_on_import:ask") == 0
    rows = read_results(out)
    assert [r["status"] for r in rows] == ["error", "error"]
    assert "exited with code 5" in rows[0]["reason"]
