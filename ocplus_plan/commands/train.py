"""``ocplus train``: train the parameter-shared PPO baseline (needs the ``rl`` extra).

Writes OUT/policy.npz, weights only (use it as ``--agents ppo:OUT/policy.npz``; the SB3
OUT/policy.zip beside it is a pickle that runs code when loaded), periodic checkpoints in
OUT/checkpoints/, OUT/episodes.csv (game reward and dishes served per episode, against
training steps) and OUT/train.json (configuration, command, wall time).
"""

from __future__ import annotations

import argparse
import functools
import shlex
import sys

from . import _types
from ._common import (
    HelpFormatter,
    add_deprecated_alias,
    add_kitchen_args,
    add_output_args,
    add_trust_arg,
    emit,
)

_POSITIVE = _types.whole("the value", 1)
_FRACTION = _types.number("a fraction", 0.0, 1.0, lo_open=False)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "train", help="train the PPO baseline (rl extra)", description=__doc__,
        formatter_class=HelpFormatter,
        epilog="example: ocplus train --preset easy --timesteps 600000 --seed 0 --out runs/easy\n"
               "(one shared policy drives every cook)",
    )
    add_kitchen_args(p, horizon=False, rules=False)
    p.add_argument("--timesteps", dest="steps", type=_POSITIVE, default=300_000,
                   help="training agent-steps (one per agent per kitchen step)")
    add_deprecated_alias(p, "--steps", "--timesteps", takes_value=True, dest="steps",
                         type=_POSITIVE)
    g = p.add_argument_group("learning")
    g.add_argument("--maps", default=None, metavar="KITCHENS",
                   help="train on a kitchen distribution, a new kitchen drawn per episode: "
                        "comma-separated gen:FAMILY:SPLIT:A-B ranges or map names, e.g. "
                        "gen:open:train:0-19,gen:split:train:0-19 (replaces --map)")
    g.add_argument("--map-stages", type=_POSITIVE, default=1,
                   help="with --maps: a curriculum that widens the pool from the smallest "
                        "kitchens to all in this many stages over --curriculum-fraction")
    g.add_argument("--obs", default="auto",
                   choices=("auto", "features", "grid", "window", "tasks", "choice"),
                   help="features: egocentric paths; grid: SPEC one-hot grid; window: features "
                        "+ a grid window (one size on every map); tasks: features + what orders "
                        "still lack (loop engine); choice: tasks + the subtasks a free cook may "
                        "take, and the actions choose one (the greedy cook's skills do the "
                        "moves; loop engine); auto: window with --maps, else features")
    g.add_argument("--obs-radius", type=_types.whole("--obs-radius", 0, 64), default=0,
                   help="grid window radius (0 = whole map; window observations: 0 means 2)")
    g.add_argument("--n-kitchens", type=_types.whole("--n-kitchens", 1, 65536), default=8,
                   help="kitchens simulated in parallel")
    g.add_argument("--n-steps", type=_POSITIVE, default=128, help="rollout length per agent slot")
    g.add_argument("--batch-size", type=_POSITIVE, default=512)
    g.add_argument("--n-epochs", type=_POSITIVE, default=8)
    g.add_argument("--lr", type=_types.number("--lr", 0.0, 1.0), default=5e-4,
                   help="initial learning rate (decays to 10%%)")
    g.add_argument("--ent-coef", type=_FRACTION, default=0.02)
    g.add_argument("--gamma", type=_types.number("--gamma", 0.0, 1.0), default=0.99)
    g.add_argument("--hidden", default="128,128", help="hidden layer sizes, comma-separated")
    g.add_argument("--anneal-fraction", type=_FRACTION, default=0.8,
                   help="fraction of training after which the shaping reward is 0")
    g.add_argument("--individual-reward", action="store_true",
                   help="each agent learns from its own rewards (default: the team's sum)")
    g.add_argument("--curriculum", default="",
                   help="comma-separated presets mixed in for the first --curriculum-fraction; "
                        "PRESET:R1/R2 restricts a preset's kitchen to those recipes, e.g. "
                        "medium:steak/tomato (one-ingredient orders teach the pan)")
    g.add_argument("--curriculum-fraction", type=_FRACTION, default=0.3)
    _jax_options(g)
    g.add_argument("--init", default=None,
                   help="start from this checkpoint's weights (a .npz; an SB3 .zip needs "
                        "--trust-pickled-checkpoint)")
    g.add_argument("--resume-from", dest="resume", default=None, metavar="CHECKPOINT",
                   help="continue a run from its policy.zip or checkpoints/step_*.zip: weights, "
                        "optimiser state and step count (the schedules go on from there); the "
                        "zip pickles, so it needs --trust-pickled-checkpoint")
    g.add_argument("--tensorboard", default=None, metavar="DIR",
                   help="also log training metrics as TensorBoard event files in DIR "
                        "(tensorboard extra)")
    g.add_argument("--partner", default=None, metavar="AGENT:SHARE",
                   help="in SHARE of the kitchens AGENT (greedy, random or stay) plays the "
                        "last cook and the policy the others (its steps are not samples); in "
                        "the rest the policy plays every cook. E.g. greedy:0.5 (loop engine)")
    g.add_argument("--checkpoint-every", type=_POSITIVE, default=None,
                   help="steps between checkpoints (default: steps / 5)")
    _add_imitation_args(p)
    s = p.add_argument_group("speed")
    s.add_argument("--engine", default="auto", choices=("auto", "batch", "loop", "jax"),
                   help="batch: the batched engine (fast extra); loop: one transition per "
                        "kitchen (the reference); auto: batch when the fast extra is "
                        "installed. Same observations and rewards either way. jax: the "
                        "jitted PPO on the JAX kitchen (jax extra; writes policy.npz)")
    s.add_argument("--algo", default="sb3", choices=("sb3", "lean"),
                   help="sb3: stable-baselines3's PPO; lean: the same PPO and network in a "
                        "plain torch loop (rl/lean.py; with many kitchens, short rollouts and "
                        "--precision bf16, see the README's Speed); both write the same "
                        "checkpoint")
    s.add_argument("--precision", default="fp32", choices=("fp32", "bf16"),
                   help="--algo lean: the network's matrix products in float32 or bfloat16 "
                        "(autocast; weights, optimiser and losses stay float32)")
    s.add_argument("--torch-threads", type=_types.whole("--torch-threads", 1, 1024), default=1,
                   help="CPU threads of torch and of the batched engine (the machine is shared: 1 "
                        "unless it is yours)")
    s.add_argument("--device", default="cpu",
                   help="torch device of the SB3 trainer: cpu, cuda, cuda:N or auto")
    s.add_argument("--max-wall", type=_types.seconds, default=None, metavar="SECONDS",
                   help="stop after this much training time and save the policy as usual")
    add_trust_arg(p)
    add_output_args(p, out=True, writes="policy.npz, policy.zip, checkpoints/, episodes.csv, "
                    "train.json")
    add_deprecated_alias(p, "--no-progress", "--quiet", takes_value=False)
    p.set_defaults(func=run)


