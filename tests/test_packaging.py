"""A non-editable install works outside the checkout.

The package data (maps, planner configurations, domains, shipped checkpoints) lives once, in
the top-level folders; pyproject maps them onto ``ocplus_plan.data.*``. This builds a wheel
from a copy of the sources (so no ``build/`` or ``*.egg-info`` lands in the checkout),
installs it into a fresh venv that borrows this venv's dependencies through a ``.pth`` file
(``--no-deps``: nothing is downloaded) and runs the CLI from another directory.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

from ocplus_plan.data import SOURCE_FOLDERS

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = ROOT / "pyproject.toml"
#: what the build reads: the project file, the readme, the code and the data folders
SOURCES = ("pyproject.toml", "README.md", "ocplus_plan", *SOURCE_FOLDERS.values())
pytestmark = pytest.mark.skipif(not PYPROJECT.is_file(), reason="needs the source tree")


def _setuptools_config() -> dict:
    tomllib = pytest.importorskip("tomllib", reason="tomllib needs Python 3.11")
    return tomllib.loads(PYPROJECT.read_text())["tool"]["setuptools"]


def test_the_package_list_covers_every_source_package_and_data_folder():
    config = _setuptools_config()
    on_disk = {".".join(p.parent.relative_to(ROOT).parts)
               for p in (ROOT / "ocplus_plan").rglob("__init__.py")}
    mapped = config["package-dir"]
    assert mapped == {f"ocplus_plan.data.{kind}": folder for kind, folder in SOURCE_FOLDERS.items()}
    assert set(config["packages"]) == on_disk | set(mapped), (
        "pyproject.toml's [tool.setuptools] packages must list every package (a missing one "
        "is silently left out of the wheel)")


def _run(argv: list[str], **kw) -> subprocess.CompletedProcess[str]:
    out = subprocess.run(argv, capture_output=True, text=True, timeout=300, check=False, **kw)
    assert out.returncode == 0, f"{argv}\n{out.stdout[-2000:]}\n{out.stderr[-2000:]}"
    return out


@pytest.fixture(scope="module")
def wheel_venv(tmp_path_factory: pytest.TempPathFactory) -> Path:
    if sys.platform == "win32":
        pytest.skip("the venv layout below is POSIX")
    work = tmp_path_factory.mktemp("wheel")
    src = work / "src"
    for name in SOURCES:
        source, target = ROOT / name, src / name
        if source.is_dir():
            shutil.copytree(source, target, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, target)
    _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation",
          "--no-index", "-q", "-w", str(work / "dist"), str(src)])
    wheel = next((work / "dist").glob("ocplus_plan-*.whl"))
    venv = work / "venv"
    _run([sys.executable, "-m", "venv", "--without-pip", str(venv)])
    site = next(venv.glob("lib/python*/site-packages"))
    borrowed = dict.fromkeys(sysconfig.get_paths()[k] for k in ("purelib", "platlib"))
    # plain path lines: this venv's packages, but not its editable ocplus_plan (whose
    # finder is installed by a .pth file in that folder, which is not processed this way)
    (site / "borrowed_deps.pth").write_text("".join(f"{p}\n" for p in borrowed))
    _run([str(venv / "bin" / "python"), "-m", "pip", "install", "--no-deps", "--no-index",
          "--ignore-installed", "-q", str(wheel)])
    return venv


def _clean_env() -> dict[str, str]:
    drop = ("PYTHONPATH", "OCPLUS_MAPS", "OCPLUS_PLANNERS_DIR")
    return {k: v for k, v in os.environ.items() if k not in drop}


def test_the_wheel_carries_the_package_data_and_reads_it_through_importlib(wheel_venv, tmp_path):
    code = ("import json, ocplus_plan; from ocplus_plan.data import data_files, SOURCE_FOLDERS; "
            "print(json.dumps({'package': ocplus_plan.__file__, **{k: sorted(f.name for f in "
            "data_files(k).iterdir()) for k in SOURCE_FOLDERS}}))")
    out = _run([str(wheel_venv / "bin" / "python"), "-c", code], cwd=tmp_path, env=_clean_env())
    got = json.loads(out.stdout)
    assert Path(got["package"]).is_relative_to(wheel_venv)
    assert {"mapA.yaml", "mapB.yaml", "mapC.yaml"} <= set(got["maps"])
    assert {"fast-downward.yaml", "kairos.yaml"} <= set(got["planners"])
    assert {"temporal_stations.pddl", "classical_stations.pddl"} <= set(got["domains"])
    assert {"easy_1agent.npz", "easy_1agent.json"} <= set(got["checkpoints"])
    assert not [n for n in got["checkpoints"] if n.endswith(".zip")]  # pickles stay out
    assert not [n for n in got["checkpoints"] if n.endswith(".csv")]  # training logs stay out


def test_the_installed_cli_runs_from_another_directory(wheel_venv, tmp_path):
    ocplus = str(wheel_venv / "bin" / "ocplus")
    env = _clean_env()
    out = _run([ocplus, "check-map", "mapC"], cwd=tmp_path, env=env).stdout
    assert out.startswith("map mapC") and str(wheel_venv) in out.splitlines()[0]
    rollout = json.loads(_run([ocplus, "rollout", "--preset", "hard", "--json"], cwd=tmp_path,
                              env=env).stdout)
    assert rollout["map"] == "mapC" and rollout["items_conserved"] and rollout["steps"] == 200
    solved = json.loads(_run([ocplus, "solve", "--preset", "easy", "--planner", "fast-downward",
                              "--json"], cwd=tmp_path, env=env).stdout)
    if solved["status"] == "unavailable":
        pytest.skip(f"fast-downward is not installed: {solved['reason']}")
    assert solved["status"] == "solved" and solved["validated"] is True
    assert list(tmp_path.iterdir()) == []  # nothing written into the working directory


def test_the_installed_ppo_agent_finds_its_shipped_checkpoint(wheel_venv, tmp_path):
    # the shipped checkpoints are weights-only .npz files: no rl extra is needed to play them
    out = _run([str(wheel_venv / "bin" / "ocplus"), "rollout", "--preset", "easy", "--agents",
                "ppo", "--steps", "5", "--json"], cwd=tmp_path, env=_clean_env()).stdout
    checkpoint = Path(json.loads(out)["controller_checkpoint"])
    assert checkpoint.name == "easy_1agent.npz" and checkpoint.is_relative_to(wheel_venv)
