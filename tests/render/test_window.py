"""The pygame window under SDL's dummy driver: opens, shows the rgb frame, reads keys,
plays a scripted episode, and matches a golden picture.

The golden PNG is refreshed only on purpose: ``OCPLUS_UPDATE_GOLDEN=1 pytest
tests/render/test_window.py`` (then look at it before committing it).
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import numpy as np
import pytest

from ocplus_plan.commands.play import PlaySession, run_loop
from ocplus_plan.errors import DependencyNotInstalled
from ocplus_plan.render import render_frame
from ocplus_plan.render.window import HUMAN_MARK, Window, panel_lines, require_pygame
from ocplus_plan.sim import make_rules

from .scripted import serve_one_dish_keys

pygame = pytest.importorskip("pygame", reason="the gui extra (pygame-ce) is not installed")

GOLDEN = Path(__file__).parent / "golden" / "window_easy_open.png"


@pytest.fixture
def window():
    w = Window("test")
    yield w
    w.close()


def easy_session(n_agents: int = 1) -> PlaySession:
    return PlaySession(make_rules("easy", map="easy_open", n_agents=n_agents), 0, humans=(0,))


def post_keys(names: list[str]) -> None:
    for name in names:
        pygame.event.post(pygame.event.Event(pygame.KEYDOWN, key=pygame.key.key_code(name)))


def test_the_window_opens_and_shows_the_rgb_frame_beside_the_panel(window):
    session = easy_session()
    window.show(session.state, scores=session.scores())
    assert pygame.display.get_surface() is not None
    pixels = window.pixels()
    frame = render_frame(session.state)
    h, w, _ = frame.shape
    scale = pixels.shape[0] // h
    assert scale >= 2 and pixels.shape[1] > w * scale  # map enlarged, panel to its right
    # one drawing code path: the map area is exactly the rgb frame, enlarged
    np.testing.assert_array_equal(pixels[: h * scale : scale, : w * scale : scale], frame)
    panel = pixels[:, w * scale :]
    assert panel.std() > 10  # text and bars were drawn


def test_keys_reach_the_window_by_name(window):
    window.show(easy_session().state)
    pygame.event.clear()
    post_keys(["w", "up", "space", "return"])
    assert window.poll() == ["w", "up", "space", "return"]
    post_keys(["escape"])
    window.poll()
    assert window.closed


def test_a_scripted_key_sequence_served_through_the_window_delivers_a_dish(window):
    session = easy_session()
    keys = serve_one_dish_keys(session.state)
    window.show(session.state)
    pygame.event.clear()
    post_keys(keys)
    run_loop(session, window, turn_based=True, wait_at_end=False, stop_when_idle=True)
    assert session.state.t == len(keys)
    assert session.state.stats["dishes_served"] == 1


def test_the_panel_reports_orders_pans_plates_switch_and_messages():
    rules = make_rules("hard", n_agents=2, order_time_limit=60)
    session = PlaySession(rules, 0, humans=(0,), agents="greedy")
    for _ in range(12):
        session.step()
    text = "\n".join(line.text for line in panel_lines(
        session.state, scores=session.scores(), messages=["agent 1 says: tomato"]))
    assert "steps left" in text and "pan (" in text and "dirty plates" in text
    assert f"layout switch in {rules.map_switch_step - 12} steps" in text
    assert "agent 1 says: tomato" in text and "team score" in text


def test_missing_pygame_names_the_gui_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "pygame", None)
    with pytest.raises(DependencyNotInstalled, match=r"ocplus-plan\[gui\]"):
        require_pygame()


def test_a_rendered_window_matches_the_golden_png(window):
    # two keyboard cooks (no AI, so only the simulator and the drawing code matter):
    # cook 0 follows the scripted dish until it is chopping; cook 1 walks left and stays
    session = PlaySession(make_rules("easy", map="easy_open", n_agents=2), 0, humans=(0, 1))
    script = serve_one_dish_keys(session.state)
    partner = ["left", "left", "up"] + ["return"] * len(script)
    chops = 0
    for key0, key1 in zip(script, partner):
        session.press(key0)
        session.press(key1)
        chops += sum(e.kind == "chop" for e in session.step().events)
        if chops == 2:
            break
    window.show(session.state, scores=session.scores(), agent_labels=session.labels(),
                messages=["hello"], key_help=session.key_help)
    got = window.pixels()
    if os.environ.get("OCPLUS_UPDATE_GOLDEN") == "1":
        window.save(GOLDEN)
        pytest.skip(f"golden picture rewritten: {GOLDEN}")
    assert GOLDEN.exists(), "no golden picture: run once with OCPLUS_UPDATE_GOLDEN=1"
    want = pygame.surfarray.array3d(pygame.image.load(str(GOLDEN))).transpose(1, 0, 2)
    assert got.shape == want.shape
    diff = np.abs(got.astype(int) - want.astype(int)).max(axis=2)
    # tolerance: font rasterisation may differ slightly between SDL_ttf builds
    assert (diff > 48).mean() < 0.01 and diff.mean() < 3.0


def test_play_command_records_an_episode_that_replays(tmp_path, capsys):
    from ocplus_plan.cli import main

    record = tmp_path / "watch.jsonl.gz"
    argv = ["play", "--preset", "easy", "--n-agents", "2", "--human", "none", "--agents",
            "greedy", "--fps", "2000", "--horizon", "60", "--no-wait", "--record", str(record),
            "--json"]
    assert main(argv) == 0
    result = capsys.readouterr().out.splitlines()[-1]
    metrics = json.loads(result)
    assert metrics["steps"] == 60 and metrics["dishes_served"] >= 1
    assert main(["replay", str(record), "--check", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["state_hash"] == metrics["state_hash"]
    assert main(["replay", str(record), "--fps", "2000", "--no-wait"]) == 0  # in the window


def _marked(pixels: np.ndarray) -> np.ndarray:
    return (pixels == np.array(HUMAN_MARK, dtype=np.uint8)).all(axis=2)


def test_the_players_cook_is_outlined_and_labelled_on_the_map(window):
    session = PlaySession(make_rules("easy", map="easy_open", n_agents=2), 0, humans=(1,))
    window.show(session.state, agent_labels=session.labels())
    assert not _marked(window.pixels()).any()  # the mark's colour is nowhere else
    window.show(session.state, agent_labels=session.labels(), humans=session.humans)
    marked = _marked(window.pixels())
    rows, cols = session.state.geo.rows, session.state.geo.cols
    frame_h = render_frame(session.state).shape[0]
    cell = frame_h // rows * -(-window.min_map_height // frame_h)  # as the window scales it
    r, c = session.state.agent_rc(1)
    outline = marked[r * cell:(r + 1) * cell, c * cell:(c + 1) * cell]
    assert outline[0].all() and outline[-1].all() and outline[:, 0].all()  # a full frame
    r0, c0 = session.state.agent_rc(0)
    assert not marked[r0 * cell + 4:(r0 + 1) * cell - 4, c0 * cell + 4:(c0 + 1) * cell - 4].any()
    label = marked[max(0, (r - 1) * cell):r * cell, :cols * cell]  # "YOU" above the cook
    assert label.sum() > cell  # the label's background box


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="display variables are X11/Wayland")
@pytest.mark.parametrize("argv, hint", [
    (["play", "--preset", "easy"], "--gif"),
    (["replay", "{rec}"], "--check"),
])
def test_play_and_a_windowed_replay_exit_at_once_without_a_display(tmp_path, argv, hint):
    import subprocess
    import time

    from ocplus_plan.render.replay import Recorder
    from ocplus_plan.sim import new_state

    rules = make_rules("easy", horizon=3)
    recorder = Recorder(rules, 0)
    rec = recorder.save(tmp_path / "r.jsonl", new_state(rules, 0))
    env = {k: v for k, v in os.environ.items()
           if k not in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER")}
    for display in (None, ":ocplus-no-such-display"):  # unset, and set but unreachable
        if display is not None:
            env["DISPLAY"] = display
        start = time.monotonic()
        proc = subprocess.run([sys.executable, "-m", "ocplus_plan.cli",
                               *[a.format(rec=rec) for a in argv]], env=env, cwd=tmp_path,
                              capture_output=True, text=True, timeout=60, check=False)
        assert proc.returncode == 2, (display, proc.stdout, proc.stderr)
        assert hint in proc.stderr and "display" in proc.stderr, proc.stderr
        assert time.monotonic() - start < 30
