"""Options the subcommands share: one definition, one type, one default, one help text,
one meaning everywhere (``tests/test_flags.py`` walks every parser to hold this; the page
is ``docs/cli.md``). Values are checked while parsing (``_types.py``), before any work.

- kitchen (:func:`add_kitchen_args`): ``--preset --map --n-agents --seed --horizon``
  and ``--rules KEY=VALUE ...`` (rule overrides, :func:`parse_rule_overrides`);
  commands that run many kitchens (``eval``, ``demo``, ``export-suite``) take a
  comma-separated ``--preset`` list and (not ``export-suite``) ``--seeds`` besides ``--seed``.
- output (:func:`add_output_args`): ``--json`` prints the result as one JSON object on
  stdout (else ``key value`` lines); ``--quiet`` drops progress bars and status lines (the
  result is still printed); ``--out`` names the folder a command writes its files to,
  ``runs/<command>-<date>-<time>`` when not given.
- running many episodes: ``--jobs``, ``--episode-timeout``, ``--plots/--no-plots`` (off)
  (:func:`add_jobs_arg`, :func:`add_episode_timeout_arg`, :func:`add_plots_arg`).
- old spellings (:func:`add_deprecated_alias`) keep working and say on stderr what
  replaced them: ``rollout --steps`` (now ``--horizon``), ``train --steps`` (now
  ``--timesteps``), ``train --no-progress`` (now ``--quiet``), ``solve/pddl --step`` (now
  ``--random-steps``), ``solve --plan`` (now ``--show-plan``).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import sys
import time
from dataclasses import fields
from pathlib import Path
from typing import Any, NoReturn

from ..errors import ConfigError, DependencyNotInstalled
from ..planning.model import ENCODINGS, GRANULARITIES
from ..sim.rules import OPTIONAL_RULE_LIMITS, RULE_LIMITS, Rules, make_rules, rule_limit_problem
from . import _types

PRESET_HELP = "easy | medium | hard"
#: the defaults of the shared options, the same on every command that takes them
DEFAULT_PRESETS = "easy,medium,hard"
DEFAULT_SEEDS = "3"
DEFAULT_HORIZON = 200
#: bad input (see ``ocplus_plan/cli.py``)
EXIT_INPUT = 2


class HelpFormatter(argparse.RawDescriptionHelpFormatter, argparse.ArgumentDefaultsHelpFormatter):
    """Every subcommand's help: its docstring as written, and each option's default."""


def add_kitchen_args(p: argparse.ArgumentParser, *, sweep: bool = False, step: bool = False,
                     horizon: bool = True, seeds: bool = True, grid: bool = False,
                     rules: bool = True) -> None:
    """``--preset --map --n-agents --seed`` and ``--horizon``.

    ``sweep``: ``--preset`` takes a comma-separated list (``--presets`` is the same
    option) and ``--seeds`` a count, list or range, exclusive with ``--seed`` (no
    ``--seeds`` without ``seeds``). ``grid`` (with ``sweep``): ``--map`` and
    ``--n-agents`` take comma-separated lists too, also spelt ``--maps`` and ``--cooks``
    (the command parses them: :func:`parse_int_list`). ``step`` adds ``--random-steps``
    (random joint actions before compiling a state; ``--step`` is its old spelling).
    ``rules``: offer ``--rules KEY=VALUE ...`` (the command passes them on:
    :func:`rules_from_args` or :func:`sweep_rules`)."""
    g = p.add_argument_group("kitchen")
    if sweep:
        g.add_argument("--preset", "--presets", dest="presets", type=_types.name,
                       default=DEFAULT_PRESETS, help=f"comma-separated presets ({PRESET_HELP})")
    else:
        g.add_argument("--preset", type=_types.name, default="easy", help=PRESET_HELP)
    lists = "; comma-separated lists" if grid else ""
    g.add_argument("--map", *(["--maps"] if grid else []), type=_types.name, default=None,
                   help=f"map name or YAML path{lists} (None: the preset's)")
    g.add_argument("--n-agents", *(["--cooks"] if grid else []),
                   type=_types.whole_list("a number of cooks", 1, _types.MAX_AGENTS) if grid
                   else _types.n_agents, default=None,
                   help=f"number of cooks, 1 to {_types.MAX_AGENTS}{lists} (None: the preset's)")
    if sweep and seeds:
        which = g.add_mutually_exclusive_group()
        which.add_argument("--seed", type=_types.seed, default=None,
                           help=f"one episode seed, 0 to {_types.MAX_SEED} (None: the --seeds)")
        which.add_argument("--seeds", type=_types.seeds, default=DEFAULT_SEEDS,
                           help="episode seeds: a count (10 = seeds 0-9), a list (0,4,7) or a "
                                f"range (5-9), at most {_types.MAX_SEEDS}")
    else:
        g.add_argument("--seed", type=_types.seed, default=0,
                       help=f"seed, 0 to {_types.MAX_SEED}: the episode's")
    if horizon:
        g.add_argument("--horizon", type=_types.horizon, default=DEFAULT_HORIZON,
                       help=f"steps per episode, 1 to {_types.MAX_HORIZON} (every preset "
                            f"plays {DEFAULT_HORIZON})")
    if step:
        g.add_argument("--random-steps", dest="step", type=_types.random_steps, default=0,
                       metavar="T",
                       help="random joint actions to take before compiling, 0 to "
                            f"{_types.MAX_HORIZON}")
        add_deprecated_alias(p, "--step", "--random-steps", takes_value=True, dest="step",
                             type=_types.random_steps)
    if rules:
        g.add_argument("--rules", nargs="+", action="extend", default=None,
                       metavar="KEY=VALUE", help="rule overrides, e.g. dynamic=false "
                       f"cook_time=8 (keys: {', '.join(RULE_KEYS)})")


def parse_int_list(text: str, option: str) -> list[int]:
    """``"1,2"`` -> ``[1, 2]`` for an option that takes a comma-separated list of integers."""
    try:
        out = [int(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise ConfigError(f"{option} {text!r}: give comma-separated whole numbers, "
                          "e.g. 1,2") from None
    if not out:
        raise ConfigError(f"{option} is empty; give comma-separated whole numbers, e.g. 1,2")
    return out


def rules_from_args(args: argparse.Namespace, **overrides: Any) -> Rules:
    """The rules the kitchen options name (``--preset --map --n-agents --horizon --rules``).
    A ``--rules`` key the caller also sets is refused (the command needs its own value)."""
    for name in ("n_agents", "horizon"):
        if getattr(args, name, None) is not None:
            overrides.setdefault(name, getattr(args, name))
    given = sweep_rules(args)
    clash = sorted(k for k in set(given) & set(overrides) if given[k] != overrides[k])
    if clash:
        raise ConfigError(f"--rules sets {', '.join(clash)}, which another option of this "
                          "command also sets; give it once")
    return make_rules(args.preset, map=args.map, **{**overrides, **given})


def sweep_rules(args: argparse.Namespace) -> dict[str, Any]:
    """``--rules`` of a command: ``--horizon`` is the one way to set the horizon (it has a
    default, so a horizon among the rules would always clash with it)."""
    given = parse_rule_overrides(getattr(args, "rules", None))
    if "horizon" in given:
        raise ConfigError("--rules horizon=...: use --horizon, the option this command "
                          "records the horizon under")
    return given


def _rule_types() -> dict[str, str]:
    """Rules field -> its type as written (``int``, ``bool``, ``int | None``, ``str``)."""
    skip = {"preset", "layout", "n_agents", "recipes", "rewards", "fixed_orders", "processes"}
    return {f.name: str(f.type) for f in fields(Rules) if f.name not in skip}


#: the keys ``--rules`` takes (``n_agents`` is ``--n-agents``)
RULE_KEYS: tuple[str, ...] = tuple(sorted(_rule_types()))
_TRUE, _FALSE = ("true", "yes", "on", "1"), ("false", "no", "off", "0")


def parse_rule_overrides(items: list[str] | None) -> dict[str, Any]:
    """``["dynamic=false", "cook_time=8"]`` -> ``{"dynamic": False, "cook_time": 8}``, each
    value read as its Rules field's type (``none`` for an optional one). An unknown key,
    a repeated key or a value of the wrong type is a :class:`ConfigError`."""
    types = _rule_types()
    out: dict[str, Any] = {}
    for item in items or ():
        key, sep, text = item.partition("=")
        key, text = key.strip(), text.strip()
        if not sep or key not in types:
            raise ConfigError(f"--rules {item!r}: write KEY=VALUE with KEY one of "
                              f"{', '.join(RULE_KEYS)}")
        if key in out:
            raise ConfigError(f"--rules gives {key} twice; give it once")
        out[key] = _rule_value(key, types[key], text)
    return out


def _rule_value(key: str, kind: str, text: str) -> Any:
    low = text.lower()
    if kind.endswith("| None") and low == "none":
        return None
    if kind.startswith("bool"):
        if low in _TRUE or low in _FALSE:
            return low in _TRUE
        raise ConfigError(f"--rules {key}={text!r}: {key} is true or false")
    if kind.startswith("int"):
        if not _types.WHOLE.fullmatch(text):
            none = " (or none)" if kind.endswith("| None") else ""
            raise ConfigError(f"--rules {key}={text!r}: {key} is a whole number in ASCII "
                              f"digits{none}")
        problem = rule_limit_problem(key, int(text)) \
            if key in RULE_LIMITS or key in OPTIONAL_RULE_LIMITS else None
        if problem:  # the limits a recording of the episode is read with
            raise ConfigError(f"--rules {key}={text}: {problem}")
        return int(text)
    return text


class _TrustPickled(argparse.Action):
    """Sets the environment switch, so that worker processes see it too."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace,
                 values: Any, option_string: str | None = None) -> None:
        from ..rl.weights import TRUST_ENV

        os.environ[TRUST_ENV] = "1"
        setattr(namespace, self.dest, True)


