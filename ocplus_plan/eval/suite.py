"""Instance sets in the IPC style, for planners and language models outside the package.

:func:`export_suite` samples reachable kitchen states (random rollouts of
:func:`~ocplus_plan.planning.fidelity.sample_state`) for every preset, map and number
of cooks asked for (or for each :class:`Cell` of an explicit list: preset, map, cooks,
goal orders, sample, rule overrides), compiles each in every encoding asked for, solves
it with the reference planners, and writes::

    OUT/manifest.json              the arguments, the encodings, the instance names, the
                                   tracks (see below)
    OUT/README.txt                 this layout and the formats, for whoever gets the set
    OUT/<encoding>/domain.pddl     one domain per encoding (the checked-in domains/ one)
    OUT/<encoding>/domain.txt      the same domain in English
    OUT/maps/<file>.yaml           copies of map files given by path (names need none)
    OUT/pNN/manifest.json          preset, map, cooks, seed, sample, step, how the state
                                   was reached, its hash, the open orders, the goal, the
                                   lower bound, and per encoding the reference plan's
                                   planner, engine, cost/makespan, validation, fidelity
    OUT/pNN/state.json             the simulator state (``State.to_dict``), exact
    OUT/pNN/<encoding>.pddl        the problem
    OUT/pNN/<encoding>.txt         the problem in English
    OUT/pNN/<encoding>.plan        the reference plan, IPC format (absent if none solved)
    OUT/pNN/<encoding>-domain.pddl only if this instance needs a bigger domain (a plate
                                   of more than three ingredients)

Same arguments, same bytes: nothing time-dependent (no timings, dates or absolute
paths) is written, and JSON keys are sorted. Planner limits are CPU seconds, so a
loaded machine does not change which planners solve an instance; the one caveat is a
planner that solves an instance within a few percent of its CPU limit (then the
reference may change). The command's own output (not the set) reports CPU and wall times.

The reference plan of an encoding comes from a portfolio (:data:`REFERENCE_PLANNERS`,
:func:`reference_plan`): Fast Downward's lama-first (satisficing, fast), then BJOLP
(optimal) and weighted A* (cost-aware), each with ``--timeout`` CPU seconds; when none
of them solves an instance, every other registered planner of the encoding installed
here is tried, so an instance has no reference only when no registered engine solves
it. Every validated plan (UP's validator and VAL) is judged in the kitchen by the judge
the league uses (:func:`judge_plan`, :mod:`~ocplus_plan.planning.fidelity_judge`: its
steps realised with collision-free routing, waits allowed); the reference is the best
faithful plan (the best unfaithful one when none is faithful). Its manifest entry names
the ``planner`` and ``engine``, says whether it is ``faithful``, how it was ``judged``,
how many simulator steps of ``waits`` its realisation needed, and when refused the
``failed_step`` and the ``divergence``; ``optimal`` says whether an optimal planner found
a plan of the same value; the ``portfolio`` lists each planner with its status, value,
faithfulness, waits, failed step and optimality.

Tracks (:mod:`.suite_witness`): an encoding of an instance is ``solved`` (a reference
planner's plan), ``open`` (none solved it; a goal-agenda witness plan, validated, proves it
solvable and is its reference), ``unsolvable`` (a complete search proved it) or
``unknown`` (none of these, or no plan that the kitchen realises: a scored instance's
reference is always faithful). The set's manifest lists the scored instances under the
encoding's name, the others under ``<encoding>-unsolvable`` and ``<encoding>-unknown``
(dropped: in no scored track).
"""

from __future__ import annotations

import json
import shutil
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import ConfigError
from ..sim.rules import make_rules
from ..sim.state import State, state_from_dict
from .suite_files import MAX_INSTANCE_JSON_BYTES, MAX_JSON_DEPTH, read_json
from .suite_witness import STATUS_SCORED

#: the reference portfolio per encoding, in the order run (and best first on ties): a
#: satisficing search first (lama-first), then an optimal one (BJOLP) and a cost-aware
#: one (weighted A*); see :func:`reference_plan`
REFERENCE_PLANNERS: dict[str, tuple[str, ...]] = {
    "classical": ("fast-downward", "fast-downward-bjolp", "fast-downward-wastar"),
    "temporal": ("kairos",),
}
FORMAT = "ocplus-suite/1"


