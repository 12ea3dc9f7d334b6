"""Compact episode recordings: save, load, replay (same ``state_hash``) and GIF export.

A recording holds what determines an episode and nothing more: the rule parameters
(the full map inline, so a file replays on a machine without that map), the seed,
one joint action per step, and a short summary of each step's events. The states
are recomputed by the simulator on replay, so a replay is proof of determinism: its
final ``state_hash`` must equal the recorded one.

File format: JSON lines (``.jsonl``), gzip-compressed when the name ends in ``.gz``.
Line 1 is the header (``format``, ``version``, ``preset``, ``map``, ``rules``,
``seed``, ``meta``), then one line per step ``{"a": [actions], "e": ["kind:agent",
...]}`` (``e`` omitted when nothing notable happened), and a last line ``{"end":
true, "steps", "state_hash", "stats"}``.

The evaluation saves chosen episodes with :class:`Recorder` (``record`` each step,
then ``save``); ``ocplus replay FILE [--gif OUT]`` plays one back.
"""

from __future__ import annotations

import gzip
import json
import zlib
from collections import Counter
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import IO, Any

import numpy as np

from ..errors import ConfigError, DependencyNotInstalled, OcplusError
from ..sim import Action, Event, Rules, State, make_rules, new_state, recipe_name, transition
from ..sim.dishes import dish_to_dict
from ..sim.process_yaml import own_processes
from ..sim.processes import PROCESSES
from ..sim.rules import OPTIONAL_RULE_LIMITS, RULE_LIMITS, Rewards

FORMAT = "ocplus-replay"
#: 2: every rule field is in the header (``fixed_orders`` included) and every line is
#: checked on reading; 1: files written before, still read (see ``ADDED_AFTER_V1``)
VERSION = 2
#: event kinds too frequent or too small to be worth a line in the summary
_QUIET_EVENTS = frozenset({"move_blocked"})


# ----------------------------------------------------------------- rules <-> JSON
def layout_to_dict(rules: Rules) -> dict[str, Any]:
    """The map of ``rules`` as a map-file dict (SPEC section 2) that ``load_map`` reads."""
    lay = rules.layout
    d: dict[str, Any] = {
        "name": lay.name,
        "game_map": lay.grid.astype(int).tolist(),
        "max_n_agent": int(lay.max_agents),
        "is_dynamic_map": bool(lay.is_dynamic),
        "map_switch_step": int(lay.map_switch_step),
        "agent_spawn_points": [[int(r), int(c)] for r, c in lay.spawn_points],
    }
    if lay.switch_grid is not None:
        d["switch_map"] = lay.switch_grid.astype(int).tolist()
    if own_processes(lay.processes):  # the kitchen file's own process records
        d["processes"] = own_processes(lay.processes)
    if lay.recipes:  # the kitchen file's own dishes
        d["recipes"] = [dish_to_dict(x) for x in lay.recipes]
    return d


def rules_to_dict(rules: Rules) -> dict[str, Any]:
    """Every rule parameter except the preset and the map, JSON-able (process records
    travel in the map dict, as a kitchen file declares them)."""
    if rules.processes != (rules.layout.processes or PROCESSES):
        raise ConfigError("these rules have process records their map does not declare; "
                          "a recording keeps a kitchen's records in its map: declare them "
                          "under the map's 'processes'")
    out: dict[str, Any] = {}
    for f in fields(Rules):
        if f.name in ("preset", "layout", "processes"):  # the map dict carries the records
            continue
        value = getattr(rules, f.name)
        if f.name == "recipes" or (f.name == "fixed_orders" and value is not None):
            value = [recipe_name(r) for r in value]
        elif f.name == "rewards":
            value = {g.name: getattr(value, g.name) for g in fields(Rewards)}
        out[f.name] = value
    return out


def rules_from_dict(preset: str, map_dict: dict[str, Any], params: dict[str, Any]) -> Rules:
    """Rebuild the :class:`Rules` of a recording (raises ``ConfigError`` if they differ)."""
    kw = dict(params)
    rules = make_rules(preset, map=map_dict, **kw)
    again = rules_to_dict(rules)
    if again != params:
        missing = object()
        diff = sorted(k for k in set(again) | set(params)
                      if again.get(k, missing) != params.get(k, missing))
        raise ConfigError(
            f"the recording's rule parameters {diff} cannot be rebuilt exactly by this version "
            "of ocplus-plan; replay it with the version that recorded it"
        )
    return rules


