"""Hand-made hostile inputs for the command line: maps, recordings and plan paths.

:func:`build` writes them under a folder and returns ``(name, argv)`` pairs; every one
must end with exit 2 and a one-line message (tests/fuzz/test_corpus.py).
"""

from __future__ import annotations

import gzip
import json
from pathlib import Path

SMALL_MAP = "game_map:\n  - [1, 3, 1, 6, 1]\n  - [5, 2, 0, 2, 7]\n  - [1, 1, 1, 1, 1]\n"


def _laughs(under: str) -> str:
    lines = ['a0: &a0 ["lol"]']
    for k in range(1, 10):
        lines.append(f"a{k}: &a{k} [" + ", ".join([f"*a{k - 1}"] * 9) + "]")
    return "\n".join(lines) + f"\n{under}: *a9\n" + SMALL_MAP


def _square(side: int) -> str:
    inner = "[1, " + "0, " * (side - 2) + "1]"
    return ("game_map:\n  - [7, 3, 6, 5" + ", 1" * (side - 4) + "]\n"
            + f"  - {inner}\n" * (side - 2) + "  - [1, 2" + ", 1" * (side - 2) + "]\n")


def map_files() -> dict[str, bytes]:
    """File name -> content of each hostile map."""
    row = "[" + ", ".join(["0"] * 2000) + "]"
    return {
        "laughs_description.yaml": _laughs("description").encode(),
        "laughs_dimensions.yaml": _laughs("dimensions").encode(),
        "aliased_rows.yaml": (f"game_map:\n  - &r {row}\n" + "  - *r\n" * 1999).encode(),
        "aliased_rows_big.yaml": (f"r: &r {row}\ngame_map:\n" + "  - *r\n" * 200_000).encode(),
        "square_2000.yaml": _square(2000).encode(),
        "square_65.yaml": _square(65).encode(),
        "latin1.yaml": SMALL_MAP.encode() + "description: caf\u00e9\n".encode("latin-1"),
        "utf16.yaml": SMALL_MAP.encode("utf-16"),
        "nested_5000.yaml": (SMALL_MAP + "description: " + "[" * 5000 + "]" * 5000).encode(),
        "nested_map_5000.yaml": (SMALL_MAP + "description: " + "{a: " * 5000
                                 + "1" + "}" * 5000).encode(),
        "duplicate_key.yaml": (SMALL_MAP + "game_map: [[7]]\n").encode(),
        "recursive_alias.yaml": (SMALL_MAP + "description: &d [*d]\n").encode(),
        "huge_integer.yaml": (SMALL_MAP + "max_n_agent: " + "9" * 10_000 + "\n").encode(),
        "python_tag.yaml": (SMALL_MAP + 'description: !!python/object/apply:os.system '
                            '["echo hostile"]\n').encode(),
        "binary.yaml": bytes(range(256)) * 64,
        "a_list.yaml": b"- 1\n- 2\n",
    }


def recording_files(good: list[str]) -> dict[str, bytes]:
    """File name -> content of each tampered recording, made from a good one's lines."""
    head = json.loads(good[0])

    def header(**changes: object) -> str:
        h = dict(head)
        h.update(changes)
        return json.dumps({k: v for k, v in h.items() if v is not KeyError})

    text = "\n".join(good) + "\n"
    flipped = bytearray(gzip.compress(text.encode()))
    for k in range(len(flipped) // 3, len(flipped) // 3 + 16):
        flipped[k] ^= 0x5A
    bad_types = dict(head, rules={**head["rules"], "horizon": [1]}, map="mapC")
    return {
        "flipped.jsonl.gz": bytes(flipped),
        "truncated.jsonl.gz": gzip.compress(text.encode())[: len(text) // 4],
        "truncated.jsonl": ("\n".join(good[:-3]) + "\n").encode(),
        "number_line.jsonl": "\n".join([good[0], "42", *good[1:]]).encode(),
        "missing_header_key.jsonl": "\n".join([header(preset=KeyError), *good[1:]]).encode(),
        "wrong_types.jsonl": "\n".join([json.dumps(bad_types), *good[1:]]).encode(),
        "negative_seed.jsonl": "\n".join([header(seed=-5), *good[1:]]).encode(),
        "string_seed.jsonl": "\n".join([header(seed="0"), *good[1:]]).encode(),
        "deep_nesting.jsonl": "\n".join([good[0], '{"a":' + "[" * 200_000 + "]" * 200_000
                                         + "}", *good[1:]]).encode(),
        "gzip_bomb.jsonl.gz": gzip.compress(b"0" * 30_000_000),
        "not_json.jsonl": b"\x00\x01\x02 not json\n",
    }


def build(root: Path, good_recording: list[str]) -> list[tuple[str, list[str]]]:
    """Write every hostile file under ``root``; ``(name, argv)`` for each case."""
    cases: list[tuple[str, list[str]]] = []
    for name, data in map_files().items():
        (root / name).write_bytes(data)
        cases.append((name, ["check-map", str(root / name)]))
    for name, data in recording_files(good_recording).items():
        (root / name).write_bytes(data)
        cases.append((name, ["replay", str(root / name), "--check"]))
    huge = root / "huge.plan"
    with huge.open("wb") as fh:
        fh.truncate(50_000_000)  # sparse
    (root / "d.pddl").write_text("(define (domain d))\n")
    for name, plan in (("plan_dev_zero", "/dev/zero"), ("plan_directory", str(root)),
                       ("plan_missing", str(root / "missing.plan")), ("plan_huge", str(huge))):
        cases.append((name, ["check-plan", "--domain", str(root / "d.pddl"), "--problem",
                             str(root / "d.pddl"), "--plan", plan]))
    cases.append(("map_dev_zero", ["check-map", "/dev/zero"]))
    return cases
