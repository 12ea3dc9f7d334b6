"""The cleaner of a private Ray instance (``eval/ray_backend.py``): a driver killed with
``kill -9`` leaves no process of its instance and no folder. Ray itself is not needed:
a stand-in instance is a shell whose command line names the folder, with a child that
renamed itself as Ray's agents do."""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap
import time

import psutil

from ocplus_plan.eval.ray_backend import kill_instance

DRIVER = textwrap.dedent("""
    import subprocess, sys, time
    from ocplus_plan.eval.ray_backend import start_cleaner
    private = sys.argv[1]
    start_cleaner(private)
    # the instance: names the folder on its command line; its child does not
    subprocess.Popen(["sh", "-c", "sleep 321.75 & wait", private])
    print("started", flush=True)
    time.sleep(120)
""")


def _sleepers() -> list[psutil.Process]:
    out = []
    for p in psutil.process_iter(["cmdline"]):
        if p.info["cmdline"] == ["sleep", "321.75"] and p.status() != psutil.STATUS_ZOMBIE:
            out.append(p)
    return out


def _gone(check, seconds: float) -> bool:
    deadline = time.monotonic() + seconds
    while check() and time.monotonic() < deadline:
        time.sleep(0.1)
    return not check()


def test_a_killed_drivers_instance_and_folder_are_gone_within_5_s(tmp_path):
    private = tmp_path / "ocray-test"
    private.mkdir()
    (private / "session").write_text("x")
    script = tmp_path / "driver.py"
    script.write_text(DRIVER)
    driver = subprocess.Popen([sys.executable, str(script), str(private)],
                              stdout=subprocess.PIPE, text=True)
    try:
        assert driver.stdout.readline().strip() == "started"
        assert _gone(lambda: not _sleepers(), 10), "the stand-in instance never started"
        driver.send_signal(signal.SIGKILL)
        driver.wait(5)
        assert _gone(_sleepers, 5)
        assert _gone(private.exists, 5)
    finally:
        driver.kill()
        for p in _sleepers():
            p.kill()


def test_kill_instance_leaves_other_processes_alone(tmp_path):
    mine = subprocess.Popen(["sh", "-c", "sleep 321.75 & wait", str(tmp_path / "ocray-a")])
    other = subprocess.Popen(["sleep", "321.5"])
    try:
        assert _gone(lambda: not _sleepers(), 10)
        killed = kill_instance(str(tmp_path / "ocray-a"))
        assert mine.pid in killed and other.pid not in killed
        mine.wait(5)
        assert other.poll() is None
        assert _gone(_sleepers, 5)
    finally:
        other.kill()
        mine.kill()