@dataclass(frozen=True)
class Cell:
    """One instance of a set: a preset's stations on a map with a number of cooks, ``orders``
    goal orders (more than the preset's queue raises the queue: rule ``n_orders``, so the
    state holds that many open orders, drawn from the preset's recipes by the episode's
    seeded generator), the ``sample``-th sampled state, and rule overrides."""

    preset: str
    map: str | None = None
    cooks: int | None = None
    orders: int | None = None
    sample: int = 0
    rules: tuple[tuple[str, Any], ...] = ()

    def to_dict(self) -> dict[str, Any]:
        return {"preset": self.preset, "map": self.map, "cooks": self.cooks,
                "orders": self.orders, "sample": self.sample, "rules": dict(self.rules)}


def cell_rules(cell: Cell, horizon: int | None = None) -> tuple[Any, dict[str, Any]]:
    """(the rules of a cell, the overrides its manifest records to rebuild them)."""
    overrides: dict[str, Any] = dict(cell.rules)
    if horizon is not None:
        overrides["horizon"] = horizon
    if cell.cooks:
        overrides["n_agents"] = cell.cooks
    rules = make_rules(cell.preset, map=cell.map, **overrides)
    if cell.orders is not None and cell.orders > rules.n_orders:
        overrides["n_orders"] = cell.orders
        rules = make_rules(cell.preset, map=cell.map, **overrides)
    overrides.pop("n_agents", None)
    overrides.pop("horizon", None)
    return rules, overrides


@dataclass(frozen=True)
class SuiteSpec:
    """What :func:`export_suite` writes (the ``ocplus export-suite`` options)."""

    presets: tuple[str, ...] = ("easy",)
    maps: tuple[str | None, ...] = (None,)
    cooks: tuple[int | None, ...] = (None,)  # None: the preset's number of cooks
    states: int = 1
    encodings: tuple[str, ...] = ("classical", "temporal")
    seed: int = 0
    granularity: str = "stations"
    orders: int | None = None
    max_steps: int = 120
    #: CPU seconds per planner and problem (see :func:`~ocplus_plan.planning.engines.solve`)
    timeout: float = 60.0
    planners: dict[str, tuple[str, ...]] = field(default_factory=lambda: dict(REFERENCE_PLANNERS))
    #: wall-clock safety per planner call (None: the default multiple of ``timeout``)
    wall_limit: float | None = None
    #: try the other registered planners of an encoding when the portfolio solves nothing
    fallback: bool = True
    #: rule overrides (``--rules``), sorted (key, value) pairs, e.g. (("dynamic", False),)
    rules: tuple[tuple[str, Any], ...] = ()
    #: the episode horizon of every instance (None: the preset's)
    horizon: int | None = None
    #: CPU seconds per goal order of the goal-agenda witness tried when no reference
    #: planner solves an instance and none proved it unsolvable (0: no witness)
    witness_timeout: float = 20.0
    #: the instances, one per cell, instead of the grid presets x maps x cooks x states
    cells: tuple[Cell, ...] | None = None
    #: (encoding, folder) pairs: reference plans found offline (:mod:`.suite_offline`),
    #: judged as candidates of that encoding's portfolio
    offline_plans: tuple[tuple[str, str], ...] = ()

    def grid(self) -> list[Cell]:
        """The cells of the set: :attr:`cells`, else presets x maps x cooks x states."""
        if self.cells is not None:
            return list(self.cells)
        return [Cell(p, m, c, self.orders, k, self.rules)
                for p in self.presets for m in self.maps for c in self.cooks
                for k in range(self.states)]

    def arguments(self) -> dict[str, Any]:
        return {"presets": list(self.presets), "maps": list(self.maps), "cooks": list(self.cooks),
                "states": self.states, "encodings": list(self.encodings), "seed": self.seed,
                "granularity": self.granularity, "orders": self.orders,
                "max_steps": self.max_steps, "timeout": self.timeout,
                "planners": {k: list(v) for k, v in sorted(self.planners.items())},
                "fallback": self.fallback, "rules": dict(self.rules),
                "horizon": self.horizon, "witness_timeout": self.witness_timeout,
                **({"cells": [c.to_dict() for c in self.cells]} if self.cells else {}),
                **({"offline_plans": dict(self.offline_plans)} if self.offline_plans else {})}


