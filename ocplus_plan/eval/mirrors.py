"""One harness for the speed mirrors: any mirror against the reference step on any list of
kitchens (in the spirit of Gymnasium's ``check_environments_match``).

:func:`check_mirror` steps each kitchen in a mirror and in ``sim.transition`` side by side
(greedy cooks, a share of random actions from a seeded generator) and raises
:class:`MirrorMismatch` at the first step where rewards, episode ends, the state or the
vector observation differ; it returns the summed stats of the finished episodes, so a
caller can check the run reached the rules it meant to test. Mirrors:

* ``numba``: :class:`~ocplus_plan.sim.fast.batch.BatchSim`, compiled (the ``fast`` extra);
* ``kernels``: the same engine's kernels as plain Python;
* ``jax``: the JAX kitchen (:mod:`ocplus_plan.sim.fast.jax_kitchen`, the ``jax`` extra), all
  kitchens in one vmapped batch (padded to one shape), orders drawn from its keys;
* ``features`` / ``features-kernels``: the batched RL features and shaped rewards
  (``rl/fast``) on the compiled or the plain kernels (:func:`check_features`).

Kitchens are rule sets (:func:`kitchens` makes them from map names: registered maps, paths,
``gen:`` names), with any process records (``Rules.processes``) and dishes;
:func:`random_kitchens` draws generated kitchens with drawn process records and menus.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from dataclasses import replace

from ..agents.greedy import GreedyAgent
from ..errors import ConfigError
from ..sim import Rules, make_rules, new_state, transition
from ..sim.codes import ItemState, Where
from ..sim.dishes import dish_to_dict
from ..sim.generate import FAMILIES, map_from_name
from ..sim.generate_recipes import draw_dishes
from ..sim.maps import load_map
from ..sim.observe import VectorEncoder
from ..sim.orders import draw_order
from ..sim.presets import PRESETS
from ..sim.processes import PROCESSES
from ..sim.rules import with_overrides
from ..sim.state import State, geometry_for

MIRRORS = ("numba", "kernels", "jax", "features", "features-kernels")


class MirrorMismatch(AssertionError):
    """A mirror and the reference disagree (the message names kitchen, step and what)."""


def kitchens(names: Sequence[str], preset: str = "medium", **overrides: Any) -> list[Rules]:
    """Rule sets of ``preset`` on each map name (``gen:`` names, registered maps, paths)."""
    return [make_rules(preset, map=name, **overrides) for name in names]


def random_kitchens(seed: int, count: int = 4, *, presets: Sequence[str] = tuple(PRESETS),
                    n_agents: int = 2, records: bool = True, **overrides: Any) -> list[Rules]:
    """``count`` generated kitchens drawn with ``seed``: a family, a train index and a preset
    (its stations) each, a menu of 1 to 3 dishes of drawn rewards written into the kitchen
    file, and (``records``) process records with drawn drives and durations; ``overrides``
    are rule parameters of every kitchen."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        preset = presets[int(rng.integers(len(presets)))]
        name = f"gen:{FAMILIES[int(rng.integers(len(FAMILIES)))]}:train:" \
               f"{int(rng.integers(50))}:{preset}"
        spec = map_from_name(name)
        lengths = (1,) if preset == "easy" else (2, 3)
        menu = draw_dishes(load_map(spec), int(rng.integers(1 << 20)), lengths,
                           int(rng.integers(1, 4)), PRESETS[preset].steak)
        spec["recipes"] = [dict(dish_to_dict(d), reward=float(rng.integers(20, 400)))
                           for d in menu]
        rules = make_rules(preset, map=load_map(spec, source=name), n_agents=n_agents,
                           dynamic=spec.get("is_dynamic_map", False), **overrides)
        out.append(with_overrides(rules, processes=_drawn_records(rng)) if records else rules)
    return out


def _drawn_records(rng: np.random.Generator) -> tuple:
    """The shipped records with drawn durations, and the board and pan each driven by bumps
    or by time (a time-driven one overruns to burnt)."""
    drawn = []
    for p in PROCESSES:
        timed = p.timed if p.verb == "wash" else bool(rng.integers(2))
        n = int(rng.integers(1, 5))
        drawn.append(replace(
            p, drive="time" if timed else "bump", duration=n, duration_param="",
            overrun_state=ItemState.BURNT if timed else None,
            overrun=n + int(rng.integers(0, 4)) if timed else 0, overrun_param=""))
    return tuple(drawn)


