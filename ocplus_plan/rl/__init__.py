"""The RL baseline: parameter-shared PPO (stable-baselines3) over per-agent observations.

Optional extra ``rl`` (``pip install 'ocplus-plan[rl]'``): torch and stable-baselines3 are
imported only inside the functions that train or load a policy, so importing this package
(and its feature encoder) costs nothing.

* :mod:`.features`  - the compact egocentric path-feature encoder (numpy only);
* :mod:`.obs`       - ``features`` or ``grid`` (the SPEC one-hot vector) observations;
* :mod:`.shaping`   - annealed reward shaping from the rules' subtask rewards;
* :mod:`.vec_env`   - a stable-baselines3 ``VecEnv`` with one slot per agent per kitchen;
* :mod:`.callbacks` - shaping annealing, episode CSV, checkpoints, progress bar;
* :mod:`.train`     - :func:`train` (what ``ocplus train`` runs);
* :mod:`.lean`      - the same PPO in a plain torch loop (``ocplus train --algo lean``);
* :mod:`.policy`    - the checkpoint format and loading a policy to act (``ppo:PATH``).
"""

from __future__ import annotations

from .features import TARGETS, FeatureEncoder

__all__ = ["TARGETS", "FeatureEncoder"]
