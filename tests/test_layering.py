"""ARCHITECTURE: the core never loads heavy optional packages.

``import ocplus_plan`` registers the Gymnasium ids (as Minigrid and ALE do), so any import
of the package loads gymnasium, a core dependency; the simulator's own modules still never
import it (checked in their source), and nothing loads the optional heavy packages.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import ocplus_plan

OPTIONAL_HEAVY = ("unified_planning", "pygame", "torch", "matplotlib")
SIM_DIR = Path(ocplus_plan.__file__).parent / "sim"


def loaded_after(statement: str) -> set[str]:
    code = f"import sys; {statement}; print(' '.join(sorted(sys.modules)))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return set(out.stdout.split())


def imported_roots(path: Path) -> set[str]:
    """Top-level names of the absolute imports in one module's source."""
    roots = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            roots |= {alias.name.split(".")[0] for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            roots.add(node.module.split(".")[0])
    return roots


def test_importing_the_simulator_loads_no_heavy_package():
    mods = loaded_after("import ocplus_plan.sim; import ocplus_plan.sim.step")
    assert not {m.split('.')[0] for m in mods} & set(OPTIONAL_HEAVY)


def test_the_simulator_modules_import_no_gymnasium_and_no_heavy_package():
    modules = sorted(SIM_DIR.glob("*.py"))
    assert len(modules) > 5
    for path in modules:
        bad = imported_roots(path) & {"gymnasium", *OPTIONAL_HEAVY}
        assert not bad, f"{path.name} imports {sorted(bad)}"


def test_running_check_map_loads_no_heavy_package():
    mods = loaded_after("from ocplus_plan.cli import main; main(['check-map', 'mapC'])")
    assert not {m.split('.')[0] for m in mods} & set(OPTIONAL_HEAVY)