def summarise_events(events: Sequence[Event]) -> list[str]:
    """``["delivery:0", "chop_done:1", ...]``: kind and agent of each notable event."""
    return [f"{e.kind}:{e.agent}" for e in events if e.kind not in _QUIET_EVENTS]


# ----------------------------------------------------------------- the recording
@dataclass
class Recording:
    """One episode: enough to recompute every state (see the module docstring)."""

    preset: str
    map: dict[str, Any]
    rules: dict[str, Any]
    seed: int | None
    actions: list[list[int]] = field(default_factory=list)
    events: list[list[str]] = field(default_factory=list)
    state_hash: str | None = None
    stats: dict[str, int] = field(default_factory=dict)
    meta: dict[str, Any] = field(default_factory=dict)

    @property
    def map_name(self) -> str:
        return str(self.map.get("name", "unnamed"))

    @property
    def n_steps(self) -> int:
        return len(self.actions)

    def make_rules(self) -> Rules:
        return rules_from_dict(self.preset, self.map, self.rules)

    def event_counts(self) -> dict[str, int]:
        """How often each notable event kind happened over the episode."""
        return dict(Counter(s.split(":", 1)[0] for step in self.events for s in step))

    # -- files
    def save(self, path: str | Path) -> Path:
        """Write the recording as JSON lines (gzip when ``path`` ends in ``.gz``)."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        header = {
            "format": FORMAT, "version": VERSION, "preset": self.preset, "map": self.map,
            "rules": self.rules, "seed": self.seed, "meta": self.meta,
        }
        with _open(path, "wt") as fh:
            fh.write(json.dumps(header, separators=(",", ":")) + "\n")
            for acts, evs in zip(self.actions, self.events):
                line: dict[str, Any] = {"a": acts}
                if evs:
                    line["e"] = evs
                fh.write(json.dumps(line, separators=(",", ":")) + "\n")
            end = {"end": True, "steps": self.n_steps, "state_hash": self.state_hash,
                   "stats": self.stats}
            fh.write(json.dumps(end, separators=(",", ":")) + "\n")
        return path

    @classmethod
    def load(cls, path: str | Path) -> Recording:
        """Read a file written by :meth:`save`, checking every line (version, keys, types,
        counts). A missing, truncated, corrupt or tampered file raises
        :class:`UnreadableRecording` (a ``ConfigError``: the CLI exits 2). Version-1 files
        get the values of the rule fields added since (``ADDED_AFTER_V1``)."""
        path = Path(path)
        if not path.is_file():
            raise UnreadableRecording(path, "does not exist or is not a regular file")
        return read_recording(path)


def _open(path: Path, mode: str) -> IO[str]:
    if path.suffix == ".gz":
        return gzip.open(path, mode, encoding="utf-8")  # type: ignore[return-value]
    return open(path, mode[0], encoding="utf-8")


# ----------------------------------------------------------------- reading a file
#: the longest line read (a header with two 64x64 grids is about 25 kB)
MAX_LINE_CHARS = 1_000_000
#: the most text read from one recording, decompressed (a step line is about 20 bytes)
MAX_RECORDING_CHARS = 64_000_000
#: rule fields added after version 1, with the value that reproduces a version-1 episode
ADDED_AFTER_V1: dict[str, Any] = {"fixed_orders": None}
_HEADER_KEYS = {"format", "version", "preset", "map", "rules", "seed"}
_INT_LIMIT = 2**31
_SEED_LIMIT = 2**64


class UnreadableRecording(ConfigError):
    """A recording file that is missing, truncated, corrupt or tampered with."""

    def __init__(self, path: Path, what: str) -> None:
        super().__init__(f"not a readable recording: {path}: {what}")


def _is_int(value: Any, low: int = 0, high: int = _INT_LIMIT) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and low <= value < high


def _is_str_list(value: Any) -> bool:
    return isinstance(value, list) and all(isinstance(x, str) for x in value)


def _is_rewards(value: Any) -> bool:
    return isinstance(value, dict) and all(
        isinstance(v, (int, float)) and not isinstance(v, bool) for v in value.values())


def _within(lo: int, hi: int, optional: bool = False) -> tuple[Any, str]:
    """A check of one integer rule against the rules' own limits (``sim.rules.RULE_LIMITS``:
    the same table ``make_rules`` and ``--rules`` use)."""
    what = f"an integer from {lo} to {hi}"
    if optional:
        return (lambda v: v is None or _is_int(v, lo, hi + 1)), f"null or {what}"
    return (lambda v: _is_int(v, lo, hi + 1)), what


_RULE_CHECKS: dict[str, tuple[Any, str]] = {
    "n_agents": (_is_int, "an integer from 0 to 2**31-1"),
    **{k: _within(lo, hi) for k, (lo, hi) in RULE_LIMITS.items()},
    **{k: _within(lo, hi, True) for k, (lo, hi) in OPTIONAL_RULE_LIMITS.items()},
    "recipes": (_is_str_list, "a list of recipe names"),
    "fixed_orders": (lambda v: v is None or _is_str_list(v), "null or a list of recipe names"),
    "dirty_plates": (lambda v: isinstance(v, bool), "true or false"),
    "dynamic": (lambda v: isinstance(v, bool), "true or false"),
    "reward_mode": (lambda v: isinstance(v, str), "text"),
    "rewards": (_is_rewards, "a mapping of reward names to numbers"),
}


def _read_lines(path: Path) -> list[Any]:
    """The file's JSON values, one per non-blank line, read within the limits above."""
    values: list[Any] = []
    total = 0
    try:
        with _open(path, "rt") as fh:
            while True:
                line = fh.readline(MAX_LINE_CHARS + 1)
                if not line:
                    return values
                total += len(line)
                if len(line) > MAX_LINE_CHARS or total > MAX_RECORDING_CHARS:
                    raise UnreadableRecording(path, f"line {len(values) + 1} goes past "
                                              "the size limits (corrupt or not a recording)")
                if line.strip():
                    values.append(json.loads(line))
    except (OSError, EOFError, zlib.error) as exc:  # gzip.BadGzipFile is an OSError
        raise UnreadableRecording(path, f"the file is damaged or truncated "
                                  f"({_one_line(exc)})") from None
    except UnicodeDecodeError:
        raise UnreadableRecording(path, "not UTF-8 text (damaged?)") from None
    except ValueError as exc:  # json.JSONDecodeError, or a number with thousands of digits
        raise UnreadableRecording(path, f"line {len(values) + 1} is not JSON "
                                  f"({_one_line(exc)})") from None
    except RecursionError:
        raise UnreadableRecording(path, f"line {len(values) + 1} is nested too deeply") from None


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())[:200]


