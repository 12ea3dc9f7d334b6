"""Session-wide: a private temporary directory, which the run must leave empty, and a
checkout the run leaves as it found it.

Everything the code under test writes to "the temporary directory" (planner logs and
working directories, Aries' server logs, stable-baselines3's logger folders, VAL files,
subprocesses, which inherit ``TMPDIR``) goes to ``ocplus-tests-XXXX/``, made for this run
alone, so two runs of the suite at once (two clones, two engineers) never share a
temporary path. When the session ends, the last test's teardown fails if anything is left
there but pytest's own ``tmp_path`` folders and other tools' per-user caches
(:data:`NOT_OURS`); a passing run then removes the directory, so nothing is left in /tmp. A
failing run keeps it and says where.
In a git checkout the same teardown compares ``git status --ignored`` before and after: no
file may appear or change (tool caches such as ``__pycache__`` aside).

Ray's session folders hold AF_UNIX sockets, whose paths may not exceed 107 bytes, so they
cannot live inside a long TMPDIR (macOS' is about 50 characters, then our prefix):
``ocplus_plan.eval.ray_backend.private_temp_dir`` makes them in the private folder when
its path is short and in /tmp otherwise; the same teardown checks that none is left in
/tmp either.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from collections.abc import Iterator
from pathlib import Path

import pytest

#: not leftovers: pytest's own basetemp (tmp_path) and the per-user caches that other tools
#: keep in the temporary directory by design and reuse across runs (torch's compiler
#: cache, the JVM's perf data of Kairos / ENHSP)
NOT_OURS = ("pytest-of-", "torchinductor_", "hsperfdata_")
#: caches that tools keep in the checkout (git ignores them)
TOOL_CACHES = ("__pycache__", ".pytest_cache", ".hypothesis", ".ruff_cache")
CHECKOUT = Path(__file__).resolve().parents[1]
_KEY = pytest.StashKey[Path]()
_FAILED = pytest.StashKey[bool]()


def ray_folders() -> set[str]:
    """Ray session folders (``ocray-*``) in /tmp, where a long TMPDIR sends them."""
    from ocplus_plan.eval.ray_backend import TEMP_PREFIX

    base = Path("/tmp")
    return {p.name for p in base.glob(f"{TEMP_PREFIX}*")} if base.is_dir() else set()


def pytest_configure(config: pytest.Config) -> None:
    private = Path(tempfile.mkdtemp(prefix="ocplus-tests-"))
    os.environ["TMPDIR"] = str(private)  # subprocesses: CLI runs, planners
    tempfile.tempdir = str(private)  # this process (gettempdir() caches its first answer)
    config.stash[_KEY] = private


def leftovers(private: Path) -> list[str]:
    """What the code under test left in the session's temporary directory."""
    return sorted(p.name for p in private.iterdir() if not p.name.startswith(NOT_OURS))


def checkout_status() -> set[str] | None:
    """``git status --ignored`` lines of the checkout (None outside a git checkout)."""
    if not (CHECKOUT / ".git").exists() or shutil.which("git") is None:
        return None
    out = subprocess.run(["git", "status", "--porcelain", "--ignored"],
                         cwd=CHECKOUT, capture_output=True, text=True, check=False)
    if out.returncode != 0:
        return None
    return {line for line in out.stdout.splitlines()
            if not any(part in TOOL_CACHES for part in Path(line[3:]).parts)}


@pytest.fixture(scope="session", autouse=True)
def _nothing_left_behind(request: pytest.FixtureRequest) -> Iterator[None]:
    private = request.config.stash[_KEY]
    before = checkout_status()
    rays_before = ray_folders()
    yield
    left = leftovers(private) + sorted(ray_folders() - rays_before)
    assert not left, (
        f"the test run left {left} in its temporary directory {private}: whatever creates "
        "them must remove them (or create them inside a directory it removes)")
    after = checkout_status()
    if before is not None and after is not None:
        assert after <= before, f"the test run wrote into the checkout: {sorted(after - before)}"


def pytest_unconfigure(config: pytest.Config) -> None:
    private = config.stash.get(_KEY, None)
    if private is None or not private.exists():
        return
    if config.stash.get(_FAILED, False):
        print(f"\nocplus tests: temporary files of this run kept in {private}")
    else:
        shutil.rmtree(private, ignore_errors=True)


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    session.config.stash[_FAILED] = exitstatus not in (0, 5)  # 5: no tests collected
