"""Proof that a kitchen can serve an order: a validated plan the simulator follows.

:func:`prove_kitchen` fixes one order (the largest recipe the kitchen's preset allows:
a steak with two vegetables, or one vegetable on ``easy``), models every cook, compiles the
initial state (classical encoding, at most this one order as the goal) and asks Fast
Downward's lama-first (the ``fast-downward`` registry entry) for a plan, validated by
unified-planning's validator and VAL. The plan is then replayed in the simulator
(:func:`.fidelity.replay`): the proof holds when the simulator serves the order as the
plan says. The ``stations`` model is tried first; when its plan is not followed (its
moves ignore the cooks standing in the way, which matters in one-lane kitchens) the
``cells`` model, which plans every cook's cell, is tried next.

On a switching kitchen the replay keeps the main layout (``freeze_layout``): the proof says
the order can be served in the main layout, not that it can be served across switches.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass, field
from typing import Any

from ..errors import DependencyNotInstalled
from ..sim import Layout, make_rules, new_state
from ..sim.codes import Cell
from ..sim.rules import Rules

#: the registry entry that proves (Fast Downward, lama-first)
PROOF_PLANNER = "fast-downward"
PROOF_GRANULARITIES = ("stations", "cells")
#: the horizon of the proof's episode: long enough for any plan on a 12 x 12 kitchen
PROOF_HORIZON = 2000


@dataclass
class Proof:
    """The outcome of :func:`prove_kitchen`; ``tries`` has one entry per model tried."""

    ok: bool
    recipe: str
    n_agents: int
    preset: str
    granularity: str = ""
    plan_length: int = 0
    simulator_steps: int = 0
    cpu_time: float = 0.0
    wall_time: float = 0.0
    reason: str = ""
    tries: list[dict[str, Any]] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def proof_recipe(layout: Layout, preset: str) -> str:
    """The order a proof serves: steak+tomato+lettuce where the kitchen has a pan and the
    preset cooks steak, else one tomato."""
    if preset != "easy" and layout.cells_of(Cell.PAN) and layout.cells_of(Cell.STEAK):
        return "lettuce+steak+tomato"
    return "tomato"


def proof_rules(layout: Layout, preset: str = "hard", n_agents: int | None = None) -> Rules:
    """The rules of a proof: the preset's, with one fixed order and every cook."""
    dynamic = preset == "hard" and layout.is_dynamic
    return make_rules(preset, map=layout, n_agents=n_agents or layout.max_agents,
                      dynamic=dynamic, fixed_orders=[proof_recipe(layout, preset)],
                      n_orders=1, horizon=PROOF_HORIZON)


def proof_available() -> str:
    """'' when the proof can run here, else why not (the fix included)."""
    try:
        from .engines import availability
    except ImportError as exc:
        return f"the planning layer cannot be imported ({exc}); install the planners extra"
    avail = availability(PROOF_PLANNER)
    return "" if avail.ok else avail.reason


def prove_kitchen(layout: Layout, preset: str = "hard", n_agents: int | None = None,
                  timeout: float = 60.0, use_val: bool = True) -> Proof:
    """Try to prove ``layout`` can serve one order with ``n_agents`` cooks (default: all)."""
    why = proof_available()
    if why:
        raise DependencyNotInstalled(f"proving kitchens needs Fast Downward: {why}")
    from . import compile
    from .engines import solve
    from .fidelity import replay

    rules = proof_rules(layout, preset, n_agents)
    state = new_state(rules, 0)
    proof = Proof(False, proof_recipe(layout, preset), rules.n_agents, preset)
    t0 = time.perf_counter()
    for granularity in PROOF_GRANULARITIES:
        compiled = compile(state, encoding="classical", granularity=granularity, max_orders=1)
        result = solve(compiled.problem, PROOF_PLANNER, timeout=timeout, use_val=use_val)
        proof.cpu_time += result.cpu_time or 0.0
        entry: dict[str, Any] = {"granularity": granularity, "status": result.status,
                                 "plan_length": result.plan_length,
                                 "cpu_time": result.cpu_time, "validated": result.validated}
        proof.tries.append(entry)
        if not result.solved:
            entry["reason"] = result.reason[:300]
            continue
        played = replay(compiled, result.plan, state, freeze_layout=True)
        entry.update(faithful=played.ok, served=len(played.served),
                     simulator_steps=played.steps)
        if not played.ok or not played.served:
            entry["reason"] = played.mismatch or "the replay served nothing"
            continue
        proof.ok, proof.granularity = True, granularity
        proof.plan_length, proof.simulator_steps = result.plan_length or 0, played.steps
        break
    proof.wall_time = round(time.perf_counter() - t0, 3)
    proof.cpu_time = round(proof.cpu_time, 3)
    if not proof.ok:
        proof.reason = "; ".join(f"{t['granularity']}: {t['status']}"
                                 + (f" ({t['reason']})" if t.get("reason") else "")
                                 for t in proof.tries)
    return proof


__all__ = ["PROOF_PLANNER", "Proof", "proof_available", "proof_recipe", "proof_rules",
           "prove_kitchen"]
