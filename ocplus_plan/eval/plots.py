"""PNG figures of an evaluation folder (matplotlib, the ``plots`` extra, imported lazily).

:func:`make_plots` reads ``results.jsonl`` and writes into ``DIR/plots/``:
- ``leaderboard.png``: dishes served per agent and preset, mean with 95% CI bars;
- ``reward_over_time.png``: mean cumulative team reward per step, with a 95% CI band;
- ``actions.png``: action distribution (right/down/left/up/stay) per agent and preset;
- ``heatmap_<preset>_<agent>.png``: visited cells per cook, drawn over the kitchen;
- ``planning.png``: replans by reason and planning time (only when a controller reports any).
"""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any

from ..errors import DependencyNotInstalled
from ..sim.stations import CELL_KINDS
from .metrics import ACTION_NAMES
from .results import latest_rows, mean_ci, read_results, summarise

_PRESET_ORDER = ["easy", "medium", "hard"]
#: each cell kind's colour and label, from its record (``sim/stations.py``): the same
#: colours as the rendered tiles and the same letters as the text observation's map
_TERRAIN_RGB: dict[int, tuple[float, float, float]] = {
    int(k.code): (k.colour[0] / 255, k.colour[1] / 255, k.colour[2] / 255) for k in CELL_KINDS}
_LABELLED = [k for k in CELL_KINDS if k.role not in ("floor", "wall", "counter")]
_TERRAIN_LABEL: dict[int, str] = {int(k.code): k.letter for k in _LABELLED}
#: cells whose terrain switches between layouts: a colour far from the walls, the floor
#: and both ends of the visit colour map (white to black through red and yellow)
_SWITCH_RGB = (0.15, 0.75, 0.85)
_HEAT_CMAP = "inferno_r"


def _pyplot() -> Any:
    try:
        import matplotlib
    except ImportError:
        raise DependencyNotInstalled(
            "plots need matplotlib: install the plots extra: pip install -e '.[plots]'"
        ) from None
    if not os.environ.get("MPLBACKEND"):
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "-", text).strip("-")


def _presets(rows: list[dict[str, Any]]) -> list[str]:
    names = {str(r["preset"]) for r in rows}
    return sorted(names, key=lambda p: (_PRESET_ORDER + sorted(names)).index(p))


def _agents(rows: list[dict[str, Any]]) -> list[str]:
    seen: list[str] = []
    for r in rows:
        if r["agent"] not in seen:
            seen.append(r["agent"])
    return seen


def make_plots(folder: str | os.PathLike[str]) -> list[Path]:
    """Write every figure for the results in ``folder``; returns the files written."""
    plt = _pyplot()
    folder = Path(folder)
    rows = latest_rows(read_results(folder))
    out = folder / "plots"
    out.mkdir(exist_ok=True)
    ok = [r for r in rows if r.get("status") == "ok" and r.get("metrics")]
    files = [_leaderboard(plt, rows, out)]
    if ok:
        files.append(_reward_curves(plt, ok, out))
        files.append(_actions(plt, ok, out))
        files.extend(_heatmaps(plt, ok, out))
        planning = _planning(plt, ok, out)
        if planning is not None:
            files.append(planning)
    plt.close("all")
    return files


def _leaderboard(plt: Any, rows: list[dict[str, Any]], out: Path) -> Path:
    summary = summarise(rows)
    presets = _presets(rows)
    agents = _agents(rows)
    fig, ax = plt.subplots(figsize=(max(6.0, 1.6 * len(presets) * max(1, len(agents)) / 2), 4.2))
    width = 0.8 / max(1, len(agents))
    cmap = plt.get_cmap("tab10")
    for j, agent in enumerate(agents):
        xs, ys, es = [], [], []
        for i, preset in enumerate(presets):
            s = next((s for s in summary if s["preset"] == preset and s["agent"] == agent), None)
            x = i - 0.4 + width * (j + 0.5)
            if s is None or not s["episodes"]:
                ax.text(x, 0.05, "skipped" if s and s["skipped"] else "n/a", rotation=90,
                        ha="center", va="bottom", fontsize=7, color="gray")
                continue
            xs.append(x)
            ys.append(s["dishes_served_mean"])
            es.append(s["dishes_served_ci95"] or 0.0)
        label = agent if xs else f"{agent} (skipped)"
        ax.bar(xs, ys, width * 0.9, yerr=es, capsize=3, label=label, color=cmap(j % 10))
        for x, y, e in zip(xs, ys, es):
            ax.text(x, y + e, f"{y:.1f}", ha="center", va="bottom", fontsize=7)
    ax.set_xticks(range(len(presets)))
    ax.set_xticklabels(presets)
    ax.set_ylabel("dishes served per episode")
    ax.set_title("Leaderboard (mean, 95% CI)")
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(axis="y", alpha=0.3)
    path = out / "leaderboard.png"
    return _save(plt, fig, path)


