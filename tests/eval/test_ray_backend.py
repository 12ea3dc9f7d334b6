"""``--backend ray``: refused without the extra, same rows as the local backend, resume
across backends, and a sweep that survives a Ray worker killed in the middle of it.

One small Ray instance (2 CPUs) serves the whole module; its session files live in a
short private folder (:func:`~ocplus_plan.eval.ray_backend.private_temp_dir`: in the test
session's TMPDIR when that path is short, else in /tmp) that is removed with it."""

from __future__ import annotations

import shutil
import signal
import sys
import threading
import time
from collections import Counter
from pathlib import Path

import psutil
import pytest

from ocplus_plan.cli import EXIT_DEPENDENCY, main
from ocplus_plan.errors import ConfigError, DependencyNotInstalled
from ocplus_plan.eval.results import read_results
from ocplus_plan.eval.runner import EvalConfig, run_eval

#: greedy cooks on the hard map for this many steps take about 3 s an episode: long
#: enough to be killed in the middle
LONG_HORIZON = 20000


def _cfg(out, **kw) -> EvalConfig:
    base = dict(presets=["easy"], agents=["greedy", "random"], seeds=[0, 1], out=out,
                horizon=80, n_agents=2, quiet=True, backend="ray")
    base.update(kw)
    return EvalConfig(**base)


def _quiet(*_args) -> None:
    return None


@pytest.fixture(scope="module")
def ray_instance():
    ray = pytest.importorskip("ray", reason="the `cluster` extra (Ray) is not installed")
    from ocplus_plan.eval.ray_backend import private_temp_dir

    private = private_temp_dir()  # short whatever TMPDIR is: Ray's socket paths are limited
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, _temp_dir=private,
             logging_level="WARNING")
    try:
        yield ray
    finally:
        ray.shutdown()
        shutil.rmtree(private, ignore_errors=True)


# ------------------------------------------------------------------ refusals
def test_ray_backend_without_the_extra_is_refused_naming_it(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "ray", None)  # import ray -> ImportError
    with pytest.raises(DependencyNotInstalled, match=r"\[cluster\]"):
        run_eval(_cfg(tmp_path / "run"), echo=_quiet)
    assert not (tmp_path / "run").exists()  # refused before anything was written


def test_cli_exit_code_for_a_missing_ray_names_the_extra(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "ray", None)
    code = main(["eval", "--preset", "easy", "--agents", "greedy", "--seeds", "1",
                 "--backend", "ray", "--out", str(tmp_path / "run"), "--quiet"])
    assert code == EXIT_DEPENDENCY and "[cluster]" in capsys.readouterr().err


def test_address_without_the_ray_backend_is_an_error(tmp_path):
    with pytest.raises(ConfigError, match="--backend ray"):
        run_eval(_cfg(tmp_path / "run", backend="local", address="auto"), echo=_quiet)


def test_unknown_backend_is_an_error(tmp_path):
    with pytest.raises(ConfigError, match="local, ray"):
        run_eval(_cfg(tmp_path / "run", backend="slurm"), echo=_quiet)


# ------------------------------------------------------------------ same rows
def test_ray_rows_have_the_same_metrics_as_local_rows(tmp_path, ray_instance):
    run_eval(_cfg(tmp_path / "local", backend="local", jobs=2), echo=_quiet)
    run_eval(_cfg(tmp_path / "ray"), echo=_quiet)
    local = {r["key"]: r for r in read_results(tmp_path / "local")}
    on_ray = {r["key"]: r for r in read_results(tmp_path / "ray")}
    assert set(local) == set(on_ray) and len(on_ray) == 4
    for key, row in on_ray.items():
        assert row["status"] == "ok"
        assert _outcome_metrics(row) == _outcome_metrics(local[key])


def _outcome_metrics(row: dict) -> dict:
    """The metrics that depend on the episode alone (not on how fast the machine thought)."""
    return {k: v for k, v in row["metrics"].items() if not k.startswith("decision_time")}


def test_ray_rows_name_the_backend_node_and_wall_time(tmp_path, ray_instance):
    run_eval(_cfg(tmp_path / "ray", agents=["greedy"], seeds=[0]), echo=_quiet)
    (row,) = read_results(tmp_path / "ray")
    assert row["worker"]["backend"] == "ray"
    assert row["worker"]["node"] and row["worker"]["node_id"] == ray_instance.get_runtime_context(
    ).get_node_id()
    assert row["timings"]["wall_time_s"] > 0


def test_cli_on_ray_shows_progress_and_leaderboard(tmp_path, ray_instance, capsys):
    code = main(["eval", "--preset", "easy", "--agents", "greedy,random", "--seeds", "2",
                 "--horizon", "60", "--backend", "ray", "--out", str(tmp_path / "run")])
    captured = capsys.readouterr()
    assert code == 0 and "on Ray" in captured.out
    assert "eval: 100%" in captured.err and "4/4" in captured.err  # the progress bar
    assert "1 greedy" in captured.out  # the leaderboard ranks greedy first