def _check_header(head: Any, path: Path) -> dict[str, Any]:
    if not isinstance(head, dict) or head.get("format") != FORMAT:
        raise UnreadableRecording(path, f"line 1 is not an {FORMAT} header; record one with "
                                  "`ocplus play --record FILE`")
    version = head.get("version")
    if not _is_int(version, 1, VERSION + 1):
        raise UnreadableRecording(path, f"format version {str(version)[:20]!r}; this "
                                  f"ocplus-plan reads versions 1 to {VERSION}")
    missing = sorted(_HEADER_KEYS - set(head))
    extra = sorted(map(str, set(head) - _HEADER_KEYS - {"meta"}))
    if missing or extra:
        raise UnreadableRecording(path, f"header keys missing {missing}, unknown {extra[:5]}")
    for key, ok, need in (
        ("preset", isinstance(head["preset"], str), "a preset name"),
        ("map", isinstance(head["map"], dict), "a map-file mapping"),
        ("rules", isinstance(head["rules"], dict), "a mapping of rule parameters"),
        ("seed", head["seed"] is None or _is_int(head["seed"], 0, _SEED_LIMIT),
         "null or an integer from 0 to 2**64-1"),
        ("meta", isinstance(head.get("meta", {}), dict), "a mapping"),
    ):
        if not ok:
            raise UnreadableRecording(path, f"header '{key}' must be {need}, got "
                                      f"{type(head[key]).__name__}")
    humans = head.get("meta", {}).get("humans", [])
    if not (isinstance(humans, list) and all(_is_int(h) for h in humans)):
        raise UnreadableRecording(path, "header meta 'humans' must be a list of agent numbers")
    return head


