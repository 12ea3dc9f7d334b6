"""Agent communication (SPEC section 9): tokens, range, failures, delay. numpy only.

Each step every agent emits one token from a vocabulary of ``vocab`` words. A copy goes
to every other agent within ``range`` cells (Chebyshev distance between the sender's and
the receiver's cells after the step's moves; 0 = unlimited) and is dropped independently
with probability ``failure_rate``. It is delivered ``delay`` steps later (1 = in the
observation that the same ``step`` call returns, i.e. the receiver sees it before its
next action). All draws come from ``numpy.random.default_rng([episode_seed, 1])``: a
stream of its own, so turning communication on never changes the simulator's order draws.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError, InvalidActionError

#: second word of the communication RNG's seed: ``default_rng([episode_seed, COMM_STREAM])``
COMM_STREAM = 1


@dataclass(frozen=True)
class CommConfig:
    """Parameters of the channel (checked on construction)."""

    vocab: int = 8
    range: int = 0
    failure_rate: float = 0.0
    delay: int = 1

    def __post_init__(self) -> None:
        for name, low in (("vocab", 1), ("range", 0), ("delay", 1)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < low:
                raise ConfigError(f"comm_{name} must be an integer >= {low}, got {v!r}")
        f = self.failure_rate
        if isinstance(f, bool) or not isinstance(f, (int, float)) or not 0.0 <= f <= 1.0:
            raise ConfigError(f"comm_failure_rate must be a number in [0, 1], got {f!r}")


class CommChannel:
    """The message channel of one kitchen. :meth:`reset` per episode, :meth:`exchange`
    once per step; received tokens are ``(n_agents, n_agents - 1)`` ints, slot k of agent
    a holding the token of agent ``(a + k + 1) % n`` or -1 (nothing arrived)."""

    def __init__(self, config: CommConfig, n_agents: int, cols: int) -> None:
        self.config = config
        self.n = n_agents
        self.cols = cols
        self.sent = 0
        self.delivered = 0
        self._queue: deque[np.ndarray] = deque()
        self._rng = np.random.default_rng([0, COMM_STREAM])
        # sender of slot k for receiver a
        self._sender = [[(a + k + 1) % n_agents for k in range(n_agents - 1)]
                        for a in range(n_agents)]

    def silence(self) -> np.ndarray:
        """Nothing received (the reset observation)."""
        return np.full((self.n, max(0, self.n - 1)), -1, dtype=np.int64)

    def reset(self, episode_seed: int) -> np.ndarray:
        self._rng = np.random.default_rng([int(episode_seed), COMM_STREAM])
        self._queue = deque(self.silence() for _ in range(self.config.delay - 1))
        self.sent = self.delivered = 0
        return self.silence()

    def exchange(self, tokens: Sequence[int], positions: Sequence[int]) -> np.ndarray:
        """Send this step's ``tokens`` from agents at flat cells ``positions``; return what
        arrives now (sent ``delay`` steps ago)."""
        cfg, n = self.config, self.n
        for a, tok in enumerate(tokens):
            if not 0 <= tok < cfg.vocab:
                raise InvalidActionError(
                    f"agent {a}: message token {tok!r} is outside the vocabulary 0..{cfg.vocab - 1} "
                    "(comm_vocab)"
                )
        # always draw the full matrix, so the stream does not depend on positions
        drops = self._rng.random((n, n)) < cfg.failure_rate if cfg.failure_rate > 0 else None
        got = self.silence()
        rc = [divmod(p, self.cols) for p in positions]
        for a in range(n):
            ra, ca = rc[a]
            for k, b in enumerate(self._sender[a]):
                self.sent += 1
                if cfg.range:
                    rb, cb = rc[b]
                    if max(abs(ra - rb), abs(ca - cb)) > cfg.range:
                        continue
                if drops is not None and drops[b, a]:
                    continue
                got[a, k] = int(tokens[b])
                self.delivered += 1
        self._queue.append(got)
        return self._queue.popleft()


__all__ = ["COMM_STREAM", "CommChannel", "CommConfig"]
