"""Options the subcommands share: one definition, one help text, one meaning everywhere.

- kitchen (:func:`add_kitchen_args`): ``--preset --map --n-agents --seed --horizon``
  and ``--rules KEY=VALUE ...`` (rule overrides, :func:`parse_rule_overrides`);
  commands that run many kitchens (``eval``, ``demo``) take a comma-separated
  ``--preset`` list and ``--seeds`` besides ``--seed``.
- output (:func:`add_output_args`): ``--json`` prints the result as one JSON object on
  stdout; ``--quiet`` drops progress bars and status lines (the result is still
  printed); ``--out`` names the folder a command writes its files to.
- old spellings (:func:`add_deprecated_alias`) keep working and say on stderr what
  replaced them: ``rollout --steps`` (now ``--horizon``), ``train --no-progress`` (now
  ``--quiet``).
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import fields
from typing import Any

from ..errors import ConfigError
from ..planning.model import ENCODINGS, GRANULARITIES
from ..sim.rules import Rules, make_rules

PRESET_HELP = "easy | medium | hard"


class HelpFormatter(argparse.RawDescriptionHelpFormatter, argparse.ArgumentDefaultsHelpFormatter):
    """Every subcommand's help: its docstring as written, and each option's default."""


def add_kitchen_args(p: argparse.ArgumentParser, *, sweep: bool = False, step: bool = False,
                     horizon: bool = True, presets: str = "easy,medium,hard",
                     seeds: str | None = "10", default_horizon: int | None = None,
                     grid: bool = False) -> None:
    """``--preset --map --n-agents --seed`` and ``--horizon``.

    ``sweep``: ``--preset`` takes a comma-separated list (``--presets`` is the same
    option) and ``--seeds`` a count, list or range, exclusive with ``--seed`` (no
    ``--seeds`` when ``seeds`` is None). ``grid`` (with ``sweep``): ``--map`` and
    ``--n-agents`` take comma-separated lists too, also spelt ``--maps`` and ``--cooks``
    (the command parses them: :func:`parse_int_list`). ``step`` adds ``--step`` (random
    joint actions before compiling a state)."""
    g = p.add_argument_group("kitchen")
    if sweep:
        g.add_argument("--preset", "--presets", dest="presets", default=presets,
                       help=f"comma-separated presets ({PRESET_HELP})")
    else:
        g.add_argument("--preset", default="easy", help=PRESET_HELP)
    g.add_argument("--map", *(["--maps"] if grid else []), default=None,
                   help="map name or YAML path (None: the preset's)")
    g.add_argument("--n-agents", *(["--cooks"] if grid else []), type=str if grid else int,
                   default=None, help="number of cooks (None: the preset's)")
    if sweep and seeds is None:
        g.add_argument("--seed", type=int, default=0, help="episode seed")
    elif sweep:
        which = g.add_mutually_exclusive_group()
        which.add_argument("--seed", type=int, default=None, help="one episode seed")
        which.add_argument("--seeds", default=seeds,
                           help="episode seeds: a count (10 = seeds 0-9), a list or a range")
    else:
        g.add_argument("--seed", type=int, default=0, help="episode seed")
    if horizon:
        g.add_argument("--horizon", type=int, default=default_horizon,
                       help="steps per episode (None: the preset's, 200)")
    if step:
        g.add_argument("--step", type=int, default=0,
                       help="random joint actions to take before compiling")
    g.add_argument("--rules", nargs="+", action="extend", default=None, metavar="KEY=VALUE",
                   help="rule overrides, e.g. dynamic=false cook_time=8 "
                        f"(keys: {', '.join(RULE_KEYS)})")


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
    given = parse_rule_overrides(getattr(args, "rules", None))
    clash = sorted(k for k in set(given) & set(overrides) if given[k] != overrides[k])
    if clash:
        raise ConfigError(f"--rules sets {', '.join(clash)}, which another option of this "
                          "command also sets; give it once")
    return make_rules(args.preset, map=args.map, **{**overrides, **given})


def _rule_types() -> dict[str, str]:
    """Rules field -> its type as written (``int``, ``bool``, ``int | None``, ``str``)."""
    skip = {"preset", "layout", "n_agents", "recipes", "rewards", "fixed_orders"}
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
        try:
            return int(text)
        except ValueError:
            none = " (or none)" if kind.endswith("| None") else ""
            raise ConfigError(f"--rules {key}={text!r}: {key} is a whole number{none}") from None
    return text


def add_output_args(p: argparse.ArgumentParser, *, out: str | None = None,
                    out_default: str | None = None, writes: str = "") -> None:
    """``--json`` and ``--quiet``; with ``out`` ("required" or "optional") also ``--out``
    (``writes`` says what goes there)."""
    g = p.add_argument_group("output")
    g.add_argument("--json", action="store_true", help="print the result as one JSON object")
    g.add_argument("--quiet", action="store_true",
                   help="no progress bars or status lines (the result is still printed)")
    if out is not None:
        g.add_argument("--out", required=out == "required", default=out_default,
                       help="folder the command writes to" + (f": {writes}" if writes else ""))


def add_deprecated_alias(p: argparse.ArgumentParser, old: str, new: str, *,
                         takes_value: bool) -> None:
    """Let ``old`` set what the option ``new`` sets, with a note on stderr."""
    dest = new.lstrip("-").replace("-", "_")
    if takes_value:
        p.add_argument(old, dest=dest, type=int, action=_Deprecated, replacement=new,
                       help=f"deprecated spelling of {new}")
    else:
        p.add_argument(old, dest=dest, nargs=0, action=_Deprecated, replacement=new,
                       help=f"deprecated spelling of {new}")


class _Deprecated(argparse.Action):
    def __init__(self, option_strings: list[str], dest: str, replacement: str,
                 **kwargs: Any) -> None:
        super().__init__(option_strings, dest, **kwargs)
        self.replacement = replacement

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace,
                 values: Any, option_string: str | None = None) -> None:
        print(f"ocplus: {option_string} is deprecated; use {self.replacement}", file=sys.stderr)
        setattr(namespace, self.dest, True if self.nargs == 0 else values)


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
        p.add_argument("--timeout", type=float, default=limits,
                       help="planner CPU seconds (user + system of the planner's processes), "
                            "per planner call" + (" (None: the planner's configured limit)"
                                                  if limits is None else ""))
        p.add_argument("--wall-limit", type=float, default=None,
                       help="wall-clock safety per planner call, in seconds (None: 5 x "
                            "--timeout + 30)")
    if many:
        p.add_argument("--encoding", "--encodings", dest="encoding", default=",".join(ENCODINGS),
                       help=f"comma-separated encodings ({' | '.join(ENCODINGS)})")
    elif auto_encoding:
        p.add_argument("--encoding", choices=("auto", *ENCODINGS), default="auto",
                       help="auto = the encoding the planner is registered for")
    else:
        p.add_argument("--encoding", choices=ENCODINGS, default=ENCODINGS[0])
    p.add_argument("--granularity", choices=GRANULARITIES, default=GRANULARITIES[0])
    p.add_argument("--orders", type=int, default=None,
                   help="serve only the first k open orders (default: all)")
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