def add_trust_arg(p: Any) -> None:
    """``--trust-pickled-checkpoint``: allow SB3 ``.zip`` checkpoints, which run code."""
    p.add_argument("--trust-pickled-checkpoint", nargs=0, action=_TrustPickled, default=False,
                   help="load stable-baselines3 .zip checkpoints: they are pickles and RUN "
                        "CODE when loaded; only for files you made yourself (convert them "
                        "with `python -m ocplus_plan.rl.weights IN.zip OUT.npz` instead)")


def add_output_args(p: argparse.ArgumentParser, *, out: bool = False, writes: str = "") -> None:
    """``--json`` and ``--quiet``; with ``out`` also ``--out`` (``writes`` says what goes
    there). ``--out`` is optional everywhere: without it a command writes to
    ``runs/<command>-<date>-<time>`` (:func:`finish_args`)."""
    g = p.add_argument_group("output")
    g.add_argument("--json", action="store_true", help="print the result as one JSON object "
                   "(else one `key value` line per entry)")
    g.add_argument("--quiet", action="store_true",
                   help="no progress bars or status lines (the result is still printed)")
    if out:
        g.add_argument("--out", type=_types.out_dir, default=None, metavar="DIR",
                       help="folder the command writes to" + (f": {writes}" if writes else "")
                       + " (None: runs/<command>-<date>-<time>)")


