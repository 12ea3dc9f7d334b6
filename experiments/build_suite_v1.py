"""Build the frozen instance set ``suites/v1/``: three tracks graded from trivial to open.

    nice -n 10 .venv/bin/python experiments/build_suite_v1.py --out suites/v1

Each track is an ``ocplus export-suite`` set (``eval/suite.py``) of explicit cells
(:data:`TRACKS`), ordered by the levers planners feel: preset stations (easy, medium,
hard), kitchen (the preset's, or a generated ``gen:`` kitchen), cooks (1 to 4) and goal
orders (1 to 16; above the preset's queue of 2 the queue is raised, rule ``n_orders``).
``suites/v1/manifest.json`` lists the tracks, their scored instances, and the instances
that went to an unsolvability track or were dropped (no plan, no witness, no proof).
Reference planners run with CPU-second limits (:data:`CLASSICAL`, :data:`TEMPORAL`), so
the set does not depend on the machine's load; ``--track`` rebuilds a track, and
``--track T --cells 20-24`` rebuilds those instances of T in place, the others kept
(``tests/eval/test_suite_v1.py`` rebuilds one instance and compares bytes).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from ocplus_plan.eval.suite import Cell, SuiteSpec, export_suite

#: reference portfolios and their CPU seconds per planner call
CLASSICAL = ("fast-downward", "fast-downward-bjolp", "fast-downward-wastar")
#: Kairos (one thread, seed 0, its first plan) in the build; kairos-anytime, whose budget
#: is wall time, runs offline (experiments/temporal_refs_v1.py) and its plans, frozen in
#: TEMPORAL_REFS, are validated, replayed and judged here with Kairos' (eval/suite_offline)
TEMPORAL = ("kairos",)
TEMPORAL_REFS = "experiments/suite_v1_temporal_refs"
TIMEOUT = 10.0
WITNESS_TIMEOUT = 20.0
HORIZON = 1000
FLAT = (("dynamic", False),)  # hard's stations on a kitchen without a layout switch


#: the generated kitchens of v1, frozen as map files: a later generator may draw other
#: kitchens under the same gen: names, and the release must not move with it
KITCHENS = "experiments/suite_v1_kitchens"


def _k(name: str) -> str:
    """The frozen map file of the generated kitchen ``name`` (run from the repository root)."""
    return f"{KITCHENS}/{name.replace(':', '-')}.yaml"


def _c(preset: str, orders: int, cooks: int, sample: int = 0, map: str | None = None,
       rules: tuple[tuple[str, object], ...] = ()) -> Cell:
    return Cell(preset, map, cooks, orders, sample, rules)


#: track -> (encoding, cells), easiest first
TRACKS: dict[str, tuple[str, tuple[Cell, ...]]] = {
    "classical-1cook": ("classical", (
        _c("easy", 1, 1, 0), _c("easy", 1, 1, 1), _c("easy", 1, 1, 2), _c("easy", 1, 1, 3),
        _c("easy", 2, 1, 0), _c("easy", 3, 1, 1), _c("medium", 1, 1, 0),
        _c("medium", 1, 1, 1),
        _c("medium", 2, 1, 2), _c("medium", 3, 1, 3), _c("easy", 6, 1, 2),
        _c("medium", 2, 1, 0, _k("gen:open:test:0:medium")),
        _c("medium", 4, 1, 0), _c("medium", 6, 1, 1),
        _c("hard", 3, 1, 0, _k("gen:open:test:0"), FLAT),
        _c("hard", 4, 1, 1, _k("gen:multiroom:test:1"), FLAT),
        _c("medium", 10, 1, 2), _c("hard", 8, 1, 0, _k("gen:open:test:2"), FLAT),
        _c("medium", 16, 1, 3, _k("gen:multiroom:test:2:medium")),
        # the open end: 48 to 96 orders in the largest generated kitchens (12x12); with
        # one cook the goals nearly serialise, so only many orders outgrow 300 CPU s
        _c("hard", 64, 1, 0, _k("gen:corridor:test:28"), FLAT),
        _c("hard", 1, 1, 0),  # hard's own map with one cook: unsolvable by construction
        _c("hard", 64, 1, 1, _k("gen:corridor:test:31"), FLAT),
        _c("hard", 48, 1, 2, _k("gen:corridor:test:31"), FLAT),
        _c("hard", 96, 1, 3, _k("gen:multiroom:test:48"), FLAT),
    )),
    "classical-multicook": ("classical", (
        _c("easy", 1, 2, 0), _c("easy", 1, 2, 1), _c("easy", 1, 2, 2), _c("easy", 1, 2, 3),
        _c("easy", 2, 2, 0), _c("easy", 3, 2, 1), _c("easy", 2, 3, 2, "trio_kitchen"),
        _c("medium", 1, 2, 0),
        _c("medium", 1, 2, 1), _c("medium", 2, 2, 2), _c("hard", 1, 2, 0, None, FLAT),
        _c("hard", 2, 2, 1, None, FLAT),
        _c("medium", 3, 2, 3), _c("medium", 2, 2, 0, _k("gen:open:test:1:medium")),
        _c("hard", 3, 2, 2, None, FLAT), _c("medium", 2, 3, 1, _k("gen:open:test:4:medium")),
        _c("medium", 6, 2, 0, _k("gen:open:test:5:medium")),
        _c("hard", 8, 3, 1, _k("gen:multiroom:test:6"), FLAT),
        _c("medium", 10, 4, 2, _k("gen:open:test:6:medium")),
        _c("hard", 12, 4, 3, _k("gen:split:test:8"), FLAT),
        _c("hard", 16, 4, 0, _k("gen:open:test:8"), FLAT),
        # its witness is refused by the kitchen (a cook in the corridor with nowhere to
        # step aside): the builder drops it as unknown, and the next cell takes its place
        _c("hard", 12, 3, 2, _k("gen:corridor:test:10"), FLAT),
        _c("hard", 20, 4, 1, _k("gen:open:test:8"), FLAT),
    )),
    "temporal": ("temporal", (
        # sample 0 stood first: Aries ran out of its 30 CPU s on it (it solves the same
        # kitchen from other start cells in 8-15 s: experiments/aries_start_cells.py), so
        # it could not open a first fifth that every working planner solves; sample 4 does
        _c("easy", 1, 1, 4), _c("easy", 1, 1, 1), _c("easy", 1, 1, 2), _c("easy", 1, 1, 3),
        _c("easy", 2, 1, 0), _c("easy", 1, 2, 1), _c("easy", 3, 1, 2), _c("easy", 2, 2, 3),
        _c("medium", 1, 1, 0), _c("medium", 2, 1, 1), _c("medium", 1, 2, 2),
        _c("hard", 1, 2, 0, None, FLAT),
        _c("medium", 3, 1, 3), _c("medium", 4, 1, 0), _c("medium", 2, 2, 1),
        _c("hard", 3, 1, 2, _k("gen:open:test:0"), FLAT),
        _c("medium", 6, 1, 2),
        # the open end: one cook (a goal-agenda witness with two or more cooks is refused
        # by the simulator when their time-triggered segments cross)
        _c("medium", 8, 1, 1), _c("hard", 8, 1, 2, _k("gen:open:test:5"), FLAT),
        # medium with 12 orders (gen:multiroom:test:2:medium) stood here: kairos-anytime
        # solved it in 285.6 of 300 CPU s, so it could not end the track
        _c("hard", 12, 1, 2, _k("gen:open:test:8"), FLAT),
        _c("hard", 16, 1, 0, _k("gen:open:test:8"), FLAT),
        _c("hard", 24, 1, 1, _k("gen:open:test:8"), FLAT),
    )),
}


def spec_of(track: str, cells: tuple[Cell, ...] | None = None) -> SuiteSpec:
    """The export-suite spec of a track (``cells``: a slice of it, for a rebuild)."""
    encoding, all_cells = TRACKS[track]
    planners = {"classical": CLASSICAL, "temporal": TEMPORAL}
    offline = (("temporal", TEMPORAL_REFS),) if encoding == "temporal" else ()
    return SuiteSpec(encodings=(encoding,), cells=cells or all_cells, timeout=TIMEOUT,
                     planners={encoding: planners[encoding]}, fallback=False,
                     horizon=HORIZON, witness_timeout=WITNESS_TIMEOUT,
                     offline_plans=offline)


def suite_manifest(out: Path) -> dict[str, object]:
    """The suite-level manifest, read from the tracks' own manifests."""
    tracks = {}
    for track, (encoding, _) in TRACKS.items():
        path = out / track / "manifest.json"
        if not path.is_file():
            continue
        sets = json.loads(path.read_text(encoding="utf-8"))["tracks"]
        tracks[track] = {"encoding": encoding, "folder": track,
                         "scored": sets.get(encoding, []),
                         "unsolvable": sets.get(f"{encoding}-unsolvable", []),
                         "dropped": sets.get(f"{encoding}-unknown", [])}
    return {"format": "ocplus-suite-release/1", "name": "v1",
            "command": "python experiments/build_suite_v1.py --out suites/v1",
            "tracks": tracks}


