"""Train the PPO baseline: :class:`TrainConfig` in, a checkpoint directory out.

Output directory layout::

    OUT/policy.npz             final checkpoint, weights only (rl/weights.py): what
                               ``ppo:OUT/policy.npz`` and ``--init`` read
    OUT/policy.zip             the same as an SB3 zip + ocplus_meta.json (it pickles the
                               optimizer and schedules too; loading it runs code, so it is
                               read only with --trust-pickled-checkpoint)
    OUT/checkpoints/step_*.npz periodic checkpoints (and step_*.zip beside them)
    OUT/episodes.csv           one row per finished kitchen episode (game reward, dishes)
    OUT/train.json             the configuration, the command, wall time and throughput

``timesteps`` everywhere count agent-steps (one per agent per kitchen step), the unit
stable-baselines3 counts; with one agent they are kitchen steps.
"""

from __future__ import annotations

import json
import platform
import sys
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from ..errors import ConfigError
from ..sim.rules import Rules, make_rules
from .imitation import Imitation, Teacher, pretrain
from .lean import PRECISIONS
from .kitchens import curriculum_stages, distribution_rules, parse_maps
from .obs import DEFAULT_WINDOW, OBS_KINDS
from .policy import load_policy, require_rl, write_meta
from .shaping import Shaping
from .weights import WeightsPolicy, pickled_trusted, refuse_pickled, save_weights


ALGOS = ("sb3", "lean")
#: the controllers ``--partner`` may name (scripted: cheap enough to act at every step)
PARTNERS = ("greedy", "random", "stay")


def parse_partner(text: str) -> tuple[str, float]:
    """``"greedy:0.5"`` -> ``("greedy", 0.5)``: the partner and the share of the kitchens
    where it plays the last cook. Refuses anything else, naming the form it takes."""
    usage = (f"write AGENT:SHARE, the agent one of {', '.join(PARTNERS)} and SHARE the "
             "fraction of the kitchens (0 < SHARE <= 1) where it plays the last cook, "
             "e.g. greedy:0.5")
    name, sep, share = text.partition(":")
    if not sep or name not in PARTNERS:
        raise ConfigError(f"--partner {text!r}: {usage}")
    try:
        value = float(share)
    except ValueError:
        value = float("nan")
    if not 0.0 < value <= 1.0:  # also refuses nan
        raise ConfigError(f"--partner {text!r}: the share must be in (0, 1]; {usage}")
    return name, value