def _check_rules(params: dict[str, Any], version: int, path: Path) -> dict[str, Any]:
    params = dict(params)
    if version == 1:
        for key, value in ADDED_AFTER_V1.items():
            params.setdefault(key, value)
    missing = sorted(set(_RULE_CHECKS) - set(params))
    extra = sorted(map(str, set(params) - set(_RULE_CHECKS)))
    if missing or extra:
        raise UnreadableRecording(path, f"rule parameters missing {missing}, unknown {extra[:5]}")
    for key, (ok, need) in _RULE_CHECKS.items():
        if not ok(params[key]):
            raise UnreadableRecording(path, f"rule parameter '{key}' must be {need}, got "
                                      f"{type(params[key]).__name__}")
    return params


def _check_step(line: Any, n_agents: int, number: int, path: Path) -> tuple[list[int], list[str]]:
    if not isinstance(line, dict) or "a" not in line or set(line) - {"a", "e"}:
        raise UnreadableRecording(path, f"line {number} is not a step {{\"a\": [...]}} "
                                  "nor the end line")
    acts, evs = line["a"], line.get("e", [])
    if not (isinstance(acts, list) and len(acts) == n_agents
            and all(_is_int(a, 0, len(Action)) for a in acts)):
        raise UnreadableRecording(path, f"line {number}: 'a' must list {n_agents} action "
                                  f"numbers from 0 to {len(Action) - 1}")
    if not _is_str_list(evs):
        raise UnreadableRecording(path, f"line {number}: 'e' must be a list of event names")
    return acts, evs


def _check_end(line: Any, steps: int, path: Path) -> tuple[str, dict[str, int]]:
    if set(line) != {"end", "steps", "state_hash", "stats"} or line["end"] is not True:
        raise UnreadableRecording(path, "the end line must hold exactly end, steps, "
                                  "state_hash and stats")
    if line["steps"] != steps or not _is_int(line["steps"]):
        raise UnreadableRecording(path, f"the end line counts {str(line['steps'])[:20]} steps "
                                  f"but the file holds {steps}")
    stats = line["stats"]
    if not isinstance(line["state_hash"], str) or not (
            isinstance(stats, dict) and all(_is_int(v) for v in stats.values())):
        raise UnreadableRecording(path, "the end line's state_hash must be text and its stats "
                                  "a mapping of counts")
    return line["state_hash"], stats


def read_recording(path: Path) -> Recording:
    """Read and check every line of a recording file (see :meth:`Recording.load`)."""
    lines = _read_lines(path)
    head = _check_header(lines[0] if lines else None, path)
    params = _check_rules(head["rules"], head["version"], path)
    rec = Recording(head["preset"], head["map"], params, head["seed"], meta=head.get("meta", {}))
    try:
        rules = rec.make_rules()
    except OcplusError as exc:
        raise UnreadableRecording(path, f"its rules cannot be rebuilt: {exc}") from None
    for number, line in enumerate(lines[1:], start=2):
        if isinstance(line, dict) and "end" in line:
            rec.state_hash, rec.stats = _check_end(line, rec.n_steps, path)
            if number != len(lines):
                raise UnreadableRecording(path, f"{len(lines) - number} lines after the end line")
            return rec
        acts, evs = _check_step(line, rules.n_agents, number, path)
        rec.actions.append(acts)
        rec.events.append(evs)
    raise UnreadableRecording(path, f"no end line after {rec.n_steps} steps: the file is "
                              "truncated")


class Recorder:
    """Builds a :class:`Recording` while an episode runs.

    ``rec = Recorder(rules, seed, meta={...})``; after each ``transition`` call
    ``rec.record(joint_action, result.events)``; at the end ``rec.finish(state)`` and
    ``rec.recording.save(path)``.
    """

    def __init__(self, rules: Rules, seed: int | None, meta: dict[str, Any] | None = None):
        self.recording = Recording(
            rules.preset, layout_to_dict(rules), rules_to_dict(rules), seed, meta=dict(meta or {})
        )

    def record(self, joint_action: Sequence[int], events: Sequence[Event]) -> None:
        self.recording.actions.append([int(a) for a in joint_action])
        self.recording.events.append(summarise_events(events))

    def finish(self, state: State) -> Recording:
        self.recording.state_hash = state.state_hash()
        self.recording.stats = dict(state.stats)
        return self.recording

    def save(self, path: str | Path, state: State | None = None) -> Path:
        if state is not None:
            self.finish(state)
        return self.recording.save(path)


