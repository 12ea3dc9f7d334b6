"""Plot files are produced, are PNG images, and are not blank."""

from __future__ import annotations

import pytest

from ocplus_plan.eval.runner import EvalConfig, run_eval

pytest.importorskip("matplotlib", reason="plots need the `plots` extra (matplotlib)")


def _not_blank(path) -> bool:
    import matplotlib.image as mpimg
    import numpy as np

    img = mpimg.imread(path)[..., :3]
    # a blank figure is one flat colour; a real one has many distinct shades
    return float(img.std()) > 0.02 and len(np.unique(img.reshape(-1, 3), axis=0)) > 20


def test_eval_with_plots_writes_every_figure(tmp_path):
    out = tmp_path / "run"
    cfg = EvalConfig(presets=["easy", "hard"], agents=["greedy", "random"], seeds=[0, 1],
                     out=out, horizon=60, jobs=1, plots=True, quiet=True)
    outcome = run_eval(cfg, echo=lambda *a: None)
    names = {p.name for p in outcome.plots}
    assert {"leaderboard.png", "reward_over_time.png", "actions.png",
            "heatmap_easy_greedy.png", "heatmap_hard_random.png"} <= names
    for path in outcome.plots:
        assert path.parent == out / "plots"
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert _not_blank(path), path.name


def test_report_redraws_plots_from_results(tmp_path, capsys):
    from ocplus_plan.cli import main

    out = tmp_path / "run"
    cfg = EvalConfig(presets=["medium"], agents=["greedy"], seeds=[0], out=out, horizon=40,
                     quiet=True)
    run_eval(cfg, echo=lambda *a: None)
    assert not (out / "plots").exists()
    assert main(["report", str(out)]) == 0
    assert "plots:" in capsys.readouterr().out
    assert (out / "plots" / "leaderboard.png").stat().st_size > 5000
    assert (out / "plots" / "heatmap_medium_greedy.png").stat().st_size > 5000


def test_planning_figure_shows_replans_reported_by_a_controller(tmp_path, monkeypatch):
    from ocplus_plan.agents import FACTORIES
    from ocplus_plan.agents.base import StayAgent

    class _Replanner(StayAgent):
        def info(self):
            return {"replans_by_reason": {"initial": 1, "deviation": 4}, "planning_time": 0.7}

    monkeypatch.setitem(FACTORIES, "replanner", lambda arg, seed: _Replanner())
    out = tmp_path / "run"
    cfg = EvalConfig(presets=["easy"], agents=["replanner", "greedy"], seeds=[0, 1], out=out,
                     horizon=30, plots=True, quiet=True)
    outcome = run_eval(cfg, echo=lambda *a: None)
    planning = out / "plots" / "planning.png"
    assert planning in outcome.plots and _not_blank(planning)
    row = next(s for s in outcome.summary if s["agent"] == "replanner")
    assert row["replans_mean"] == 5 and row["planning_time_s_mean"] == 0.7


def test_missing_matplotlib_is_a_clear_dependency_error(tmp_path, monkeypatch):
    import builtins

    from ocplus_plan.errors import DependencyNotInstalled
    from ocplus_plan.eval import plots

    real_import = builtins.__import__

    def no_matplotlib(name, *args, **kwargs):
        if name.startswith("matplotlib"):
            raise ImportError("No module named 'matplotlib'")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_matplotlib)
    with pytest.raises(DependencyNotInstalled, match=r"\.\[plots\]"):
        plots.make_plots(tmp_path)


def test_heatmaps_key_the_letters_and_colour_the_switching_cells_apart():
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib import colormaps

    from ocplus_plan.eval import plots
    from ocplus_plan.sim import make_rules

    rules = make_rules("hard")
    grid, switching = plots._terrain({"map": rules.layout.name})
    assert switching is not None and switching.any()
    fig, ax = plt.subplots()
    shown = plots._draw_kitchen(ax, grid, switching)
    plots._key(fig, shown, True)
    drawn = ax.get_images()[0].get_array()
    assert np.allclose(drawn[switching], plots._SWITCH_RGB)
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert "D serving window" in labels and "switches wall/floor" in labels
    assert len(labels) == len(shown) + 1
    plt.close(fig)
    # the switching colour is far from the walls and from both ends of the visit colours
    cmap = colormaps[plots._HEAT_CMAP]
    for other in (plots._TERRAIN_RGB[-1], cmap(0.0)[:3], cmap(1.0)[:3]):
        assert np.abs(np.subtract(plots._SWITCH_RGB, other)).sum() > 0.6
