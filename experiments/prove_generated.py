"""Solvability of the generated kitchens: the proof of ``ocplus generate --prove`` on the
first kitchens of a split, per family, and the generator's own speed.

For every family and index 0 .. N-1 of ``--split``: the kitchen ``gen:FAMILY:SPLIT:INDEX``
(hard stations, its drawn size and cooks) is proven with
:func:`ocplus_plan.planning.prove.prove_kitchen` (Fast Downward lama-first, all cooks
modelled, one steak+tomato+lettuce order, plan validated and replayed in the simulator);
when candidate 0 fails, the next candidates are tried as ``ocplus generate`` does. One JSON
line per kitchen (sizes, cooks, which model proved it, plan length, simulator steps,
planner CPU seconds, every try), then one summary line per family and a line with the
generator's time per kitchen (``--no-prove``: that line only).

    python experiments/prove_generated.py --split test --n 20 \
        --out experiments/results/generated_kitchens/proof_test_first20.jsonl
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import time
from typing import Any

from ocplus_plan.sim.generate import FAMILIES, generate_map, split_seed
from ocplus_plan.sim.maps import load_map


def _commit() -> str:
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                              text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def _prove(family: str, split: str, index: int, candidates: int, timeout: float
           ) -> dict[str, Any]:
    from ocplus_plan.planning.prove import prove_kitchen

    seed = split_seed(split, index)
    row: dict[str, Any] = {"family": family, "split": split, "index": index, "seed": seed,
                           "failed_candidates": []}
    for candidate in range(candidates):
        layout = load_map(generate_map(family, seed, candidate=candidate))
        proof = prove_kitchen(layout, "hard", timeout=timeout)
        row.update(candidate=candidate, rows=layout.rows, cols=layout.cols,
                   cooks=layout.max_agents, proof=proof.to_dict())
        if proof.ok:
            break
        row["failed_candidates"].append({"candidate": candidate, "reason": proof.reason})
    return row


def _summary(family: str, rows: list[dict[str, Any]]) -> dict[str, Any]:
    proofs = [r["proof"] for r in rows]
    ok = [p for p in proofs if p["ok"]]
    return {"summary": family, "kitchens": len(rows), "proven": len(ok),
            "proven_by_candidate_0": sum(r["candidate"] == 0 and r["proof"]["ok"] for r in rows),
            "by_model": {g: sum(p["granularity"] == g for p in ok) for g in ("stations", "cells")},
            "cooks": sorted({r["cooks"] for r in rows}),
            "sizes": sorted({f"{r['rows']}x{r['cols']}" for r in rows}),
            "median_plan_length": (sorted(p["plan_length"] for p in ok)[len(ok) // 2]
                                   if ok else None),
            "planner_cpu_s_total": round(sum(p["cpu_time"] for p in proofs), 2)}


def _generator_speed(split: str, n: int) -> dict[str, Any]:
    t0 = time.process_time()
    for family in FAMILIES:
        for index in range(n):
            generate_map(family, split_seed(split, index))
    per = (time.process_time() - t0) / (n * len(FAMILIES))
    return {"generator_cpu_ms_per_kitchen": round(per * 1000, 2), "kitchens": n * len(FAMILIES)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--split", default="test", choices=("train", "test"))
    ap.add_argument("--n", type=int, default=20, help="kitchens per family")
    ap.add_argument("--families", default=",".join(FAMILIES))
    ap.add_argument("--candidates", type=int, default=5)
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--no-prove", action="store_true")
    ap.add_argument("--out", default=None, help="also append the lines to this file")
    args = ap.parse_args()
    meta = {"commit": _commit(), "machine": platform.node(), "cpus": os.cpu_count(),
            "load_at_start": os.getloadavg()[0], "split": args.split, "n": args.n,
            "command": "python experiments/prove_generated.py " + " ".join(
                f"--{k.replace('_', '-')} {v}" for k, v in vars(args).items()
                if v not in (None, False))}
    sink = open(args.out, "a", encoding="utf-8") if args.out else None  # noqa: SIM115

    def emit(line: dict[str, Any]) -> None:
        text = json.dumps({**line, **meta})
        print(text, flush=True)
        if sink:
            sink.write(text + "\n")
            sink.flush()

    emit(_generator_speed(args.split, args.n))
    if not args.no_prove:
        for family in args.families.split(","):
            rows = []
            for index in range(args.n):
                row = _prove(family, args.split, index, args.candidates, args.timeout)
                rows.append(row)
                emit(row)
            emit({**_summary(family, rows), "load_at_end": os.getloadavg()[0]})
    if sink:
        sink.close()


if __name__ == "__main__":
    main()