def add_plots_arg(g: Any) -> None:
    """``--plots`` / ``--no-plots``: write PNG figures or not (``--plots`` without matplotlib
    is refused before any work: :func:`finish_args`)."""
    g.add_argument("--plots", action=argparse.BooleanOptionalAction, default=False,
                   help="write PNG figures into OUT/plots/ (the plots extra), or not")


def add_jobs_arg(g: Any) -> None:
    """``--jobs``: episodes at once."""
    g.add_argument("--jobs", type=_types.jobs, default=None,
                   help=f"episodes at once, 1 to {_types.MAX_JOBS}: worker processes (None: 1), "
                        "or with --backend ray the Ray tasks in flight (None: all CPUs of the "
                        "cluster)")


def add_episode_timeout_arg(g: Any) -> None:
    """``--episode-timeout``: seconds before an episode is stopped."""
    g.add_argument("--episode-timeout", type=_types.seconds, default=None, metavar="SECONDS",
                   help="seconds before an episode is killed and recorded as an error, at most "
                        f"{_types.MAX_SECONDS:.0f} (None: no limit)")


def finish_args(args: argparse.Namespace) -> None:
    """What the options mean once all are read, checked before any work starts: ``--out``
    without a value becomes ``runs/<command>-<date>-<time>``; ``--resume`` needs an explicit
    ``--out``; ``--plots`` without matplotlib is refused (exit 3)."""
    if getattr(args, "resume", False) and getattr(args, "out", "") is None:
        raise ConfigError("--resume continues the run in --out: give --out DIR")
    if hasattr(args, "out") and args.out is None:
        command = getattr(args, "command", None) or "run"
        default = str(Path("runs") / time.strftime(f"{command}-%Y%m%d-%H%M%S"))
        try:
            args.out = _types.out_dir(default)
        except argparse.ArgumentTypeError as exc:
            raise ConfigError(f"no --out given, and the default {exc}") from None
    if getattr(args, "plots", False) and importlib.util.find_spec("matplotlib") is None:
        raise DependencyNotInstalled("--plots needs matplotlib: pip install -e '.[plots]' "
                                     "(or leave --plots out)")