def _numbers(text: str) -> set[int]:
    """``20-24,3`` -> the cell indices {19, ..., 23, 2} (instance pNN is cell NN)."""
    out: set[int] = set()
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        if not lo.isdigit() or not (hi or lo).isdigit():
            raise SystemExit(f"--cells {text!r}: write instance numbers, e.g. 20-24 or 1,3")
        out.update(range(int(lo) - 1, int(hi or lo)))
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="suites/v1")
    ap.add_argument("--track", action="append", choices=sorted(TRACKS),
                    help="build only these tracks (default: all)")
    ap.add_argument("--cells", default=None,
                    help="rebuild only these cells of each --track in a set already in OUT, "
                         "by instance number: e.g. 20-24 or 1,3 (the others are kept)")
    ap.add_argument("--manifest-only", action="store_true",
                    help="only (re)write OUT/manifest.json from the tracks' manifests")
    args = ap.parse_args(argv)
    out = Path(args.out)
    select = _numbers(args.cells) if args.cells else None
    if select is not None and not args.track:
        ap.error("--cells needs --track (the cells of which track)")
    for track in [] if args.manifest_only else args.track or list(TRACKS):
        rows = export_suite(spec_of(track), out / track, select=select,
                            progress=lambda m, t=track: print(f"[{t}] {m}", flush=True))
        for r in rows:
            cpu = sum(t["cpu_time"] or 0 for t in r["tried"])
            print(f"[{track}] {r['instance']} {r['status']} {r['planner']} "
                  f"cost {r['cost']} makespan {r['makespan']} faithful {r['faithful']} "
                  f"optimal {r['optimal']} portfolio CPU {cpu:.1f} s", flush=True)
    (out / "manifest.json").write_text(json.dumps(suite_manifest(out), indent=1,
                                                  sort_keys=True) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
