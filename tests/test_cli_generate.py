"""``ocplus generate``, ``--map gen:...`` and ``--rules KEY=VALUE`` from the command line."""

from __future__ import annotations

import json

import pytest

from ocplus_plan.cli import main
from ocplus_plan.commands._common import RULE_KEYS, parse_rule_overrides
from ocplus_plan.errors import ConfigError
from ocplus_plan.sim.generate import map_from_name, map_to_yaml


def _generate(tmp_path, name, *extra):
    out = tmp_path / name
    code = main(["generate", "--family", "split", "--n", "2", "--seed", "3", "--no-prove",
                 "--out", str(out), "--quiet", *extra])
    return code, out


def test_generate_writes_one_yaml_per_kitchen_and_a_manifest(tmp_path):
    code, out = _generate(tmp_path, "a")
    assert code == 0
    assert sorted(p.name for p in out.iterdir()) == [
        "manifest.json", "split-seed000003.yaml", "split-seed000004.yaml"]
    manifest = json.loads((out / "manifest.json").read_text())
    assert [k["seed"] for k in manifest["kitchens"]] == [3, 4]
    assert manifest["proved"] is False and manifest["not_proved_because"] == "--no-prove"


def test_generate_proves_only_when_asked(tmp_path):
    out = tmp_path / "plain"
    assert main(["generate", "--family", "open", "--n", "1", "--out", str(out), "--quiet"]) == 0
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["proved"] is False
    assert manifest["not_proved_because"] == "not asked for (give --prove)"


def test_generate_twice_gives_the_same_bytes(tmp_path):
    _, a = _generate(tmp_path, "a")
    _, b = _generate(tmp_path, "b")
    for name in ("split-seed000003.yaml", "split-seed000004.yaml"):
        assert (a / name).read_bytes() == (b / name).read_bytes()


def test_generate_with_a_split_writes_what_the_gen_name_loads(tmp_path):
    out = tmp_path / "s"
    assert main(["generate", "--family", "multiroom", "--split", "test", "--seed", "7",
                 "--n", "1", "--no-prove", "--quiet", "--out", str(out)]) == 0
    written = (out / "multiroom-test-0007.yaml").read_text()
    assert written == map_to_yaml(map_from_name("gen:multiroom:test:7"))


def test_a_generated_file_passes_check_map(tmp_path, capsys):
    _, out = _generate(tmp_path, "a")
    capsys.readouterr()
    assert main(["check-map", str(out / "split-seed000003.yaml")]) == 0
    assert "every station reachable" in capsys.readouterr().out


def test_generate_refuses_one_cook_for_a_split_kitchen(tmp_path, capsys):
    code, _ = _generate(tmp_path, "a", "--cooks", "1")
    assert code == 2 and "2 to 4 cooks" in capsys.readouterr().err


def test_generate_refuses_zero_kitchens(tmp_path, capsys):
    assert main(["generate", "--family", "open", "--n", "0", "--no-prove",
                 "--out", str(tmp_path / "z")]) == 2
    assert "--n is a whole number from 1" in capsys.readouterr().err


