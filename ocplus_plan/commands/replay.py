"""``ocplus replay FILE``: re-run a recorded episode, check it, and show it or write a GIF.

The simulator recomputes every state from the recorded seed, rules and actions;
the command reports whether the final ``state_hash`` and the per-step events
equal the recorded ones (exit 1 if not: that would be a determinism bug). A file that
is not a whole, well-formed recording (missing, truncated, damaged, edited into a wrong
shape) is refused before anything is replayed: "not a readable recording: ...", exit 2.
Without ``--gif`` or ``--check`` it plays the episode back in a window (space pauses,
the right arrow steps while paused, Escape quits).
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from . import _types
from ._common import HelpFormatter, add_output_args, emit

if TYPE_CHECKING:
    from ..render.replay import Recording

_PLAYBACK_HELP = "replay: space pauses, right arrow steps, Escape quits"


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("replay", help="check a recorded episode; show it or write a GIF",
                       description=__doc__, formatter_class=HelpFormatter)
    p.add_argument("file", help="a recording from `ocplus play --record` (.jsonl or .jsonl.gz)")
    p.add_argument("--gif", type=_types.out_file, default=None, metavar="OUT",
                   help="write an animated GIF here")
    p.add_argument("--check", action="store_true",
                   help="only verify the recording (no window, no GIF)")
    p.add_argument("--fps", type=_types.number("--fps (steps per second)", 0.0, 10_000.0),
                   default=8.0, help="playback speed in the window")
    p.add_argument("--frame-ms", type=_types.whole("--frame-ms", 1, 60_000), default=120,
                   help="GIF: milliseconds per frame")
    p.add_argument("--every", type=_types.whole("--every", 1), default=1,
                   help="GIF: keep one step in EVERY")
    p.add_argument("--max-frames", type=_types.whole("--max-frames", 1), default=None,
                   help="GIF: at most this many frames")
    p.add_argument("--no-wait", action="store_true",
                   help="close the window as soon as the playback ends")
    add_output_args(p)
    p.set_defaults(func=run)


#: what works without a display (named when there is none)
HEADLESS_HINT = ("playing a recording back needs a window; without one use --check (verify "
                 "only) or --gif OUT (write an animation)")


def run(args: argparse.Namespace) -> int:
    from ..render.replay import Recording, export_gif, verify

    if not args.gif and not args.check:
        from ..render.window import require_display

        require_display(HEADLESS_HINT)  # at once, before replaying anything
    rec = Recording.load(args.file)
    check = verify(rec)
    summary = {
        "file": args.file, "preset": rec.preset, "map": rec.map_name, "seed": rec.seed,
        "steps": check.steps, "state_hash": check.state_hash,
        "matches_recording": check.ok, "events_match": check.events_match,
        "event_counts": rec.event_counts(),
    }
    summary.update({k: v for k, v in rec.meta.items() if k not in summary})  # never overrides
    if args.gif:
        summary["gif"] = str(export_gif(rec, args.gif, frame_ms=args.frame_ms, every=args.every,
                                        max_frames=args.max_frames))
    elif not args.check:
        _play_back(rec, args.fps, wait_at_end=not args.no_wait)
    emit(summary, args)
    return 0 if check.ok else 1


def _play_back(rec: Recording, fps: float, *, wait_at_end: bool) -> None:
    from ..render.replay import replay_states
    from ..render.window import Window

    window = Window(f"ocplus replay: {rec.preset} / {rec.map_name}", headless_hint=HEADLESS_HINT)
    humans = tuple(int(h) for h in rec.meta.get("humans", ()))  # a recorded play session's
    paused = False
    try:
        for state, events in replay_states(rec):
            if window.closed:
                break
            notes = [f"{e.kind} (agent {e.agent})" for e in events
                     if e.kind in ("delivery", "wrong_delivery", "burnt", "layout_switch")]
            window.show(state, messages=notes, status=_PLAYBACK_HELP, humans=humans)
            while True:  # space pauses / resumes; right arrow steps while paused
                keys = window.poll()
                if "space" in keys:
                    paused = not paused
                if window.closed or not paused or "right" in keys:
                    break
                window.tick(30)
            window.tick(fps)
        while wait_at_end and not window.closed:
            window.poll()
            window.tick(20)
    finally:
        window.close()