def check_mirror(mirror: str, rules_list: Sequence[Rules], *, steps: int = 30, seed: int = 0,
                 noise: float = 0.25, radius: int = 0, n_envs: int = 2,
                 **options: Any) -> dict[str, float]:
    """Step every kitchen in ``mirror`` and in the reference for ``steps`` steps; raise
    :class:`MirrorMismatch` at the first difference; return the finished episodes' stats
    (the features mirrors: ``{"shaped": the reference's summed absolute shaping}``).
    ``n_envs``: kitchens per rule set (numba, kernels, features); ``options``: those of
    :func:`check_jax` or :func:`check_features`."""
    if mirror not in MIRRORS:
        raise ConfigError(f"unknown mirror {mirror!r}; choose one of {', '.join(MIRRORS)}")
    if mirror == "jax":
        return check_jax(rules_list, steps=steps, seed=seed, noise=noise, radius=radius,
                         **options)
    totals: dict[str, float] = {}
    for k, rules in enumerate(rules_list):
        if mirror.startswith("features"):
            got = {"shaped": check_features(rules, compiled=mirror == "features", steps=steps,
                                            seed=seed + k, noise=noise, n_envs=n_envs,
                                            **options)}
        else:
            got = check_batch(rules, compiled=mirror == "numba", steps=steps, seed=seed + k,
                              noise=noise, radius=radius, n_envs=n_envs)
        for name, v in got.items():
            totals[name] = totals.get(name, 0) + v
    return totals


def _expect(ok: bool, rules: Rules, step: int, what: str) -> None:
    if not ok:
        raise MirrorMismatch(f"kitchen {rules.layout.name!r} ({rules.preset}), step {step}: "
                             f"{what} differs from the reference")


def _acts(cooks: list[GreedyAgent], refs: list[State], rng: np.random.Generator,
          noise: float) -> np.ndarray:
    acts = np.array([cooks[e].act(refs[e]) for e in range(len(refs))])
    rand = rng.random(acts.shape) < noise
    acts[rand] = rng.integers(0, 5, size=int(rand.sum()))
    return acts


def _add(totals: dict[str, int], state: State) -> None:
    for k, v in state.stats.items():
        totals[k] = totals.get(k, 0) + v


def check_batch(rules: Rules, *, compiled: bool, steps: int, seed: int = 0,
                noise: float = 0.25, radius: int = 0, n_envs: int = 2) -> dict[str, int]:
    """The batched engine (numba or its plain kernels): ``n_envs`` kitchens of ``rules``."""
    from ..sim.fast.batch import BatchSim

    sim = BatchSim(rules, n_envs, seed=seed, obs_radius=radius, compiled=compiled)
    obs = sim.reset()
    enc = VectorEncoder(rules, radius)
    refs = [new_state(rules, int(sim.seeds[e])) for e in range(n_envs)]
    cooks = [GreedyAgent(seed + e) for e in range(n_envs)]
    for e in range(n_envs):
        cooks[e].reset(refs[e])
        _expect(np.array_equal(obs[e], enc.encode(refs[e])), rules, 0, "the first observation")
    rng = np.random.default_rng(seed)
    totals: dict[str, int] = {}
    for t in range(steps):
        acts = _acts(cooks, refs, rng, noise)
        out = sim.step(acts)
        for e in range(n_envs):
            res = transition(refs[e], acts[e].tolist())
            _expect(sim.arrays.rewards[e].tolist() == res.rewards, rules, t, "the rewards")
            _expect((out.terminated[e], out.truncated[e]) == (res.terminated, res.truncated),
                    rules, t, "the episode end")
            if res.terminated or res.truncated:
                _expect(np.array_equal(out.final_obs[e], enc.encode(refs[e])), rules, t,
                        "the final observation")
                _add(totals, refs[e])
                refs[e] = new_state(rules, int(sim.seeds[e]))
                cooks[e].reset(refs[e])
            _expect(sim.state(e).state_hash() == refs[e].state_hash(), rules, t, "the state")
            _expect(np.array_equal(out.obs[e], enc.encode(refs[e])), rules, t,
                    "the observation")
    return totals


