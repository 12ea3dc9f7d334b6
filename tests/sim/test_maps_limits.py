"""Map files from anywhere: bounded size, nesting and aliases; strict keys; UTF-8 text.

Every refusal is a MapFormatError naming the file and the line/column or key at fault.
"""

from __future__ import annotations

import time
from pathlib import Path

import pytest

from ocplus_plan.cli import main
from ocplus_plan.errors import MapFormatError
from ocplus_plan.sim import load_map, make_rules
from ocplus_plan.sim.map_yaml import MAX_DEPTH, MAX_MAP_BYTES, MAX_NODES
from ocplus_plan.sim.maps import MAX_GRID_SIDE

SMALL = "name: s\ngame_map:\n  - [1, 3, 1, 6, 1]\n  - [5, 2, 0, 2, 7]\n  - [1, 1, 1, 1, 1]\n"


def write(tmp_path: Path, data: str | bytes, name: str = "m.yaml") -> Path:
    path = tmp_path / name
    if isinstance(data, str):
        path.write_text(data, encoding="utf-8")
    else:
        path.write_bytes(data)
    return path


def refused(path: Path, match: str) -> str:
    with pytest.raises(MapFormatError, match=match) as info:
        load_map(path)
    message = str(info.value)
    assert str(path) in message and "\n" not in message
    return message


def laughs(under: str, levels: int = 9) -> str:
    """The classic alias bomb: each level lists the previous one nine times."""
    lines = ['a0: &a0 ["lol"]']
    for k in range(1, levels + 1):
        lines.append(f"a{k}: &a{k} [" + ", ".join([f"*a{k - 1}"] * 9) + "]")
    return "\n".join(lines) + f"\n{under}: *a{levels}\n" + SMALL.split("\n", 1)[1]


def square(side: int, rows: int | None = None) -> str:
    """A legal side x side kitchen (every inner cell a spawn floor), ``rows`` rows of it."""
    grid = [[1] * side] + [[1] + [2] * (side - 2) + [1] for _ in range(side - 2)] + [[1] * side]
    grid[0][1:5] = [7, 3, 6, 5]
    grid = grid[: rows or side]
    return "game_map:\n" + "".join(f"  - {row}\n" for row in grid)


def test_a_byte_order_mark_is_accepted(tmp_path):
    plain = load_map(write(tmp_path, SMALL, "plain.yaml"))
    marked = load_map(write(tmp_path, "\ufeff" + SMALL, "bom.yaml"))
    assert (marked.grid == plain.grid).all() and marked.name == plain.name


def test_non_utf8_bytes_are_refused_with_the_line_and_column(tmp_path):
    path = write(tmp_path, SMALL.encode() + b"description: caf\xe9\n")
    refused(path, r"line 6, column 17: byte 0xe9 is not UTF-8")


def test_a_repeated_key_is_refused_naming_it_and_both_lines(tmp_path):
    path = write(tmp_path, SMALL + "name: again\n")
    refused(path, r"line 6, column 1: key 'name' repeats the one at line 1, column 1")


def test_a_repeated_key_inside_a_nested_mapping_is_refused(tmp_path):
    path = write(tmp_path, SMALL + "description: {a: 1, a: 2}\n")
    refused(path, "key 'a' repeats")


@pytest.mark.parametrize("under", ["description", "dimensions", "game_map"])
def test_an_alias_bomb_is_refused_before_it_grows(tmp_path, under):
    path = write(tmp_path, laughs(under))
    start = time.process_time()
    refused(path, f"more than {MAX_NODES} values once the aliases")
    assert time.process_time() - start < 5


def test_a_few_aliases_within_the_limits_load(tmp_path):
    text = ("game_map:\n  - &wall [1, 1, 1, 1, 1]\n  - [5, 2, 0, 2, 7]\n  - *wall\n"
            "switch_map:\n  - *wall\n  - [5, 2, 1, 2, 7]\n  - *wall\n")
    layout = load_map(write(tmp_path, text))
    assert layout.shape == (3, 5) and layout.is_dynamic


def test_a_recursive_alias_is_refused(tmp_path):
    refused(write(tmp_path, SMALL + "description: &d [1, *d]\n"), "recursive")


def test_deep_nesting_is_refused_with_its_line(tmp_path):
    path = write(tmp_path, SMALL + "description: " + "[" * 5000 + "]" * 5000 + "\n")
    refused(path, f"line 6, column .*nested more than {MAX_DEPTH} levels")


def test_a_file_over_the_size_limit_is_refused(tmp_path):
    path = write(tmp_path, SMALL + "# " + "x" * MAX_MAP_BYTES + "\n")
    refused(path, f"larger than {MAX_MAP_BYTES} bytes")


def test_too_many_rows_are_refused_naming_the_count(tmp_path):
    path = write(tmp_path, square(MAX_GRID_SIDE, rows=MAX_GRID_SIDE) +
                 "".join(f"  - {[1] * MAX_GRID_SIDE}\n" for _ in range(3)))
    refused(path, f"'game_map' has {MAX_GRID_SIDE + 3} rows; a map has at most {MAX_GRID_SIDE}")


def test_too_many_columns_are_refused_naming_the_row(tmp_path):
    path = write(tmp_path, square(MAX_GRID_SIDE + 1, rows=5))
    refused(path, f"'game_map' row 0 has {MAX_GRID_SIDE + 1} cells; a map has at most")


def test_a_2000_by_2000_map_is_refused_quickly(tmp_path):
    path = write(tmp_path, square(2000))
    start = time.process_time()
    refused(path, "larger than")
    assert time.process_time() - start < 2


def test_the_largest_legal_map_loads_and_check_map_finishes_fast(tmp_path, capsys):
    path = write(tmp_path, square(MAX_GRID_SIDE))
    start = time.process_time()
    assert main(["check-map", str(path)]) == 0
    assert time.process_time() - start < 5
    out = capsys.readouterr().out
    assert f"{MAX_GRID_SIDE} rows x {MAX_GRID_SIDE} cols" in out and "in all)" in out
    assert make_rules("easy", map=str(path)).layout.shape == (MAX_GRID_SIDE, MAX_GRID_SIDE)


def test_a_number_beyond_python_limits_is_refused(tmp_path):
    refused(write(tmp_path, SMALL + "max_n_agent: " + "9" * 6000 + "\n"), "value cannot be read")


def test_a_description_that_is_not_text_is_refused(tmp_path):
    refused(write(tmp_path, SMALL + "description: [1, 2]\n"), "'description' must be text")


def test_a_huge_value_is_not_repeated_in_the_message(tmp_path):
    message = refused(write(tmp_path, SMALL + f"dimensions: {list(range(5000))}\n"),
                      "'dimensions' must be")
    assert len(message) < 400


def test_the_cli_exits_2_with_one_line(tmp_path, capsys):
    path = write(tmp_path, laughs("description"))
    assert main(["check-map", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("ocplus: error: ") and "\n" not in err and str(path) in err
