"""House rule: a function holds at most 100 lines and a module at most 600 (a longer one
holds two ideas). Lines are counted from the ``def`` to the last line of the body,
decorators and docstrings included; a module counts every line of its file."""

from __future__ import annotations

import ast
from pathlib import Path

import ocplus_plan

PACKAGE_DIR = Path(ocplus_plan.__file__).parent
MAX_FUNCTION_LINES = 100
MAX_MODULE_LINES = 600

#: known offenders whose split is under way elsewhere, by name (the list empties at merge);
#: a name listed here that no longer breaks the rule fails the test, so the list only shrinks
ALLOWED: set[str] = set()


def function_lengths(path: Path) -> dict[str, int]:
    """``qualified.name -> lines`` for every function and method of one module."""
    lengths: dict[str, int] = {}

    def visit(node: ast.AST, prefix: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                name = f"{prefix}{child.name}"
                if not isinstance(child, ast.ClassDef):
                    start = min([child.lineno] + [d.lineno for d in child.decorator_list])
                    lengths[name] = child.end_lineno - start + 1
                visit(child, f"{name}.")
            else:
                visit(child, prefix)

    visit(ast.parse(path.read_text()), "")
    return lengths


def offenders() -> dict[str, int]:
    found = {}
    for path in sorted(PACKAGE_DIR.rglob("*.py")):
        rel = path.relative_to(PACKAGE_DIR).as_posix()
        lines = len(path.read_text().splitlines())
        if lines > MAX_MODULE_LINES:
            found[rel] = lines
        for name, n in function_lengths(path).items():
            if n > MAX_FUNCTION_LINES:
                found[f"{rel}::{name.rpartition('.')[2]}"] = n
    return found


def test_the_counter_measures_functions_and_methods(tmp_path):
    source = tmp_path / "m.py"
    source.write_text("class A:\n    @staticmethod\n    def f():\n        return 1\n\n\n"
                      "def g():\n    def h():\n        pass\n    return h\n")
    assert function_lengths(source) == {"A.f": 3, "g": 4, "g.h": 2}


def test_functions_and_modules_stay_within_the_limits():
    found = offenders()
    new = {k: v for k, v in found.items() if k not in ALLOWED}
    assert not new, f"over {MAX_FUNCTION_LINES} lines a function or {MAX_MODULE_LINES} a module: {new}"


def test_the_allow_list_names_only_real_offenders():
    stale = ALLOWED - set(offenders())
    assert not stale, f"no longer over the limits, remove from ALLOWED: {sorted(stale)}"
