"""A distribution of training kitchens: ``ocplus train --maps gen:FAMILY:SPLIT:A-B[,...]``.

:func:`parse_maps` expands a comma-separated list of kitchens, where a ``gen:`` name may
give a range of indices (``gen:open:train:0-19``: the generator's kitchens 0 to 19 of
family ``open``, train split), into kitchen names; :func:`distribution_rules` makes one rule
set per kitchen (the preset's stations and recipes, layout switches only where the
kitchen has a switch layout). The trainer draws a new kitchen for every episode
(:class:`~ocplus_plan.rl.vec_env.KitchenVecEnv` with ``draw=True``), so a policy sees as
many kitchens as it plays episodes; the observation it needs is one that every kitchen
gives with the same size (``window``: the path features and an egocentric grid window,
:mod:`.obs`).

An optional curriculum (:func:`curriculum_stages`) starts on the smallest kitchens and
widens the pool to the largest over the first part of training.
"""

from __future__ import annotations

import re
from typing import Any

from ..errors import ConfigError
from ..sim.generate import FAMILIES, GEN_PREFIX, SPLITS
from ..sim.kitchens import load_kitchen
from ..sim.rules import PRESETS, Rules, make_rules

#: at most this many kitchens in one distribution (each holds its tables while training)
MAX_KITCHENS = 2000
_RANGE = re.compile(r"^gen:([a-z]+):([a-z]+):(\d+)-(\d+)$")


def parse_maps(text: str, preset: str) -> list[str]:
    """``"gen:open:train:0-9,gen:split:train:0-9,mapA"`` -> kitchen names (a ``gen:`` name
    without a preset gets ``preset``'s stations). Refuses an empty list, a reversed or
    too long range, an unknown family or split, naming the form it takes."""
    usage = ("write comma-separated kitchens, each a map name, a gen:FAMILY:SPLIT:INDEX name "
             "or a range gen:FAMILY:SPLIT:A-B (e.g. gen:open:train:0-19,gen:split:train:0-19; "
             f"families: {', '.join(FAMILIES)}; splits: {', '.join(SPLITS)})")
    names: list[str] = []
    for part in (p.strip() for p in text.split(",")):
        if not part:
            continue
        m = _RANGE.match(part)
        if m:
            family, split, lo, hi = m.group(1), m.group(2), int(m.group(3)), int(m.group(4))
            if family not in FAMILIES or split not in SPLITS:
                raise ConfigError(f"--maps {part!r}: unknown family or split; {usage}")
            if hi < lo:
                raise ConfigError(f"--maps {part!r}: the range ends before it starts; {usage}")
            if hi - lo + 1 > MAX_KITCHENS:
                raise ConfigError(f"--maps {part!r}: at most {MAX_KITCHENS} kitchens")
            names += [f"gen:{family}:{split}:{i}:{preset}" for i in range(lo, hi + 1)]
        elif part.startswith(GEN_PREFIX) and part.count(":") == 3:
            names.append(f"{part}:{preset}")
        else:
            names.append(part)
    if not names:
        raise ConfigError(f"--maps {text!r} names no kitchen; {usage}")
    if len(names) > MAX_KITCHENS:
        raise ConfigError(f"--maps names {len(names)} kitchens; at most {MAX_KITCHENS}")
    return names


def kitchen_rules(preset: str, name: str, **overrides: Any) -> Rules:
    """The rules of ``preset`` in kitchen ``name``; the preset's layout switches only where
    the kitchen has a switch layout (the generator gives one to the ``switching`` family)."""
    if preset not in PRESETS:
        raise ConfigError(f"unknown preset {preset!r}; choose one of {', '.join(PRESETS)}")
    layout = load_kitchen(name)
    dynamic = PRESETS[preset].dynamic and layout.is_dynamic
    return make_rules(preset, map=layout, dynamic=dynamic, **overrides)


def distribution_rules(names: list[str], preset: str, **overrides: Any) -> list[Rules]:
    """One rule set per kitchen of ``names`` (:func:`kitchen_rules`)."""
    return [kitchen_rules(preset, name, **overrides) for name in names]


def curriculum_stages(rules: list[Rules], stages: int) -> list[list[Rules]]:
    """``stages`` growing pools over ``rules`` ordered by area: stage ``k`` holds the
    smallest ``(k + 1) / stages`` of the kitchens (by area) (the last stage holds them all)."""
    if stages < 1:
        raise ConfigError(f"a curriculum needs at least one stage, got {stages}")
    ordered = sorted(rules, key=lambda r: (_floor(r), r.layout.name))
    return [ordered[: max(1, len(ordered) * (k + 1) // stages)] for k in range(stages)]


def _floor(rules: Rules) -> int:
    return int(rules.layout.grid.size)


__all__ = ["MAX_KITCHENS", "curriculum_stages", "distribution_rules", "kitchen_rules",
           "parse_maps"]