def _reward_curves(plt: Any, ok: list[dict[str, Any]], out: Path) -> Path:
    presets = _presets(ok)
    agents = _agents(ok)
    fig, axes = plt.subplots(1, len(presets), figsize=(4.6 * len(presets), 3.6), squeeze=False)
    cmap = plt.get_cmap("tab10")
    for ax, preset in zip(axes[0], presets):
        for j, agent in enumerate(agents):
            curves = [r["metrics"]["reward_curve"] for r in ok
                      if r["preset"] == preset and r["agent"] == agent]
            if not curves:
                continue
            n = min(len(c) for c in curves)
            means, lo, hi = [], [], []
            for t in range(n):
                m, ci = mean_ci([c[t] for c in curves])
                means.append(m)
                lo.append(m - ci)
                hi.append(m + ci)
            steps = list(range(1, n + 1))
            ax.plot(steps, means, label=agent, color=cmap(j % 10))
            ax.fill_between(steps, lo, hi, color=cmap(j % 10), alpha=0.2)
        ax.set_title(preset)
        ax.set_xlabel("step")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("cumulative team reward")
    axes[0][-1].legend(fontsize=8)
    fig.suptitle("Reward over time (mean, 95% CI)")
    path = out / "reward_over_time.png"
    return _save(plt, fig, path)


def _actions(plt: Any, ok: list[dict[str, Any]], out: Path) -> Path:
    presets = _presets(ok)
    agents = _agents(ok)
    fig, axes = plt.subplots(1, len(presets), figsize=(4.6 * len(presets), 0.6 * len(agents) + 1.8),
                             squeeze=False)
    cmap = plt.get_cmap("Set2")
    for ax, preset in zip(axes[0], presets):
        labels = []
        for j, agent in enumerate(agents):
            rs = [r for r in ok if r["preset"] == preset and r["agent"] == agent]
            if not rs:
                continue
            labels.append(agent)
            left = 0.0
            for k, name in enumerate(ACTION_NAMES):
                frac = sum(r["metrics"]["action_fractions"][name] for r in rs) / len(rs)
                ax.barh(len(labels) - 1, frac, left=left, color=cmap(k),
                        label=name if len(labels) == 1 else None)
                left += frac
        ax.set_yticks(range(len(labels)))
        ax.set_yticklabels(labels, fontsize=8)
        ax.set_xlim(0, 1)
        ax.set_xlabel("fraction of actions")
        ax.set_title(preset)
    handles, names = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, names, fontsize=8, loc="lower center", ncol=len(ACTION_NAMES))
    fig.suptitle("Action distribution")
    path = out / "actions.png"
    return _save(plt, fig, path, rect=(0, 0.08, 1, 1))


def _terrain(row: dict[str, Any]) -> Any:
    """The kitchen's main grid for a row and the mask of its switching cells (or None),
    or (None, None) when the map cannot be found any more."""
    from ..sim.kitchens import load_kitchen

    try:
        layout = load_kitchen(row.get("map_source") or row["map"])
    except Exception:
        return None, None
    switching = None if layout.switch_grid is None else layout.grid != layout.switch_grid
    return layout.grid, switching


def _draw_kitchen(ax: Any, grid: Any, switching: Any) -> set[int]:
    """The kitchen under a heatmap: cell colours, switching cells, station letters;
    returns the codes it labelled (for the key)."""
    import numpy as np

    rgb = np.array([[_TERRAIN_RGB.get(int(v), (1, 0, 1)) for v in line] for line in grid])
    if switching is not None:
        rgb[switching] = _SWITCH_RGB
    ax.imshow(rgb, interpolation="nearest")
    shown = set()
    for (r, c), v in np.ndenumerate(grid):
        if int(v) in _TERRAIN_LABEL:
            dark = sum(_TERRAIN_RGB[int(v)]) < 1.2
            ax.text(c, r, _TERRAIN_LABEL[int(v)], ha="center", va="center", fontsize=7,
                    color="white" if dark else "black")
            shown.add(int(v))
    return shown


def _key(fig: Any, shown: set[int], switching: bool) -> None:
    """A key under the figure: each label's cell kind, and the switching cells' colour."""
    from matplotlib.patches import Patch

    handles = [Patch(facecolor=_TERRAIN_RGB[int(k.code)], edgecolor="gray",
                     label=f"{k.letter} {k.word}") for k in _LABELLED if int(k.code) in shown]
    if switching:
        handles.append(Patch(facecolor=_SWITCH_RGB, edgecolor="gray",
                             label="switches wall/floor"))
    if handles:
        fig.legend(handles=handles, loc="lower center", ncol=min(4, len(handles)),
                   fontsize=7, frameon=False)


