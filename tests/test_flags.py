"""One meaning per flag: every subcommand's parser is walked, and each shared option has the
same name, type, default and help wherever it appears (``commands/_common.py`` declares
them once); old spellings keep working with a note."""

from __future__ import annotations

import argparse

import pytest

from ocplus_plan.cli import COMMANDS, build_parser
from ocplus_plan.commands import _common, _types

#: the shared options: value type (None for flags), default. The sweep commands (eval, demo,
#: export-suite: many kitchens in one run) take --preset as a comma-separated list and, where
#: they also take --seeds, --seed as its one-seed form: SWEEP lists those two differences.
SHARED = {
    "--out": (_types.out_dir, None),
    "--json": (None, False),
    "--quiet": (None, False),
    "--plots": (None, False),
    "--seed": (_types.seed, 0),
    "--seeds": (_types.seeds, _common.DEFAULT_SEEDS),
    "--horizon": (_types.horizon, _common.DEFAULT_HORIZON),
    "--jobs": (_types.jobs, None),
    "--episode-timeout": (_types.seconds, None),
    "--map": (_types.name, None),
    "--preset": (_types.name, "easy"),
    "--n-agents": (_types.n_agents, None),
}
SWEEP = {"--preset": (_types.name, _common.DEFAULT_PRESETS), "--seed": (_types.seed, None)}
#: export-suite writes a grid of kitchens: --map (--maps) and --n-agents (--cooks) take lists
GRID = {"--map", "--n-agents"}


def _subparsers() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


def _options(sub: argparse.ArgumentParser, *, deprecated: bool = False) -> dict:
    return {s: a for a in sub._actions for s in a.option_strings
            if deprecated or not isinstance(a, _common._Deprecated)}


def _form(sub: argparse.ArgumentParser, flag: str) -> str:
    """"grid", "sweep" or "one": which declaration of ``flag`` this command should have."""
    opts = _options(sub)
    if flag in GRID and "--cooks" in opts:
        return "grid"
    sweep = "--preset" in opts and opts["--preset"].dest == "presets"
    if sweep and flag in SWEEP and (flag != "--seed" or "--seeds" in opts):
        return "sweep"
    return "one"


SUBS = _subparsers()


def test_the_walk_sees_every_command():
    assert set(SUBS) == set(COMMANDS)


@pytest.mark.parametrize("name", sorted(SUBS))
def test_shared_flags_have_one_type_and_one_default(name):
    sub = SUBS[name]
    opts = _options(sub)
    for flag, (kind, default) in SHARED.items():
        if flag not in opts:
            continue
        action = opts[flag]
        if _form(sub, flag) == "grid":
            assert action.default is None, (name, flag)
            continue
        if _form(sub, flag) == "sweep":
            kind, default = SWEEP[flag]
        assert action.type is kind, (name, flag, action.type)
        assert action.default == default, (name, flag, action.default)
        assert not action.required, (name, flag)


@pytest.mark.parametrize("flag", sorted(SHARED))
def test_a_shared_flag_has_one_help_text(flag):
    helps: dict[str, set[str]] = {}
    for name, sub in SUBS.items():
        opts = _options(sub)
        if flag in opts:
            helps.setdefault(_form(sub, flag), set()).add(opts[flag].help.split(": ", 1)[0])
    assert all(len(texts) == 1 for texts in helps.values()), helps


def test_json_and_quiet_are_on_every_command_and_off_by_default():
    for name, sub in SUBS.items():
        opts = _options(sub)
        assert opts["--json"].default is False and opts["--quiet"].default is False, name
        assert sub.get_default("json") is False, name  # no set_defaults(json=True) no-op


def test_commands_that_write_files_take_an_optional_out():
    writers = {"eval", "demo", "train", "export-suite", "pddl", "generate", "league"}
    assert {n for n, s in SUBS.items() if "--out" in _options(s)} == writers


def test_plots_is_one_on_off_switch_wherever_plots_are_made():
    for name in ("eval", "demo", "report", "league"):
        opts = _options(SUBS[name])
        assert opts["--plots"] is opts["--no-plots"], name


def test_an_option_name_is_a_flag_everywhere_or_takes_a_value_everywhere():
    kinds: dict[str, set[bool]] = {}
    for sub in SUBS.values():
        for option, action in _options(sub).items():
            kinds.setdefault(option, set()).add(action.nargs == 0)
    assert {o: k for o, k in kinds.items() if len(k) > 1} == {}


def test_no_command_has_a_step_or_steps_option_of_its_own():
    for name, sub in SUBS.items():
        assert not {"--step", "--steps"} & set(_options(sub)), name


def test_kitchen_flags_come_together():
    kitchen = ("--preset", "--map", "--n-agents", "--seed")
    for name, sub in SUBS.items():
        opts = _options(sub)
        if "--preset" in opts:
            assert all(k in opts for k in kitchen), name
    assert {n for n, s in SUBS.items() if "--preset" in _options(s)} == {
        "rollout", "eval", "demo", "play", "train", "solve", "pddl", "export-suite"}


OLD_AND_NEW = [
    (["rollout", "--steps", "30"], ["rollout", "--horizon", "30"]),
    (["train", "--steps", "64"], ["train", "--timesteps", "64"]),
    (["train", "--no-progress"], ["train", "--quiet"]),
    (["solve", "--step", "5"], ["solve", "--random-steps", "5"]),
    (["pddl", "--step", "5"], ["pddl", "--random-steps", "5"]),
    (["solve", "--plan"], ["solve", "--show-plan"]),
]


@pytest.mark.parametrize(("old", "new"), OLD_AND_NEW, ids=lambda argv: " ".join(argv))
def test_an_old_spelling_reads_as_the_new_one_with_a_note(old, new, capsys):
    parser = build_parser()
    then = vars(parser.parse_args(old))
    assert f"{old[1]} is deprecated; use {new[1]}" in capsys.readouterr().err
    now = vars(parser.parse_args(new))
    assert then == now


def test_an_old_spelling_is_checked_as_the_new_one(capsys):
    from ocplus_plan.cli import main

    assert main(["rollout", "--steps", "0"]) == 2
    assert "horizon" in capsys.readouterr().err


def test_finish_args_names_the_default_out_after_the_command(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    args = build_parser().parse_args(["eval"])
    _common.finish_args(args)
    assert args.out.startswith("runs/eval-")
    assert not (tmp_path / "runs").exists()  # checked, not made: the command makes it


@pytest.mark.skipif(__import__("os").geteuid() == 0, reason="root may write anywhere")
def test_a_default_out_that_cannot_be_made_is_bad_input(tmp_path, monkeypatch):
    from ocplus_plan.errors import ConfigError

    tmp_path.chmod(0o500)
    monkeypatch.chdir(tmp_path)
    try:
        args = build_parser().parse_args(["eval"])
        with pytest.raises(ConfigError, match="no --out given"):
            _common.finish_args(args)
    finally:
        tmp_path.chmod(0o700)


def test_a_default_out_below_a_file_is_bad_input(tmp_path, monkeypatch):
    from ocplus_plan.errors import ConfigError

    (tmp_path / "runs").write_text("a file where the default folder goes")
    monkeypatch.chdir(tmp_path)
    args = build_parser().parse_args(["pddl"])
    with pytest.raises(ConfigError, match="no --out given.*runs"):
        _common.finish_args(args)
