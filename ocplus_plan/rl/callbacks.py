"""Training callbacks: shaping annealing, curriculum, episode CSV, checkpoints, progress.

Imports stable-baselines3 at module level; :mod:`ocplus_plan.rl.train` imports it lazily.
"""

from __future__ import annotations

import csv
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any, TextIO

from stable_baselines3.common.callbacks import BaseCallback

from .vec_env import KitchenVecEnv

EPISODE_FIELDS = (
    "timesteps", "wall_s", "episode", "kitchen", "preset", "rules", "map", "seed", "steps",
    "game_reward", "train_return", "dishes", "shaping_coef", "partner",
)


def shaping_coefficient(timesteps: int, total: int, anneal_fraction: float) -> float:
    """1 at the start, linearly down to 0 at ``anneal_fraction`` of training, then 0."""
    if anneal_fraction <= 0:
        return 0.0
    return max(0.0, 1.0 - timesteps / (anneal_fraction * total))


class TrainingMonitor(BaseCallback):
    """Anneals the shaping, logs finished episodes to CSV, saves periodic checkpoints and
    draws a one-line progress bar on ``stream`` (None = no bar)."""

    def __init__(
        self,
        venv: KitchenVecEnv,
        total_steps: int,
        out_dir: Path,
        *,
        anneal_fraction: float,
        checkpoint_every: int,
        save: Callable[[Path, int], None],
        stream: TextIO | None = sys.stderr,
        max_wall_s: float | None = None,
    ) -> None:
        super().__init__()
        self.venv = venv
        self.total = total_steps
        self.out_dir = out_dir
        self.anneal_fraction = anneal_fraction
        self.checkpoint_every = checkpoint_every
        self.save = save
        self.stream = stream
        self.max_wall_s = max_wall_s
        #: True once training stopped early because ``max_wall_s`` ran out
        self.out_of_time = False
        self.t0 = time.perf_counter()
        self.episodes = 0
        self.recent: list[int] = []
        self._next_checkpoint = checkpoint_every
        self._last_draw = 0.0
        self._csv_file = open(out_dir / "episodes.csv", "w", newline="")  # noqa: SIM115
        self._csv = csv.DictWriter(self._csv_file, fieldnames=EPISODE_FIELDS)
        self._csv.writeheader()

    def _on_rollout_start(self) -> None:
        # with a wall budget, progress is the further of steps and time: the shaping still
        # reaches 0 when the budget, not the step count, ends the run
        done = self.num_timesteps
        if self.max_wall_s:
            spent = (time.perf_counter() - self.t0) / self.max_wall_s
            done = max(done, int(spent * self.total))
        self.venv.shaping_coef = shaping_coefficient(done, self.total, self.anneal_fraction)

    def _on_step(self) -> bool:
        if self.venv.finished:
            wall = round(time.perf_counter() - self.t0, 2)
            for ep in self.venv.finished:
                self.episodes += 1
                row: dict[str, Any] = {"timesteps": self.num_timesteps, "wall_s": wall,
                                       "episode": self.episodes, **ep}
                row["game_reward"] = round(row["game_reward"], 3)
                row["train_return"] = round(row["train_return"], 3)
                row["shaping_coef"] = round(row["shaping_coef"], 4)
                self._csv.writerow(row)
                self.recent = (self.recent + [ep["dishes"]])[-50:]
            self.venv.finished.clear()
            self._csv_file.flush()
        if self.checkpoint_every and self.num_timesteps >= self._next_checkpoint:
            self.save(self.out_dir / "checkpoints" / f"step_{self.num_timesteps:09d}.zip",
                      self.num_timesteps)
            self._next_checkpoint += self.checkpoint_every
        self._draw()
        if self.max_wall_s is not None and time.perf_counter() - self.t0 >= self.max_wall_s:
            self.out_of_time = True
            return False  # SB3 stops learn(); train() saves the policy as usual
        return True

    def _draw(self, final: bool = False) -> None:
        if self.stream is None:
            return
        now = time.perf_counter()
        if not final and now - self._last_draw < 0.5:
            return
        self._last_draw = now
        frac = min(self.num_timesteps / max(self.total, 1), 1.0)
        width = 30
        bar = "#" * int(frac * width) + "-" * (width - int(frac * width))
        elapsed = now - self.t0
        rate = self.num_timesteps / elapsed if elapsed > 0 else 0.0
        eta = (self.total - self.num_timesteps) / rate if rate > 0 else 0.0
        dishes = sum(self.recent) / len(self.recent) if self.recent else 0.0
        self.stream.write(
            f"\r[{bar}] {self.num_timesteps}/{self.total} {rate:.0f} steps/s "
            f"eta {eta:.0f}s | episodes {self.episodes} dishes/ep (last 50) {dishes:.2f} "
            f"shaping {self.venv.shaping_coef:.2f}"
        )
        if final:
            self.stream.write("\n")
        self.stream.flush()

    def _on_training_end(self) -> None:
        self._draw(final=True)

    def close(self) -> None:
        """Close the CSV log (after the last ``learn`` call)."""
        self._csv_file.close()


__all__ = ["EPISODE_FIELDS", "TrainingMonitor", "shaping_coefficient"]
