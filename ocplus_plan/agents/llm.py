"""A language model as a cook: any callable ``prompt -> reply`` (the user's model client).

Two ways to use one (registered as ``llm`` in :data:`ocplus_plan.agents.FACTORIES`):

* ``LLMAgent(model)`` (``mode="policy"``): every step the model reads the kitchen in
  words (:mod:`ocplus_plan.sim.observe_text`) and answers one line per driven cook,
  ``cook N: ACTION`` (ACTION: right, down, left, up, stay, or its number 0-4; a bare
  ACTION when it drives one cook).
* ``LLMAgent(model, mode="planner")``: when the executive asks for a plan, the model reads
  the kitchen in words plus the state's PDDL domain and problem (LLM+P style) and answers
  with a whole plan, one PDDL action per line. The plan is read against the problem
  (:mod:`ocplus_plan.planning.plan_text`), validated (UP's validator and VAL) and run by the
  executive like any planner's plan (:class:`~.planner.PlannerAgent`).

Nothing a model says is trusted: a reply is parsed, never evaluated, and a reply that cannot
be read (unknown action, bad number, a line of garbage, a reply over ``max_reply_chars``)
is an error naming the line: the cooks stay (policy) or the plan is refused (planner), and
the error is counted in :meth:`info` (``reply_errors``). A model that raises counts the same
way. Every prompt and reply is logged in :meth:`info` (``transcript``; ``log="errors"``
keeps only the exchanges that failed, ``log="none"`` none), which the evaluation writes to
its results. Nothing here downloads a model or opens a connection.
"""

from __future__ import annotations

import importlib
import re
import time
from collections.abc import Callable, Sequence
from typing import Any

from ..errors import ConfigError, UnreadableText
from ..sim.codes import Action
from ..sim.observe_text import actions_text, kitchen_text, rules_text
from ..sim.state import State
from ..sim.words import ACTION_BY_WORD, ACTION_WORDS, at
from .base import Controller

#: a model: prompt text in, reply text out
Model = Callable[[str], str]
MODES = ("policy", "planner")
LOG_LEVELS = ("all", "errors", "none")
#: the default limit on a reply (characters); a longer one is refused unread
MAX_REPLY_CHARS = 20_000
_COOK = re.compile(r"^cook\s+(\S+)$", re.IGNORECASE)
_ACTION_CHOICES = ", ".join(ACTION_WORDS[a] for a in Action)


def _show(text: str, limit: int = 60) -> str:
    return repr(text if len(text) <= limit else text[:limit] + "...")


def _action(word: str, number: int) -> int:
    """An action word or number (0-4) -> its index."""
    token = word.strip().rstrip(".").strip("`*'\"").lower()
    if token in ACTION_BY_WORD:
        return ACTION_BY_WORD[token]
    if re.fullmatch(r"[+-]?\d{1,6}", token):
        value = int(token)
        if 0 <= value < len(Action):
            return value
        raise UnreadableText(f"line {number}: {value} is not an action number (0-4: "
                             f"{_ACTION_CHOICES})", number)
    raise UnreadableText(f"line {number}: {_show(word.strip())} is not an action; use one of "
                         f"{_ACTION_CHOICES} (or its number 0-4)", number)