def _heatmaps(plt: Any, ok: list[dict[str, Any]], out: Path) -> list[Path]:
    import numpy as np

    files = []
    for preset in _presets(ok):
        for agent in _agents(ok):
            rs = [r for r in ok if r["preset"] == preset and r["agent"] == agent]
            if not rs:
                continue
            heat = np.sum([np.array(r["metrics"]["heatmaps"], dtype=float) for r in rs], axis=0)
            n_cooks, rows, cols = heat.shape
            grid, switching = _terrain(rs[0])
            fits = grid is not None and grid.shape == (rows, cols)
            fig, axes = plt.subplots(1, n_cooks, figsize=(0.45 * cols * n_cooks + 1.2,
                                                          0.45 * rows + 1.8), squeeze=False)
            shown: set[int] = set()
            for a, ax in enumerate(axes[0]):
                if fits:
                    shown |= _draw_kitchen(ax, grid, switching)
                share = heat[a] / max(1.0, heat[a].sum())
                masked = np.ma.masked_where(share <= 0, share)
                im = ax.imshow(masked, cmap=_HEAT_CMAP, alpha=0.85, interpolation="nearest",
                               vmin=0, vmax=max(1e-9, float(share.max())))
                ax.set_title(f"cook {a}", fontsize=9)
                ax.set_xticks([])
                ax.set_yticks([])
                fig.colorbar(im, ax=ax, fraction=0.046, pad=0.04, label="share of steps")
            fig.suptitle(f"Visited cells: {agent} on {preset} ({rs[0]['map']}, {len(rs)} episodes)",
                         fontsize=9)
            _key(fig, shown, fits and switching is not None and bool(switching.any()))
            path = out / f"heatmap_{_slug(preset)}_{_slug(agent)}.png"
            _save(plt, fig, path)
            files.append(path)
    return files


def _planning(plt: Any, ok: list[dict[str, Any]], out: Path) -> Path | None:
    groups: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for r in ok:
        groups.setdefault((r["preset"], r["agent"]), []).append(r)
    labels, reasons_per, times = [], [], []
    for (preset, agent), rs in groups.items():
        reasons: dict[str, float] = {}
        for r in rs:
            for k, v in (r.get("planner") or {}).get("replans_by_reason", {}).items():
                reasons[k] = reasons.get(k, 0.0) + v / len(rs)
        t = [(r.get("planner") or {}).get("planning_time_s", 0.0) for r in rs]
        if reasons or any(t):
            labels.append(f"{agent} / {preset}")
            reasons_per.append(reasons)
            times.append(mean_ci(t))
    if not labels:
        return None
    all_reasons = sorted({k for d in reasons_per for k in d})
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(max(8.0, 1.1 * len(labels) * 2), 4.0))
    cmap = plt.get_cmap("tab20")
    bottom = [0.0] * len(labels)
    for k, reason in enumerate(all_reasons):
        vals = [d.get(reason, 0.0) for d in reasons_per]
        ax1.bar(range(len(labels)), vals, bottom=bottom, label=reason, color=cmap(k % 20))
        bottom = [b + v for b, v in zip(bottom, vals)]
    ax1.set_xticks(range(len(labels)))
    ax1.set_xticklabels(labels, fontsize=7, rotation=30, ha="right")
    ax1.set_ylabel("replans per episode")
    ax1.set_title("Replans by reason")
    if all_reasons:
        ax1.legend(fontsize=7)
    ax2.bar(range(len(labels)), [m or 0 for m, _ in times], yerr=[c or 0 for _, c in times],
            capsize=3, color="tab:gray")
    ax2.set_xticks(range(len(labels)))
    ax2.set_xticklabels(labels, fontsize=7, rotation=30, ha="right")
    ax2.set_ylabel("seconds per episode")
    ax2.set_ylim(bottom=0)
    ax2.set_title("Planning time (mean, 95% CI)")
    for ax in (ax1, ax2):
        ax.grid(axis="y", alpha=0.3)
    path = out / "planning.png"
    return _save(plt, fig, path)


__all__ = ["make_plots"]


def _save(plt: Any, fig: Any, path: Path, rect: tuple[float, ...] | None = None) -> Path:
    """Lay out, write (110 dpi) and close a figure."""
    if rect is None:
        fig.tight_layout()
    else:
        fig.tight_layout(rect=rect)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
