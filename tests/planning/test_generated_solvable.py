"""Generated kitchens are solvable: a validated lama-first plan for one order, with every
cook modelled, that the simulator follows (``ocplus_plan.planning.prove``)."""

from __future__ import annotations

import json

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.cli import main  # noqa: E402
from ocplus_plan.planning.prove import proof_available, proof_recipe, prove_kitchen  # noqa: E402
from ocplus_plan.sim.generate import FAMILIES, generate_map  # noqa: E402
from ocplus_plan.sim.generate_families import MIN_SIZE  # noqa: E402
from ocplus_plan.sim.maps import load_map  # noqa: E402

_WHY = proof_available()
pytestmark = pytest.mark.skipif(bool(_WHY), reason=f"Fast Downward unavailable: {_WHY}")


def _small(family: str, seed: int = 1, cooks: int = 2):
    rows, cols = MIN_SIZE[family]
    return load_map(generate_map(family, seed, rows=rows + 1, cols=cols + 1, cooks=cooks))


@pytest.mark.parametrize("family", FAMILIES)
def test_a_small_kitchen_of_every_family_is_proven(family):
    proof = prove_kitchen(_small(family))
    assert proof.ok, proof.reason
    assert proof.n_agents == 2 and proof.recipe == "lettuce+steak+tomato"
    assert proof.simulator_steps >= proof.plan_length > 0


def test_a_split_kitchen_with_one_cook_is_not_proven():
    proof = prove_kitchen(_small("split"), n_agents=1)
    assert not proof.ok
    assert proof.tries and all(t["status"] != "solved" for t in proof.tries)


def test_an_easy_kitchen_is_proven_with_one_tomato():
    layout = load_map(generate_map("open", 4, rows=5, cols=6, cooks=1, preset="easy"))
    assert proof_recipe(layout, "easy") == "tomato"
    assert prove_kitchen(layout, "easy").ok


def test_generate_prove_records_the_proof_in_the_manifest(tmp_path):
    out = tmp_path / "k"
    assert main(["generate", "--family", "corridor", "--n", "1", "--rows", "5", "--cols", "7",
                 "--cooks", "2", "--prove", "--quiet", "--out", str(out)]) == 0
    kitchen = json.loads((out / "manifest.json").read_text())["kitchens"][0]
    assert kitchen["proof"]["ok"] and (out / kitchen["file"]).is_file()