def parse_actions(reply: Any, agent_ids: Sequence[int],
                  max_chars: int = MAX_REPLY_CHARS) -> list[int]:
    """A policy reply -> one action per cook of ``agent_ids``, in that order.

    Lines ``cook N: ACTION``, one per driven cook (a bare ``ACTION`` line when only one cook
    is driven); blank lines and Markdown fences are skipped. Anything else raises
    :class:`UnreadableText` naming the line."""
    from ..planning.plan_text import check_size  # the same size rule as plan files

    check_size(reply, max_chars, "reply")
    chosen: dict[int, tuple[int, int]] = {}  # cook -> (action, line)
    for number, raw in enumerate(reply.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith("```"):
            continue
        head, colon, tail = line.partition(":")
        if not colon:
            if len(agent_ids) != 1:
                raise UnreadableText(
                    f"line {number}: {_show(line)}: you drive cooks "
                    f"{', '.join(map(str, agent_ids))}; write one line 'cook N: ACTION' each",
                    number)
            cook, action = agent_ids[0], _action(line, number)
        else:
            match = _COOK.match(head.strip())
            if match is None:
                raise UnreadableText(f"line {number}: {_show(line)} is not 'cook N: ACTION'",
                                     number)
            token = match.group(1)
            if not re.fullmatch(r"\d{1,6}", token):
                raise UnreadableText(f"line {number}: {_show(token)} is not a cook number",
                                     number)
            cook = int(token)
            if cook not in agent_ids:
                raise UnreadableText(f"line {number}: cook {cook} is not one of the cooks you "
                                     f"drive ({', '.join(map(str, agent_ids))})", number)
            action = _action(tail, number)
        if cook in chosen:
            raise UnreadableText(f"line {number}: cook {cook} already has an action (line "
                                 f"{chosen[cook][1]})", number)
        chosen[cook] = (action, number)
    missing = [a for a in agent_ids if a not in chosen]
    if missing:
        raise UnreadableText(f"no action for cook {', '.join(map(str, missing))}: write one "
                             "line 'cook N: ACTION' per cook", 0)
    return [chosen[a][0] for a in agent_ids]


class Transcript:
    """The model calls of one episode: counts, time, errors and (per ``log``) the text."""

    def __init__(self, model: Model, log: str = "all",
                 max_reply_chars: int = MAX_REPLY_CHARS) -> None:
        if not callable(model):
            raise ConfigError(f"the model must be a callable prompt -> reply, got "
                              f"{type(model).__name__}")
        if log not in LOG_LEVELS:
            raise ConfigError(f"log must be one of {', '.join(LOG_LEVELS)}, got {log!r}")
        if isinstance(max_reply_chars, bool) or not isinstance(max_reply_chars, int) \
                or max_reply_chars < 1:
            raise ConfigError(f"max_reply_chars must be a positive int, got {max_reply_chars!r}")
        self.model, self.log, self.max_reply_chars = model, log, max_reply_chars
        self.reset()

    def reset(self) -> None:
        self.calls = 0
        self.errors = 0
        self.model_time = 0.0
        self.entries: list[dict[str, Any]] = []
        self.last_error = ""

    def ask(self, t: int, prompt: str, read: Callable[[str], Any]) -> Any:
        """Call the model and read its reply with ``read``; None (and the error counted and
        remembered) when the model fails or its reply cannot be read."""
        self.calls += 1
        t0 = time.perf_counter()
        reply: Any = None
        error = ""
        try:
            reply = self.model(prompt)
        except Exception as exc:  # noqa: BLE001 - the user's client failing is data here
            error = f"the model call failed: {type(exc).__name__}: {exc}"
        self.model_time += time.perf_counter() - t0
        result = None
        if not error:
            try:
                result = read(reply)
            except UnreadableText as exc:
                error = str(exc)
        if error:
            self.errors += 1
        self.last_error = error
        if self.log == "all" or (self.log == "errors" and error):
            shown = reply if isinstance(reply, str) else repr(reply)
            self.entries.append({"t": t, "prompt": prompt,
                                 "reply": shown[: self.max_reply_chars], "error": error})
        return result

    def info(self) -> dict[str, object]:
        return {"model": getattr(self.model, "__name__", type(self.model).__name__),
                "model_calls": self.calls, "reply_errors": self.errors,
                "model_time_s": round(self.model_time, 6), "transcript": list(self.entries)}


POLICY_TASK = (
    "You are playing a cooperative cooking game as {who}. Serve the open orders as fast as "
    "you can.\nRules:\n{rules}\n\nThe kitchen now:\n{kitchen}\n\n{cooks}\n\n{feedback}"
    "Reply with exactly one line per cook you control, 'cook N: ACTION', where ACTION is one "
    "of {choices}. Write nothing else.")


class LLMAgent(Controller):
    """A controller whose cooks are played by a language model (see the module doc)."""

    name = "llm"

    def __init__(self, model: Model, mode: str = "policy", *, log: str = "all",
                 max_reply_chars: int = MAX_REPLY_CHARS, **planner_options: Any) -> None:
        if mode not in MODES:
            raise ConfigError(f"llm mode must be one of {', '.join(MODES)}, got {mode!r}")
        if mode == "policy" and planner_options:
            raise ConfigError(f"options {sorted(planner_options)} apply to mode='planner' only")
        self.mode = mode
        self.transcript = Transcript(model, log, max_reply_chars)
        self._planner: Any = None
        if mode == "planner":
            from .llm_planner import make_llm_planner_agent

            self._planner = make_llm_planner_agent(self.transcript, **planner_options)

    def _reset(self, state: State) -> None:
        self.transcript.reset()
        if self._planner is not None:
            self._planner.reset(state, self.agent_ids)

    def prompt(self, state: State) -> str:
        """The step's prompt: the rules, the kitchen, each driven cook's actions."""
        ids = self.agent_ids
        who = (f"cook {ids[0]}" if len(ids) == 1
               else "cooks " + ", ".join(map(str, ids)))
        cooks = "\n".join(
            f"Cook {a} is at {at(state, state.agent_pos[a])}; its actions now:\n"
            f"{actions_text(state, a)}" for a in ids)
        last = self.transcript.last_error
        feedback = (f"Your last reply could not be used ({last}); those cooks stayed.\n\n"
                    if last else "")
        return POLICY_TASK.format(who=who, rules=rules_text(state.rules),
                                  kitchen=kitchen_text(state), cooks=cooks, feedback=feedback,
                                  choices=_ACTION_CHOICES)

    def act(self, state: State) -> list[int]:
        if self._planner is not None:
            return self._planner.act(state)
        ids = self.agent_ids
        actions = self.transcript.ask(
            state.t, self.prompt(state),
            lambda reply: parse_actions(reply, ids, self.transcript.max_reply_chars))
        return actions if actions is not None else [int(Action.STAY)] * len(ids)

    def observe(self, state: State, events: Sequence[object]) -> None:
        if self._planner is not None:
            self._planner.observe(state, events)

    def info(self) -> dict[str, object]:
        base = self._planner.info() if self._planner is not None else {}
        return {**base, "mode": self.mode, **self.transcript.info()}


def load_model(path: str) -> Model:
    """``package.module:function`` -> that callable (imported, never evaluated as text)."""
    module_name, sep, attr = path.partition(":")
    ident = r"[A-Za-z_][A-Za-z0-9_]*"
    if not sep or not re.fullmatch(rf"{ident}(\.{ident})*", module_name) \
            or not re.fullmatch(rf"{ident}(\.{ident})*", attr):
        raise ConfigError(f"llm:{path}: give the model as MODULE:FUNCTION, e.g. "
                          "llm:mypkg.models:ask (a callable prompt -> reply)")
    try:
        target: Any = importlib.import_module(module_name)
    except ImportError as exc:
        raise ConfigError(f"llm:{path}: cannot import {module_name!r} ({exc}); is it on "
                          "PYTHONPATH?") from None
    for part in attr.split("."):
        if not hasattr(target, part):
            raise ConfigError(f"llm:{path}: {module_name!r} has no attribute {attr!r}")
        target = getattr(target, part)
    if not callable(target):
        raise ConfigError(f"llm:{path}: {attr!r} is a {type(target).__name__}, not a callable "
                          "prompt -> reply")
    return target  # type: ignore[no-any-return]


def make_llm_agent(arg: str | None, seed: int = 0) -> LLMAgent:
    """Factory for ``llm:MODULE:FUNCTION[:MODE]`` (MODE ``policy`` or ``planner``)."""
    if not arg:
        raise ConfigError("agent 'llm' needs the model: llm:MODULE:FUNCTION[:MODE], e.g. "
                          "llm:mypkg.models:ask or llm:mypkg.models:ask:planner")
    parts = arg.split(":")
    if len(parts) not in (2, 3):
        raise ConfigError(f"llm:{arg}: expected llm:MODULE:FUNCTION[:MODE]")
    mode = parts[2] if len(parts) == 3 else "policy"
    return LLMAgent(load_model(":".join(parts[:2])), mode)


__all__ = ["MAX_REPLY_CHARS", "LLMAgent", "Model", "Transcript", "load_model", "make_llm_agent",
           "parse_actions"]
