"""Without the rl extra, training and ppo agents fail with an error that names the extra."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

BLOCK = "import sys; sys.modules['torch'] = None; sys.modules['stable_baselines3'] = None; "


def _run(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", BLOCK + code], capture_output=True, text=True,
                          check=False)


def test_train_without_the_extra_exits_3_naming_it(tmp_path):
    out = _run("from ocplus_plan.cli import main; "
               f"sys.exit(main(['train', '--steps', '10', '--out', {str(tmp_path / 'x')!r}]))")
    assert out.returncode == 3
    assert "pip install 'ocplus-plan[rl]'" in out.stderr


def test_ppo_agent_plays_without_the_extra_and_an_sb3_zip_names_it():
    zipped = Path(__file__).resolve().parents[2] / "experiments/checkpoints/easy_1agent.zip"
    out = _run("import os\nfrom ocplus_plan.agents import make_controller\n"
               "from ocplus_plan.sim import make_rules, new_state\n"
               "a = make_controller('ppo'); s = new_state(make_rules('easy'), 0); a.reset(s)\n"
               "print(len(a.act(s)))\n"
               "os.environ['OCPLUS_TRUST_PICKLED_CHECKPOINT'] = '1'\n"
               f"try:\n    make_controller('ppo:{zipped}')\nexcept Exception as e:\n"
               "    print(type(e).__name__, e)")
    first, second = out.stdout.splitlines()
    assert first == "1"  # the weights-only checkpoint needs numpy alone
    assert second.startswith("DependencyNotInstalled") and "[rl]" in second


def test_importing_the_rl_package_loads_no_torch():
    code = ("import sys, ocplus_plan.rl, ocplus_plan.agents.ppo, ocplus_plan.commands.train; "
            "print('torch' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