def _jax_options(g: argparse._ArgumentGroup) -> None:
    """The learning options only ``--engine jax`` takes."""
    g.add_argument("--order-curriculum", type=_FRACTION, default=None, metavar="STRENGTH",
                   help="--engine jax: while training, new orders lean this much towards the "
                        "recipes served least (default 0.5; 0: drawn as in evaluation)")
    g.add_argument("--restart-after", type=_FRACTION, default=None, metavar="FRACTION",
                   help="--engine jax: a learner that has served no order within this "
                        "fraction of the updates is started again with fresh weights "
                        "(default 0.2; 0: never)")
    g.add_argument("--shaping-bonus", type=_types.number("--shaping-bonus", 0.0, 10.0,
                                                         lo_open=False),
                   default=None, metavar="WEIGHT",
                   help="--engine jax: add this weight of the potential shaping's own "
                        "advantage, which the critic cannot cancel (default 0.5; 0: none)")


def _add_imitation_args(p: argparse.ArgumentParser) -> None:
    """The behaviour-cloning warm start's options."""
    b = p.add_argument_group("imitation warm start")
    b.add_argument("--bc", default=None, metavar="AGENT",
                   help="behaviour-clone this controller first (e.g. greedy), then run PPO "
                        "from the cloned policy; OUT/bc_policy.zip keeps the clone")
    b.add_argument("--bc-steps", type=_POSITIVE, default=100_000,
                   help="kitchen steps of teacher-labelled play per round")
    b.add_argument("--bc-rounds", type=_POSITIVE, default=1,
                   help="rounds; after the first, the learner drives and the teacher labels "
                        "(DAgger)")
    b.add_argument("--bc-epochs", type=_POSITIVE, default=8, help="fitting passes after each round")
    b.add_argument("--bc-focus", type=_types.number("--bc-focus", 1.0, 100.0, lo_open=False),
                   default=1.0, help="in DAgger rounds, weigh the samples where the learner's "
                                     "own choice missed the teacher's this many times (1: plain)")


def _hidden(text: str) -> tuple[int, ...]:
    from ..errors import ConfigError

    try:
        sizes = tuple(int(x) for x in text.split(",") if x.strip())
    except ValueError as exc:
        raise ConfigError(f"--hidden {text!r}: use comma-separated integers like 128,128") from exc
    return sizes


