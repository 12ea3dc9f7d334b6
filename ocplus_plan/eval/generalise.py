"""The generalisation protocol: agents on the generator's train and test kitchens, and
cross-play (``experiments/bench_generalise.py`` runs it).

In the spirit of the Overcooked Generalisation Challenge: every agent (the greedy cook, the
default planner where asked, each learned baseline) plays train-split and test-split
kitchens of every family (``gen:FAMILY:SPLIT:INDEX:PRESET``), with 1-3 cooks and several
seeds; :func:`generalisation_table` gives per family and split each agent's mean dishes,
its ratio to greedy's on the same episodes, and the share of test kitchens where it served
anything. :func:`crossplay_pairs` pairs every agent with every other (and itself) as the
two cooks of a kitchen, and :func:`crossplay_table` gives the dishes of each pair.

An episode is one JSON-able row (:func:`play`); the tables read rows only, so they can be
rebuilt from a results file.
"""

from __future__ import annotations

import itertools
import statistics
from collections import defaultdict
from collections.abc import Sequence
from typing import Any

from ..agents import make_controller, run_episode
from ..errors import ConfigError
from ..sim.generate import FAMILIES
from ..sim.kitchens import load_kitchen
from ..sim.rules import PRESETS, Rules, make_rules
from ..sim.state import new_state

#: the families whose kitchens need at least this many cooks (a wall to hand over)
MIN_COOKS = {"split": 2}


def kitchen_name(family: str, split: str, index: int, preset: str) -> str:
    return f"gen:{family}:{split}:{index}:{preset}"


def rules_for(name: str, preset: str, cooks: int, horizon: int) -> Rules:
    """``preset``'s rules in kitchen ``name`` with ``cooks`` cooks (layout switches only
    where the kitchen has a switch layout)."""
    layout = load_kitchen(name)
    return make_rules(preset, map=layout, n_agents=cooks, horizon=horizon,
                      dynamic=PRESETS[preset].dynamic and layout.is_dynamic)


def cells(families: Sequence[str], splits: Sequence[str], kitchens: int, cooks: Sequence[int],
          seeds: Sequence[int]) -> list[tuple[str, str, int, int, int]]:
    """Every (family, split, index, cooks, seed) to play; families that need more cooks than
    a cell has are left out of that cook count."""
    bad = sorted(set(families) - set(FAMILIES))
    if bad:
        raise ConfigError(f"unknown families {bad}; choose from {', '.join(FAMILIES)}")
    return [(f, s, i, n, seed) for n in cooks for f in families for s in splits
            for i in range(kitchens) for seed in seeds if n >= MIN_COOKS.get(f, 1)]


def play(cell: tuple[str, str, int, int, int], agent: str, label: str, preset: str,
         horizon: int = 200, partner: tuple[str, str] | None = None,
         factory: Any = make_controller) -> dict[str, Any]:
    """One episode of ``agent`` (a controller name) in ``cell``; with ``partner`` (name,
    label) the partner plays the last cook. Returns the episode's row."""
    family, split, index, cooks, seed = cell
    name = kitchen_name(family, split, index, preset)
    state = new_state(rules_for(name, preset, cooks, horizon), seed)
    controller = factory(agent, seed)
    drivers: Any = controller
    if partner is not None:
        drivers = [(controller, list(range(cooks - 1))),
                   (factory(partner[0], seed), [cooks - 1])]
    stats = run_episode(state, drivers)
    info = controller.info() if hasattr(controller, "info") else {}
    return {"family": family, "split": split, "index": index, "kitchen": name, "cooks": cooks,
            "seed": seed, "agent": label, "partner": partner[1] if partner else None,
            "dishes": int(stats["dishes_served"]), "steps": int(stats["t"]),
            **({"checkpoint": info["checkpoint"]} if "checkpoint" in info else {})}


def crossplay_pairs(labels: Sequence[str]) -> list[tuple[str, str]]:
    """Every ordered pair of agents (each with itself too): the first drives cook 0, the
    second cook 1."""
    if len(set(labels)) != len(labels):
        raise ConfigError(f"agent labels must differ, got {list(labels)}")
    return list(itertools.product(labels, repeat=2))


def _mean(xs: list[float]) -> float | None:
    return round(statistics.mean(xs), 3) if xs else None


def generalisation_table(rows: list[dict[str, Any]], reference: str = "greedy",
                         ) -> list[dict[str, Any]]:
    """Per (cooks, family, agent) and overall per (cooks, agent) (rows marked ``skipped``
    are left out): mean dishes on train and test kitchens, the train-test gap, the ratio to ``reference`` on the test episodes both
    played, and the share of test kitchens (over seeds: mean dishes > 0) it served in."""
    solo = [r for r in rows if r.get("partner") is None and "skipped" not in r]
    dishes: dict[tuple, list[int]] = defaultdict(list)
    for r in solo:
        for family in (r["family"], "all"):
            dishes[(r["cooks"], family, r["agent"], r["split"])].append(r["dishes"])
    per_kitchen: dict[tuple, list[int]] = defaultdict(list)
    for r in solo:
        if r["split"] == "test":
            for family in (r["family"], "all"):
                per_kitchen[(r["cooks"], family, r["agent"], r["kitchen"])].append(r["dishes"])
    out = []
    keys = sorted({(k[0], k[1], k[2]) for k in dishes},
                  key=lambda k: (k[0], k[1] == "all", k[1], k[2] != reference, k[2]))
    for cooks, family, agent in keys:
        train, test = dishes.get((cooks, family, agent, "train"), []), \
            dishes.get((cooks, family, agent, "test"), [])
        ref = dishes.get((cooks, family, reference, "test"), [])
        kitchens = [statistics.mean(v) for (c, f, a, _), v in per_kitchen.items()
                    if (c, f, a) == (cooks, family, agent)]
        mt, ms, mr = (statistics.mean(x) if x else None for x in (train, test, ref))
        out.append({
            "cooks": cooks, "family": family, "agent": agent, "train": _mean(train),
            "test": _mean(test), "episodes_test": len(test),
            "gap": round(abs(mt - ms) / max(mt, ms), 3) if mt is not None and ms is not None
            and max(mt, ms) > 0 else None,
            "test_vs_" + reference: round(ms / mr, 3) if ms is not None and mr else None,
            "test_kitchens_served": round(sum(k > 0 for k in kitchens) / len(kitchens), 3)
            if kitchens else None})
    return out


def crossplay_table(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Mean dishes per (first agent, partner) pair over the rows with a partner."""
    pairs: dict[tuple[str, str], list[int]] = defaultdict(list)
    for r in rows:
        if r.get("partner") is not None and "skipped" not in r:
            pairs[(r["agent"], r["partner"])].append(r["dishes"])
    return [{"agent": a, "partner": p, "dishes": _mean(v), "episodes": len(v)}
            for (a, p), v in sorted(pairs.items())]


def markdown(table: list[dict[str, Any]]) -> str:
    """A list of flat rows as a Markdown table (columns of the first row)."""
    if not table:
        return ""
    cols = list(table[0])

    def cell(v: Any) -> str:
        return "-" if v is None else str(v)

    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    lines += ["| " + " | ".join(cell(r.get(c)) for c in cols) + " |" for r in table]
    return "\n".join(lines) + "\n"


__all__ = ["MIN_COOKS", "cells", "crossplay_pairs", "crossplay_table", "generalisation_table",
           "kitchen_name", "markdown", "play", "rules_for"]