def test_resume_continues_a_local_run_on_ray(tmp_path, ray_instance):
    out = tmp_path / "run"
    run_eval(_cfg(out, backend="local", seeds=[0]), echo=_quiet)
    outcome = run_eval(_cfg(out, seeds=[0, 1, 2], resume=True), echo=_quiet)
    rows = read_results(out)
    assert outcome.ran == 4  # seeds 1 and 2 of both agents
    assert Counter(r["key"] for r in rows).most_common(1)[0][1] == 1 and len(rows) == 6
    assert Counter(r["worker"]["backend"] for r in rows) == {"local": 2, "ray": 4}


def test_episode_timeout_on_ray_becomes_an_error_row(tmp_path, ray_instance):
    cfg = _cfg(tmp_path / "run", presets=["hard"], agents=["greedy"], seeds=[0],
               horizon=LONG_HORIZON, episode_timeout=0.5)
    outcome = run_eval(cfg, echo=_quiet)
    (row,) = read_results(tmp_path / "run")
    assert outcome.errors == 1 and row["status"] == "error"
    assert "timed out after 0.5 s" in row["reason"]


# ------------------------------------------------------------------ faults
def _busy_workers() -> list[psutil.Process]:
    """Ray workers (children of the raylet) that are running an episode right now: the
    episode's own process (forked by the task) is their child."""
    busy = []
    for proc in psutil.process_iter(["cmdline"]):
        try:
            if (proc.info["cmdline"] or [""])[0] != "ray::ocplus-episode":
                continue
            if proc.parent().name() == "raylet" and proc.children():
                busy.append(proc)
        except (psutil.Error, AttributeError):  # ended while we looked
            continue
    return busy


def _kill_one_busy_worker(killed: list[int], stop: threading.Event) -> None:
    """Wait until an episode has run for a moment, then SIGKILL the Ray worker running it."""
    while not stop.is_set():
        for worker in _busy_workers():
            if time.time() - worker.children()[0].create_time() > 0.5:
                worker.send_signal(signal.SIGKILL)
                killed.append(worker.pid)
                return
        time.sleep(0.1)


def _sweep_with_a_killed_worker(out, retries: int):
    killed: list[int] = []
    stop = threading.Event()
    killer = threading.Thread(target=_kill_one_busy_worker, args=(killed, stop), daemon=True)
    killer.start()
    try:
        outcome = run_eval(_cfg(out, presets=["hard"], agents=["greedy"], seeds=[0, 1, 2],
                                horizon=LONG_HORIZON, retries=retries), echo=_quiet)
    finally:
        stop.set()
        killer.join(5)
    assert len(killed) == 1, "no Ray worker was found running an episode"
    return outcome, read_results(out)


def test_killed_worker_has_its_episode_retried_and_every_row_once(tmp_path, ray_instance):
    outcome, rows = _sweep_with_a_killed_worker(tmp_path / "run", retries=2)
    assert outcome.errors == 0 and all(r["status"] == "ok" for r in rows)
    assert sorted(r["seed"] for r in rows) == [0, 1, 2]  # each episode exactly once


def test_episode_whose_worker_dies_past_its_retries_is_an_error_row(tmp_path, ray_instance):
    outcome, rows = _sweep_with_a_killed_worker(tmp_path / "run", retries=0)
    assert sorted(r["seed"] for r in rows) == [0, 1, 2]
    (failed,) = [r for r in rows if r["status"] == "error"]
    assert outcome.errors == 1 and "failed after 1 attempt(s)" in failed["reason"]
    assert "Worker" in failed["reason"] or "died" in failed["reason"]


def test_cluster_that_cannot_be_joined_is_an_error_before_any_file(tmp_path, monkeypatch):
    ray = pytest.importorskip("ray", reason="the `cluster` extra (Ray) is not installed")

    def refuse(**_kwargs):
        raise ConnectionError("Failed to connect to Ray cluster at 10.0.0.9:6379")

    monkeypatch.setattr(ray, "is_initialized", lambda: False)
    monkeypatch.setattr(ray, "init", refuse)
    with pytest.raises(ConfigError, match="could not join the Ray cluster at 10.0.0.9:6379.*"
                                          "ray start --head"):
        run_eval(_cfg(tmp_path / "run", address="10.0.0.9:6379"), echo=_quiet)
    assert not (tmp_path / "run").exists()


# ------------------------------------------------------------------ Ray's temporary folder
def test_rays_folder_is_short_whatever_tmpdir_is(tmp_path, monkeypatch):
    import tempfile

    from ocplus_plan.eval import ray_backend

    long = tmp_path / ("a-directory-name-of-sixty-characters-like-the-ones-macos-uses"[:60])
    long.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(long))
    private = ray_backend.private_temp_dir()
    try:
        # Ray's deepest socket path under it stays inside the 107 bytes of AF_UNIX
        deepest = f"{private}/session_2026-11-24_22-49-35_123456_1234567/sockets/plasma_store"
        assert len(deepest) <= 107 and not private.startswith(str(long))
        assert Path(private).name.startswith(ray_backend.TEMP_PREFIX)
    finally:
        Path(private).rmdir()
    monkeypatch.setattr(tempfile, "tempdir", "/tmp")
    assert ray_backend.short_temp_base() == Path("/tmp")