def add_deprecated_alias(p: argparse.ArgumentParser, old: str, new: str, *,
                         takes_value: bool, dest: str | None = None,
                         type: Any = int) -> None:
    """Let ``old`` set what the option ``new`` sets (``dest``: its attribute, by default
    named after ``new``), with a note on stderr. ``type`` checks a value as ``new`` does."""
    dest = dest or new.lstrip("-").replace("-", "_")
    if takes_value:
        p.add_argument(old, dest=dest, type=type, action=_Deprecated, replacement=new,
                       default=argparse.SUPPRESS, help=f"deprecated spelling of {new}")
    else:
        p.add_argument(old, dest=dest, nargs=0, action=_Deprecated, replacement=new,
                       default=argparse.SUPPRESS, help=f"deprecated spelling of {new}")


class _Deprecated(argparse.Action):
    def __init__(self, option_strings: list[str], dest: str, replacement: str,
                 **kwargs: Any) -> None:
        super().__init__(option_strings, dest, **kwargs)
        self.replacement = replacement

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace,
                 values: Any, option_string: str | None = None) -> None:
        print(f"ocplus: {option_string} is deprecated; use {self.replacement}", file=sys.stderr)
        setattr(namespace, self.dest, True if self.nargs == 0 else values)


class Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line on stderr (what is wrong, what is
    allowed, where the help is) and exit 2."""

    def error(self, message: str) -> NoReturn:
        line = " ".join(message.split())
        self.exit(EXIT_INPUT, f"{self.prog}: error: {line} (see {self.prog} --help)\n")


def add_compile_args(p: argparse.ArgumentParser, *, auto_encoding: bool = False,
                     many: bool = False, switches: bool = True,
                     limits: float | None | bool = False) -> None:
    """``--encoding --granularity --orders --anticipate-switches`` of the planning compiler
    (``many``: ``--encoding`` takes a comma-separated list; ``switches``: offer
    ``--anticipate-switches``). ``limits`` (a number, or None for the planner's own
    limit; False: none) adds the planner limits ``--timeout`` (CPU seconds of the
    planner's process group, as the IPC counts them) and ``--wall-limit`` (a wall-clock
    safety); check them with :func:`check_limits`."""
    if limits is not False:
        p.add_argument("--timeout", type=_types.seconds, default=limits,
                       help="planner CPU seconds (user + system of the planner's processes), "
                            "per planner call" + (" (None: the planner's configured limit)"
                                                  if limits is None else ""))
        p.add_argument("--wall-limit", type=_types.seconds, default=None,
                       help="wall-clock safety per planner call, in seconds (None: 30 x "
                            "--timeout + 60)")
    if many:
        p.add_argument("--encoding", "--encodings", dest="encoding", default=",".join(ENCODINGS),
                       help=f"comma-separated encodings ({' | '.join(ENCODINGS)})")
    elif auto_encoding:
        p.add_argument("--encoding", choices=("auto", *ENCODINGS), default="auto",
                       help="auto = the encoding the planner is registered for")
    else:
        p.add_argument("--encoding", choices=ENCODINGS, default=ENCODINGS[0])
    p.add_argument("--granularity", choices=GRANULARITIES, default=GRANULARITIES[0])
    p.add_argument("--orders", type=_types.whole("--orders", 1, 1000), default=None,
                   help="serve only the first k open orders (default: all)" if not many else
                   "goal orders per instance: the first k open orders; k above the "
                   "preset's queue raises the queue (rule n_orders), so the state holds k "
                   "open orders drawn from the preset's recipes (default: the queue)")
    if switches:
        p.add_argument("--anticipate-switches", action="store_true",
                       help="temporal only: the coming layout switches as timed initial literals")


def check_limits(args: argparse.Namespace) -> None:
    """Refuse a ``--timeout`` or ``--wall-limit`` that is not a positive finite number."""
    import math

    for option in ("timeout", "wall_limit"):
        value = getattr(args, option, None)
        if value is not None and not (value > 0 and math.isfinite(value)):
            raise ConfigError(f"--{option.replace('_', '-')} must be a positive number of "
                              f"seconds, got {value}")


def emit(result: Any, args: argparse.Namespace, width: int = 16) -> None:
    """Print a command's result: one JSON object with ``--json``, else one ``key value``
    line per entry."""
    if getattr(args, "json", False) or not isinstance(result, dict):
        print(json.dumps(result, default=str))
    else:
        for key, value in result.items():
            print(f"{key:{width}s} {value}")


def say(args: argparse.Namespace, message: str) -> None:
    """A status line: none with ``--quiet``; on stderr with ``--json`` (stdout stays JSON)."""
    if not getattr(args, "quiet", False):
        note(args, message)


def note(args: argparse.Namespace, message: str) -> None:
    """A line that goes with the result (e.g. why an agent was skipped), even with
    ``--quiet``; on stderr with ``--json``."""
    print(message, file=sys.stderr if getattr(args, "json", False) else sys.stdout)