# ----------------------------------------------------------------- replaying
def replay_states(rec: Recording) -> Iterator[tuple[State, list[Event]]]:
    """Yield ``(state, events)`` for the initial state (no events) and after every step.

    The same state object is yielded each time (updated in place); copy it to keep it.
    """
    rules = rec.make_rules()
    state = new_state(rules, rec.seed)
    yield state, []
    for i, acts in enumerate(rec.actions):
        if len(acts) != rules.n_agents:
            raise ConfigError(
                f"recording step {i}: {len(acts)} actions for {rules.n_agents} agents"
            )
        result = transition(state, acts)
        yield state, list(result.events)


@dataclass
class ReplayCheck:
    """Outcome of re-running a recording: does it reach the recorded state?"""

    steps: int
    state_hash: str
    recorded_hash: str | None
    events_match: bool

    @property
    def ok(self) -> bool:
        return self.recorded_hash == self.state_hash and self.events_match


def verify(rec: Recording) -> ReplayCheck:
    """Re-run the recording and compare the final hash and the per-step event summaries."""
    events_match = True
    final_hash = ""
    for i, (state, events) in enumerate(replay_states(rec)):
        if i and summarise_events(events) != rec.events[i - 1]:
            events_match = False
        final_hash = state.state_hash() if i == rec.n_steps else final_hash
    return ReplayCheck(rec.n_steps, final_hash, rec.state_hash, events_match)


def export_gif(
    rec: Recording,
    out: str | Path,
    *,
    tile: int = 32,
    frame_ms: int = 120,
    every: int = 1,
    max_frames: int | None = None,
) -> Path:
    """Write the episode as an animated GIF (frames from :func:`render.rgb.render_frame`).

    Frames are drawn at ``tile`` pixels per cell; ``every``
    keeps one frame in ``every`` steps and ``max_frames`` caps the count (to keep files
    small). Needs Pillow (``pip install 'ocplus-plan[gui]'``).
    """
    try:
        from PIL import Image
    except ImportError as exc:  # pragma: no cover - depends on the installation
        raise DependencyNotInstalled(
            "GIF export needs Pillow: pip install 'ocplus-plan[gui]'"
        ) from exc
    for name, value in (("every", every), ("tile", tile), ("frame_ms", frame_ms)):
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise ConfigError(f"GIF export: {name} must be a positive integer, got {value!r}")
    from .rgb import render_frame

    frames: list[Any] = []
    for i, (state, _events) in enumerate(replay_states(rec)):
        if i % every and i != rec.n_steps:
            continue
        frames.append(Image.fromarray(np.ascontiguousarray(render_frame(state, tile=tile))))
        if max_frames is not None and len(frames) >= max_frames:
            break
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    # one palette shared by all frames keeps the file small and the colours stable; it is
    # made from a strip of up to 16 frames spread over the episode, so items that appear
    # late (a cooked or burnt steak) get their own colours
    sample = frames[:: max(1, len(frames) // 16)][:16]
    strip = Image.new("RGB", (sample[0].width, sample[0].height * len(sample)))
    for k, frame in enumerate(sample):
        strip.paste(frame, (0, k * frame.height))
    palette = strip.quantize(colors=128, method=Image.Quantize.MEDIANCUT)
    paletted = [f.quantize(palette=palette, dither=Image.Dither.NONE) for f in frames]
    paletted[0].save(out, save_all=True, append_images=paletted[1:], duration=frame_ms, loop=0,
                     optimize=True, disposal=1)
    return out


__all__ = [
    "ADDED_AFTER_V1",
    "Recorder",
    "Recording",
    "UnreadableRecording",
    "ReplayCheck",
    "export_gif",
    "layout_to_dict",
    "replay_states",
    "rules_from_dict",
    "rules_to_dict",
    "summarise_events",
    "verify",
]
