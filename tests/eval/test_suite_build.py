"""The suite builder's levers and tracks: cells, orders above the preset's queue, ``gen:``
kitchens with ``--rules`` on hard, the goal-agenda witness, the unsolvability track and
dropped instances. Each set is one or two instances solved in about a second."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.cli import main
from ocplus_plan.eval.suite import Cell, SuiteSpec, cell_rules, export_suite, load_instance
from ocplus_plan.planning.engines import availability
from ocplus_plan.planning.fidelity import sample_state

warnings.simplefilter("ignore", UserWarning)
LAMA = {"classical": ("fast-downward",)}
#: a set whose portfolio (BJOLP at 0.05 CPU s) solves nothing: its instance needs the witness
UNSOLVED = SuiteSpec(encodings=("classical",), timeout=0.05, fallback=False, witness_timeout=20,
                     planners={"classical": ("fast-downward-bjolp",)},
                     cells=(Cell("easy", None, 1, 3, 1),))


def _need(*names: str) -> None:
    for name in names:
        if not availability(name).ok:
            pytest.skip(f"{name} unavailable: {availability(name).reason}")


def _files(root: Path) -> dict[str, bytes]:
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*"))
            if p.is_file()}


def _manifests(root: Path) -> tuple[dict, dict]:
    top = json.loads((root / "manifest.json").read_text())
    return top, json.loads((root / "p01" / "manifest.json").read_text())


def test_orders_above_the_queue_raise_it_and_the_state_holds_them_all():
    rules, overrides = cell_rules(Cell("easy", cooks=1, orders=5))
    assert overrides == {"n_orders": 5} and rules.n_orders == 5
    assert len(sample_state(rules, 0, 0).orders) == 5
    _, none = cell_rules(Cell("easy", cooks=1, orders=1))  # at most the queue: a cut
    assert none == {}


def test_hard_on_a_generated_kitchen_needs_the_rules_option(tmp_path, capsys):
    assert main(["export-suite", "--presets", "hard", "--maps", "gen:open:test:0",
                 "--encoding", "classical", "--out", str(tmp_path / "a")]) == 2
    assert "dynamic=False" in capsys.readouterr().err
    rules, overrides = cell_rules(Cell("hard", "gen:open:test:0", 1, 1, 0,
                                       (("dynamic", False),)))
    assert overrides == {"dynamic": False} and rules.layout.name == "gen:open:test:0"


def test_a_cell_set_is_written_byte_for_byte_again_and_loads_back(tmp_path):
    _need("fast-downward")
    # a kitchen lama-first solves in about 1 CPU s, so the 20 s limit holds on a loaded machine
    # (gen:open:test:0 needs about 15, and on a slower machine is left open)
    spec = SuiteSpec(encodings=("classical",), planners=LAMA, timeout=20, fallback=False,
                     cells=(Cell("hard", "gen:open:test:2", 1, 3, 0, (("dynamic", False),)),))
    export_suite(spec, tmp_path / "a")
    export_suite(spec, tmp_path / "b")
    assert _files(tmp_path / "a") == _files(tmp_path / "b")
    top, inst = _manifests(tmp_path / "a")
    assert top["tracks"] == {"classical": ["p01"]}
    assert top["arguments"]["cells"][0]["map"] == "gen:open:test:2"
    assert inst["rules"] == {"dynamic": False, "n_orders": 3}
    assert inst["goal_orders"] == [o["id"] for o in inst["orders"]] and len(inst["orders"]) == 3
    entry = inst["encodings"]["classical"]
    assert entry["status"] == "solved" and entry["reference"]["faithful"] is True
    assert {"cost", "planner", "engine", "optimal", "portfolio"} <= set(entry["reference"])
    assert inst["bound"]["cost"] <= entry["reference"]["cost"]
    loaded = load_instance(tmp_path / "a" / "p01")
    assert loaded.state.rules.n_orders == 3 and not loaded.state.rules.dynamic
    loaded.compiled("classical")  # the problem file matches the rebuilt state


def test_proven_unsolvable_goes_to_its_track_and_unknown_is_dropped(tmp_path):
    _need("fast-downward", "fast-downward-bjolp")
    spec = SuiteSpec(encodings=("classical",), timeout=20, fallback=False, witness_timeout=0,
                     planners={"classical": ("fast-downward",)},
                     cells=(Cell("hard", None, 1, 1),))  # hard's own map, one cook
    export_suite(spec, tmp_path / "u")
    top, inst = _manifests(tmp_path / "u")
    assert top["tracks"] == {"classical-unsolvable": ["p01"]}
    assert inst["encodings"]["classical"]["status"] == "unsolvable"
    assert not (tmp_path / "u" / "p01" / "classical.plan").exists()
    drop = SuiteSpec(encodings=("classical",), timeout=0.05, fallback=False, witness_timeout=0,
                     planners={"classical": ("fast-downward-bjolp",)},
                     cells=(Cell("medium", None, 1, 4),))
    export_suite(drop, tmp_path / "d")
    top, inst = _manifests(tmp_path / "d")
    assert top["tracks"] == {"classical-unknown": ["p01"]}
    assert inst["encodings"]["classical"]["status"] == "unknown"


def test_an_unsolved_instance_is_scored_open_with_a_validated_goal_agenda_witness(tmp_path):
    _need("fast-downward", "fast-downward-bjolp")
    export_suite(UNSOLVED, tmp_path / "w")
    top, inst = _manifests(tmp_path / "w")
    assert top["tracks"] == {"classical": ["p01"]}
    entry = inst["encodings"]["classical"]
    ref = entry["reference"]
    assert entry["status"] == "open" and ref["engine"] == "goal-agenda"
    assert ref["planner"] == "goal-agenda:fast-downward" and ref["optimal"] is False
    assert "Plan valid" in ref["witness"]["validated"] and ref["faithful"] is True
    assert ref["judged"] == "realised" and ref["failed_step"] is None  # the league's judge
    assert ref["waits"] == 0 and ref["divergence"] is None  # one cook: nobody in the way
    assert ref["tried"] == {"fast-downward-bjolp": "timeout"}
    assert (tmp_path / "w" / "p01" / "classical.plan").is_file()


def test_the_model_agenda_proves_a_multi_cook_instance_solvable():
    """Where cooks would walk into each other in the simulator, the classical agenda
    plans in the model alone; the concatenation is still one validated plan."""
    _need("fast-downward")
    from ocplus_plan.eval.suite_witness import pddl_agenda
    from ocplus_plan.planning import compile

    rules, _ = cell_rules(Cell("easy", None, 2, 3, 1), 1000)
    whole = compile(sample_state(rules, 0, 1), encoding="classical")
    plan, info = pddl_agenda(whole, "fast-downward", 20, None, {})
    assert "Plan valid" in info["validated"] and len(plan.actions) > 0


def _verdict(faithful: bool, step: int) -> dict:
    """What the league's judge says of a plan (a stand-in: accepted, or refused at ``step``)."""
    return {"faithful": faithful, "judged": "realised" if faithful else "refused", "waits": 0,
            "failed_step": None if faithful else step,
            "divergence": None if faithful else "a cook walks into another"}