# ---------------------------------------------------------------- the batched features
def check_features(rules: Rules, *, compiled: bool, steps: int, seed: int = 0,
                   noise: float = 0.25, n_envs: int = 2, shaping: Any = None,
                   team: bool = True, coef: float = 0.75) -> float:
    """The batched RL features and shaped rewards (``rl/fast``) against ``FeatureEncoder``
    and ``RewardShaper`` on the reference states, bit for bit, at every step; returns the
    summed absolute shaping of the reference (so a caller can check shaping happened)."""
    from ..rl.fast.features_batch import BatchFeatures
    from ..rl.features import FeatureEncoder
    from ..rl.shaping import RewardShaper, Shaping
    from ..sim.fast.batch import BatchSim

    shaping = Shaping() if shaping is None else shaping
    sim = BatchSim(rules, n_envs, seed=seed, compiled=compiled, observe=False)
    sim.reset()
    feats = BatchFeatures(sim, shaping)
    feats.reset(np.arange(n_envs))
    enc = FeatureEncoder(rules)
    refs = [new_state(rules, int(sim.seeds[e])) for e in range(n_envs)]
    shapers = [RewardShaper(shaping) for _ in range(n_envs)]
    cooks = [GreedyAgent(seed + e) for e in range(n_envs)]
    for e in range(n_envs):
        shapers[e].reset(refs[e])
        cooks[e].reset(refs[e])
    rng = np.random.default_rng(seed)
    shaped_total = 0.0
    for t in range(steps):
        obs = feats.encode()
        for e in range(n_envs):
            _expect(obs[e].tobytes() == enc.encode_all(refs[e]).tobytes(), rules, t,
                    "the features")
        acts = _acts(cooks, refs, rng, noise)
        terminated, truncated = sim.step_active(acts)
        reward = feats.rewards(coef, team)
        for e in range(n_envs):
            res = transition(refs[e], acts[e].tolist())
            true, shaped = shapers[e].step(refs[e], res.events, res.rewards)
            mixed = [(sum(true) if team else r) + coef * x for r, x in zip(true, shaped)]
            _expect(reward[e].tolist() == mixed, rules, t, "the shaped reward")  # exactly
            shaped_total += sum(abs(x) for x in shaped)
            if res.terminated or res.truncated:
                _expect(bool(terminated[e] or truncated[e]), rules, t, "the episode end")
                _expect(feats.encode()[e].tobytes() == enc.encode_all(refs[e]).tobytes(),
                        rules, t, "the final features")
                sim.reset_envs(np.array([e]))
                feats.reset(np.array([e]))
                refs[e] = new_state(rules, int(sim.seeds[e]))
                shapers[e].reset(refs[e])
                cooks[e].reset(refs[e])
    return shaped_total


# ---------------------------------------------------------------- the JAX kitchen
class _Draws:
    """Stands in for the reference's order generator: order number k gets the recipe the
    JAX kitchen draws for it (``order_draw``)."""

    def __init__(self, state: State, key: Any, n_recipes: int) -> None:
        from ..sim.fast import jax_kitchen as jk

        self.state = state
        ids = jk.jnp.arange(512)
        self.table = np.asarray(jk.jax.vmap(lambda k: jk.order_draw(key, k, n_recipes))(ids))

    def integers(self, n: int) -> int:
        return int(self.table[self.state.next_order_id])


def reference_state(rules: Rules, key: Any) -> State:
    """``new_state`` whose orders come from the JAX kitchen's draws for ``key``."""
    s = new_state(rules, 0)
    s.orders, s.next_order_id = [], 0
    s.rng = _Draws(s, key, len(rules.recipes))  # type: ignore[assignment]
    for _ in range(rules.n_orders):
        draw_order(s)
    return s


