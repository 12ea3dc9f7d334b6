"""Process records are the rules' single source: the shipped ones compile to the presets'
rules, other records change what every engine does, bad records are refused. Map G (3x7):

    row 0:  counter steak counter pan  counter tomato counter
    row 1:  plate   .     .       .    .       .      delivery
    row 2:  counter trash board   sink counter counter counter
"""

from __future__ import annotations

import re
from dataclasses import replace

import pytest

from ocplus_plan.cli import main
from ocplus_plan.errors import CompileError, ConfigError, MapFormatError
from ocplus_plan.sim import Item, ItemState, Where, make_rules, new_state
from ocplus_plan.sim.codes import Action, Cell
from ocplus_plan.sim.maps import load_map
from ocplus_plan.sim.processes import PROCESSES, READY_STATE, Process, process_tables
from ocplus_plan.sim.queries import Bump, bump_effect
from ocplus_plan.sim.rules import with_overrides

from .conftest import kitchen
from .helpers import give, item_of, kinds, place, run, set_pos

R, D, L, U, S = (int(a) for a in (Action.RIGHT, Action.DOWN, Action.LEFT, Action.UP, Action.STAY))
G = [
    [1, 10, 1, 9, 1, 3, 1],
    [5, 0, 0, 0, 0, 0, 7],
    [1, 12, 6, 11, 1, 1, 1],
]
CHOP, COOK, WASH = PROCESSES
#: a pan driven by bumps: two sears cook a steak
SEAR = Process("sear", "seared", Cell.PAN, (Item.STEAK,), ItemState.FRESH, ItemState.COOKED,
               "bump", 2, stat="cooks")
#: a board driven by time: a vegetable is ready after 2 ticks and spoils (burnt) after 4
MARINATE = Process("marinate", "marinated", Cell.BOARD, (Item.TOMATO, Item.LETTUCE, Item.ONION),
                   ItemState.FRESH, ItemState.CHOPPED, "time", 2, "", ItemState.BURNT, 4,
                   stat="chops")

#: what the greedy cooks use unchanged: a board kneaded by four bumps of another verb (so
#: each is a Bump.WORK) and a pan that roasts in 2 ticks and burns after 5
KNEAD = replace(CHOP, verb="knead", past="kneaded", duration=4, duration_param="")
ROAST = replace(COOK, verb="roast", past="roasted", duration=2, duration_param="", overrun=5,
                overrun_param="")


def g_kitchen(processes=PROCESSES, **kw):
    kw.setdefault("recipes", ["tomato+steak"])
    rules, _ = kitchen(G, [[1, 1]], preset="medium", **kw)
    rules = with_overrides(rules, processes=processes)
    return rules, new_state(rules, 0)


def test_the_shipped_records_are_the_presets_rules():
    t = process_tables()
    assert [p.verb for p in t.processes] == ["chop", "cook", "wash"]
    assert READY_STATE == {Item.TOMATO: ItemState.CHOPPED, Item.LETTUCE: ItemState.CHOPPED,
                           Item.ONION: ItemState.CHOPPED, Item.STEAK: ItemState.COOKED}
    board, pan, sink = (t.by_code[int(c)] for c in (Cell.BOARD, Cell.PAN, Cell.SINK))
    assert t.works[board, Item.TOMATO, ItemState.FRESH]
    assert not t.works[board, Item.TOMATO, ItemState.CHOPPED]
    assert t.accepts[pan, Item.STEAK, ItemState.FRESH] and t.accepts[pan, Item.STEAK, ItemState.COOKED]
    assert not t.accepts[pan, Item.STEAK, ItemState.BURNT] and not t.works[pan].any()
    assert t.works[sink, Item.PLATE, ItemState.DIRTY] and not t.plates[sink] and t.plates[pan]
    assert (t.duration, t.overrun) == ((3, 10, 3), (-1, 20, -1))


def test_durations_come_from_the_rule_parameters_a_record_names():
    rules, _ = g_kitchen(chop_steps=5, cook_time=4, burn_time=7)
    assert process_tables(rules).duration == (5, 4, 3)
    assert process_tables(rules).overrun == (-1, 7, -1)


def test_a_bump_driven_record_makes_the_pan_work_by_bumps():
    rules, s = g_kitchen((CHOP, SEAR, WASH))
    steak = item_of(s, Item.STEAK)
    give(s, 0, steak)
    set_pos(s, 0, (1, 3))
    run(s, U)  # onto the pan
    assert s.item_where[steak] == Where.CELL
    assert bump_effect(s, -1, s.geo.flat(0, 3)) == Bump.WORK
    ev, _ = run(s, S, S, S)  # time does nothing on a bump-driven pan
    assert s.item_state[steak] == ItemState.FRESH and s.item_progress[steak] == 0
    ev, rw = run(s, U)
    assert kinds(ev) == ["sear"]
    ev, rw = run(s, U)
    assert "sear_done" in kinds(ev) and s.item_state[steak] == ItemState.COOKED
    assert s.stats["cooks"] == 1 and rw[-1][0] == pytest.approx(rules.rewards.subtask_finished
                                                                + rules.rewards.step_penalty)
    run(s, U)  # nothing left to sear: picked up
    assert s.agent_hand[0] == steak


