"""``ocplus generate``: write generated kitchens as YAML map files, with a manifest.

``--family F --n N --seed S`` writes the kitchens of seeds S .. S+N-1; with ``--split
train|test`` the kitchens of indices S .. S+N-1 of that split instead (the ones
``gen:F:SPLIT:INDEX`` names, with the same bytes). Sizes and cooks are drawn from each
seed unless ``--rows``, ``--cols`` or ``--cooks`` fix them. With ``--prove`` (opt-in:
it runs Fast Downward per kitchen, seconds to minutes each) every kitchen must get a validated plan for one
order with all its cooks, which the simulator follows (``ocplus_plan.planning.prove``);
a kitchen that fails is replaced by the next candidate of its seed, and ``manifest.json``
lists what was replaced and why. With ``--recipes LENGTHS`` each kitchen also gets a menu
drawn from its seed (``--menu`` dishes of those lengths that it can make,
``sim.generate_recipes.draw_dishes``), written into its file under ``recipes:``. The YAML
files are the same bytes for the same arguments.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from ..errors import ConfigError, DependencyNotInstalled
from ..sim.generate import (
    FAMILIES,
    PRESET_STATIONS,
    SPLITS,
    first_candidate,
    generate_map,
    map_to_yaml,
    split_seed,
)
from ..sim.dishes import MAX_RECIPES, dish_to_dict
from ..sim.generate_recipes import MAX_LENGTH, draw_dishes
from ..sim.maps import load_map
from ..sim.presets import PRESETS
from . import _types
from ._common import HelpFormatter, add_output_args, emit, say


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("generate", help="write generated kitchens (YAML maps and a manifest)",
                       description=__doc__, formatter_class=HelpFormatter)
    p.add_argument("--family", required=True, choices=FAMILIES, help="kitchen family")
    p.add_argument("--n", type=_types.whole("--n", 1, 10_000), default=1, help="how many kitchens")
    p.add_argument("--seed", type=_types.seed, default=0,
                   help=f"seed, 0 to {_types.MAX_SEED}: the first kitchen's (with --split: "
                        "its index in the split)")
    p.add_argument("--split", choices=tuple(SPLITS), default=None,
                   help="take the kitchens of this split (train: seed = index; "
                        "test: seed = 1000000 + index)")
    p.add_argument("--stations", choices=tuple(PRESET_STATIONS), default="hard",
                   help="the preset whose stations the kitchens carry")
    p.add_argument("--rows", type=_types.whole("--rows", 5, 12), default=None, help="rows (None: drawn per seed)")
    p.add_argument("--cols", type=_types.whole("--cols", 5, 12), default=None, help="columns (None: drawn per seed)")
    p.add_argument("--cooks", type=_types.whole("--cooks", 1, 4), default=None,
                   help="cooks = spawn points (None: 3 or 4, drawn per seed)")
    p.add_argument("--recipes", type=_types.whole_list("a recipe length", 1, MAX_LENGTH),
                   default=None, metavar="LENGTHS",
                   help="draw each kitchen a menu of dishes of these lengths (e.g. 2,3), "
                        "seeded by its seed, and write it into its file (default: none; the "
                        "preset draws its pool)")
    p.add_argument("--menu", type=_types.whole("--menu", 1, MAX_RECIPES), default=3,
                   help="dishes per drawn menu (with --recipes)")
    proof = p.add_mutually_exclusive_group()
    proof.add_argument("--prove", dest="prove", action="store_true", default=None,
                       help="prove each kitchen solvable with Fast Downward (slow; default: off)")
    proof.add_argument("--no-prove", dest="prove", action="store_false",
                       help="write the kitchens without proving them (the default)")
    p.add_argument("--candidates", type=_types.whole("--candidates", 1, 100), default=5,
                   help="candidates tried per kitchen before it is given up")
    p.add_argument("--timeout", type=_types.seconds, default=60.0,
                   help="planner CPU seconds per proof try")
    add_output_args(p, out=True, writes="one YAML map per kitchen, manifest.json")
    p.set_defaults(func=run)


def _should_prove(flag: bool | None) -> tuple[bool, str]:
    """(prove?, why not) from ``--prove`` / ``--no-prove`` / the default."""
    if flag is False:
        return False, "--no-prove"
    if flag is None:
        return False, "not asked for (give --prove)"
    try:
        from ..planning.prove import proof_available
        why = proof_available()
    except ImportError as exc:
        why = f"the planning layer cannot be imported ({exc})"
    if why and flag:
        raise DependencyNotInstalled(
            f"--prove needs Fast Downward: {why}; install the planners extra: "
            "pip install -e '.[planners]'")
    return not why, why


def _check(args: argparse.Namespace) -> None:
    if args.n < 1:
        raise ConfigError(f"--n must be at least 1, got {args.n}")
    if args.seed < 0:
        raise ConfigError(f"--seed must be >= 0, got {args.seed}")
    if args.split is None and args.seed + args.n - 1 > _types.MAX_SEED:
        raise ConfigError(f"--seed {args.seed} --n {args.n} would write seeds up to "
                          f"{args.seed + args.n - 1}, past the largest seed {_types.MAX_SEED}; "
                          f"start at {_types.MAX_SEED - args.n + 1} or lower")
    if args.candidates < 1:
        raise ConfigError(f"--candidates must be at least 1, got {args.candidates}")
    if args.timeout <= 0:
        raise ConfigError(f"--timeout must be positive, got {args.timeout}")


def _one_kitchen(args: argparse.Namespace, seed: int, stem: str, name: str, prove: bool,
                 out: Path, index: int) -> dict[str, Any]:
    """Draw (and prove) one kitchen; write its file; its manifest entry. A split's kitchen
    starts from the candidate its ``gen:`` name loads (``first_candidate``)."""
    entry: dict[str, Any] = {"file": f"{stem}.yaml", "seed": seed, "replaced": []}
    if args.split is not None:
        entry.update(split=args.split, index=index)
    first = (first_candidate(args.family, args.split, entry["index"], args.stations)
             if args.split is not None and (args.rows, args.cols, args.cooks) == (None,) * 3
             else 0)
    entry["replaced"] += [{"candidate": c, "reason": "failed its proof when the split was "
                           "measured (sim.generate.PROOF_REPLACEMENTS)"} for c in range(first)]
    for candidate in range(first, first + args.candidates):
        spec = generate_map(args.family, seed, rows=args.rows, cols=args.cols,
                            cooks=args.cooks, preset=args.stations, candidate=candidate,
                            name=name if candidate == first else f"{name} (candidate {candidate})")
        layout = load_map(spec, source=stem)
        if args.recipes:  # the kitchen's own menu, drawn from its seed
            lengths = tuple(sorted({int(n) for n in args.recipes.split(",") if n.strip()}))
            menu = draw_dishes(layout, seed, lengths, args.menu, PRESETS[args.stations].steak)
            spec = dict(spec, recipes=[dish_to_dict(d) for d in menu])
            layout = load_map(spec, source=stem)
            entry["recipes"] = ["+".join(k.name.lower() for k in d.recipe) for d in menu]
        entry.update(candidate=candidate, rows=layout.rows, cols=layout.cols,
                     cooks=layout.max_agents, dynamic=layout.is_dynamic)
        if not prove:
            entry["proof"] = None
            break
        from ..planning.prove import prove_kitchen

        proof = prove_kitchen(layout, args.stations, timeout=args.timeout)
        entry["proof"] = proof.to_dict()
        if proof.ok:
            break
        entry["replaced"].append({"candidate": candidate, "reason": proof.reason})
    else:
        entry["failed"] = True
        return entry
    (out / entry["file"]).write_text(map_to_yaml(spec), encoding="utf-8")
    return entry


def run(args: argparse.Namespace) -> int:
    _check(args)
    try:
        return _generate(args)
    except OSError as exc:  # a folder that cannot be made or written (/proc, a full disk)
        raise ConfigError(f"cannot write the kitchens under {args.out}: "
                          f"{exc.strerror or exc}") from None


def _generate(args: argparse.Namespace) -> int:
    prove, why_not = _should_prove(args.prove)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    kitchens = []
    for k in range(args.n):
        index = args.seed + k
        if args.split is not None:
            seed, stem = split_seed(args.split, index), f"{args.family}-{args.split}-{index:04d}"
            name = f"gen:{args.family}:{args.split}:{index}" + (
                f":{args.stations}" if args.stations != "hard" else "")
        else:
            seed, stem = index, f"{args.family}-seed{index:06d}"
            name = f"gen-{args.family}-{index}"
        entry = _one_kitchen(args, seed, stem, name, prove, out, index)
        kitchens.append(entry)
        status = ("given up" if entry.get("failed") else
                  "proven" if prove else "written, not proven")
        say(args, f"{entry['file']}: {entry['rows']}x{entry['cols']}, {entry['cooks']} cooks, "
                  f"{status}" + (f" (candidate {entry['candidate']})" if entry['candidate']
                                 else ""))
    manifest = {
        "generator": {"family": args.family, "split": args.split, "first": args.seed,
                      "n": args.n, "stations": args.stations, "rows": args.rows,
                      "cols": args.cols, "cooks": args.cooks, "recipes": args.recipes,
                      "menu": args.menu if args.recipes else None},
        "proved": prove, "not_proved_because": why_not if not prove else "",
        "kitchens": kitchens,
    }
    (out / "manifest.json").write_text(json.dumps(manifest, indent=1) + "\n", encoding="utf-8")
    failed = [e["file"] for e in kitchens if e.get("failed")]
    result = {"out": str(out), "kitchens": len(kitchens) - len(failed), "given_up": failed,
              "replaced": sum(bool(e["replaced"]) for e in kitchens), "proved": prove,
              "manifest": str(out / "manifest.json")}
    emit(result, args)
    return 0