@dataclass(frozen=True)
class TrainConfig:
    """Everything a training run depends on (defaults tuned on 2 shared CPU cores)."""

    preset: str = "easy"
    n_agents: int | None = None
    map: str | None = None
    #: a kitchen distribution (rl/kitchens.py): ``gen:FAMILY:SPLIT:A-B[,...]``; each
    #: episode draws one of its kitchens (exclusive with ``map`` and ``curriculum``)
    maps: str | None = None
    #: with ``maps``: grow the pool from the smallest kitchens to all of them in this many
    #: stages over the first ``curriculum_fraction`` of training (1: no curriculum)
    map_stages: int = 1
    steps: int = 300_000
    seed: int = 0
    out: str = "runs/ppo"
    #: "features", "grid", "window", "tasks" (features + what the orders still lack, loop
    #: engine), or "auto": window (radius 2) with ``maps``, else features
    obs: str = "auto"
    obs_radius: int = 0
    n_kitchens: int = 8
    n_steps: int = 128
    batch_size: int = 512
    n_epochs: int = 8
    learning_rate: float = 5e-4
    gamma: float = 0.99
    gae_lambda: float = 0.95
    ent_coef: float = 0.02
    hidden: tuple[int, ...] = (128, 128)
    reward_scale: float = 0.02
    team_reward: bool = True
    anneal_fraction: float = 0.8
    shaping: Shaping = field(default_factory=Shaping)
    curriculum: tuple[str, ...] = ()
    curriculum_fraction: float = 0.3
    init: str | None = None
    checkpoint_every: int | None = None
    #: "batch" (the batched engine, numba), "loop" (per-kitchen ``transition``, the
    #: reference) or "auto": batch when the ``fast`` extra is installed, else loop. Same
    #: observations and rewards either way.
    engine: str = "auto"
    #: torch's CPU threads, and the batched engine's (it splits 256+ kitchens over them)
    torch_threads: int = 1
    #: stop (and save) after this many seconds of training; None = no limit
    max_wall_s: float | None = None
    #: behaviour-cloning warm start (rl/imitation.py): the teacher's name (the caller
    #: passes its factory to :func:`train`), kitchen steps per round, DAgger rounds, epochs
    bc: str | None = None
    bc_steps: int = 100_000
    bc_rounds: int = 1
    bc_epochs: int = 8
    #: cross-entropy weight of a DAgger sample the learner's argmax missed (1: plain DAgger)
    bc_focus: float = 1.0
    #: "sb3" (stable-baselines3's PPO.learn) or "lean" (rl/lean.py: the same PPO and
    #: network in a torch loop over the batched kitchens); both save the same checkpoint
    algo: str = "sb3"
    #: the lean loop's matrix products: "fp32" or "bf16" (autocast; weights stay float32)
    precision: str = "fp32"
    #: continue this checkpoint's run (a ``policy.zip`` or ``checkpoints/step_*.zip``): its
    #: weights, Adam state and step count, so the learning-rate schedule, the shaping anneal
    #: and the checkpoints go on where they stopped
    resume: str | None = None
    #: also log SB3's training metrics as TensorBoard event files in this folder (the
    #: ``tensorboard`` extra)
    tensorboard: str | None = None
    #: torch device of the SB3 trainer: "cpu", "cuda", "cuda:N" or "auto" (cuda when
    #: torch sees one); the lean loop runs on the CPU
    device: str = "cpu"
    #: ``AGENT:SHARE`` (e.g. ``greedy:0.5``): in that share of the kitchens (the first
    #: ``round(SHARE * n_kitchens)``) the agent plays the last cook, whose steps are not
    #: samples; in the rest the policy plays every cook (the caller passes the factory)
    partner: str | None = None

    def __post_init__(self) -> None:
        if self.obs == "auto":
            object.__setattr__(self, "obs", "window" if self.maps else "features")
        if self.obs == "window" and self.obs_radius == 0:
            object.__setattr__(self, "obs_radius", DEFAULT_WINDOW)
        if self.engine == "auto":
            from ..sim.fast.batch import numba_available

            batch = numba_available() and self.obs not in ("tasks", "choice") \
                and self.partner is None
            object.__setattr__(self, "engine", "batch" if batch else "loop")

    def validate(self) -> None:
        for name in ("steps", "n_kitchens", "n_steps", "batch_size", "n_epochs"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise ConfigError(f"{name} must be a positive integer, got {v!r}")
        if self.obs not in OBS_KINDS:
            raise ConfigError(f"obs must be one of {', '.join(OBS_KINDS)}, got {self.obs!r}")
        if not 0.0 <= self.anneal_fraction <= 1.0:
            raise ConfigError(f"anneal_fraction must be in [0, 1], got {self.anneal_fraction}")
        if not 0.0 <= self.curriculum_fraction < 1.0:
            raise ConfigError(
                f"curriculum_fraction must be in [0, 1), got {self.curriculum_fraction}"
            )
        if self.engine not in ("loop", "batch"):
            raise ConfigError(f"engine must be 'loop', 'batch' or 'auto', got {self.engine!r}")
        if self.engine == "batch" and self.obs in ("tasks", "choice"):
            raise ConfigError("the batched engine computes the path features only: train "
                              f"obs {self.obs!r} with --engine loop (or auto)")
        if self.obs == "choice" and (self.bc is not None or self.algo != "sb3"):
            raise ConfigError("obs 'choice' (a policy choosing subtasks) trains with PPO "
                              "(--algo sb3) from scratch or --init: --bc clones moves, not "
                              "choices; drop --bc and --algo lean")
        if isinstance(self.torch_threads, bool) or not isinstance(self.torch_threads, int) \
                or self.torch_threads < 1:
            raise ConfigError(
                f"torch_threads must be a positive integer, got {self.torch_threads!r}"
            )
        if self.max_wall_s is not None and self.max_wall_s <= 0:
            raise ConfigError(f"max_wall_s must be positive seconds, got {self.max_wall_s}")
        if not self.hidden or any(h < 1 for h in self.hidden):
            raise ConfigError(f"hidden layer sizes must be positive, got {self.hidden}")
        if self.init is not None and not self.init.endswith(".npz") and not pickled_trusted():
            raise refuse_pickled(self.init)
        if self.resume is not None and not pickled_trusted():  # an SB3 zip: optimiser state
            raise refuse_pickled(self.resume)
        if self.bc is not None:
            self.imitation().validate()
        if self.partner is not None:
            self._validate_partner()
        if self.resume is not None and (self.init or self.bc or self.curriculum
                                        or self.map_stages > 1 or self.algo != "sb3"):
            raise ConfigError("resume continues a plain sb3 run: drop init, bc, the curricula "
                              "and --algo lean (they belong to the run being resumed)")
        if self.maps is not None and (self.map is not None or self.curriculum):
            raise ConfigError("maps (a kitchen distribution) replaces map and curriculum: "
                              "give one of them")
        if isinstance(self.map_stages, bool) or not isinstance(self.map_stages, int) \
                or self.map_stages < 1:
            raise ConfigError(f"map_stages must be a positive integer, got {self.map_stages!r}")
        if self.algo not in ALGOS:
            raise ConfigError(f"algo must be one of {', '.join(ALGOS)}, got {self.algo!r}")
        if self.precision not in PRECISIONS:
            raise ConfigError(
                f"precision must be one of {', '.join(PRECISIONS)}, got {self.precision!r}")
        if not (self.device in ("cpu", "cuda", "auto") or self.device.startswith("cuda:")):
            raise ConfigError(f"device must be cpu, cuda, cuda:N or auto, got {self.device!r}")
        if self.device != "cpu" and self.algo == "lean":
            raise ConfigError(f"device {self.device!r} needs algo 'sb3' (the lean loop runs on "
                              "the CPU): drop --algo lean or use --device cpu")
        if self.precision != "fp32" and self.algo != "lean":
            raise ConfigError(f"precision {self.precision!r} needs algo 'lean' (the SB3 "
                              "trainer computes in float32): add --algo lean")

    def partner_kitchens(self) -> int:
        """The kitchens where the partner plays the last cook (0 without ``partner``)."""
        return 0 if self.partner is None else round(parse_partner(self.partner)[1]
                                                        * self.n_kitchens)

    def _validate_partner(self) -> None:
        """``partner`` goes with PPO on the loop engine with 2 cooks or more, not with the
        paths it does not reach (cloning, resuming, the lean loop)."""
        if self.partner_kitchens() < 1:
            raise ConfigError(f"--partner {self.partner!r} with {self.n_kitchens} kitchens "
                              "gives the partner no kitchen: raise the share or --n-kitchens")
        if self.n_agents is not None and self.n_agents < 2:
            raise ConfigError("--partner plays the last cook beside the learner's: it needs "
                              f"--n-agents 2 or more, got {self.n_agents}")
        if self.engine != "loop":
            raise ConfigError("--partner acts on the simulator's state: it needs --engine loop "
                              f"(or auto), not {self.engine!r}")
        for flag, used, how in (
                ("--bc", self.bc is not None, "clone without a partner first, then run PPO "
                 "from the clone: --init OUT/bc_policy.npz --partner ..."),
                ("--resume-from", self.resume is not None, "start a partner run afresh, "
                 "e.g. --init OUT/policy.npz"),
                ("--algo lean", self.algo != "sb3", "a partner run uses --algo sb3")):
            if used:
                raise ConfigError(f"--partner does not go with {flag}: {how}")

    def imitation(self) -> Imitation:
        """The behaviour-cloning settings of this run (meaningful when ``bc`` is set)."""
        return Imitation(self.bc_steps, self.bc_rounds, self.bc_epochs, focus=self.bc_focus)


def _rules(config: TrainConfig, preset: str, with_map: bool) -> Rules:
    """Training rules for ``preset`` or, in a curriculum, ``PRESET:RECIPE/RECIPE...`` (the
    preset's kitchen with only those recipes, e.g. ``medium:steak/tomato``)."""
    kw: dict[str, Any] = {"reward_mode": "individual"}
    preset, _, recipes = preset.partition(":")
    if recipes:
        kw["recipes"] = [r for r in recipes.split("/") if r]
    if config.n_agents is not None:
        kw["n_agents"] = config.n_agents
    return make_rules(preset, map=config.map if with_map else None, **kw)


def _pool(config: TrainConfig) -> list[Rules]:
    """The kitchens of ``config.maps`` as training rules (empty without ``maps``)."""
    if config.maps is None:
        return []
    kw: dict[str, Any] = {"reward_mode": "individual"}
    if config.n_agents is not None:
        kw["n_agents"] = config.n_agents
    return distribution_rules(parse_maps(config.maps, config.preset), config.preset, **kw)


def _lr_schedule(initial: float):
    def schedule(progress_remaining: float) -> float:
        # linear decay to 10 % of the initial rate: late updates refine, not rewrite
        return initial * (0.1 + 0.9 * progress_remaining)

    return schedule


def build(config: TrainConfig, partner: Callable[[int], Any] | None = None,
          chooser: Any = None) -> tuple[Any, Any, list[Rules], Rules]:
    """The PPO model and its vec env for ``config`` (no training yet): ``(model, venv,
    curriculum stages, target rules)``; ``partner`` (``seed -> Controller``) with
    ``config.partner``, ``chooser`` (the task-choice controller's class) with
    ``obs="choice"``. Also used by experiments/bench_train.py."""
    config.validate()
    if config.partner is not None and partner is None:
        raise ConfigError(f"partner={config.partner!r} needs the partner's factory "
                          "(train(..., partner=))")
    if config.obs == "choice" and chooser is None:
        raise ConfigError("obs 'choice' needs the task-choice controller (train(..., "
                          "chooser=TaskChoice): ocplus train passes it)")
    pool = _pool(config)
    target = pool[0] if pool else _rules(config, config.preset, with_map=True)
    stages = [_rules(config, p, with_map=config.map is not None) for p in config.curriculum]
    require_rl()
    if config.tensorboard:
        import importlib.util

        from ..errors import DependencyNotInstalled

        if importlib.util.find_spec("tensorboard") is None:
            raise DependencyNotInstalled("--tensorboard needs the tensorboard package: pip "
                                         "install 'ocplus-plan[tensorboard]'")
    import torch
    from stable_baselines3 import PPO

    from .vec_env import KitchenVecEnv

    torch.set_num_threads(config.torch_threads)
    torch.manual_seed(config.seed)
    if config.device.startswith("cuda") and not torch.cuda.is_available():
        raise ConfigError(f"device {config.device!r}: torch sees no CUDA device here; "
                          "use --device cpu (or auto)")
    venv = KitchenVecEnv(
        pool or ([target, *stages] if stages else target), config.n_kitchens, config.seed,
        obs=config.obs, obs_radius=config.obs_radius, shaping=config.shaping,
        team_reward=config.team_reward, reward_scale=config.reward_scale, engine=config.engine,
        threads=config.torch_threads, draw=bool(pool),
        partner=partner, partner_kitchens=config.partner_kitchens(),
        chooser=chooser if config.obs == "choice" else None,
    )
    venv.rule_labels = {id(r): spec for r, spec in zip(stages, config.curriculum)}
    venv.rule_labels[id(target)] = config.preset
    n_slots = venv.num_envs
    batch = min(config.batch_size, n_slots * config.n_steps)
    model = PPO(
        "MlpPolicy", venv,
        learning_rate=_lr_schedule(config.learning_rate),
        n_steps=config.n_steps, batch_size=batch, n_epochs=config.n_epochs,
        gamma=config.gamma, gae_lambda=config.gae_lambda, ent_coef=config.ent_coef,
        policy_kwargs={"net_arch": {"pi": list(config.hidden), "vf": list(config.hidden)}},
        seed=config.seed, device=config.device, verbose=0,
    )
    return model, venv, stages, target


def train(config: TrainConfig, *, command: str | None = None, progress: bool = True,
          teacher: Teacher | None = None, partner: Callable[[int], Any] | None = None,
          chooser: Any = None) -> dict:
    """Run one training; return the summary that is also written to ``OUT/train.json``.
    With ``config.bc``, ``teacher`` (``seed -> Controller``) is behaviour-cloned first
    (``OUT/bc_policy.zip`` keeps the imitation-only policy), then PPO continues. With
    ``config.partner``, ``partner`` (``seed -> Controller``) plays the last cook of its
    share of the kitchens; with ``obs="choice"``, ``chooser`` (the task-choice controller's
    class) turns the policy's subtask choices into moves."""
    if config.bc is not None and teacher is None:
        raise ConfigError(f"bc={config.bc!r} needs the teacher's factory (train(..., teacher=))")
    model, venv, stages, target = build(config, partner, chooser)
    import torch

    from .callbacks import TrainingMonitor

    out = Path(config.out)
    (out / "checkpoints").mkdir(parents=True, exist_ok=True)
    # SB3's default logger makes an empty tempdir/SB3-<date> folder on every learn(): log
    # nowhere, into the run's own folder (the monitor writes episodes.csv itself)
    from stable_baselines3.common.logger import configure

    model.set_logger(configure(config.tensorboard or str(out),
                               ["tensorboard"] if config.tensorboard else []))
    if config.init:
        _start_from(model, venv, config)
    start_steps = _resume(model, venv, config) if config.resume else 0

    meta_base = {
        "obs": config.obs, "obs_radius": config.obs_radius, "obs_size": venv.obs_size,
        "preset": config.preset, "map": config.maps or target.layout.name,
        "n_agents": target.n_agents, "act": "sample",
        **({"maps": config.maps, "kitchens": len(venv.rule_list)} if config.maps else {}),
        **({"partner": config.partner} if config.partner else {}),
    }
    t0 = time.perf_counter()

    def save(path: Path, timesteps: int) -> None:
        path.parent.mkdir(parents=True, exist_ok=True)
        model.save(str(path))
        meta = {**meta_base, "train": {
            "timesteps": timesteps, "seed": config.seed, "command": command,
            "wall_time_s": round(time.perf_counter() - t0, 1),
            **({"bc": config.bc} if config.bc else {}), "algo": config.algo}}
        write_meta(path, meta)
        save_weights(path.with_suffix(".npz"), model.policy.state_dict(), meta)

    imitation = None
    if config.bc is not None:
        rounds = pretrain(
            model, list(venv.rule_list) if config.maps else target, config.obs, config.obs_radius, teacher, config.imitation(),
            seed=config.seed, gamma=config.gamma, reward_scale=config.reward_scale,
            team_reward=config.team_reward,
        )
        imitation = {"teacher": config.bc, "rounds": rounds,
                     "wall_time_s": round(time.perf_counter() - t0, 1),
                     "policy": str(out / "bc_policy.npz")}
        save(out / "bc_policy.zip", 0)

    learner = model
    if config.algo == "lean":
        from .lean import LeanPPO

        learner = LeanPPO(model, venv, config.precision, config.seed)
    every = config.checkpoint_every or max(config.steps // 5, 1)
    monitor = TrainingMonitor(
        venv, config.steps, out, anneal_fraction=config.anneal_fraction,
        checkpoint_every=every, save=save, stream=sys.stderr if progress else None,
        max_wall_s=config.max_wall_s,
    )
    monitor._next_checkpoint = (model.num_timesteps // every + 1) * every
    try:
        _learn(learner, venv, config, monitor, stages, target)
    finally:
        monitor.close()
    wall = time.perf_counter() - t0
    save(out / "policy.zip", model.num_timesteps)
    summary = {
        "command": command,
        "config": {k: (list(v) if isinstance(v, tuple) else v)
                   for k, v in asdict(config).items()},
        "timesteps": model.num_timesteps,
        **({"resumed_from_timesteps": start_steps} if config.resume else {}),
        "stopped_by_wall_budget": monitor.out_of_time,
        "episodes": monitor.episodes,
        "dishes_per_episode_last50": (
            round(sum(monitor.recent) / len(monitor.recent), 3) if monitor.recent else None
        ),
        "wall_time_s": round(wall, 1),
        "steps_per_s": own_speed(model.num_timesteps, start_steps, wall, imitation),
        "imitation": imitation,
        "policy": str(out / "policy.npz"),
        # where the lean loop's time went (rl/lean.py); SB3 does not split its own
        **({"seconds": {k: round(v, 2) for k, v in learner.seconds.items()}}
           if config.algo == "lean" else {}),
        "machine": {"python": platform.python_version(), "cpus": _cpus(),
                    "torch_threads": torch.get_num_threads(), "device": str(model.device)},
    }
    (out / "train.json").write_text(json.dumps(summary, indent=2) + "\n")
    return summary


def _learn(learner: Any, venv: Any, config: TrainConfig, monitor: Any, stages: list[Rules],
           target: Rules) -> None:
    """PPO for ``config.steps``: through the kitchen curriculum, the preset curriculum
    (``stages``, then ``target``), or plainly."""
    if config.maps and config.map_stages > 1:
        _learn_widening(learner, venv, config, monitor)
    elif stages:
        switch = int(config.steps * config.curriculum_fraction)
        if switch:
            learner.learn(switch, callback=monitor)
        venv.set_rules(target)
        if not monitor.out_of_time:
            learner.learn(config.steps - switch, callback=monitor, reset_num_timesteps=False)
    else:
        done = learner.num_timesteps if config.resume else 0
        learner.learn(max(config.steps - done, 1), callback=monitor,
                      reset_num_timesteps=not config.resume)


def _learn_widening(learner: Any, venv: Any, config: TrainConfig, monitor: Any) -> None:
    """The kitchen curriculum: the pools of :func:`curriculum_stages`, each for an equal
    share of the first ``curriculum_fraction`` of training, then every kitchen."""
    pools = curriculum_stages(list(venv.rule_list), config.map_stages)
    share = int(config.steps * config.curriculum_fraction) // (len(pools) - 1)
    done = 0
    for k, pool in enumerate(pools):
        steps = share if k < len(pools) - 1 else config.steps - done
        venv.set_rules(pool)
        if steps > 0 and not monitor.out_of_time:
            learner.learn(steps, callback=monitor, reset_num_timesteps=k == 0)
        done += steps


def _start_from(model: Any, venv: Any, config: TrainConfig) -> None:
    """Load ``config.init``'s weights into ``model`` (same observations and shapes)."""
    import numpy as np
    import torch

    if config.init.endswith(".npz"):
        source: Any = WeightsPolicy(config.init)
        state = {k: torch.as_tensor(np.array(v)) for k, v in source.tensors.items()}
    elif pickled_trusted():
        source = load_policy(config.init)
        state = source.model.policy.state_dict()
    else:
        raise refuse_pickled(config.init)
    torch.set_num_threads(config.torch_threads)  # load_policy's require_rl reset it
    if source.meta["obs"] != config.obs or source.meta["obs_size"] != venv.obs_size:
        raise ConfigError(
            f"--init {config.init}: its observations ({source.meta['obs']}, "
            f"{source.meta['obs_size']}) differ from this run's ({config.obs}, {venv.obs_size})"
        )
    try:
        model.policy.load_state_dict(state)
    except RuntimeError as exc:
        raise ConfigError(f"--init {config.init}: network shapes differ ({exc})") from exc


def _resume(model: Any, venv: Any, config: TrainConfig) -> int:
    """Load ``config.resume``'s weights, Adam state and step count into ``model``; returns
    the step count."""
    from stable_baselines3.common.save_util import load_from_zip_file

    meta = load_policy(config.resume).meta
    if meta["obs"] != config.obs or meta["obs_size"] != venv.obs_size:
        raise ConfigError(f"--resume-from {config.resume}: its observations ({meta['obs']}, "
                          f"{meta['obs_size']}) differ from this run's ({config.obs}, "
                          f"{venv.obs_size}); resume with the run's own options")
    data, _, _ = load_from_zip_file(config.resume, device=model.device)
    try:
        model.set_parameters(config.resume, exact_match=True, device=model.device)
    except (RuntimeError, ValueError) as exc:
        raise ConfigError(f"--resume-from {config.resume}: network shapes differ ({exc})") from exc
    model.num_timesteps = int(data["num_timesteps"])
    if model.num_timesteps >= config.steps:
        raise ConfigError(f"--resume-from {config.resume}: it has {model.num_timesteps} steps "
                          f"already; raise --timesteps above that")
    return model.num_timesteps


def own_speed(timesteps: int, start: int, wall: float, imitation: dict | None) -> float:
    """Agent-steps a second of PPO: the steps this run made (a resumed run's earlier ones
    are not its speed) over its wall time less the imitation warm start's."""
    return round((timesteps - start) / (wall - (imitation or {}).get("wall_time_s", 0.0)), 1)


def _cpus() -> int:
    import os

    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 0


__all__ = ["ALGOS", "PARTNERS", "TrainConfig", "build", "own_speed", "parse_partner", "train"]
