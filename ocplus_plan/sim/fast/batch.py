"""Many kitchens of one rule set stepped together as arrays: the batched engine.

:class:`BatchSim` holds ``n_envs`` kitchens (same :class:`Rules`, independent seeds and
actions) in flat arrays and steps them all with the kernels of
:mod:`ocplus_plan.sim.fast.kernels`, compiled by numba when the ``fast`` extra is
installed and run as plain Python otherwise (correct, about 80 times slower).
It keeps every agent's vector observation (SPEC section 8, exactly what
:class:`VectorEncoder` gives) up to date in :attr:`BatchSim.obs`, rewriting only the
entries that changed.

Two ways to step: :meth:`BatchSim.step` restarts finished kitchens in the same call (the
observation returned is the new episode's first, the last one is in
:attr:`BatchStep.final_obs`); :meth:`BatchSim.step_active` and :meth:`BatchSim.reset_envs`
are the parts it is made of, for callers with their own reset policy (the Gymnasium
vector env). Episode seeds come from one generator per kitchen, ``default_rng([seed, e])``,
so a batch is reproducible from ``seed`` alone; :meth:`BatchSim.state` rebuilds any
kitchen as a :class:`State` (same :meth:`State.state_hash` as :func:`transition` gives).

Design note: this is a second implementation of the rules, kept the same kitchen as
``step.py`` by a differential property test (``tests/sim/fast/test_batch.py``), not by being
the one implementation. ``transition`` stays the readable reference: it returns events,
which planners, the executive and reward shaping read, and its list state is what every
other layer inspects.
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import sys
import types
from functools import lru_cache
from typing import Any, NamedTuple

import numpy as np

from ...errors import ConfigError, DependencyNotInstalled, InvalidActionError
from . import arrays as ba
from . import kernels as bk
from ..codes import Item
from ..processes import ProcessTables
from ..observe import _CH_KIND0, _CH_STATE0, CH_OTHER, CH_PROGRESS, CH_SELF, VectorEncoder
from ..rules import Rules
from ..state import Order, State, geometry_for, new_state

_SEED_HIGH = 2**31 - 1
#: batches this large are split over threads (below it waking a thread costs more)
_PARALLEL_FROM = 256
_STATIC_CHANNELS = _CH_KIND0  # terrain one-hots and ``unknown`` come first
_INGREDIENTS = (Item.TOMATO, Item.LETTUCE, Item.ONION, Item.STEAK)


def seed_sequence(seed: int, kitchen: int) -> np.random.Generator:
    """The generator of kitchen ``kitchen``'s episode seeds in a batch seeded ``seed``
    (:func:`next_seed` draws one); anything that runs kitchens one by one and wants the
    batch's episodes uses it too."""
    return np.random.default_rng([seed, kitchen])


def next_seed(seeds: np.random.Generator) -> int:
    """The next episode seed from a :func:`seed_sequence`."""
    return int(seeds.integers(_SEED_HIGH))


class BatchStep(NamedTuple):
    obs: np.ndarray  # (n_envs, n_agents, size) float32, after any restart (a view: copy to keep)
    rewards: np.ndarray  # (n_envs, n_agents) float32
    terminated: np.ndarray  # (n_envs,) bool
    truncated: np.ndarray  # (n_envs,) bool
    final_obs: dict[int, np.ndarray]  # env index -> (n_agents, size), for envs that ended


def numba_available() -> bool:
    return importlib.util.find_spec("numba") is not None


def kernels(compiled: bool) -> Any:
    """The kernel module: as written (``compiled=False``), or a copy of it whose functions
    numba compiled (without the GIL, so threads can step disjoint kitchens)."""
    return compile_kernels(bk, compiled)