def test_a_time_driven_record_makes_the_board_work_and_spoil_by_itself():
    _, s = g_kitchen((MARINATE, COOK, WASH))
    tomato = item_of(s, Item.TOMATO)
    place(s, tomato, (2, 2))
    ev, _ = run(s, S)
    assert s.item_state[tomato] == ItemState.FRESH and s.item_progress[tomato] == 1
    ev, _ = run(s, S)
    assert "marinate_done" in kinds(ev) and s.item_state[tomato] == ItemState.CHOPPED
    ev, _ = run(s, S, S, S)
    assert "burnt" in kinds(ev) and s.item_state[tomato] == ItemState.BURNT
    assert s.stats["burns"] == 1 and s.stats["chops"] == 1


@pytest.mark.parametrize("bad, message", [
    ((CHOP, replace(COOK, station=Cell.BOARD), WASH), "already runs"),
    ((replace(CHOP, drive="magic"), COOK, WASH), "drive"),
    ((replace(CHOP, duration=0, duration_param=""), COOK, WASH), "positive integer"),
    ((CHOP, replace(COOK, overrun=3, overrun_param=""), WASH), "overrun time"),
    ((replace(CHOP, stat="dances"), COOK, WASH), "counter"),
    ((CHOP, replace(COOK, takes=(Item.STEAK, Item.TOMATO)), WASH), "two processes"),
])
def test_a_record_no_engine_could_run_is_refused_naming_it(bad, message):
    rules, _ = g_kitchen()
    with pytest.raises(ConfigError, match=message):
        with_overrides(rules, processes=bad)


# ---------------------------------------------------------------- a kitchen file's records
ROAST_PAN = {"station": "pan", "verb": "roast", "takes": ["steak"], "from": "raw",
             "to": "cooked", "drive": "time", "duration": 6,
             "overrun": {"state": "burnt", "after": 9}}


def roast_map(**entry):
    return {"name": "roast", "game_map": G, "agent_spawn_points": [[1, 1]],
            "processes": [dict(ROAST_PAN, **entry)]}


def test_a_kitchen_file_gives_its_pan_another_record_and_the_step_follows_it():
    rules = make_rules("medium", map=roast_map(), recipes=["tomato+steak"])
    assert [p.verb for p in rules.processes] == ["chop", "roast", "wash"]  # others kept
    s = new_state(rules, 0)
    steak = item_of(s, Item.STEAK)
    place(s, steak, (0, 3))
    ev, _ = run(s, *[S] * 6)
    assert "roast_done" in kinds(ev) and s.item_state[steak] == ItemState.COOKED
    ev, _ = run(s, *[S] * 4)
    assert "burnt" in kinds(ev) and s.item_state[steak] == ItemState.BURNT


@pytest.mark.parametrize("entry, message", [
    ({"station": "grill"}, "station 'grill' is not one of board, pan, sink, oven"),
    ({"drive": "bump"}, "only a time-driven station overruns"),
    ({"duration": 0}, "'duration' must be an integer from 1 to 1000"),
    ({"duration": "6"}, "'duration' must be an integer"),
    ({"takes": ["bread"]}, "takes 'bread' is not one of"),
    ({"overrun": {"state": "burnt"}}, "'overrun' must be a mapping"),
    ({"verb": "Roast it"}, "'verb' must be one lower-case word"),
    ({"colour": "red"}, "unknown key 'colour'"),
    ({"takes": ["tomato"]}, "taken by two processes"),
])
def test_a_bad_record_in_a_kitchen_file_is_refused_naming_the_file_and_entry(entry, message):
    with pytest.raises(MapFormatError, match=re.escape(message)) as err:
        load_map(roast_map(**entry))
    assert "processes" in str(err.value)


def test_the_planning_model_refuses_records_it_does_not_cover():
    pytest.importorskip("unified_planning")
    from ocplus_plan.planning import compile

    rules = make_rules("medium", map=roast_map(), recipes=["tomato+steak"])
    compile(new_state(rules, 0))  # another verb and times on the pan: covered
    rules = make_rules("medium", map=roast_map(drive="bump", overrun=None, verb="sear"),
                       recipes=["tomato+steak"])
    with pytest.raises(CompileError, match="covers the shipped process stations"):
        compile(new_state(rules, 0))


def test_check_map_lists_a_kitchen_files_records_and_refuses_a_bad_one(tmp_path, capsys):
    import yaml

    good, bad = tmp_path / "roast.yaml", tmp_path / "bad.yaml"
    good.write_text(yaml.safe_dump(roast_map()))
    bad.write_text(yaml.safe_dump(roast_map(duration=0)))
    assert main(["check-map", str(good)]) == 0
    assert "pan: roast steak fresh -> cooked by time, 6, burnt after 9" in capsys.readouterr().out
    assert main(["check-map", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert "bad.yaml: processes[0]: 'duration'" in err and "\n" not in err


def test_a_recording_keeps_a_kitchen_files_records_and_replays_them():
    from ocplus_plan.render.replay import layout_to_dict, rules_from_dict, rules_to_dict

    rules = make_rules("medium", map=roast_map(), recipes=["tomato+steak"])
    again = rules_from_dict("medium", layout_to_dict(rules), rules_to_dict(rules))
    assert again.processes == rules.processes
    with pytest.raises(ConfigError, match="declare them under the map's 'processes'"):
        rules_to_dict(with_overrides(rules, processes=(KNEAD, ROAST, WASH)))


def test_a_state_given_other_rules_follows_their_durations():
    rules, s = g_kitchen()
    s.rules = with_overrides(rules, chop_steps=4)
    tomato = item_of(s, Item.TOMATO)
    place(s, tomato, (2, 2))
    set_pos(s, 0, (1, 2))
    run(s, D, D, D)
    assert s.item_state[tomato] == ItemState.FRESH
    ev, _ = run(s, D)
    assert "chop_done" in kinds(ev)
