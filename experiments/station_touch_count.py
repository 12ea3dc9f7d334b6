"""How many package files a new kind of station ("oven") touches, counted with grep at a
commit (read with ``git show``, no checkout).

Two counts over ``ocplus_plan/**/*.py``:

* ``enumerating``: files that name *every* existing station kind (board, pan, sink, trash
  can, serving window) by its code (``Cell.BOARD``, ``CELL_BOARD`` or a private
  ``_BOARD``): each enumerates the stations one by one, so a new kind joins it;
* ``presentation``: files that tie a station's code to a word, letter, colour, sprite or
  planning name in place: a line with a station code followed by a string or a tuple
  literal (``Cell.PAN: "pan"``, ``CellKind(Cell.PAN, "pan", ...``), or, under
  ``render/``, a drawing branch (``elif code == Cell.PAN:``). A station whose rules are
  those of an existing one touches these files only;
* ``rule_code``: files outside ``sim/rules.py`` and ``sim/processes.py`` that write a process
  station's rule in place (a comparison with the board's, pan's or sink's code, a walk over
  ``geo.pans``, a read of ``chop_steps`` / ``cook_time`` / ``burn_time`` / ``wash_steps``);
* ``added_station``: files that name an added process station (the oven: ``Cell.OVEN``,
  ``CELL_OVEN``, ``_OVEN``), the files adding it touched (0 before the oven existed).
  ``examples/oven_kitchen.yaml`` (its record in a kitchen file) is outside the package and
  counted by hand; ``golden_domains`` counts the checked-in domains (``domains/``) that
  differ from the commit given before it (adding the oven changed none).

Example::

    .venv/bin/python experiments/station_touch_count.py cf6e435 HEAD \\
        --out experiments/results/house/station-touch-count.jsonl
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
from pathlib import Path

STATIONS = ("BOARD", "PAN", "SINK", "TRASH", "DELIVERY")
CODE = r"(?:Cell\.|CELL_|\b_)({})\b"
PRESENTATION = re.compile(CODE.format("|".join(STATIONS)) + r"(?:\)?: *[\"(]|, *\")")
DRAWING = re.compile(r"code == " + CODE.format("|".join(STATIONS)) + r":$", re.MULTILINE)
PROCESS_STATIONS = ("BOARD", "PAN", "SINK")
_PROC = CODE.format("|".join(PROCESS_STATIONS))
RULE = re.compile(rf"(?:==|!=)\s*{_PROC}|{_PROC}\s*(?:==|!=)|\bgeo\.pans\b"
                  r"|\brules?\.(?:chop_steps|cook_time|burn_time|wash_steps)\b")
RULE_HOMES = ("ocplus_plan/sim/rules.py", "ocplus_plan/sim/processes.py")
ADDED = re.compile(CODE.format("OVEN"))
GOLDEN = "domains"


def files_at(commit: str) -> dict[str, str]:
    names = subprocess.run(["git", "ls-tree", "-r", "--name-only", commit, "ocplus_plan"],
                           capture_output=True, text=True, check=True).stdout.split()
    return {n: subprocess.run(["git", "show", f"{commit}:{n}"], capture_output=True,
                              text=True, check=True).stdout
            for n in names if n.endswith(".py")}


def golden_at(commit: str) -> dict[str, str]:
    names = subprocess.run(["git", "ls-tree", "-r", "--name-only", commit, GOLDEN],
                           capture_output=True, text=True, check=True).stdout.split()
    return {n: subprocess.run(["git", "show", f"{commit}:{n}"], capture_output=True,
                              text=True, check=True).stdout for n in names}


def counts(commit: str, base: dict[str, str] | None = None) -> dict:
    files = files_at(commit)
    enumerating = sorted(n for n, text in files.items()
                         if all(re.search(CODE.format(s), text) for s in STATIONS))
    presentation = sorted(n for n, text in files.items() if PRESENTATION.search(text) or (
        n.startswith("ocplus_plan/render/") and DRAWING.search(text)))
    rule_code = sorted(n for n, text in files.items()
                       if n not in RULE_HOMES and RULE.search(text))
    added = sorted(n for n, text in files.items() if ADDED.search(text))
    golden = golden_at(commit)
    changed = sorted(n for n in set(golden) | set(base or golden)
                     if golden.get(n) != (base or golden).get(n))
    sha = subprocess.run(["git", "rev-parse", "--short", commit], capture_output=True,
                         text=True, check=True).stdout.strip()
    return {"commit": sha, "package_files": len(files), "enumerating": len(enumerating),
            "presentation": len(presentation), "rule_code": len(rule_code),
            "added_station": len(added), "golden_domains": len(changed),
            "enumerating_files": enumerating, "presentation_files": presentation,
            "rule_code_files": rule_code, "added_station_files": added,
            "golden_domains_changed": changed}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("commits", nargs="+")
    p.add_argument("--out", type=Path, default=None)
    args = p.parse_args()
    lines, base = [], None
    for c in args.commits:  # golden domains: against the commit given before
        lines.append(counts(c, base))
        base = golden_at(c)
    for line in lines:
        print(json.dumps(line))
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text("".join(json.dumps(line) + "\n" for line in lines))


if __name__ == "__main__":
    main()