@lru_cache(maxsize=8)
def compile_kernels(module: types.ModuleType, compiled: bool, nrt: bool = False) -> Any:
    """``module`` as written (``compiled=False``), or a copy of it whose functions named in
    its ``KERNELS`` numba compiled without the GIL. ``nrt=False`` (the engine's kernels,
    which allocate nothing): no reference counting, which on shared arrays cost a quarter
    of the step and made the threads fight; kernels that allocate need ``nrt=True``.
    A module's ``KERNELS_FROM`` (name -> module) names kernels it imports from another
    kernel module: the compiled copy calls that module's compiled ones."""
    if not compiled:
        return module
    try:
        import numba
    except ImportError as exc:
        raise DependencyNotInstalled(
            "the compiled batch engine needs numba: pip install 'ocplus-plan[fast]' "
            "(or pass compiled=False for the plain-Python kernels)"
        ) from exc
    spec = importlib.util.find_spec(module.__name__)
    source = spec.loader.get_source(module.__name__)  # type: ignore[union-attr]
    mod = types.ModuleType(module.__name__ + "_compiled")
    mod.__file__ = module.__file__
    sys.modules[mod.__name__] = mod
    exec(compile(source, module.__file__, "exec"), mod.__dict__)  # noqa: S102 (our own source)
    for name in module.KERNELS:
        setattr(mod, name, numba.njit(cache=True, nogil=True, _nrt=nrt)(getattr(mod, name)))
    for name, home in getattr(module, "KERNELS_FROM", {}).items():  # imported kernels
        setattr(mod, name, getattr(compile_kernels(importlib.import_module(home), True, nrt),
                                   name))
    return mod


def static_arrays(rules: Rules, encoder: VectorEncoder, observe: bool = True,
                  ) -> ba.StaticArrays:
    """The kernels' tables for one rule set and observation encoder (``observe``: keep
    the vector observations up to date)."""
    geo = geometry_for(rules)
    i64 = np.int64
    params = np.zeros(17, i64)
    params[[ba.P_CHOP, ba.P_COOK, ba.P_BURN, ba.P_WASH, ba.P_HORIZON, ba.P_SWITCH_STEP]] = (
        rules.chop_steps, rules.cook_time, rules.burn_time, rules.wash_steps, rules.horizon,
        rules.map_switch_step)
    limit, stop = rules.order_time_limit, rules.stop_after_orders
    params[ba.P_LIMIT] = -1 if limit is None else limit
    params[ba.P_STOP] = -1 if stop is None else stop
    params[ba.P_DIRTY], params[ba.P_DYNAMIC] = rules.dirty_plates, rules.dynamic
    params[ba.P_SHARED] = rules.reward_mode == "shared"
    params[ba.P_FIXED] = rules.fixed_orders is not None
    params[ba.P_RADIUS], params[ba.P_ROWS], params[ba.P_COLS] = (
        encoder.radius, geo.rows, geo.cols)
    params[ba.P_HAS_SWITCH] = encoder._has_switch
    params[ba.P_OBSERVE] = observe
    rw = rules.rewards
    rewards = np.array([rw.subtask_finished, rw.correct_delivery, rw.wrong_delivery,
                        rw.step_penalty, rw.burned_penalty, rw.order_expired,
                        *rules.recipe_rewards], np.float64)
    kind_index = np.zeros(16, i64)
    for j, kind in enumerate((*_INGREDIENTS, Item.PLATE)):
        kind_index[int(kind)] = j
    recipe_counts = np.array([[r.count(k) for k in _INGREDIENTS] for r in rules.recipes], i64)
    fixed = [rules.recipes.index(r) for r in rules.fixed_orders or ()] or [0]
    cells_w = encoder.window[0] * encoder.window[1]
    static_size = _STATIC_CHANNELS * cells_w
    # read-only tables shared by every batch of the same encoder tables
    if encoder.radius:
        static_obs = encoder._padded_ext
        gather = encoder._window.derived(
            "static_gather", lambda: np.ascontiguousarray(encoder._gather[:, :static_size], i64))
    else:
        static_obs = encoder._planes.derived(
            "static_obs", lambda: np.ascontiguousarray(encoder._blank[:, 0, :static_size]))
        gather = encoder._window.derived("static_gather", lambda: np.arange(static_size)[None, :])
    view = np.array([
        cells_w, encoder.window[1], _CH_KIND0, _CH_STATE0, CH_PROGRESS, CH_SELF, CH_OTHER,
        encoder.grid_size, encoder.grid_size + encoder._order0, static_size], i64)
    spawn = [geo.flat(r, c) for r, c in rules.layout.spawn_points[: rules.n_agents]]
    t = rules.tables
    return ba.StaticArrays(
        params, rewards, np.array(geo.terrains, i64), np.array(geo.walkables, bool),
        np.array(geo.neighbors, i64), np.array(geo.timed, i64).reshape(-1),
        np.array(geo.switch_cells, i64).reshape(-1), np.array(geo.item_kind, i64),
        np.array(geo.item_home, i64), kind_index, np.array(encoder._prog_den, np.float64),
        recipe_counts, np.array(fixed, i64), np.array(spawn, i64), view,
        static_obs, gather, *process_arrays(t))


