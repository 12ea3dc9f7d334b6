"""Learning curves of the PPO baseline: dishes per 200-step episode against training steps.

    .venv/bin/python experiments/plot_learning_curves.py   # needs the plots extra

Reads ``experiments/checkpoints/*.episodes.csv`` (the training logs of the shipped
checkpoints, copied there by experiments/train_baselines.py), averages the episodes that finished in each bin of
training steps, writes ``experiments/figures/ppo_learning_curves.png`` and prints one
JSON line per run with its final bin. Steps are agent-steps, counted from the start of
each run's first stage: a run initialised from earlier stages (the medium chain) is drawn
after them, each up to the checkpoint that was carried on; the 2-agent run starts from
the easy checkpoint. Episodes in curriculum kitchens are left out. Runs that started by
cloning the greedy cook (``--bc``) are labelled so; their curve is the PPO part (its first
bin is about what the clone serves). The step axis is logarithmic: the runs span 0.2M to
20M steps.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def target_rows(rows: list[dict], info: dict) -> list[dict]:
    """Only the episodes played in the target kitchen, not in curriculum stages. Logs
    without a ``rules`` column (older runs) are filtered by kitchen index: kitchen j ran
    stage j % (1 + stages) until the switch (plus one episode that was under way)."""
    stages = info.get("curriculum") or []
    if not stages:
        return rows
    if rows and "rules" in rows[0]:
        return [r for r in rows if r["rules"] == info["preset"]]
    k = 1 + len(stages)
    switch = info["steps"] * info["curriculum_fraction"]
    slack = 200 * info["n_kitchens"] * int(info.get("n_agents") or 1)
    return [r for r in rows
            if int(r["kitchen"]) % k == 0 or int(r["timesteps"]) > switch + slack]


def chained_rows(path: Path, info: dict) -> list[dict]:
    """The run's target-kitchen episodes, preceded by those of the earlier stages it was
    initialised from (each up to the checkpoint that was used), on one step axis."""
    rows: list[dict] = []
    offset = 0
    for stage in info.get("lineage", []):
        part = target_rows(list(csv.DictReader((path.parent / stage["episodes"]).open())),
                           stage["config"])
        rows += [{**r, "timesteps": int(r["timesteps"]) + offset} for r in part
                 if int(r["timesteps"]) <= stage["used_timesteps"]]
        offset += stage["used_timesteps"]
    part = target_rows(list(csv.DictReader(path.open())), info.get("config", {}))
    return rows + [{**r, "timesteps": int(r["timesteps"]) + offset} for r in part]


def curve(path: Path, info: dict, bins: int = 25) -> tuple[list[float], list[float]]:
    rows = chained_rows(path, info)
    if not rows:
        return [], []
    last = max(int(r["timesteps"]) for r in rows)
    width = max(last / bins, 1.0)
    sums: dict[int, list[float]] = {}
    for r in rows:
        b = min(int(int(r["timesteps"]) / width), bins - 1)
        sums.setdefault(b, []).append(float(r["dishes"]))
    xs = [(b + 0.5) * width for b in sorted(sums)]
    ys = [sum(sums[b]) / len(sums[b]) for b in sorted(sums)]
    return xs, ys


def main() -> None:
    from ocplus_plan.errors import DependencyNotInstalled

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as exc:
        raise DependencyNotInstalled(
            "plotting needs the plots extra: pip install -e '.[plots]'"
        ) from exc
    runs = sorted(p for p in (ROOT / "experiments" / "checkpoints").glob("*.episodes.csv")
                  if ".stage" not in p.name)
    fig, ax = plt.subplots(figsize=(11, 5))
    for path in runs:
        name = path.name.removesuffix(".episodes.csv")
        info = json.loads((path.parent / f"{name}.json").read_text())
        xs, ys = curve(path, info)
        if not xs:
            continue
        init = info.get("init")
        if info.get("lineage"):
            label = f"{name} ({len(info['lineage']) + 1} stages, curriculum kitchens excluded)"
        else:
            label = name + (f" (from {Path(init).stem})" if init else "")
        if info.get("imitation"):
            label += ", cloned greedy first"
        if info.get("config", {}).get("obs") == "grid":
            label += ", grid observation"
        ax.plot([x / 1000 for x in xs], ys, marker="o", markersize=3, label=label)
        print(json.dumps({"run": name, "final_bin_steps": round(xs[-1]),
                          "dishes_per_episode": round(ys[-1], 3),
                          "timesteps": info["timesteps"], "wall_time_s": info["wall_time_s"]}))
    ax.set_xscale("log")
    ax.set_xlabel("training steps (thousands of agent-steps, log scale)")
    ax.set_ylabel("dishes per 200-step episode")
    ax.set_title("PPO baseline (parameter-shared, path features unless noted, annealed shaping)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    out = ROOT / "experiments" / "figures" / "ppo_learning_curves.png"
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(json.dumps({"figure": str(out.relative_to(ROOT))}))


if __name__ == "__main__":
    main()
