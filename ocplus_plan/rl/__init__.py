"""The RL baseline: parameter-shared PPO (stable-baselines3) over per-agent observations.

Optional extra ``rl`` (``pip install 'ocplus-plan[rl]'``): torch and stable-baselines3 are
imported only inside the functions that train or load a policy, so importing this package
(and its feature encoder) costs nothing.

* :mod:`.features` - the compact egocentric feature encoder (numpy only);
* :mod:`.shaping`  - annealed reward shaping from the rules' subtask rewards;
* :mod:`.vec_env`  - a stable-baselines3 ``VecEnv`` with one slot per agent per kitchen;
* :mod:`.train`    - :func:`train` (what ``ocplus train`` runs) and the checkpoint format;
* :mod:`.policy`   - loading a checkpoint for acting (used by ``ppo:PATH`` agents).
"""

from __future__ import annotations

from .features import TARGETS, FeatureEncoder

__all__ = ["TARGETS", "FeatureEncoder"]
