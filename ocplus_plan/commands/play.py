"""``ocplus play``: humans and AI agents in one kitchen, in a pygame window.

Humans steer with the keyboard (one human: WASD or arrows, stay with space or
enter; two humans: WASD + space and arrows + enter; Escape quits). The other
agents are driven by ``--agents`` (``greedy``, ``planner:NAME``, ``ppo:PATH``, ...).
``--turn-based`` advances the kitchen only when every human has chosen an action;
otherwise it runs at ``--fps`` steps per second and a human who pressed nothing stays.

``--mode coop`` scores the kitchen as one team; ``--mode adversarial`` scores the
humans separately from the AI team (per-agent rewards, never shared) and reports
the AI team's own metrics (reward, dishes it served, its subtasks). ``--record FILE``
saves the episode for ``ocplus replay``.
"""

from __future__ import annotations

import argparse
from collections import Counter
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ..agents.base import Controller
from ..errors import ConfigError
from ..sim import PRESETS, Action, Rules, State, StepResult, make_rules, new_state
from . import _types
from ._common import (
    HelpFormatter,
    add_kitchen_args,
    add_output_args,
    add_trust_arg,
    emit,
    rules_from_args,
    say,
)

MODES = ("coop", "adversarial")
_FPS = _types.number("--fps (steps per second)", 0.0, 10_000.0)
#: event kinds counted per side in the metrics
_COUNTED = ("delivery", "wrong_delivery", "chop_done", "wash_done", "plate_add", "trash",
            "pickup", "putdown", "move_blocked")


def parse_humans(text: str | None) -> tuple[int, ...]:
    """``"0"`` -> (0,), ``"0,1"`` -> (0, 1), ``"none"`` / ``""`` -> () (watch only)."""
    if text is None or text.strip().lower() in ("", "none"):
        return ()
    try:
        humans = tuple(int(x) for x in text.split(","))
    except ValueError:
        raise ConfigError(
            f"--human {text!r}: give agent indices separated by commas (0 or 0,1), or none"
        ) from None
    if len(set(humans)) != len(humans) or any(h < 0 for h in humans):
        raise ConfigError(f"--human {text!r}: indices must be distinct and >= 0")
    if len(humans) > 2:
        raise ConfigError(f"--human {text!r}: the keyboard has keysets for at most 2 humans")
    return humans


class _Keyboard(Controller):
    """The humans as a controller: each plays the key it pressed last, or stays."""

    name = "keyboard"

    def __init__(self, pending: dict[int, int]) -> None:
        self.pending = pending  # the session's: agent -> action, cleared after each step

    def act(self, state: State) -> list[int]:
        return [self.pending.get(h, int(Action.STAY)) for h in self.agent_ids]


