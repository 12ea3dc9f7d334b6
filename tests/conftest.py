"""Session-wide: a private temporary directory, which the run must leave empty.

Everything the code under test writes to "the temporary directory" (planner logs and
working directories, Aries' server logs, stable-baselines3's logger folders, VAL files,
subprocesses, which inherit ``TMPDIR``) goes to ``ocplus-tests-XXXX/``, made for this run
alone, so two runs of the suite at once (two clones, two engineers) never share a
temporary path. When the session ends, the last test's teardown fails if anything is left
there but pytest's own ``tmp_path`` folders and other tools' per-user caches
(:data:`NOT_OURS`); a passing run then removes the directory, so nothing is left in /tmp. A
failing run keeps it and says where.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

import pytest

#: not leftovers: pytest's own basetemp (tmp_path) and the per-user caches that other tools
#: keep in the temporary directory by design and reuse across runs (torch's compiler
#: cache, the JVM's perf data of Kairos / ENHSP)
NOT_OURS = ("pytest-of-", "torchinductor_", "hsperfdata_")
_KEY = pytest.StashKey[Path]()
_FAILED = pytest.StashKey[bool]()


def pytest_configure(config: pytest.Config) -> None:
    private = Path(tempfile.mkdtemp(prefix="ocplus-tests-"))
    os.environ["TMPDIR"] = str(private)  # subprocesses: CLI runs, planners
    tempfile.tempdir = str(private)  # this process (gettempdir() caches its first answer)
    config.stash[_KEY] = private


def leftovers(private: Path) -> list[str]:
    """What the code under test left in the session's temporary directory."""
    return sorted(p.name for p in private.iterdir() if not p.name.startswith(NOT_OURS))


@pytest.fixture(scope="session", autouse=True)
def _nothing_left_in_the_temporary_directory(request: pytest.FixtureRequest) -> Iterator[None]:
    private = request.config.stash[_KEY]
    yield
    left = leftovers(private)
    assert not left, (
        f"the test run left {left} in its temporary directory {private}: whatever creates "
        "them must remove them (or create them inside a directory it removes)")


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