def test_an_instance_whose_only_plan_the_kitchen_refuses_is_dropped(tmp_path, monkeypatch):
    """A scored instance's reference is faithful: when the judge refuses the witness (a
    cook walked through another in the model), the instance is unknown, not open."""
    _need("fast-downward", "fast-downward-bjolp")
    from ocplus_plan.eval import suite

    monkeypatch.setattr(suite, "judge_plan", lambda compiled, plan, state: _verdict(False, 3))
    export_suite(UNSOLVED, tmp_path / "r")
    top, inst = _manifests(tmp_path / "r")
    assert top["tracks"] == {"classical-unknown": ["p01"]}
    entry = inst["encodings"]["classical"]
    assert entry["status"] == "unknown" and entry["reference"]["faithful"] is False
    assert entry["reference"]["failed_step"] == 3
    assert "Plan valid" in entry["reference"]["witness"]["validated"]  # a plan of the model


def test_a_solved_instance_whose_plans_the_kitchen_refuses_falls_to_the_witness(
        tmp_path, monkeypatch):
    _need("fast-downward")
    from ocplus_plan.eval import suite

    verdicts = iter([False, True])  # the portfolio's plan refused, the witness realised

    monkeypatch.setattr(suite, "judge_plan",
                        lambda compiled, plan, state: _verdict(next(verdicts), 5))
    spec = SuiteSpec(encodings=("classical",), planners=LAMA, timeout=20, fallback=False,
                     witness_timeout=20, cells=(Cell("easy", None, 1, 1, 0),))
    export_suite(spec, tmp_path / "s")
    _, inst = _manifests(tmp_path / "s")
    entry = inst["encodings"]["classical"]
    assert entry["status"] == "open" and entry["reference"]["engine"] == "goal-agenda"
    assert entry["reference"]["faithful"] is True