def as_reference(js: Any, e: int, rules: Rules) -> dict:
    """Kitchen ``e`` of a batched JAX state, in the reference's indexing."""
    from ..sim.fast import jax_kitchen as jk

    geo = geometry_for(rules)
    cols, n = geo.cols, len(geo.item_kind)

    def unpad(flat: int) -> int:
        return (flat // jk.GRID) * cols + flat % jk.GRID

    pad = [jk.pad_cell(f, cols) for f in range(geo.rows * cols)]
    where = js.item_where[e][:n].tolist()
    loc = [unpad(v) if w in (Where.CELL, Where.WAITING) else v
           for w, v in zip(where, js.item_loc[e][:n].tolist())]
    orders = list(zip(*(x[e].tolist() for x in (js.order_id, js.order_recipe,
                                                 js.order_created, js.order_deadline))))
    return dict(
        agent_pos=[unpad(v) for v in js.pos[e].tolist()], agent_hand=js.hand[e].tolist(),
        cell_item=js.cell_item[e][pad].tolist(), item_state=js.item_state[e][:n].tolist(),
        item_progress=js.item_prog[e][:n].tolist(), item_where=where, item_loc=loc,
        item_agent=js.item_owner[e][:n].tolist(), t=int(js.t[e]), layout=int(js.layout[e]),
        next_switch=int(js.next_switch[e]), next_order_id=int(js.next_order_id[e]),
        orders=orders, stats=dict(zip(jk.STAT_NAMES, js.stats[e].tolist())))


def of_reference(s: State) -> dict:
    """The reference state as :func:`as_reference` lists it."""
    rules = s.rules
    return dict(
        agent_pos=s.agent_pos, agent_hand=s.agent_hand, cell_item=s.cell_item,
        item_state=s.item_state, item_progress=s.item_progress, item_where=s.item_where,
        item_loc=s.item_loc, item_agent=s.item_agent, t=s.t, layout=s.layout_index,
        next_switch=s.next_switch, next_order_id=s.next_order_id,
        orders=[(o.order_id, rules.recipes.index(o.recipe), o.created, o.deadline)
                for o in s.orders], stats=s.stats)


def crop(obs: np.ndarray, rules: Rules, radius: int, padded: bool) -> np.ndarray:
    """A padded whole-grid observation cut to the map's own cells (a window: as it is)."""
    from ..sim.fast import jax_kitchen as jk
    from ..sim.fast.jax_observe import N_CHANNELS

    if radius or not padded:
        return obs
    rows, cols = rules.layout.shape
    cells = jk.GRID * jk.GRID
    grid = obs[:, : N_CHANNELS * cells].reshape(-1, N_CHANNELS, jk.GRID, jk.GRID)
    return np.concatenate([grid[:, :, :rows, :cols].reshape(len(obs), -1),
                           obs[:, N_CHANNELS * cells:]], 1)


_JITTED: dict[str, Any] = {}


def _jitted() -> dict[str, Any]:
    """The vmapped, jitted step and reset (with observations), made once."""
    if not _JITTED:
        from ..sim.fast import jax_kitchen as jk
        from ..sim.fast.jax_observe import observe

        jax = jk.jax

        def step(states: Any, actions: Any) -> Any:
            out = jax.vmap(jk.step, (None, 0, 0))(None, states, actions)
            return out, jax.vmap(observe)(out.state)

        def reset(keys: Any, params: Any) -> Any:
            s = jax.vmap(jk.reset)(keys, params)
            return s, jax.vmap(observe)(s)

        _JITTED.update(step=jax.jit(step), reset=jax.jit(reset))
    return _JITTED


def check_jax(rules_list: Sequence[Rules], *, steps: int, seed: int = 0, noise: float = 0.25,
              radius: int = 0, batch: int = 4, padded: bool = True, max_items: int = 8,
              max_recipes: int = 12) -> dict[str, int]:
    """The JAX kitchen: ``batch`` kitchens cycling through ``rules_list`` in one vmapped
    batch (``padded``: one padded shape of ``max_items`` / ``max_recipes`` and the padded
    whole-grid view, so kitchens of every size share one compilation)."""
    from ..sim.fast import jax_kitchen as jk

    jax, fns = jk.jax, _jitted()
    rules_list = [rules_list[e % len(rules_list)] for e in range(batch)]
    params = jk.stack_params([
        jk.kitchen_params(r, radius, max_items=max_items, max_recipes=max_recipes,
                          padded_view=True) if padded else jk.kitchen_params(r, radius)
        for r in rules_list])
    keys = jax.random.split(jax.random.PRNGKey(seed), batch)
    js, _ = fns["reset"](keys, params)
    refs = [reference_state(r, keys[e]) for e, r in enumerate(rules_list)]
    encs = [VectorEncoder(r, radius) for r in rules_list]
    cooks = [GreedyAgent(seed + e) for e in range(batch)]
    for e in range(batch):
        cooks[e].reset(refs[e])
    rng = np.random.default_rng(seed)
    totals: dict[str, int] = {}
    episode = 0
    for t in range(steps):
        acts = _acts(cooks, refs, rng, noise)
        out, obs = fns["step"](js, acts)
        js, host, obs = out.state, jax.device_get(out), np.asarray(obs)
        for e, rules in enumerate(rules_list):
            res = transition(refs[e], acts[e].tolist())
            _expect(np.allclose(host.rewards[e], res.rewards, rtol=1e-5, atol=1e-4), rules, t,
                    "the rewards")
            _expect((bool(host.terminated[e]), bool(host.truncated[e])) == (
                res.terminated, res.truncated), rules, t, "the episode end")
            _expect(as_reference(host.state, e, rules) == of_reference(refs[e]), rules, t,
                    "the state")
            # XLA may divide by a loop-invariant divisor through its reciprocal: the
            # normalised features (time, position, progress) may differ in the last bit
            _expect(np.allclose(crop(obs[e], rules, radius, padded), encs[e].encode(refs[e]),
                                rtol=3e-7, atol=0), rules, t, "the observation")
            if res.terminated or res.truncated:
                _add(totals, refs[e])
                episode += 1
                new_keys = jax.random.split(jax.random.PRNGKey(seed + 1000 * episode), batch)
                fresh, _ = fns["reset"](new_keys, params)
                js = jax.tree_util.tree_map(lambda b, o, e=e: b.at[e].set(o[e]), js, fresh)
                refs[e] = reference_state(rules, new_keys[e])
                cooks[e].reset(refs[e])
                _expect(as_reference(jax.device_get(js), e, rules) == of_reference(refs[e]),
                        rules, t, "the state after a reset")
    return totals


__all__ = ["MIRRORS", "MirrorMismatch", "as_reference", "check_batch", "check_features",
           "check_jax", "check_mirror", "crop", "kitchens", "of_reference", "random_kitchens",
           "reference_state"]
