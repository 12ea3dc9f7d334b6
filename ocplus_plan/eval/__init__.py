"""Evaluation: run controllers on presets, compute metrics, write results and plots.

- :mod:`.runner`: ``run_eval(EvalConfig)``, ``--resume``, Ctrl-C.
- :mod:`.episode`: one episode (``EpisodeSpec``, ``evaluate_episode``), its faults and row.
- :mod:`.local_backend`: worker processes that die with their driver; :mod:`.ray_backend`.
- :mod:`.progress`: the progress bar (planner statistics of long episodes, per-agent ETA).
- :mod:`.metrics`: ``EpisodeLog`` and ``compute_metrics`` (from the simulator's events).
- :mod:`.results`: ``results.jsonl`` / ``summary.csv`` and the terminal leaderboard.
- :mod:`.plots`: PNG figures (matplotlib, the ``plots`` extra; imported lazily).
"""

from __future__ import annotations

from .metrics import EpisodeLog, compute_metrics
from .results import leaderboard, read_results, summarise
from .runner import EvalConfig, run_eval

__all__ = ["EpisodeLog", "EvalConfig", "compute_metrics", "leaderboard", "read_results",
           "run_eval", "summarise"]
