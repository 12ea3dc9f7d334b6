"""Screenshots of the play window for each preset and a short GIF of a recorded episode.

Runs headless (SDL's dummy video driver), with greedy cooks, and writes:

- ``docs/figures/window_<preset>.png``: the window (rgb frame + side panel) of one
  state per preset, picked to show a busy kitchen (a steak on the pan when the
  preset has one, a plate in use),
- ``docs/figures/hard_greedy.jsonl.gz``: the recording of a hard-preset episode,
- ``docs/figures/hard_greedy.gif``: that recording exported by ``export_gif`` (the same
  as ``ocplus replay docs/figures/hard_greedy.jsonl.gz --gif OUT --tile 24``).

Prints one JSON line per file (path, size, what it shows).

    python experiments/gui_figures.py [--out docs/figures] [--gif-steps 90]
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")

from ocplus_plan.commands.play import PlaySession
from ocplus_plan.render.replay import export_gif, verify
from ocplus_plan.render.window import Window
from ocplus_plan.sim import Where, make_rules

#: preset -> (agents, earliest step, latest step) of the screenshot
SHOTS = {"easy": (2, 10, 60), "medium": (2, 20, 120), "hard": (2, 30, 150)}


def busy(session: PlaySession) -> bool:
    """A steak on a pan (if the map has one) and a vegetable on a plate or board."""
    state = session.state
    pans_busy = not state.geo.pans or any(state.cell_item[p] >= 0 for p in state.geo.pans)
    plated = any(w == Where.PLATE for w in state.item_where)
    return pans_busy and plated


def screenshot(preset: str, out: Path, seed: int = 0) -> dict:
    n_agents, first, last = SHOTS[preset]
    session = PlaySession(make_rules(preset, n_agents=n_agents), seed, humans=(),
                          agents="greedy", record=False)
    while session.state.t < last and not (session.state.t >= first and busy(session)):
        session.step()
    window = Window()
    try:
        window.show(session.state, scores=session.scores(), agent_labels=session.labels())
        path = window.save(out / f"window_{preset}.png")
        h, w, _ = window.pixels().shape
    finally:
        window.close()
    return {"file": str(path), "bytes": path.stat().st_size, "preset": preset,
            "map": session.rules.layout.name, "step": session.state.t, "size": [w, h]}


def gif(out: Path, steps: int, seed: int = 0) -> list[dict]:
    session = PlaySession(make_rules("hard", n_agents=2, horizon=steps), seed, humans=(),
                          agents="greedy", record=True)
    while not session.finished:
        session.step()
    assert session.recorder is not None
    rec_path = session.recorder.save(out / "hard_greedy.jsonl.gz", session.state)
    rec = session.recorder.recording
    check = verify(rec)
    gif_path = export_gif(rec, out / "hard_greedy.gif", tile=24, frame_ms=150)
    return [
        {"file": str(rec_path), "bytes": rec_path.stat().st_size, "steps": rec.n_steps,
         "replay_matches": check.ok, **session.state.stats},
        {"file": str(gif_path), "bytes": gif_path.stat().st_size, "frames": rec.n_steps + 1},
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="docs/figures")
    parser.add_argument("--gif-steps", type=int, default=90)
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for preset in SHOTS:
        print(json.dumps(screenshot(preset, out)))
    for line in gif(out, args.gif_steps):
        print(json.dumps(line))


if __name__ == "__main__":
    main()