class PlaySession:
    """One episode with keyboard humans and AI controllers (no pygame here: testable).

    Feed key names with :meth:`press`; call :meth:`step` when :meth:`ready`; read
    :meth:`scores` and :meth:`metrics`. With ``record=True`` a :class:`Recorder` keeps
    the episode (``session.recorder.save(path, session.state)``).
    """

    def __init__(self, rules: Rules, seed: int = 0, *, humans: Sequence[int] = (0,),
                 agents: str = "greedy", mode: str = "coop", record: bool = True) -> None:
        from ..agents import Episode, Team, make_controller
        from ..render.replay import Recorder
        from ..render.window import KEY_HELP, key_map

        if mode not in MODES:
            raise ConfigError(f"--mode {mode!r}: choose coop or adversarial")
        n = rules.n_agents
        bad = [h for h in humans if h >= n]
        if bad:
            raise ConfigError(
                f"--human {bad}: the kitchen has {n} agents (0..{n - 1}); pass --n-agents"
            )
        if mode == "adversarial" and rules.reward_mode != "individual":
            raise ConfigError("adversarial mode scores each side apart: use reward_mode individual")
        self.rules, self.seed, self.mode = rules, seed, mode
        self.humans = tuple(humans)
        self.ai = tuple(a for a in range(n) if a not in self.humans)
        self.state = new_state(rules, seed)
        self.controller = make_controller(agents, seed) if self.ai else None
        self.keys = key_map(len(self.humans)) if self.humans else {}
        self.key_help = KEY_HELP.get(len(self.humans), ())
        self.pending: dict[int, int] = {}
        drivers = [(c, ids) for c, ids in ((self.controller, self.ai),
                                           (_Keyboard(self.pending), self.humans)) if ids]
        self.episode = Episode(self.state, Team([c for c, _ in drivers], [i for _, i in drivers]))
        self.events_by_agent: list[Counter[str]] = [Counter() for _ in range(n)]
        self.agents_spec = agents
        meta = {"humans": list(self.humans), "agents": agents, "mode": mode}
        self.recorder = Recorder(rules, seed, meta) if record else None

    # -- input
    def press(self, key: str) -> bool:
        """Register a key press; True if it is a human's key. The last press per human wins."""
        if key not in self.keys:
            return False
        human, action = self.keys[key]
        self.pending[self.humans[human]] = int(action)
        return True

    def ready(self, turn_based: bool) -> bool:
        """Turn-based: every human has chosen. Real time: always."""
        if self.finished:
            return False
        return not turn_based or all(h in self.pending for h in self.humans)

    # -- stepping
    @property
    def finished(self) -> bool:
        return self.episode.finished

    @property
    def rewards(self) -> list[float]:
        return self.episode.rewards

    def step(self) -> StepResult:
        """Advance one step with the pending human actions (stay if none) and the AI's."""
        if self.finished:
            raise ConfigError("the episode is over; start a new session")
        result = self.episode.step()
        if self.recorder is not None:
            self.recorder.record(self.episode.joint, result.events)
        for e in result.events:
            if 0 <= e.agent < len(self.events_by_agent) and e.kind in _COUNTED:
                self.events_by_agent[e.agent][e.kind] += 1
        self.pending.clear()
        return result

    # -- scoring
    def labels(self) -> dict[int, str]:
        names = {h: (f"you (agent {h})" if len(self.humans) == 1 else f"human {i + 1} (agent {h})")
                 for i, h in enumerate(self.humans)}
        side = self.agents_spec if self.mode == "coop" else f"AI team ({self.agents_spec})"
        return {a: names.get(a, f"agent {a}: {side}") for a in range(self.rules.n_agents)}

    def scores(self) -> dict[str, float]:
        """Coop: the team's reward. Adversarial: humans and AI team apart."""
        if self.mode == "coop":
            return {"team score": sum(self.rewards)}
        out = {"human score": sum(self.rewards[h] for h in self.humans)}
        if self.ai:
            out["AI team score"] = sum(self.rewards[a] for a in self.ai)
        return out

    def _side(self, agents: Sequence[int]) -> dict[str, Any]:
        counts: Counter[str] = Counter()
        for a in agents:
            counts.update(self.events_by_agent[a])
        return {
            "agents": list(agents),
            "reward": round(sum(self.rewards[a] for a in agents), 6),
            "dishes_served": counts["delivery"],
            **{k: counts[k] for k in _COUNTED if k != "delivery"},
        }

    def metrics(self) -> dict[str, Any]:
        """The episode's results; adversarial mode adds per-side ``humans`` / ``ai_team``."""
        out: dict[str, Any] = {
            "preset": self.rules.preset, "map": self.rules.layout.name, "seed": self.seed,
            "mode": self.mode, "humans": list(self.humans), "agents": self.agents_spec,
            "steps": self.state.t, **self.state.stats,
            "scores": {k: round(v, 6) for k, v in self.scores().items()},
            "state_hash": self.state.state_hash(),
        }
        if self.mode == "adversarial":
            out["humans_side"] = self._side(self.humans)
            out["ai_team"] = self._side(self.ai)
            if self.controller is not None:
                out["ai_team"].update({f"controller_{k}": v
                                       for k, v in self.controller.info().items()})
        return out