README = """\
An instance set of ocplus-plan (a symbolic-planning benchmark on an Overcooked-style
kitchen simulator), written by `ocplus export-suite`. Layout:

  manifest.json                 how the set was made (`ocplus export-suite` arguments)
  <encoding>/domain.pddl        the PDDL domain of an encoding (classical: STRIPS with
                                action costs; temporal: PDDL 2.1 durative actions)
  <encoding>/domain.txt         the same domain in English, generated from the model
  pNN/manifest.json             where the state comes from, its orders, the lower bound on
                                plan quality, and the reference plan of each encoding
  pNN/<encoding>.pddl           the problem (use <encoding>-domain.pddl if present)
  pNN/<encoding>.txt            the problem in English
  pNN/<encoding>.plan           the reference plan in IPC format (sequential: `N: (a x y)`;
                                temporal: `T: (a x y) [D]`), validated with VAL and
                                unified-planning
  pNN/state.json                the simulator state the problem was compiled from

Check any plan against the planner-independent validators and the simulator:
  ocplus check-plan pNN --encoding classical --plan my.plan
Exit codes: 0 valid and faithful, 4 invalid, 5 valid but the simulator diverges.
"""


def _dump(data: Any) -> str:
    return json.dumps(data, indent=1, sort_keys=True) + "\n"


