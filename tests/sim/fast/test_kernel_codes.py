"""The kernels' codes are ``sim/codes.py``'s: every module-level code constant a kernel
module sees (``CELL_*``, ``ITEM_*``, ``STATE_*``, ``WHERE_*``, ``ACTION_*``) equals the enum
member of that name, and each is defined once, in ``sim/fast/arrays.py``, from the enum."""

from __future__ import annotations

import ast
import inspect
import re

import pytest

from ocplus_plan.rl.fast import features_kernels
from ocplus_plan.sim.codes import Action, Cell, Item, ItemState, Where
from ocplus_plan.sim.fast import arrays, kernels, observe_kernels

ENUMS = {"CELL": Cell, "ITEM": Item, "STATE": ItemState, "WHERE": Where, "ACTION": Action}
CODE_NAME = re.compile(r"^(CELL|ITEM|STATE|WHERE|ACTION)_([A-Z]+)$")
MODULES = (arrays, kernels, observe_kernels, features_kernels)


@pytest.mark.parametrize("module", MODULES, ids=lambda m: m.__name__.rpartition(".")[2])
def test_every_code_constant_equals_its_enum_member(module):
    found = {name: value for name, value in vars(module).items() if CODE_NAME.match(name)}
    assert found, f"{module.__name__} sees no code constant"
    for name, value in found.items():
        prefix, member = CODE_NAME.match(name).groups()
        assert type(value) is int, f"{name} is {type(value).__name__}: numba needs a plain int"
        assert value == ENUMS[prefix][member], f"{module.__name__}.{name} = {value}"


@pytest.mark.parametrize("module", MODULES, ids=lambda m: m.__name__.rpartition(".")[2])
def test_no_kernel_module_writes_a_code_as_a_number(module):
    """A module-level name bound to a bare int literal is a layout index, never a code."""
    tree = ast.parse(inspect.getsource(module))
    for node in tree.body:
        if not isinstance(node, ast.Assign):
            continue
        names = [n.id for t in node.targets for n in ast.walk(t) if isinstance(n, ast.Name)]
        codes = [n for n in names if CODE_NAME.match(n)]
        if codes:
            enums = {n.id for n in ast.walk(node.value) if isinstance(n, ast.Name)}
            assert module is arrays and enums & {e.__name__ for e in ENUMS.values()}, (
                f"{codes} in {module.__name__} not built from the enums of sim/codes.py")


def test_the_kernels_use_the_codes_they_are_given():
    """Every code name in a kernel body is one of the checked constants (a stray literal
    name such as ``_PAN`` would not be)."""
    for module in (kernels, observe_kernels, features_kernels):
        source = inspect.getsource(module)
        stray = set(re.findall(r"\b_(?:COUNTER|TOMATO|LETTUCE|ONION|STEAK|PLATE_KIND|BOARD|"
                               r"DELIVERY|PAN|SINK|TRASH|FRESH|CHOPPED|COOKED|BURNT|CLEAN|"
                               r"DIRTY|ON_PLATE|STAY)\b", source))
        assert not stray, f"{module.__name__} keeps private code copies {sorted(stray)}"