def run_loop(session: PlaySession, window: Any, *, turn_based: bool, fps: float = 4.0,
             wait_at_end: bool = True, stop_when_idle: bool = False) -> None:
    """Show the kitchen and step it from keyboard input until the episode ends or the
    window closes. ``stop_when_idle`` (turn-based, for scripted tests) returns as soon as
    no key is waiting; ``wait_at_end`` keeps the last frame until the window is closed."""

    def show(status: str = "") -> None:
        if not status and turn_based and session.pending:
            labels = session.labels()
            waiting = [labels[h] for h in session.humans if h not in session.pending]
            status = "waiting for " + ", ".join(waiting)
        window.show(session.state, scores=session.scores(), agent_labels=session.labels(),
                    status=status, key_help=session.key_help, humans=session.humans)

    show("press a key to start" if turn_based and session.humans else "")
    if not turn_based:  # a held key keeps moving the cook in real time
        window.pg.key.set_repeat(150, 100)
    while not session.finished and not window.closed:
        keys = window.poll()
        if turn_based:
            if stop_when_idle and not keys:
                return
            for key in keys:
                session.press(key)
                if session.ready(True):  # with no human, any key advances one step
                    session.step()
            show()
            window.tick(60)
        else:
            for key in keys:
                session.press(key)
            session.step()
            show()
            window.tick(fps)
    if session.finished:
        show("episode over: close the window or press Escape")
        while wait_at_end and not window.closed:
            window.poll()
            window.tick(20)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("play", help="play in a kitchen window with the keyboard, beside AI agents",
                       description=__doc__, formatter_class=HelpFormatter,
                       epilog="Without --n-agents the kitchen has the preset's cooks and, when "
                              "the map has room, at least one AI cook beside the humans.")
    add_kitchen_args(p)
    p.add_argument("--human", default="0",
                   help="agent indices the keyboard drives: 0, 0,1 or none")
    p.add_argument("--agents", type=_types.name, default="greedy",
                   help="controller of the other agents: greedy, planner:NAME, ppo:PATH, random")
    p.add_argument("--mode", default="coop", choices=MODES,
                   help="coop: one team score; adversarial: humans and AI scored apart")
    speed = p.add_mutually_exclusive_group()
    speed.add_argument("--fps", type=_FPS, default=4.0, help="steps per second")
    speed.add_argument("--turn-based", action="store_true",
                       help="step only when every human has pressed a key")
    p.add_argument("--record", type=_types.out_file, default=None, metavar="FILE",
                   help="save the episode (.jsonl or .jsonl.gz) for `ocplus replay`")
    p.add_argument("--no-wait", action="store_true",
                   help="close the window as soon as the episode ends")
    add_trust_arg(p)
    add_output_args(p)
    p.set_defaults(func=run)


def build_session(args: argparse.Namespace) -> PlaySession:
    """Rules and session from the parsed ``play`` options (no window)."""
    humans = parse_humans(args.human)
    if args.fps is not None and args.fps <= 0:
        raise ConfigError(f"--fps {args.fps}: must be a positive number of steps per second")
    kw: dict[str, Any] = {}
    if args.n_agents is None and humans:
        # by default every human gets at least one AI cook beside them, if the map has room
        layout = make_rules(args.preset, map=args.map).layout
        wanted = max(PRESETS[args.preset].n_agents, len(humans) + 1)
        kw["n_agents"] = max(min(wanted, layout.max_agents), max(humans) + 1)
    rules = rules_from_args(args, **kw)
    return PlaySession(rules, args.seed, humans=humans, agents=args.agents, mode=args.mode,
                       record=args.record is not None)


#: what works without a display (named when there is none)
HEADLESS_HINT = ("`ocplus play` needs a window. Without one: `ocplus rollout` runs an episode, "
                 "`ocplus replay FILE --check` verifies a recording and `ocplus replay FILE "
                 "--gif OUT` draws it; or set SDL_VIDEODRIVER=dummy to play off-screen")


def run(args: argparse.Namespace) -> int:
    from ..render.window import Window, require_display

    require_display(HEADLESS_HINT)  # before anything slow: exit at once, never wait for keys
    session = build_session(args)
    window = Window(f"ocplus play: {session.rules.preset} / {session.rules.layout.name}",
                    headless_hint=HEADLESS_HINT)
    try:
        run_loop(session, window, turn_based=args.turn_based, fps=args.fps,
                 wait_at_end=not args.no_wait)
    finally:
        window.close()
        if session.recorder is not None and args.record:
            path = session.recorder.save(Path(args.record), session.state)
            say(args, f"recorded {session.state.t} steps to {path}")
    emit(session.metrics(), args)
    return 0