def _write(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")


def _bound(state: State, orders: int | None) -> dict[str, float | None]:
    from .bounds import plan_bound

    b = plan_bound(state, max_orders=orders)
    return {k: (None if v == float("inf") else float(v))
            for k, v in (("cost", b.cost), ("makespan", b.makespan))}


def reference_plan(compiled: Any, state: State, planners: tuple[str, ...], timeout: float,
                   wall_limit: float | None = None, fallback: bool = True,
                   offline: list[tuple[str, str, Any]] | None = None,
                   ) -> tuple[Any, dict[str, Any], list[dict[str, Any]]]:
    """The reference plan of a portfolio: (best plan or None, what the manifest says about
    it, one row per planner tried with its CPU and wall seconds for the command's output).

    Every planner of ``planners`` runs in order with ``timeout`` CPU seconds; each plan
    that UP's validator and VAL accept is judged in the kitchen. The reference is the
    best faithful plan (lowest cost, classical; shortest makespan, temporal; ties to the
    planner listed first), else the best unfaithful one, flagged ``faithful: false``
    (faithful: by the league's judge, :func:`judge_plan`).
    With ``fallback``, when none of them solves the problem, every other registered
    planner of the encoding that is installed here is tried (the default portfolio first,
    then the others in name order) until one does:
    an instance gets no reference only when no registered engine solves it. ``offline``
    plans ((label, engine, plan), :mod:`.suite_offline`) are judged the same way after the
    planners, as candidates ranked after them. ``optimal``
    says whether the reference's value is proven optimal (an optimal planner found a plan
    of the same value)."""
    from ..planning.engines import available_planners
    from .suite_offline import offline_result

    found: list[tuple[bool, float, int, Any, Any]] = []
    portfolio: dict[str, dict[str, Any]] = {}
    rows: list[dict[str, Any]] = []
    optimum: float | None = None
    names = list(planners)
    # the fallback: the default portfolio first, then every other installed planner by name
    default = list(REFERENCE_PLANNERS.get(compiled.encoding, ()))
    installed = available_planners(compiled.encoding)
    extra = [n for n in default + installed if n not in names and n in installed] \
        if fallback else []
    extra = list(dict.fromkeys(extra))
    offline = offline or []
    for rank, name in enumerate(names + extra + [o[0] for o in offline]):
        if len(names) <= rank < len(names) + len(extra) and found:
            continue
        if rank >= len(names) + len(extra):
            result = offline_result(compiled, *offline[rank - len(names) - len(extra)])
            result, verdict, row = _judged(compiled, state, result, result.planner)
        else:
            result, verdict, row = _try_planner(compiled, state, name, timeout, wall_limit)
        rows.append(row)
        portfolio[row["planner"]] = {k: row.get(k) for k in (
            "status", "value", "faithful", "waits", "failed_step", "optimal")}
        if verdict is None:
            continue
        value = row["value"]
        if row["optimal"]:
            optimum = value if optimum is None else min(optimum, value)
        found.append((not verdict["faithful"], value, rank, result, verdict))
    info: dict[str, Any] = {"tried": {n: e["status"] for n, e in portfolio.items()},
                            "portfolio": portfolio}
    if not found:
        return None, info, rows
    _, value, _, result, verdict = min(found, key=lambda f: f[:3])
    info.update(planner=result.planner, engine=result.engine, cost=result.cost,
                makespan=result.makespan, plan_length=result.plan_length,
                validated=result.validation_detail, **verdict,
                optimal=optimum is not None and value <= optimum + 1e-9)
    return result.plan, info, rows


#: planners whose plans are cost-optimal (UP reports bjolp's custom configuration as
#: satisficing, so the registry name says it)
OPTIMAL_PLANNERS = frozenset({"fast-downward-bjolp", "fast-downward-opt", "symk"})


def _try_planner(compiled: Any, state: State, name: str, timeout: float,
                 wall_limit: float | None) -> tuple[Any, Any, dict[str, Any]]:
    """Solve with one planner; judge a validated plan: (result, judgement or None, row)."""
    from ..planning.engines import solve

    return _judged(compiled, state, solve(compiled.problem, name, timeout=timeout,
                                          wall_limit=wall_limit), name)


def _judged(compiled: Any, state: State, result: Any, name: str) -> tuple[Any, Any, dict]:
    """A planner's (or an offline plan's) result judged when validated, and its row."""
    ok = result.solved and result.validated is True
    row: dict[str, Any] = {
        "planner": result.planner, "status": result.status if ok or not result.solved
        else "not validated", "planning_time": result.planning_time,
        "cpu_time": result.cpu_time, "reason": result.reason[:200], "value": None,
        "faithful": None, "optimal": False}
    if not ok:
        return result, None, row
    value = result.cost if compiled.encoding == "classical" else result.makespan
    if value is None:
        row["status"] = "no value"
        return result, None, row
    verdict = judge_plan(compiled, result.plan, state)
    row.update(value=float(value), faithful=verdict["faithful"], waits=verdict["waits"],
               failed_step=verdict["failed_step"],
               optimal=bool(result.optimal or name in OPTIMAL_PLANNERS))
    return result, verdict, row


def judge_plan(compiled: Any, plan: Any, state: State) -> dict[str, Any]:
    """What a manifest says of a validated plan's faithfulness, by the league's judge
    (:func:`~ocplus_plan.planning.fidelity_judge.judge`: collision-free routing, waits
    allowed): ``faithful``, ``judged`` (how it was realised), ``waits`` (simulator steps
    spent letting a cook step aside or walking around), ``failed_step`` (0-based, when
    refused) and ``divergence`` (why, when refused)."""
    from ..planning.fidelity_judge import judge

    verdict = judge(compiled, plan, state)
    return {"faithful": bool(verdict.faithful), "judged": verdict.how,
            "waits": int(verdict.waits), "failed_step": verdict.failed_step,
            "divergence": None if verdict.faithful else (verdict.reason or None)}


def replay_plan(compiled: Any, plan: Any, state: State) -> Any:
    """Replay a plan of ``compiled`` in ``state`` (sequential or time-triggered)."""
    from ..planning.fidelity import replay
    from ..planning.fidelity_temporal import replay_temporal

    if plan.kind.name == "TIME_TRIGGERED_PLAN":
        return replay_temporal(compiled, plan, state)
    return replay(compiled, plan, state)


def _map_entry(spec: str | None, out: Path) -> str | None:
    """How the manifest names a map: a registry name as is; a file copied into the set."""
    if spec is None:
        return None
    path = Path(spec)
    if spec.endswith((".yaml", ".yml")) and path.is_file():
        target = out / "maps" / path.name
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(path, target)
        return f"maps/{path.name}"
    return spec


def rules_of(instance: dict[str, Any], root: Path) -> Any:
    """The rules an instance manifest names (a copied map file is read from the set)."""
    map_spec = instance["map"]
    if map_spec is not None and map_spec.startswith("maps/"):
        map_spec = str(root / map_spec)
    return make_rules(instance["preset"], map=map_spec, n_agents=instance["n_agents"],
                      horizon=instance["horizon"], **instance.get("rules", {}))


def export_suite(spec: SuiteSpec, out: str | Path, progress: Any = None,
                 select: Any = None) -> list[dict[str, Any]]:
    """Write the instance set of ``spec`` into ``out`` (see the module docstring).

    Returns one row per instance and encoding (planning times included) for the caller
    to print; ``progress(message)`` is called as instances are done. ``select`` (cell
    indices from 0) rebuilds those instances of a set in ``out``, named as in the whole
    set; the manifest and ``maps/`` are rewritten from every instance's manifest: the
    bytes a whole build writes, without solving the others again."""
    from ..planning.language import describe_domain
    from ..planning.model import ENCODINGS
    from ..planning.pddl import domain_text

    bad = [e for e in spec.encodings if e not in ENCODINGS]
    if bad or not spec.encodings:
        raise ConfigError(f"--encoding {','.join(spec.encodings)}: use one or more of "
                          f"{', '.join(ENCODINGS)}")
    if spec.states < 1:
        raise ConfigError(f"--states must be at least 1, got {spec.states}")
    cells = spec.grid()
    rules = [cell_rules(c, spec.horizon) for c in cells]  # bad arguments fail before work
    root = Path(out)
    width = max(2, len(str(len(cells))))
    names = [f"p{i + 1:0{width}d}" for i in range(len(cells))]
    chosen = _check_out(root, names, select)
    root.mkdir(parents=True, exist_ok=True)
    for enc in spec.encodings:
        _write(root / enc / "domain.pddl", domain_text(enc, spec.granularity))
        _write(root / enc / "domain.txt", describe_domain(enc, spec.granularity))
    rows: list[dict[str, Any]] = []
    for index, (cell, (cell_rule, overrides)) in enumerate(zip(cells, rules)):
        if index not in chosen:
            continue
        name = names[index]
        if (root / name).exists():
            shutil.rmtree(root / name)
        instance, cell_rows = _export_instance(spec, root, name, cell, cell_rule, overrides)
        rows.extend(cell_rows)
        if progress is not None:
            progress(f"{name}: {cell.preset}, map {cell_rule.layout.name}, "
                     f"{cell_rule.n_agents} cook(s), {len(instance['goal_orders'])} "
                     f"order(s), step {instance['step']}: " + ", ".join(
                         f"{e} {v['status']}" for e, v in instance["encodings"].items()))
    _write(root / "README.txt", README)
    tracks: dict[str, list[str]] = {}
    maps: set[str] = set()
    for name in names:
        instance = read_json(root / name / "manifest.json")
        if (instance.get("map") or "").startswith("maps/"):
            maps.add(instance["map"][len("maps/"):])
        for enc, entry in instance["encodings"].items():
            label = enc if STATUS_SCORED[entry["status"]] else f"{enc}-{entry['status']}"
            tracks.setdefault(label, []).append(name)
    for path in sorted((root / "maps").glob("*")):
        if path.name not in maps:  # a kitchen of a cell the set no longer has
            path.unlink()
    _write(root / "manifest.json", _dump({
        "format": FORMAT, "generated_by": "ocplus export-suite", "arguments": spec.arguments(),
        "encodings": {e: {"domain": f"{e}/domain.pddl", "text": f"{e}/domain.txt"}
                      for e in spec.encodings},
        "instances": names, "tracks": dict(sorted(tracks.items()))}))
    return rows


def _check_out(root: Path, names: list[str], select: Any) -> set[int]:
    """The cell indices to build into ``root``: all into a new or empty folder; ``select``
    into a set there, whose other instances must be present (stale folders go)."""
    if select is None and root.exists() and any(root.iterdir()):
        raise ConfigError(f"--out {root} exists and is not empty; give a new folder (a set "
                          "is written whole; --cells rebuilds chosen instances of one)")
    chosen = set(range(len(names)) if select is None else select)
    if bad := sorted(i + 1 for i in chosen if i not in range(len(names))):
        raise ConfigError(f"--cells {bad}: the set has cells 1 to {len(names)}")
    if missing := [n for i, n in enumerate(names)
                   if i not in chosen and not (root / n / "manifest.json").is_file()]:
        raise ConfigError(f"{root} lacks {', '.join(missing)}: rebuild the whole set into a "
                          "new folder, or choose those cells too")
    for path in sorted(root.glob("p[0-9]*")):
        if path.is_dir() and path.name not in names:
            shutil.rmtree(path)
    return chosen


def _export_instance(spec: SuiteSpec, root: Path, name: str, cell: Cell, rules: Any,
                     overrides: dict[str, Any]) -> tuple[dict[str, Any], list[dict[str, Any]]]:
    """Write one instance folder; (its manifest, one row per encoding)."""
    from ..planning.fidelity import SAMPLE_RECIPE, sample_state

    state = sample_state(rules, spec.seed, cell.sample, spec.max_steps)
    folder = root / name
    _write(folder / "state.json", _dump(state.to_dict()))
    max_orders = cell.orders
    instance: dict[str, Any] = {
        "name": name, "preset": cell.preset, "map": _map_entry(cell.map, root),
        "layout": rules.layout.name, "n_agents": rules.n_agents, "horizon": rules.horizon,
        "rules": dict(sorted(overrides.items())), "seed": spec.seed, "sample": cell.sample,
        "max_steps": spec.max_steps, "step": state.t,
        "reached": f"sample {cell.sample} of seed {spec.seed}: {SAMPLE_RECIPE}",
        "state_hash": state.state_hash(), "granularity": spec.granularity,
        "orders": [{"id": o.order_id, "recipe": [i.name.lower() for i in o.recipe]}
                   for o in state.orders],
        "max_orders": max_orders, "bound": _bound(state, max_orders), "encodings": {},
    }
    rows = []
    for enc in spec.encodings:
        entry, row = _export_encoding(spec, root, folder, enc, state, max_orders, instance)
        instance["encodings"][enc] = entry
        rows.append({"instance": name, "encoding": enc, "preset": cell.preset,
                     "n_agents": rules.n_agents, "step": state.t, "bound": instance["bound"],
                     **row})
    _write(folder / "manifest.json", _dump(instance))
    return instance, rows


def _export_encoding(spec: SuiteSpec, root: Path, folder: Path, enc: str, state: State,
                     max_orders: int | None, instance: dict[str, Any],
                     ) -> tuple[dict[str, Any], dict[str, Any]]:
    """Write one encoding of an instance: problem, English, reference plan or witness."""
    from ..planning import compile
    from ..planning.language import describe_problem
    from ..planning.pddl import pddl_texts
    from ..planning.plan_io import format_plan
    from .suite_offline import offline_plans
    from .suite_witness import agenda_witness, track_status

    compiled = compile(state, encoding=enc, granularity=spec.granularity, max_orders=max_orders)
    instance["goal_orders"] = list(compiled.goal_orders)
    domain, problem = pddl_texts(compiled.problem)
    entry: dict[str, Any] = {"problem": f"{enc}.pddl", "text": f"{enc}.txt",
                             "domain": f"../{enc}/domain.pddl"}
    if domain != (root / enc / "domain.pddl").read_text(encoding="utf-8"):
        _write(folder / f"{enc}-domain.pddl", domain)
        entry["domain"] = f"{enc}-domain.pddl"
    _write(folder / f"{enc}.pddl", problem)
    _write(folder / f"{enc}.txt", describe_problem(compiled))
    refs = dict(spec.offline_plans).get(enc)
    offline = offline_plans(refs, instance["name"], compiled) if refs else None
    plan, info, tried = reference_plan(compiled, state, spec.planners.get(enc, ()),
                                       spec.timeout, spec.wall_limit, spec.fallback, offline)
    status = track_status(info, None)
    if status == "solved" and info.get("faithful") is False:
        status = "unknown"  # no plan the kitchen accepts yet; a witness may still give one
    if status == "unknown" and spec.witness_timeout > 0:
        found, witness = agenda_witness(state, enc, spec.granularity, spec.witness_timeout,
                                        spec.wall_limit, max_orders)
        info["witness"] = witness
        if found is not None:
            plan = found
            _reference_from_witness(compiled, plan, state, info, witness)
            # scored only with a plan the kitchen realises: a witness planned in the model
            # alone may walk one cook through another, which proves nothing of the kitchen
            status = "open" if info["faithful"] else "unknown"
    entry["status"] = status
    entry["reference"] = info
    if plan is not None:
        entry["plan"] = f"{enc}.plan"
        _write(folder / f"{enc}.plan", format_plan(
            plan, f"reference plan of {instance['name']} ({enc}) by {info['planner']}"))
    return entry, {"status": status, "tried": tried,
                   **{k: info.get(k) for k in ("planner", "cost", "makespan", "faithful",
                                               "optimal")}}


def _reference_from_witness(compiled: Any, plan: Any, state: State, info: dict[str, Any],
                            witness: dict[str, Any]) -> None:
    """Fill the reference entry from a validated goal-agenda witness plan."""
    from ..planning.validate import plan_quality

    verdict = judge_plan(compiled, plan, state)
    quality = plan_quality(compiled.problem, plan)
    info.update(planner=f"goal-agenda:{witness['planner']}", engine="goal-agenda",
                cost=quality.cost, makespan=quality.makespan,
                plan_length=len(getattr(plan, "actions", None) or plan.timed_actions),
                validated=witness["validated"], **verdict, optimal=False)


@dataclass
class Instance:
    """One instance of a set, loaded back: its manifest, state and folder."""

    folder: Path
    manifest: dict[str, Any]
    state: State

    def compiled(self, encoding: str) -> Any:
        """The instance compiled again; refused if its problem file no longer matches."""
        from ..planning import compile
        from ..planning.pddl import pddl_texts

        entry = self.manifest["encodings"].get(encoding)
        if entry is None:
            raise ConfigError(f"instance {self.folder} has no {encoding} encoding; it has "
                              f"{', '.join(sorted(self.manifest['encodings']))}")
        compiled = compile(self.state, encoding=encoding,
                           granularity=self.manifest["granularity"],
                           max_orders=self.manifest["max_orders"])
        stored = (self.folder / entry["problem"]).read_text(encoding="utf-8")
        if pddl_texts(compiled.problem)[1] != stored:
            raise ConfigError(f"{self.folder / entry['problem']} does not match the instance's "
                              "state.json (edited by hand, or written by another version); "
                              "export the set again")
        return compiled


def load_instance(folder: str | Path) -> Instance:
    """An instance folder written by :func:`export_suite` (bad folders raise ConfigError)."""
    path = Path(folder)
    manifest_path = path / "manifest.json"
    if not manifest_path.is_file():
        raise ConfigError(f"{path} is not an instance of an ocplus set (no manifest.json); "
                          "give a folder pNN written by `ocplus export-suite`, or the "
                          "domain, problem and plan files")
    try:
        manifest = read_json(manifest_path)
        if not isinstance(manifest, dict):
            raise ValueError("manifest.json is not a JSON object")
        if "instances" in manifest:
            raise ConfigError(f"{path} is a whole set; give one of its instances, e.g. "
                              f"{path / manifest['instances'][0]}")
        rules = rules_of(manifest, path.parent)
        state = state_from_dict(rules, read_json(path / "state.json"))
    except (OSError, ValueError, KeyError, TypeError, IndexError, AttributeError) as exc:
        raise ConfigError(f"{path}: cannot read the instance ({type(exc).__name__}: {exc}); "
                          "export the set again") from None
    if state.state_hash() != manifest.get("state_hash"):
        raise ConfigError(f"{path}/state.json does not match its manifest's state_hash; "
                          "export the set again")
    return Instance(path, manifest, state)


__all__ = ["FORMAT", "Cell", "cell_rules", "OPTIMAL_PLANNERS", "REFERENCE_PLANNERS", "Instance", "SuiteSpec", "export_suite",
           "judge_plan", "load_instance", "MAX_INSTANCE_JSON_BYTES", "MAX_JSON_DEPTH",
           "read_json", "reference_plan", "replay_plan", "rules_of"]
