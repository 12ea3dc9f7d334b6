"""Named planners, their availability, and ``solve(problem, planner) -> PlanResult``.

Each planner is one YAML file in ``planners/`` (the UP engine name, its
parameters, a default time limit, the encoding it is meant for, what must be
installed, notes), or a planner binary's ``command:`` (see :mod:`._command`; a
user's YAML may also be named by its path). :func:`solve` runs the engine in a forked child that leads
its own process group (see :mod:`._proc`), kills the group when it has used its CPU
seconds (``timeout``: CPU seconds of the whole group, as the IPC counts them) or at a
wall-clock safety limit, whichever comes first,
rebuilds the plan against the caller's problem, and validates it with UP's
validator and, where installed, VAL. Outcomes are data: a missing planner, a
timeout, an unsolvable problem, a crash or an invalid plan is a
:class:`PlanResult` status, never an exception. Unknown planner names and
malformed configurations raise :class:`~ocplus_plan.errors.PlannerError`.

Typical use::

    from ocplus_plan.planning.engines import solve
    result = solve(problem, "fast-downward", timeout=30)
    print(result.status, result.cost, result.validated)
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import re
import resource
import shutil
import tempfile
import warnings
from dataclasses import asdict, dataclass, field
from functools import cache, lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import DependencyNotInstalled, PlannerError
from . import _command, _proc, portfolio
from .adapt import adapt_for_engine, without_quality_metrics
from .model import ENCODINGS
from .validate import plan_from_steps, plan_quality, plan_to_steps, validate_plan

if TYPE_CHECKING:
    from importlib.resources.abc import Traversable

# up-lpg imports pkg_resources, which warns on every import (UP's factory imports it too);
# the pin setuptools<81 is deliberate, so this one message is noise.
warnings.filterwarnings("ignore", message="pkg_resources is deprecated")


#: Every status a :class:`PlanResult` can have.
#: ``unsolvable`` is a proof (or a planner binary's claim: exit 0 without a plan);
#: ``gave-up`` an incomplete search that stopped without a plan (LPG's restarts ran out).
STATUSES = ("solved", "unsolvable", "gave-up", "timeout", "memout", "error", "crashed",
            "unsupported", "unavailable", "invalid")

#: Seconds a planner gets past its own time limit to report before its group is killed.
GRACE_SECONDS = 2.0

#: The default wall-clock safety limit of a call with CPU limit ``c``:
#: ``WALL_FACTOR * c + WALL_SLACK`` seconds. A planner beside six busy processes on two
#: cores gets about a quarter of a core, at a load average of 25 about a tenth (measured:
#: 0.9 CPU s of Fast Downward took 10 s), and under ``nice`` less: TAMER was killed by a
#: 10 x + 60 s safety after 5 of its 10 CPU s at a load of 25. The safety only stops a
#: planner that waits without computing, never one that is merely slowed down.
WALL_FACTOR = 30.0
WALL_SLACK = 60.0


def wall_safety(cpu_limit: float) -> float:
    """The default wall-clock safety limit for a CPU limit (see :data:`WALL_FACTOR`)."""
    return WALL_FACTOR * cpu_limit + WALL_SLACK

_UP_STATUS = {
    "SOLVED_SATISFICING": "solved",
    "SOLVED_OPTIMALLY": "solved",
    "UNSOLVABLE_PROVEN": "unsolvable",
    "UNSOLVABLE_INCOMPLETELY": "gave-up",
    "TIMEOUT": "timeout",
    "MEMOUT": "memout",
    "INTERNAL_ERROR": "error",
    "UNSUPPORTED_PROBLEM": "unsupported",
}


@dataclass(frozen=True)
class PlannerConfig:
    """One planner: a registry name bound to a UP engine and how to run it."""

    name: str
    engine: str
    encoding: str
    timeout: float = 60.0
    params: dict[str, Any] = field(default_factory=dict, hash=False)
    modules: tuple[str, ...] = ()
    binaries: tuple[str, ...] = ()
    register: str | None = None
    env: dict[str, str] = field(default_factory=dict, hash=False)
    notes: str = ""
    #: a planner binary instead of a UP engine: the argument list (see :mod:`._command`)
    command: tuple[str, ...] = ()
    #: other entries run in turn, each with its share of the CPU limit (:mod:`.portfolio`)
    portfolio: tuple[tuple[str, float | None], ...] = ()

    @classmethod
    def from_mapping(cls, data: dict[str, Any], source: str = "<dict>") -> PlannerConfig:
        """Build a config from a parsed YAML mapping; bad fields raise PlannerError."""
        if not isinstance(data, dict):
            raise PlannerError(f"{source}: a planner config must be a mapping, got {data!r}")
        known = {"name", "engine", "encoding", "timeout", "params", "requires", "register",
                 "env", "notes", "command", "portfolio"}
        bad = sorted(set(data) - known)
        if bad:
            raise PlannerError(f"{source}: unknown key(s) {bad}; known keys: {sorted(known)}")
        command: tuple[str, ...] = ()
        if "command" in data:
            if "engine" in data or "register" in data or "params" in data:
                raise PlannerError(f"{source}: give either 'command' (a planner binary) or "
                                   "'engine' (a unified-planning engine, with its 'params' "
                                   "and 'register'), not both")
            command = _command.parse_command(data["command"], source)
            data = {**data, "engine": "command"}
        members: tuple[tuple[str, float | None], ...] = ()
        if "portfolio" in data:
            if set(data) & {"command", "engine", "register", "params"}:
                raise PlannerError(f"{source}: a 'portfolio' runs other registry entries: "
                                   "give it no 'engine', 'params', 'register' or 'command'")
            members = portfolio.parse_members(data["portfolio"], source)
            data = {**data, "engine": "portfolio"}
        for key in ("name", "engine", "encoding"):
            if not isinstance(data.get(key), str) or not data[key]:
                raise PlannerError(f"{source}: '{key}' must be a non-empty string")
        if data["encoding"] not in ENCODINGS:
            raise PlannerError(f"{source}: encoding {data['encoding']!r} is not one of {ENCODINGS}")
        timeout = data.get("timeout", 60.0)
        if not isinstance(timeout, (int, float)) or timeout <= 0:
            raise PlannerError(f"{source}: timeout must be a positive number of seconds")
        params = data.get("params") or {}
        requires = data.get("requires") or {}
        env = data.get("env") or {}
        if not all(isinstance(x, dict) for x in (params, requires, env)):
            raise PlannerError(f"{source}: 'params', 'requires' and 'env' must be mappings")
        return cls(
            name=data["name"], engine=data["engine"], encoding=data["encoding"],
            timeout=float(timeout), params=dict(params),
            modules=tuple(requires.get("modules") or ()),
            binaries=tuple(requires.get("binaries") or ()),
            register=data.get("register"), env={str(k): str(v) for k, v in env.items()},
            notes=str(data.get("notes") or "").strip(), command=command, portfolio=members,
        )


@dataclass
class PlanResult:
    """The outcome of one planner run. ``status`` is one of :data:`STATUSES`.

    ``plan`` is the UP plan (SequentialPlan / TimeTriggeredPlan) bound to the
    caller's problem, ``steps`` the same plan as JSON-friendly dicts. ``cost`` is
    the value of the problem's action-cost metric (or the plan length),
    ``makespan`` the end of the last action of a temporal plan. ``planning_time``
    (also ``wall_time``) is wall time (process start included); ``cpu_time`` the CPU
    seconds of the planner process and every process of its group (at the last sample
    when it was stopped), the number the CPU limit ``cpu_limit`` is compared with and a
    steady one on a loaded machine. ``wall_limit`` is the wall-clock safety limit of the
    call; ``limit_hit`` says which limit stopped a ``timeout``: "cpu", "wall", or "engine"
    (the engine stopped itself at the time limit it was given; "" when none was hit). ``validated`` is
    None when validation was skipped, else whether every validator accepted.
    """

    status: str
    engine: str
    planner: str
    plan: Any = None
    steps: list[dict[str, Any]] = field(default_factory=list)
    planning_time: float = 0.0
    cpu_time: float | None = None
    cpu_limit: float | None = None
    wall_limit: float | None = None
    limit_hit: str = ""
    cost: float | None = None
    makespan: float | None = None
    plan_length: int | None = None
    optimal: bool = False
    validated: bool | None = None
    validation_detail: str = ""
    reason: str = ""
    notes: list[str] = field(default_factory=list)
    pgid: int | None = None

    @property
    def solved(self) -> bool:
        return self.status == "solved"

    @property
    def wall_time(self) -> float:
        """Wall seconds of the call (the same as ``planning_time``)."""
        return self.planning_time

    def to_dict(self) -> dict[str, Any]:
        """Everything but the UP plan object, ready for ``json.dumps``."""
        out = asdict(self)
        out.pop("plan")
        out["wall_time"] = self.planning_time
        return out


# ---------------------------------------------------------------- registry

def planners_dir() -> Traversable:
    """Where the planner configurations are read from: ``OCPLUS_PLANNERS_DIR`` when set,
    else the shipped ones (package data from the top-level ``planners/``)."""
    override = os.environ.get("OCPLUS_PLANNERS_DIR")
    if override:
        return Path(override)
    from ..data import data_files

    return data_files("planners")


def load_registry(directory: str | os.PathLike[str] | None = None) -> dict[str, PlannerConfig]:
    """Read every ``*.yaml`` planner config in ``directory`` (default :func:`planners_dir`)."""
    root = Path(directory) if directory else planners_dir()
    if not root.is_dir():
        raise PlannerError(f"planner configs not found: {root} is not a directory; "
                           "point OCPLUS_PLANNERS_DIR at a folder of planner YAML files")
    registry: dict[str, PlannerConfig] = {}
    for path in sorted((f for f in root.iterdir() if f.name.endswith(".yaml")),
                       key=lambda f: f.name):
        config = load_config(path)
        if config.name in registry:
            raise PlannerError(f"{path}: planner name {config.name!r} is defined twice")
        registry[config.name] = config
    return registry


def load_config(path: str | os.PathLike[str] | Traversable) -> PlannerConfig:
    """One planner YAML file (a shipped one, or a user's: see ``planners/README.md``)."""
    import yaml

    source = Path(path) if isinstance(path, (str, os.PathLike)) else path
    try:
        data = yaml.safe_load(source.read_text(encoding="utf-8"))
    except yaml.YAMLError as exc:
        raise PlannerError(f"{path}: not valid YAML: {exc}") from exc
    return PlannerConfig.from_mapping(data, str(path))


@lru_cache(maxsize=1)
def _default_registry() -> dict[str, PlannerConfig]:
    return load_registry()


def planner_names(encoding: str | None = None) -> list[str]:
    """Registry names, optionally only those for one encoding."""
    return sorted(n for n, c in _default_registry().items()
                  if encoding is None or c.encoding == encoding)


def get_planner(name: str | PlannerConfig) -> PlannerConfig:
    """The config of a registry name; an unknown name raises PlannerError listing all."""
    if isinstance(name, PlannerConfig):
        return name
    if name.endswith((".yaml", ".yml")):  # a planner YAML of the user's, by path
        if not Path(name).is_file():
            raise PlannerError(f"planner config {name} does not exist")
        return _config_at(str(Path(name).resolve()))
    registry = _default_registry()
    if name not in registry:
        known = ", ".join(sorted(registry))
        raise PlannerError(f"unknown planner {name!r}; known planners: {known}")
    return registry[name]


@lru_cache(maxsize=32)
def _config_at(path: str) -> PlannerConfig:
    return load_config(path)


@dataclass(frozen=True)
class Availability:
    """Whether a planner can run here, and if not, why (the fix is in the reason)."""

    ok: bool
    reason: str = ""


def availability(name: str | PlannerConfig) -> Availability:
    """Check modules, binaries and the UP factory entry of a planner (cached per process)."""
    return _availability(get_planner(name))


@cache
def _availability(config: PlannerConfig) -> Availability:
    if config.portfolio:
        for member, _ in config.portfolio:
            sub = get_planner(member)
            problem = portfolio.member_problem(config.name, config.encoding, sub)
            if problem:
                return Availability(False, problem)
            found = availability(sub)
            if not found.ok:
                return Availability(False, f"member {member}: {found.reason}")
        return Availability(True)
    for module in config.modules:
        if importlib.util.find_spec(module) is None:
            return Availability(False, f"Python package {module!r} is not installed; "
                                       "install the planners extra: pip install -e '.[planners]'")
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                importlib.import_module(module)
        except Exception as exc:  # noqa: BLE001 - e.g. up_lpg without pkg_resources (setuptools>=81)
            return Availability(False, f"importing {module!r} failed ({type(exc).__name__}: "
                                       f"{exc}); see planners/README.md for working pins")
    for binary in config.binaries:
        if shutil.which(binary) is None:
            return Availability(False, f"the {binary!r} executable is not on PATH "
                                       f"(e.g. apt-get install default-jre-headless for java)")
    if config.command:
        problem = _command.program_problem(config.command)
        return Availability(not problem, problem)
    try:
        _register(config)
    except Exception as exc:  # noqa: BLE001 - reported as data
        return Availability(False, f"registering {config.engine!r} with unified-planning "
                                   f"failed: {type(exc).__name__}: {exc}")
    factory = _up_environment().factory
    if config.engine not in factory.engines:
        return Availability(False, f"unified-planning has no engine named {config.engine!r}")
    return Availability(True)


def available_planners(encoding: str | None = None) -> list[str]:
    """Registry names whose planner is installed and runnable here."""
    return [n for n in planner_names(encoding) if availability(n).ok]


def _up_environment() -> Any:
    try:
        from unified_planning.shortcuts import get_environment
    except ImportError as exc:  # pragma: no cover - a core dependency
        raise DependencyNotInstalled("unified-planning is missing: pip install -e .") from exc
    return get_environment()


def _register(config: PlannerConfig) -> None:
    if not config.register:
        return
    module, _, func = config.register.partition(":")
    if not func:
        raise PlannerError(f"planner {config.name!r}: register must be 'module:function', "
                           f"got {config.register!r}")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        getattr(importlib.import_module(module), func)()


# ------------------------------------------------------------------ solving

def solve(problem: Any, planner: str | PlannerConfig, timeout: float | None = None,
          validate: bool = True, use_val: bool = True,
          wall_limit: float | None = None, memory_limit: float | None = None) -> PlanResult:
    """Solve a UP problem with a named planner in an isolated, CPU-limited process.

    ``timeout`` is the CPU limit (default: the planner's): the CPU seconds (user + system)
    of the planner's whole process group, as the IPC counts them; the group is killed
    when it has used them, so a loaded machine slows a planner down without cutting its
    search short. ``wall_limit`` (default :func:`wall_safety` of the CPU limit) is a
    wall-clock safety for a planner that waits without computing. The engine itself is
    given the wall limit as its own time limit (it would otherwise stop early on a loaded
    machine), except an anytime engine (``anytime: true`` in its params), which uses its
    time limit as its improvement budget and gets the CPU limit (its budget is then wall
    time: how far it improves depends on the load, not whether it finds a plan).
    ``memory_limit`` (MiB; None: none) caps the address space of the engine's process
    and every process it starts (``RLIMIT_AS``); running out is status ``memout``.
    With ``validate``, the plan is checked by UP's validator and by VAL (unless
    ``use_val`` is False or VAL is missing); a rejected plan gets status ``invalid``.
    """
    config = get_planner(planner)
    limit = float(timeout if timeout is not None else config.timeout)
    if not limit > 0 or limit == float("inf"):
        raise PlannerError(f"timeout must be a positive number of CPU seconds, got {timeout!r}")
    wall = float(wall_limit) if wall_limit is not None else wall_safety(limit)
    if not wall > 0 or wall == float("inf"):
        raise PlannerError(f"wall_limit must be a positive number of seconds, got {wall_limit!r}")
    result = PlanResult(status="unavailable", engine=config.engine, planner=config.name,
                        cpu_limit=limit, wall_limit=wall)
    avail = availability(config)
    if not avail.ok:
        result.reason = avail.reason
        return result
    if config.portfolio:
        result.status = "timeout"
        return portfolio.run(config, limit, lambda member, budget: solve(
            problem, member, budget, validate, use_val, wall_safety(budget)), result)

    anytime = config.params.get("anytime") is True
    own_limit = min(limit, wall) if anytime else wall
    # A private working directory: Fast Downward and SymK write output.sas into the current
    # directory, so two solves in one directory (two test runs) corrupt each other's files.
    workdir = tempfile.mkdtemp(prefix="ocplus-solve-", dir=short_temp_base())
    try:
        if config.command:
            outcome = _command.run_command(problem, config.command, limit, workdir,
                                           wall, config.env, memory_limit)
        else:
            outcome = _proc.run_isolated(_solve_in_child,
                                         (problem, config, own_limit, workdir, memory_limit),
                                         hard_limit=wall + GRACE_SECONDS,
                                         cpu_limit=limit + (GRACE_SECONDS if anytime else 0.0))
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
    result.planning_time = round(outcome.wall_time, 4)
    result.pgid = outcome.pgid
    if outcome.cpu_time is not None:
        result.cpu_time = round(outcome.cpu_time, 4)
    if outcome.kind == _proc.TIMEOUT:
        result.status, result.reason = "timeout", outcome.value
        result.limit_hit = outcome.limit or ""
        return result
    if outcome.kind in (_proc.CRASHED, _proc.RAISED):
        result.status = "crashed" if outcome.kind == _proc.CRASHED else "error"
        result.reason = outcome.value + _tail_hint(outcome.log_tail)
        if memory_limit and _command.out_of_memory(outcome.value + outcome.log_tail):
            result.status = "memout"
        return result

    return _from_report(result, outcome.value, problem, validate, use_val)


def _from_report(result: PlanResult, report: dict[str, Any], problem: Any, validate: bool,
                 use_val: bool) -> PlanResult:
    """Fill ``result`` from the child's report: status, plan (rebound to ``problem``),
    quality and validation."""
    result.notes = report["notes"]
    if report.get("cpu_time") is not None:
        result.cpu_time = report["cpu_time"]
    result.status = report.get("status") or _UP_STATUS.get(report["up_status"], "error")
    if result.status == "timeout":
        result.limit_hit = report.get("limit_hit", "engine")
    result.optimal = report["up_status"] == "SOLVED_OPTIMALLY"
    result.reason = report.get("reason", "")
    if result.status == "unsolvable" and "Traceback (most recent call last)" in report["log"]:
        # UP's FD/SymK wrappers report a crashed translator as UNSOLVABLE_PROVEN
        result.status = "error"
        result.reason = (f"engine reported {report['up_status']} after a Python traceback, "
                         "so the planner failed rather than proved anything")
        result.reason += _tail_hint(report["log"])
        return result
    if result.status == "error" and _command.out_of_memory(report["log"]):
        result.status = "memout"
    compiled_in = re.search(r"recompiled with a higher value for the parameter (\w+)", report["log"])
    if result.status == "error" and compiled_in:  # LPG-td's fixed array sizes
        result.status, result.reason = "unsupported", (
            f"too big for LPG-td: its compiled-in limit {compiled_in.group(1)} is exceeded "
            "(fixed in the binary up-lpg ships; no runtime option raises it)")
    if result.status != "solved":
        if not result.reason:
            result.reason = f"engine reported {report['up_status']}" + _tail_hint(report["log"])
        return result
    if report["steps"] is None:
        result.status, result.reason = "error", "engine reported success but returned no plan"
        return result
    try:
        result.plan = plan_from_steps(problem, report["steps"], report["temporal"])
    except Exception as exc:  # noqa: BLE001 - reported as data
        result.status = "error"
        result.reason = f"the plan names something the problem lacks: {type(exc).__name__}: {exc}"
        return result
    result.steps = plan_to_steps(result.plan)
    result.plan_length = len(result.steps)
    check = validate_plan(problem, result.plan, use_val=use_val) if validate else None
    if check is not None and check.cost is not None:  # the validator already evaluated it
        result.cost = check.cost
        result.makespan = plan_quality(problem, result.plan, with_cost=False).makespan
    else:
        quality = plan_quality(problem, result.plan)
        result.cost, result.makespan = quality.cost, quality.makespan
    if check is not None:
        result.validated, result.validation_detail = check.ok, check.detail
        if check.ok is False:
            result.status = "invalid"
            result.reason = "the planner's plan was rejected by validation: " + check.detail
    return result


def _tail_hint(log: str) -> str:
    lines = [ln for ln in log.strip().splitlines() if ln.strip()]
    return f"; last output: {' | '.join(lines[-3:])[:400]}" if lines else ""


def _freeze_queries(problem: Any, writes_pddl: bool = True) -> None:
    """In the (disposable) planner child: answer ``problem.kind`` and ``initial_values``
    from one computation each.

    UP recomputes the kind on every access (five times per Fast Downward solve), and
    ``initial_values`` builds an expression for every grounding of every fluent although
    the PDDL writer, its only user here, skips the false ones. Together that was a
    third of a Fast Downward call on MapC (profiled: ~0.4 of ~1.2 s). The problem is
    final once it reaches the engine, so the kind is computed once, and the initial
    values are the explicit ones plus every numeric grounding (the writer prints those,
    defaults included); an engine that reads the problem itself (``writes_pddl`` False:
    TAMER, Aries) gets every grounding, computed once. Only classes in this child are
    patched; it exits after the solve.
    """
    from unified_planning.model.fluent import get_all_fluent_exp

    cls = type(problem)
    kind = problem.kind
    if writes_pddl:
        values = dict(problem.explicit_initial_values)
        defaults = problem.fluents_defaults
        for fluent in problem.fluents:
            if fluent.type.is_bool_type() or fluent not in defaults:
                continue
            for exp in get_all_fluent_exp(problem, fluent):
                values.setdefault(exp, defaults[fluent])
    else:
        values = dict(problem.initial_values)
    plain_kind, plain_values = cls.kind, cls.initial_values
    cls.kind = property(lambda self: kind if self is problem else plain_kind.fget(self))
    cls.initial_values = property(
        lambda self: values if self is problem else plain_values.fget(self))


#: the longest temporary folder planners get their files in; a longer TMPDIR (macOS gives
#: about 50 characters) is replaced by /tmp, since some planners overflow fixed-size buffers
#: on long paths (LPG)
MAX_TEMP_BASE_CHARS = 30


def short_temp_base() -> str:
    """The temporary folder when its path is short, else /tmp (where writable)."""
    base = tempfile.gettempdir()
    if len(base) <= MAX_TEMP_BASE_CHARS or not os.access("/tmp", os.W_OK | os.X_OK):
        return base
    return "/tmp"


def _solve_in_child(problem: Any, config: PlannerConfig, limit: float,
                    workdir: str, memory_limit: float | None = None) -> dict[str, Any]:
    """Runs in the forked child: call the engine and return a picklable report."""
    warnings.simplefilter("ignore")
    _command.limit_memory(memory_limit)
    os.chdir(workdir)
    # the engines' own temporary files go here too: a short path whatever TMPDIR is
    # (LPG aborts with "buffer overflow detected" on long file names)
    tempfile.tempdir = workdir
    from unified_planning.shortcuts import OneshotPlanner

    os.environ.update(config.env)  # only in this child and the planner processes it starts
    env = _up_environment()
    env.credits_stream = None
    _register(config)
    notes: list[str] = []
    report: dict[str, Any] = {"notes": notes, "steps": None, "log": "",
                              "temporal": False, "up_status": "INTERNAL_ERROR"}
    with OneshotPlanner(name=config.engine, params=dict(config.params) or None) as engine:
        target, why = adapt_for_engine(problem, engine.supports,
                                       type(engine).supported_kind(), config.engine, notes)
        if target is None:
            report["up_status"], report["reason"] = "UNSUPPORTED_PROBLEM", why
            return report
        from unified_planning.engines.pddl_planner import PDDLPlanner

        _freeze_queries(target, writes_pddl=isinstance(engine, PDDLPlanner))
        res = engine.solve(target, timeout=limit)
        # planner servers still running (Aries) are not in RUSAGE_CHILDREN: add them
        servers_cpu = _proc.group_cpu_seconds(os.getpgid(0), exclude=(os.getpid(),))
    report["up_status"] = res.status.name
    usage = [resource.getrusage(who) for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)]
    report["cpu_time"] = round(sum(u.ru_utime + u.ru_stime for u in usage) + servers_cpu, 4)
    report["log"] = "\n".join(str(m) for m in (res.log_messages or []))[-2000:]
    if res.plan is not None:
        report["temporal"] = res.plan.kind.name == "TIME_TRIGGERED_PLAN"
        report["steps"] = plan_to_steps(res.plan)
    return report


__all__ = [
    "ENCODINGS",
    "GRACE_SECONDS",
    "WALL_FACTOR",
    "WALL_SLACK",
    "STATUSES",
    "Availability",
    "PlanResult",
    "PlannerConfig",
    "availability",
    "available_planners",
    "get_planner",
    "wall_safety",
    "load_config",
    "load_registry",
    "planner_names",
    "planners_dir",
    "solve",
    "without_quality_metrics",
]