def process_arrays(t: ProcessTables) -> tuple[np.ndarray, ...]:
    """The kernels' copy of a rule set's process tables: (proc_of, proc, accepts, works,
    plateable); see :class:`.arrays.StaticArrays`."""
    proc_of = np.full(ba.N_CODES, -1, np.int64)
    for code, j in t.by_code.items():
        proc_of[code] = j
    rows = [[p.timed, int(p.takes_state), t.duration[j], t.done_state[j], t.overrun_state[j],
             t.overrun[j], p.plates, ba.STAT_NAMES.index(p.stat),
             ba.STAT_NAMES.index(p.overrun_stat)] for j, p in enumerate(t.processes)]
    proc = np.array(rows, np.int64).reshape(len(rows), 9)
    return (proc_of, proc, np.ascontiguousarray(t.accepts), np.ascontiguousarray(t.works),
            np.ascontiguousarray(t.plateable))


class BatchSim:
    """``n_envs`` kitchens of ``rules`` with vector observations of radius ``obs_radius``.

    ``compiled``: None uses numba when installed; True requires it (``fast`` extra);
    False runs the kernels as plain Python. ``threads``: how many threads step a large
    batch (default: the cores this process may use). ``observe=False`` keeps no vector
    observations (:attr:`obs` is empty): for callers that encode the state themselves
    (the trainer's features), it saves their upkeep and most of the memory.
    """

    def __init__(self, rules: Rules, n_envs: int, *, seed: int = 0, obs_radius: int = 0,
                 compiled: bool | None = None, threads: int | None = None,
                 observe: bool = True) -> None:
        if isinstance(n_envs, bool) or not isinstance(n_envs, int) or n_envs < 1:
            raise ConfigError(f"n_envs must be a positive integer, got {n_envs!r}")
        self.rules = rules
        self.n_envs = n_envs
        self.n_agents = n = rules.n_agents
        self.compiled = numba_available() if compiled is None else bool(compiled)
        self._k = kernels(self.compiled)
        #: threads a large batch is split over (default: the cores this process may use)
        self.threads = len(os.sched_getaffinity(0)) if threads is None else int(threads)
        self._pool: Any = None
        self.encoder = VectorEncoder(rules, obs_radius)
        self.static = static_arrays(rules, self.encoder, observe)
        geo = geometry_for(rules)
        n_items, n_cells, n_orders = len(geo.item_kind), geo.rows * geo.cols, rules.n_orders
        self._per_step_draws = n + n_orders  # deliveries + expiries
        self._queue_len = 2 * self._per_step_draws + n_orders + 8
        n_entries = 4 * n_items + n + 8 + 6 * n_orders if observe else 0
        obs_size = self.encoder.size if observe else 0
        i32, e = np.int32, n_envs

        def z(*shape: int, dtype: Any = i32) -> np.ndarray:
            return np.zeros((e, *shape), dtype)

        self.arrays = ba.KitchenArrays(
            clock=z(5), agents=z(2, n), cells=z(n_cells), items=z(6, n_items),
            orders=z(4, n_orders), stats=z(9), queue=z(self._queue_len),
            rewards=z(n, dtype=np.float64), subtasks=z(n), bumps=z(3, n),
            obs=z(n, obs_size, dtype=np.float32),
            static_at=np.full((e, n), -1, i32), ent_idx=z(n + 1, n_entries),
            ent_val=z(n + 1, n_entries, dtype=np.float32), ent_n=z(n),
            scratch=z(3, n, dtype=np.int64))
        self.reseed(seed)
        self._draw_rngs: list[np.random.Generator | None] = [None] * n_envs
        #: per kitchen: its episode's RNG state before the episode's first draw
        self._rng_start: list[dict[str, Any] | None] = [None] * n_envs
        self.seeds: list[int | None] = [None] * n_envs  # each kitchen's episode seed
        self._drawn_before = np.zeros(n_envs, np.int64)  # draws no longer in the queue
        self.episodes = np.zeros(n_envs, np.int64)
        self._all = np.ones(n_envs, bool)
        self._started = False

    # ------------------------------------------------------------ public
    def reseed(self, seed: int) -> None:
        """Restart the kitchens' episode-seed sequences from ``seed`` (next resets use it)."""
        self._seed_rngs = [seed_sequence(seed, i) for i in range(self.n_envs)]

    def reseed_each(self, seeds: list[int]) -> None:
        """Kitchen ``e``'s episode seeds now come from ``default_rng(seeds[e])``: the
        generator a Gymnasium env reseeded with ``seeds[e]`` draws its next seeds from."""
        if len(seeds) != self.n_envs:
            raise ConfigError(f"reseed_each needs {self.n_envs} seeds, got {len(seeds)}")
        self._seed_rngs = [np.random.default_rng(int(s)) for s in seeds]

    @property
    def obs(self) -> np.ndarray:
        """``(n_envs, n_agents, size)`` float32: every agent's current observation (live:
        the next step rewrites it; copy what you keep)."""
        return self.arrays.obs

    def reset(self, seeds: list[int] | None = None) -> np.ndarray:
        """Start a new episode everywhere (seeded ``seeds[e]``, or from each kitchen's
        sequence); returns :attr:`obs`."""
        self.reset_envs(np.arange(self.n_envs), seeds)
        self.episodes[:] = 0
        return self.arrays.obs

    def reset_envs(self, envs: np.ndarray, seeds: list[int] | None = None) -> None:
        """Start the next episode of each listed kitchen, seeded from its own sequence or
        with the given ``seeds`` (one per kitchen listed)."""
        envs = np.asarray(envs, np.int64).reshape(-1)
        for j, e in enumerate(envs.tolist()):
            self.seeds[e] = next_seed(self._seed_rngs[e]) if seeds is None else int(seeds[j])
            self._start_draws(e, np.random.default_rng(self.seeds[e]))
        self._k.reset_some(self.arrays, self.static, envs)
        self._started = True

    def load(self, e: int, state: State) -> None:
        """Put a copy of ``state`` (of these rules) into kitchen ``e``: its episode goes on
        from there, drawing orders from the state's generator."""
        if state.rules != self.rules:
            raise ConfigError("the state belongs to other rules than this batch's")
        a = self.arrays
        a.cells[e] = state.cell_item
        a.items[e, : ba.I_LIFE] = (state.item_state, state.item_progress, state.item_where,
                                   state.item_loc, state.item_agent)
        a.items[e, ba.I_LIFE] = 0
        a.agents[e] = (state.agent_pos, state.agent_hand)
        a.clock[e] = (state.t, state.layout_index, state.next_switch, state.next_order_id, 0)
        index = {r: i for i, r in enumerate(self.rules.recipes)}
        a.orders[e] = np.array([(o.order_id, index[o.recipe], o.created, o.deadline)
                                for o in state.orders]).T
        a.stats[e] = [state.stats[name] for name in ba.STAT_NAMES]
        self.seeds[e] = state.seed
        rng = np.random.Generator(np.random.PCG64())
        rng.bit_generator.state = state.rng_state()
        self._start_draws(e, rng)
        self._k.observe_some(self.arrays, self.static, np.array([e], np.int64))
        self._started = True

    def _start_draws(self, e: int, rng: np.random.Generator) -> None:
        """Kitchen ``e``'s orders now come from ``rng``: fill its queue from it."""
        self._rng_start[e] = rng.bit_generator.state
        if self.rules.fixed_orders is None:
            self.arrays.queue[e] = rng.integers(len(self.rules.recipes), size=self._queue_len)
        self._draw_rngs[e] = rng
        self.arrays.clock[e, ba.C_QPOS] = 0
        self._drawn_before[e] = 0

    def step_active(self, actions: np.ndarray, active: np.ndarray | None = None,
                    ) -> tuple[np.ndarray, np.ndarray]:
        """Step the kitchens with ``active`` (all when None) without restarting any;
        returns (terminated, truncated) per kitchen (False where not active)."""
        if not self._started:
            raise ConfigError("call reset() before step()")
        acts = np.asarray(actions)
        if acts.shape != (self.n_envs, self.n_agents):
            raise InvalidActionError(
                f"actions must have shape (n_envs, n_agents) = {(self.n_envs, self.n_agents)}, "
                f"got {acts.shape}"
            )
        acts = acts.astype(np.int64, copy=False)
        if (acts.view(np.uint64) > 4).any():  # negatives wrap to huge
            e, a = np.argwhere((acts < 0) | (acts > 4))[0]
            raise InvalidActionError(
                f"kitchen {e}, agent {a}: action {int(acts[e, a])} is not one of 0 right, 1 down, "
                "2 left, 3 up, 4 stay"
            )
        act = self._all if active is None else np.asarray(active, bool)
        self._step_range(acts, act)
        self._refill_queues()
        a, p = self.arrays, self.static.params
        stop = p[ba.P_STOP]
        terminated = (a.stats[:, ba.COMPLETED] >= stop) & act if stop >= 0 else \
            np.zeros(self.n_envs, bool)
        truncated = ~terminated & (a.clock[:, ba.C_T] >= p[ba.P_HORIZON]) & act
        return terminated, truncated

    def step(self, actions: np.ndarray) -> BatchStep:
        """Step every kitchen; finished ones restart at once (see the module note)."""
        terminated, truncated = self.step_active(actions)
        rewards = self.arrays.rewards.astype(np.float32)
        ended = np.flatnonzero(terminated | truncated)
        final: dict[int, np.ndarray] = {}
        if len(ended):
            last = self.arrays.obs[ended]
            final = {int(e): last[j] for j, e in enumerate(ended)}
            self.reset_envs(ended)
            self.episodes[ended] += 1
        return BatchStep(self.arrays.obs, rewards, terminated, truncated, final)

    def state(self, e: int) -> State:
        """Kitchen ``e`` as a :class:`State` (an independent copy, hash-identical to the
        state :func:`transition` reaches from the same seed and actions)."""
        a, rules = self.arrays, self.rules
        s = new_state(rules, self.seeds[e])
        s.cell_item = a.cells[e].tolist()
        (s.item_state, s.item_progress, s.item_where, s.item_loc,
         s.item_agent) = a.items[e, : ba.I_LIFE].tolist()
        s.agent_pos, s.agent_hand = a.agents[e].tolist()
        s.t, s.layout_index, s.next_switch, s.next_order_id, used = a.clock[e].tolist()
        s.orders = [Order(i, rules.recipes[r], c, d) for i, r, c, d in zip(*a.orders[e].tolist())]
        s.stats = dict(zip(ba.STAT_NAMES, a.stats[e].tolist()))
        rng = np.random.Generator(np.random.PCG64())
        rng.bit_generator.state = self._rng_start[e]
        drawn = int(self._drawn_before[e]) + used
        if rules.fixed_orders is None and drawn:
            rng.integers(len(rules.recipes), size=drawn)
        s.rng = rng
        return s

    def close(self) -> None:
        """Stop the stepping threads (a later step starts them again)."""
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None

    def memory_per_kitchen(self) -> int:
        """Bytes held per kitchen: state, observations and the kernels' bookkeeping."""
        return sum(x.nbytes for x in self.arrays) // self.n_envs

    # ------------------------------------------------------------ internals
    def _step_range(self, acts: np.ndarray, active: np.ndarray) -> None:
        self.split(self._k.step_range, self.arrays, self.static, acts, active)

    def split(self, kernel: Any, *args: Any) -> None:
        """``kernel(*args, start, stop)`` over all kitchens, split over :attr:`threads`
        threads when the batch is large enough to pay for waking them (compiled kernels
        release the GIL; each thread takes a disjoint range of kitchens)."""
        n, parts = self.n_envs, self.threads
        if parts < 2 or n < _PARALLEL_FROM or not self.compiled:
            kernel(*args, 0, n)
            return
        if self._pool is None:
            from concurrent.futures import ThreadPoolExecutor

            self._pool = ThreadPoolExecutor(parts - 1, thread_name_prefix="ocplus-batch")
        bounds = [n * i // parts for i in range(parts + 1)]
        futures = [self._pool.submit(kernel, *args, bounds[i], bounds[i + 1])
                   for i in range(1, parts)]
        kernel(*args, bounds[0], bounds[1])
        for f in futures:
            f.result()

    def _refill_queues(self) -> None:
        """Top up the recipe queues that a next step could run dry (rare: a draw is a
        delivery or an expired order)."""
        if self.rules.fixed_orders is not None:
            return
        a, q = self.arrays, self._queue_len
        low = np.flatnonzero(a.clock[:, ba.C_QPOS] > q - self._per_step_draws)
        n_recipes = len(self.rules.recipes)
        for e in low.tolist():
            used = int(a.clock[e, ba.C_QPOS])
            a.queue[e, : q - used] = a.queue[e, used:].copy()
            a.queue[e, q - used :] = self._draw_rngs[e].integers(n_recipes, size=used)
            a.clock[e, ba.C_QPOS] = 0
            self._drawn_before[e] += used


__all__ = ["BatchSim", "BatchStep", "compile_kernels", "kernels", "next_seed", "numba_available",
           "seed_sequence", "static_arrays"]