def test_map_gen_name_is_accepted_by_rollout(capsys):
    assert main(["rollout", "--map", "gen:corridor:test:1", "--preset", "medium",
                 "--n-agents", "2", "--horizon", "20", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["map"] == "gen:corridor:test:1" and out["n_agents"] == 2


def test_rules_override_gives_a_static_map_the_hard_preset(capsys):
    assert main(["rollout", "--map", "gen:open:test:0", "--preset", "hard", "--n-agents", "2",
                 "--horizon", "5", "--json"]) == 2
    assert "dynamic=False" in capsys.readouterr().err
    assert main(["rollout", "--map", "gen:open:test:0", "--preset", "hard", "--n-agents", "2",
                 "--horizon", "5", "--rules", "dynamic=false", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["preset"] == "hard"


def test_rules_values_take_their_field_type():
    assert parse_rule_overrides(["dynamic=false", "cook_time=8", "order_time_limit=none",
                                 "reward_mode=shared"]) == {
        "dynamic": False, "cook_time": 8, "order_time_limit": None, "reward_mode": "shared"}


def test_rules_reach_the_simulator(capsys):
    assert main(["rollout", "--preset", "easy", "--agents", "greedy", "--rules",
                 "stop_after_orders=1", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["steps"] < 200  # stopped at the first dish


@pytest.mark.parametrize("item, match", [
    ("cooking=3", "KEY one of"),
    ("dynamic", "KEY=VALUE"),
    ("dynamic=maybe", "true or false"),
    ("cook_time=fast", "whole number"),
    ("n_agents=2", "KEY one of"),
])
def test_a_bad_rule_names_the_allowed_keys_or_type(item, match):
    with pytest.raises(ConfigError, match=match):
        parse_rule_overrides([item])


def test_an_unknown_rule_key_exits_2_and_lists_the_keys(capsys):
    assert main(["rollout", "--preset", "easy", "--rules", "speed=3"]) == 2
    err = capsys.readouterr().err
    assert all(key in err for key in RULE_KEYS)


def test_a_rule_given_twice_is_refused():
    with pytest.raises(ConfigError, match="twice"):
        parse_rule_overrides(["cook_time=8", "cook_time=9"])


def test_the_horizon_is_set_by_its_own_option_not_by_rules(capsys):
    assert main(["rollout", "--preset", "easy", "--horizon", "9", "--rules", "horizon=7"]) == 2
    assert "use --horizon" in capsys.readouterr().err


def test_eval_passes_rules_to_every_episode_and_records_them(tmp_path, capsys):
    out = tmp_path / "e"
    assert main(["eval", "--map", "gen:open:test:0", "--preset", "hard", "--n-agents", "2",
                 "--rules", "dynamic=false", "--agents", "greedy", "--seeds", "2",
                 "--horizon", "10", "--quiet", "--out", str(out), "--json"]) == 0
    rows = [json.loads(line) for line in (out / "results.jsonl").read_text().splitlines()]
    assert len(rows) == 2 and all(r["status"] == "ok" for r in rows)
    assert all(r["rules"] == {"dynamic": False} and "dynamic=False" in r["key"] for r in rows)


def test_eval_takes_the_horizon_from_its_own_option(tmp_path, capsys):
    assert main(["eval", "--preset", "easy", "--rules", "horizon=3", "--agents", "greedy",
                 "--seeds", "1", "--out", str(tmp_path / "e")]) == 2
    assert "use --horizon" in capsys.readouterr().err


def test_every_command_that_builds_rules_from_the_kitchen_options_takes_rules():
    from ocplus_plan.cli import build_parser

    parser = build_parser()
    for command in ("rollout", "solve", "pddl", "play", "eval", "demo"):
        args = parser.parse_args([command, "--rules", "cook_time=8", "--preset", "easy",
                                  *(["--out", "x"] if command == "eval" else [])])
        assert args.rules == ["cook_time=8"], command


def test_a_split_kitchen_replaced_after_its_proof_is_the_one_its_name_loads(tmp_path):
    out = tmp_path / "m"
    assert main(["generate", "--family", "multiroom", "--split", "test", "--seed", "5",
                 "--n", "1", "--no-prove", "--quiet", "--out", str(out)]) == 0
    written = (out / "multiroom-test-0005.yaml").read_text()
    assert written == map_to_yaml(map_from_name("gen:multiroom:test:5"))
    kitchen = json.loads((out / "manifest.json").read_text())["kitchens"][0]
    assert kitchen["candidate"] == 1 and kitchen["replaced"][0]["candidate"] == 0


def test_generate_draws_each_kitchen_a_menu_into_its_file(tmp_path):
    from ocplus_plan.sim import make_rules
    from ocplus_plan.sim.generate_recipes import draw_recipes
    from ocplus_plan.sim.maps import load_map

    code, out = _generate(tmp_path, "m", "--stations", "medium", "--recipes", "2,3",
                          "--menu", "2")
    assert code == 0
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["generator"]["recipes"] == "2,3" and manifest["generator"]["menu"] == 2
    for entry in manifest["kitchens"]:
        layout = load_map(str(out / entry["file"]))
        bare = load_map(_spec_without_recipes(out / entry["file"]))
        assert bare.recipes is None
        assert entry["recipes"] == draw_recipes(bare, entry["seed"], (2, 3), 2, "required")
        rules = make_rules("medium", map=layout)
        assert ["+".join(k.name.lower() for k in r) for r in rules.recipes] == entry["recipes"]
    _, again = _generate(tmp_path, "m2", "--stations", "medium", "--recipes", "2,3",
                         "--menu", "2")
    assert (out / "split-seed000003.yaml").read_bytes() == \
        (again / "split-seed000003.yaml").read_bytes()


def _spec_without_recipes(path):
    import yaml

    spec = yaml.safe_load(path.read_text())
    spec.pop("recipes")
    return spec


@pytest.mark.parametrize("extra, message", [
    (["--recipes", "0"], "--recipes: 0 is out of range; a recipe length is a whole number "
                         "from 1 to 6"),
    (["--recipes", "2", "--menu", "33"], "--menu"),
])
def test_generate_refuses_bad_menu_options_in_one_line(tmp_path, capsys, extra, message):
    code, out = _generate(tmp_path, "bad", *extra)
    err = capsys.readouterr().err
    assert code == 2 and message in err and err.count("\n") == 1 and not out.exists()
