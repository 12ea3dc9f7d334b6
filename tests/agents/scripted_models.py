"""Scripted stand-ins for a language model (prompt -> reply): no download, no network.

Importable by path, as ``llm:tests.agents.scripted_models:FUNCTION`` in an agent spec."""

from __future__ import annotations

import re


def always_right(prompt: str) -> str:
    """Every driven cook walks right (or bumps what is there)."""
    cooks = re.findall(r"^Cook (\d+) is at", prompt, re.MULTILINE)
    return "\n".join(f"cook {c}: right" for c in cooks)


def first_useful(prompt: str) -> str:
    """Each cook takes the first listed action that picks up, puts, chops or serves
    something, else walks the first way that is free: a model that reads the text."""
    lines = []
    for cook, block in re.findall(r"^Cook (\d+) is at [^\n]*\n((?:- [^\n]*\n?)+)", prompt,
                                  re.MULTILINE):
        options = re.findall(r"^- (\w+): (.*)$", block, re.MULTILINE)
        useful = [a for a, words in options if re.match(r"(pick up|put|chop|serve|take)", words)]
        free = [a for a, words in options if words.startswith("walk to") and "stands" not in words]
        lines.append(f"cook {cook}: {(useful or free or ['stay'])[0]}")
    return "\n".join(lines)


def gibberish(prompt: str) -> str:
    return "As an AI cook I would rather not."
