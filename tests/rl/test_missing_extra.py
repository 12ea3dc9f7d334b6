"""Without the rl extra, training and ppo agents fail with an error that names the extra."""

from __future__ import annotations

import subprocess
import sys

BLOCK = "import sys; sys.modules['torch'] = None; sys.modules['stable_baselines3'] = None; "


def _run(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", BLOCK + code], capture_output=True, text=True,
                          check=False)


def test_train_without_the_extra_exits_3_naming_it(tmp_path):
    out = _run("from ocplus_plan.cli import main; "
               f"sys.exit(main(['train', '--steps', '10', '--out', {str(tmp_path / 'x')!r}]))")
    assert out.returncode == 3
    assert "pip install 'ocplus-plan[rl]'" in out.stderr


def test_ppo_agent_without_the_extra_names_it():
    out = _run("from ocplus_plan.agents import make_controller\n"
               "try:\n    make_controller('ppo')\nexcept Exception as e:\n"
               "    print(type(e).__name__, e)")
    assert out.stdout.startswith("DependencyNotInstalled") and "[rl]" in out.stdout


def test_importing_the_rl_package_loads_no_torch():
    code = ("import sys, ocplus_plan.rl, ocplus_plan.agents.ppo, ocplus_plan.commands.train; "
            "print('torch' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
