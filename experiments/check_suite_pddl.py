"""Does the code still write a frozen instance set's PDDL byte for byte? Every instance of
every track is loaded (its ``state.json`` and rules), compiled again in its encoding and
its problem text compared with the checked-in file; each track's domain with the one the
code writes. Planner-free: compilation only (about a second per instance on one core).

    nice -n 10 .venv/bin/python experiments/check_suite_pddl.py suites/v1
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ocplus_plan.errors import ConfigError
from ocplus_plan.eval.suite import load_instance
from ocplus_plan.planning.pddl import domain_text


def check(root: Path) -> dict:
    top = json.loads((root / "manifest.json").read_text(encoding="utf-8"))
    same = differ = 0
    wrong: list[str] = []
    for track, info in top["tracks"].items():
        folder, enc = root / info["folder"], info["encoding"]
        names = json.loads((folder / "manifest.json").read_text())["instances"]
        granularity = json.loads((folder / names[0] / "manifest.json").read_text())["granularity"]
        if domain_text(enc, granularity) != (folder / enc / "domain.pddl").read_text():
            wrong.append(f"{track}/{enc}/domain.pddl")
        for name in names:
            try:
                load_instance(folder / name).compiled(enc)
                same += 1
            except ConfigError as exc:
                differ += 1
                wrong.append(f"{track}/{name}: {exc}")
    return {"set": str(root), "instances_same": same, "instances_differ": differ,
            "wrong": wrong}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("root", type=Path, nargs="?", default=Path("suites/v1"))
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    out = check(args.root)
    print(json.dumps(out))
    sys.exit(1 if out["wrong"] else 0)


if __name__ == "__main__":
    main()
