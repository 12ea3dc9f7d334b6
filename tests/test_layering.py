"""ARCHITECTURE: the core never loads heavy optional packages."""

from __future__ import annotations

import subprocess
import sys

HEAVY = ("unified_planning", "pygame", "torch", "matplotlib", "gymnasium")


def loaded_after(statement: str) -> set[str]:
    code = f"import sys; {statement}; print(' '.join(sorted(sys.modules)))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return set(out.stdout.split())


def test_importing_the_simulator_loads_no_heavy_package():
    mods = loaded_after("import ocplus_plan.sim; import ocplus_plan.sim.step")
    assert not {m.split('.')[0] for m in mods} & set(HEAVY)


def test_running_check_map_loads_no_heavy_package():
    mods = loaded_after("from ocplus_plan.cli import main; main(['check-map', 'mapC'])")
    assert not {m.split('.')[0] for m in mods} & {"unified_planning", "pygame", "torch", "matplotlib"}
