"""Package data: maps, planner configurations, generated PDDL domains, shipped checkpoints.

Each kind of file lives once, in its top-level folder of the source tree (``maps/``,
``planners/``, ``domains/``, ``experiments/checkpoints/``). ``pyproject.toml`` maps those
folders onto the subpackages ``ocplus_plan.data.maps``, ``.planners``, ``.domains`` and
``.checkpoints`` (setuptools ``package-dir``): a wheel carries them inside the package, and
an editable install finds them where they are. Everything reads them through
:mod:`importlib.resources`, so no path is computed from a source file's location.
"""

from __future__ import annotations

from importlib import resources
from typing import TYPE_CHECKING

from ..errors import OcplusError

if TYPE_CHECKING:
    from importlib.resources.abc import Traversable

#: data kind -> the source folder it is built from (relative to the project root)
SOURCE_FOLDERS: dict[str, str] = {
    "maps": "maps",
    "planners": "planners",
    "domains": "domains",
    "checkpoints": "experiments/checkpoints",
}


def data_files(kind: str) -> Traversable:
    """The folder of one kind of package data (``maps``, ``planners``, ``domains``,
    ``checkpoints``), as an :mod:`importlib.resources` traversable."""
    if kind not in SOURCE_FOLDERS:
        raise OcplusError(f"unknown kind of package data {kind!r}; kinds: {', '.join(SOURCE_FOLDERS)}")
    package = f"{__name__}.{kind}"
    try:
        return resources.files(package)
    except ModuleNotFoundError:
        raise OcplusError(
            f"package data {package} (the {SOURCE_FOLDERS[kind]}/ folder) is not installed: "
            "install the package (`make install`, `pip install -e .` or `pip install .`; after "
            "a change to pyproject.toml an editable install must be redone)"
        ) from None


__all__ = ["SOURCE_FOLDERS", "data_files"]
