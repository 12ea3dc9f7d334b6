"""The Python API group of the hostile corpus (tests/fuzz/corpus_api.py): float, NaN and
huge actions, oversized env options, the JAX kitchen's actions and a checkpoint header that
asks for a terabyte, each in a forked child under the corpus limits, each ending in the
package's own error with one readable line."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from tests.fuzz.corpus_api import CASES, available
from tests.fuzz.limited import SECONDS

ROOT = Path(__file__).resolve().parents[2]


def test_every_api_case_raises_the_packages_error_in_one_line():
    done = subprocess.run([sys.executable, "-m", "tests.fuzz.corpus_api"], cwd=ROOT,
                          capture_output=True, text=True, check=True,
                          timeout=SECONDS * len(CASES) + 60)
    rows = [json.loads(line) for line in done.stdout.splitlines()]
    assert [r["case"] for r in rows] == [name for name in CASES if available(name)]
    bad = [r for r in rows if not r["package_error"] or r["killed"] or "\n" in r["message"]
           or r["seconds"] >= SECONDS or "-9223372036854775808" in r["message"]]
    assert not bad, json.dumps(bad, indent=1)
