"""Hostile user code and planner binaries for the command line: processes that exit, crash,
loop at import or leave a process behind in a new session.

A group of its own, beside the hostile files of :mod:`tests.fuzz.corpus`. :func:`build`
writes the modules and the planner under a folder, which must be on ``PYTHONPATH`` when the
cases run, and returns ``(name, argv, expected exit code)`` for each: 0 where the sweep
records the agent's failure as ``error`` rows and writes its summary, 2 where the command
line is refused. Every process a case starts (a ``sleep`` of :data:`SLEEP_MARK` seconds)
must be gone when it ends (tests/fuzz/test_corpus_processes.py).
"""

from __future__ import annotations

from pathlib import Path

#: the seconds of the sleepers the cases start: a mark to find what they leave behind
SLEEP_MARK = "654.25"

MODULES = {
    "hostile_exit": "import os\ndef ask(prompt):\n    os._exit(7)\n",
    "hostile_segv": "import ctypes\ndef ask(prompt):\n    ctypes.string_at(0)\n",
    "hostile_loop_import": "while True:\n    pass\n",
    "hostile_setsid": ("import subprocess\ndef ask(prompt):\n"
                       f"    subprocess.Popen(['setsid', 'sleep', '{SLEEP_MARK}'])\n"
                       "    return 'stay'\n"),
}
PLANNER = f"#!/bin/sh\nsetsid sleep {SLEEP_MARK} &\nexit 0\n"


def build(root: Path) -> list[tuple[str, list[str], int]]:
    """Write the modules and the planner under ``root``; (name, argv, expected code)."""
    for name, text in MODULES.items():
        (root / f"{name}.py").write_text(text)
    script = root / "setsid_planner.sh"
    script.write_text(PLANNER)
    script.chmod(0o755)
    (root / "setsid_planner.yaml").write_text(
        f"name: setsid-planner\ncommand: [{str(script)!r}, '{{domain}}', '{{problem}}', "
        "'{plan}']\nencoding: classical\ntimeout: 5\n")

    def sweep(case: str, agent: str, *extra: str) -> list[str]:
        return ["eval", "--presets", "easy", "--agents", agent, "--seeds", "1", "--horizon",
                "5", "--n-agents", "1", "--jobs", "1", "--quiet", "--out",
                str(root / f"run_{case}"), *extra]

    return [
        ("llm_os_exit_jobs1", sweep("exit", "llm:hostile_exit:ask"), 0),
        ("llm_segfault_jobs1", sweep("segv", "llm:hostile_segv:ask"), 0),
        ("llm_loop_at_import", sweep("loop", "llm:hostile_loop_import:ask",
                                     "--episode-timeout", "2"), 0),
        ("partner_loops_at_import", sweep("partner", "greedy", "--n-agents", "2",
                                          "--partner", "llm:hostile_loop_import:ask",
                                          "--episode-timeout", "2"), 2),
        ("llm_setsid_sleeper", sweep("setsid", "llm:hostile_setsid:ask"), 0),
        ("planner_setsid_sleeper", ["solve", "--preset", "easy", "--planner",
                                    str(root / "setsid_planner.yaml"), "--json"], 0),
    ]