def _run_jax(args: argparse.Namespace) -> int:
    """``--engine jax``: the jitted PPO (rl/fast/jax_ppo.py) on the JAX kitchen."""
    from ..env import make_jax_env
    from ..errors import ConfigError
    from ..rl.fast.jax_ppo import PPOConfig, train_to_folder

    hidden = set(_hidden(args.hidden))
    if len(hidden) != 1:
        raise ConfigError(f"--engine jax: --hidden {args.hidden!r} must repeat one width "
                          "(its MLP has two equal layers), e.g. 128,128")
    kw = {k: v for k, v in (("n_agents", args.n_agents), ("map", args.map)) if v is not None}
    env = make_jax_env(args.preset, obs_radius=args.obs_radius, **kw)
    per_update = args.n_steps * args.n_kitchens * env.num_agents
    config = PPOConfig(n_envs=args.n_kitchens, n_steps=args.n_steps,
                       n_updates=max(1, args.steps // per_update), n_epochs=args.n_epochs,
                       hidden=hidden.pop(), lr=args.lr, gamma=args.gamma,
                       ent_coef=args.ent_coef)
    if args.order_curriculum is not None:
        config = config._replace(order_curriculum=args.order_curriculum)
    if args.restart_after is not None:
        config = config._replace(restart_after=args.restart_after)
    if args.shaping_bonus is not None:
        config = config._replace(shaping_bonus=args.shaping_bonus)
    command = "ocplus " + shlex.join(sys.argv[1:]) if sys.argv[1:2] == ["train"] else None
    summary = train_to_folder(env, config, args.out, args.seed, command,
                              stream=None if args.quiet else sys.stderr)
    emit({k: summary[k] for k in ("policy", "timesteps", "wall_time_s", "steps_per_s",
                                  "device")}, args)
    return 0


def run(args: argparse.Namespace) -> int:
    if args.engine == "jax":
        if args.partner is not None:
            from ..errors import ConfigError

            raise ConfigError("--partner trains beside a scripted cook on the loop engine, "
                              "not --engine jax")
        return _run_jax(args)
    for flag, value, hint in (
            ("--order-curriculum", args.order_curriculum, "; the other engines take --curriculum"),
            ("--restart-after", args.restart_after, ""),
            ("--shaping-bonus", args.shaping_bonus, "")):
        if value is not None:
            from ..errors import ConfigError

            raise ConfigError(f"{flag} is an option of --engine jax{hint}")
    from ..rl.train import TrainConfig, train

    config = TrainConfig(
        preset=args.preset, n_agents=args.n_agents, map=args.map, steps=args.steps,
        maps=args.maps, map_stages=args.map_stages,
        seed=args.seed, out=args.out, obs=args.obs, obs_radius=args.obs_radius,
        n_kitchens=args.n_kitchens, n_steps=args.n_steps, batch_size=args.batch_size,
        n_epochs=args.n_epochs, learning_rate=args.lr, gamma=args.gamma,
        ent_coef=args.ent_coef, hidden=_hidden(args.hidden),
        team_reward=not args.individual_reward, anneal_fraction=args.anneal_fraction,
        curriculum=tuple(p.strip() for p in args.curriculum.split(",") if p.strip()),
        curriculum_fraction=args.curriculum_fraction, init=args.init,
        checkpoint_every=args.checkpoint_every, engine=args.engine,
        resume=args.resume, tensorboard=args.tensorboard,
        torch_threads=args.torch_threads, max_wall_s=args.max_wall,
        bc=args.bc, bc_steps=args.bc_steps, bc_rounds=args.bc_rounds, bc_epochs=args.bc_epochs,
        bc_focus=args.bc_focus,
        algo=args.algo, precision=args.precision, device=args.device, partner=args.partner,
    )
    teacher = None
    if args.bc is not None:
        from ..agents import make_controller

        make_controller(args.bc, args.seed)  # an unknown name fails now, not after set-up
        teacher = functools.partial(make_controller, args.bc)  # seed -> a new teacher
    partner = None
    if args.partner is not None:
        from ..agents import make_controller
        from ..rl.train import parse_partner

        partner = functools.partial(make_controller, parse_partner(args.partner)[0])
    if sys.argv[1:2] == ["train"]:
        command = "ocplus " + shlex.join(sys.argv[1:])
    else:  # called in-process (tests, scripts): the essential options
        parts = ["train", "--preset", args.preset, "--timesteps", str(args.steps), "--seed",
                 str(args.seed), "--out", args.out]
        if args.n_agents is not None:
            parts += ["--n-agents", str(args.n_agents)]
        if args.maps is not None:
            parts += ["--maps", args.maps]
        if args.partner is not None:
            parts += ["--partner", args.partner]
        command = "ocplus " + shlex.join(parts)
    chooser = None
    if config.obs == "choice":
        from ..agents.task_choice import TaskChoice

        chooser = TaskChoice
    summary = train(config, command=command, progress=not args.quiet, teacher=teacher,
                    partner=partner, chooser=chooser)
    emit({k: summary[k] for k in (
        "policy", "timesteps", "stopped_by_wall_budget", "episodes",
        "dishes_per_episode_last50", "wall_time_s", "steps_per_s")}, args)
    return 0
