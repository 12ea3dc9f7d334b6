"""Hostile data for the command line, second group: checkpoints, ``--rules`` values, result
files, check-plan inputs and small argument cases (docs/input-limits.md).

:func:`build_data` writes the files under a folder and returns one :class:`Case` per
command line, with the exit code it must end with (2: refused with one line; 0: handled,
as documented, e.g. a bad row in ``results.jsonl`` is skipped and counted). Cases run in
order: a later case may read what an earlier one left (a resumed folder is reported).
``MARKER`` must never exist afterwards: every planted checkpoint tries to create it.
"""

from __future__ import annotations

import base64
import io
import json
import os
import pickle
import zipfile
from pathlib import Path
from typing import NamedTuple

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = ROOT / "experiments" / "checkpoints"
MARKER = "planted-checkpoint-ran"
#: the folder the corpus holds locked (``results.folder_lock``) while the cases run
LOCKED = "locked_run"


class Case(NamedTuple):
    name: str
    argv: list[str]
    expected: int


class _System:
    """Pickles as a call of ``os.system(command)``."""

    def __init__(self, command: str) -> None:
        self.command = command

    def __reduce__(self):
        return (os.system, (self.command,))


def planted_sb3(path: Path, marker: Path) -> Path:
    """The shipped easy SB3 checkpoint with ``os.system('touch MARKER')`` pickled into its
    ``data`` member (SB3's loader would unpickle it)."""
    with zipfile.ZipFile(SHIPPED / "easy_1agent.zip") as zf:
        members = {n: zf.read(n) for n in zf.namelist()}
    data = json.loads(members["data"])
    blob = base64.b64encode(pickle.dumps(_System(f"touch {marker}"))).decode()
    data["observation_space"] = {":type:": "x", ":serialized:": blob}
    members["data"] = json.dumps(data).encode()
    with zipfile.ZipFile(path, "w") as zf:
        for name, raw in members.items():
            zf.writestr(name, raw)
    return path


def _npz(path: Path, members: dict[str, bytes], deflate: bool = True) -> Path:
    method = zipfile.ZIP_DEFLATED if deflate else zipfile.ZIP_STORED
    with zipfile.ZipFile(path, "w", method) as zf:
        for name, raw in members.items():
            zf.writestr(name, raw)
    return path


def _npy_header(shape: tuple[int, ...], descr: str = "<f4") -> bytes:
    import numpy as np

    raw = io.BytesIO()
    np.lib.format.write_array_header_1_0(raw, {"descr": descr, "fortran_order": False,
                                               "shape": shape})
    return raw.getvalue()


def checkpoint_files(root: Path) -> dict[str, Path]:
    """Hostile checkpoints: a planted SB3 zip, a pickled object array, a header that asks
    for a terabyte, a member that expands to 400 MB."""
    marker = root / MARKER
    evil = _System(f"touch {marker}")
    return {
        "sb3": planted_sb3(root / "planted.zip", marker),
        "object": _npz(root / "object.npz", {"ocplus_meta.npy": _npy_header((1,), "|O")
                                             + pickle.dumps([evil])}),
        "header": _npz(root / "header.npz", {"w.npy": _npy_header((1 << 20, 1 << 20))
                                             + b"\0" * 64}),
        "bomb": _bomb(root / "bomb.npz"),
    }


def _bomb(path: Path) -> Path:
    """A .npz of about 400 kB whose one member expands to 400 MB (its sizes declared)."""
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
        with zf.open("w.npy", "w", force_zip64=True) as fh:
            fh.write(_npy_header((100_000_000,)))
            zeros = bytes(1 << 22)
            for _ in range(400_000_000 // len(zeros)):
                fh.write(zeros)
    return path


def result_folders(root: Path) -> dict[str, Path]:
    """Evaluation folders whose ``results.jsonl`` is damaged, forged or no file at all."""
    from ocplus_plan.eval.results import row_key

    def row(seed: int, **kw: object) -> str:
        r = {"preset": "easy", "map": "easy_open", "n_agents": 1, "agent": "greedy",
             "seed": seed, "horizon": 5, "status": "ok", "metrics": {"dishes_served": 0}}
        r.update(kw)
        r["key"] = row_key(r)
        return json.dumps(r) + "\n"

    def folder(name: str, content: bytes | None = None) -> Path:
        d = root / name
        d.mkdir()
        if content is not None:
            (d / "results.jsonl").write_bytes(content)
        return d

    forged = json.loads(row(0))
    forged["horizon"] = 99999  # the key still says 5
    out = {
        "garbage_last": folder("garbage_last", (row(0) + "garbage").encode()),
        "not_object": folder("not_object", (row(0) + "[1, 2]\n\"x\"\n").encode()),
        "list_for_string": folder("list_for_string", (row(0) + row(1, agent=["greedy"]))
                                  .encode()),
        "binary": folder("binary", row(0).encode() + bytes(range(256)) + b"\n"),
        "deep": folder("deep", (row(0) + "[" * 100_000 + "]" * 100_000 + "\n").encode()),
        "forged": folder("forged", (json.dumps(forged) + "\n").encode()),
        "torn": folder("torn", (row(0) + row(1)[:40]).encode()),
        "dev_full": folder("dev_full"),
        "fifo": folder("fifo"),
        "directory": folder("directory"),
        LOCKED: folder(LOCKED),
    }
    (out["dev_full"] / "results.jsonl").symlink_to("/dev/full")
    os.mkfifo(out["fifo"] / "results.jsonl")
    (out["directory"] / "results.jsonl").mkdir()
    return out


def plan_files(root: Path) -> dict[str, Path]:
    """check-plan inputs: a 5 MB problem, a plan of 180,000 actions under the 4 MB limit,
    a problem of 60,000 objects, an instance whose manifest is nested 100,000 deep."""
    out = {"domain": ROOT / "domains" / "classical_cells.pddl"}
    big = root / "big_problem.pddl"
    with big.open("wb") as fh:
        fh.truncate(5_000_000)  # sparse
    out["big_problem"] = big
    small = root / "small_problem.pddl"
    small.write_text("(define (problem p) (:domain ocplus_classical_cells-domain))\n")
    out["small_problem"] = small
    long_plan = root / "long.plan"
    long_plan.write_text("(a)\n" * 180_000)
    out["long_plan"] = long_plan
    empty = root / "empty.plan"
    empty.write_text("")
    out["empty_plan"] = empty
    many = root / "many_objects.pddl"
    objects = " ".join(f"s{i}" for i in range(60_000))
    many.write_text("(define (problem p) (:domain ocplus_classical_cells-domain)\n"
                    f" (:objects {objects} - spot)\n (:init)\n (:goal (and)))\n")
    out["many_objects"] = many
    instance = root / "deep_instance"
    instance.mkdir()
    (instance / "manifest.json").write_text('{"a":' * 100_000 + "1" + "}" * 100_000)
    out["deep_instance"] = instance
    return out


def _eval(out: Path, *extra: str, seeds: str = "1") -> list[str]:
    return ["eval", "--agents", "greedy", "--presets", "easy", "--n-agents", "1",
            "--seeds", seeds, "--horizon", "5", "--jobs", "1", "--quiet", "--out", str(out),
            *extra]


def build_data(root: Path) -> list[Case]:
    """Write every file of this group under ``root``; its cases, in order."""
    ck = checkpoint_files(root)
    res = result_folders(root)
    pl = plan_files(root)
    new = root / "runs"
    cases = [
        Case("ppo_planted_sb3_eval", _eval(new / "a", "--agents", f"ppo:{ck['sb3']}"), 2),
        Case("ppo_planted_sb3_partner", _eval(new / "b", "--n-agents", "2", "--partner",
                                              f"ppo:{ck['sb3']}"), 2),
        Case("ppo_planted_sb3_rollout", ["rollout", "--agents", f"ppo:{ck['sb3']}"], 2),
        Case("ppo_planted_sb3_train_init", ["train", "--init", str(ck["sb3"]), "--out",
                                            str(new / "t")], 2),
        Case("ppo_pickled_object_npz", ["rollout", "--agents", f"ppo:{ck['object']}"], 2),
        Case("ppo_terabyte_header_npz", ["rollout", "--agents", f"ppo:{ck['header']}"], 2),
        Case("ppo_400mb_member_npz", ["rollout", "--agents", f"ppo:{ck['bomb']}"], 2),
        Case("ppo_shipped_bare", ["rollout", "--agents", "ppo", "--preset", "hard",
                                  "--horizon", "20"], 0),
        Case("ppo_shipped_partner", _eval(new / "c", "--n-agents", "2", "--partner", "ppo"), 0),
        Case("rules_burn_time_huge", _eval(new / "d", "--rules", f"burn_time={2**40}",
                                           "--save-replays", "0"), 2),
        Case("rules_n_orders_1001", _eval(new / "e", "--rules", "n_orders=1001"), 2),
        Case("rules_n_orders_1e8_rollout", ["rollout", "--rules", "n_orders=100000000"], 2),
    ]
    for name in ("garbage_last", "not_object", "list_for_string", "binary", "deep"):
        cases.append(Case(f"results_{name}_report", ["report", str(res[name])], 0))
    cases += [
        Case("results_forged_resume", _eval(res["forged"], "--resume"), 0),
        Case("results_torn_resume", _eval(res["torn"], "--resume", seeds="0,1"), 0),
        Case("results_torn_then_report", ["report", str(res["torn"])], 0),
        Case("results_garbage_resume", _eval(res["garbage_last"], "--resume"), 0),
        Case("results_dev_full_report", ["report", str(res["dev_full"])], 2),
        Case("results_dev_full_resume", _eval(res["dev_full"], "--resume"), 2),
        Case("results_fifo_report", ["report", str(res["fifo"])], 2),
        Case("results_directory_report", ["report", str(res["directory"])], 2),
        Case("results_locked_folder", _eval(res[LOCKED]), 2),
        Case("checkplan_problem_5mb", ["check-plan", "--domain", str(pl["domain"]),
                                       "--problem", str(pl["big_problem"]), "--plan",
                                       str(pl["empty_plan"])], 2),
        Case("checkplan_180k_actions", ["check-plan", "--domain", str(pl["domain"]),
                                        "--problem", str(pl["small_problem"]), "--plan",
                                        str(pl["long_plan"])], 2),
        Case("checkplan_cpu_limit", ["check-plan", "--domain", str(pl["domain"]), "--problem",
                                     str(pl["many_objects"]), "--plan",
                                     str(pl["empty_plan"]), "--no-val", "--cpu-limit", "0.5"], 2),
        Case("checkplan_deep_manifest", ["check-plan", str(pl["deep_instance"])], 2),
        Case("faults_empty", _eval(new / "f", "--faults", ""), 2),
        Case("faults_commas", _eval(new / "g", "--faults", ",,,"), 2),
        Case("faults_fullwidth_digit", _eval(new / "h", "--faults", "burns:\uff13"), 2),
        Case("agents_empty_item", _eval(new / "i", "--agents", "greedy,,greedy"), 2),
        Case("seed_fullwidth_digit", ["rollout", "--seed", "\uff13"], 2),
        Case("generate_seed_past_max", ["generate", "--family", "open", "--no-prove",
                                        "--seed", "4294967295", "--n", "5", "--out",
                                        str(new / "gen")], 2),
        Case("generate_out_proc", ["generate", "--family", "open", "--no-prove", "--out",
                                   "/proc/ocplus-corpus"], 2),
        Case("solve_unknown_planner", ["solve", "--preset", "easy", "--planner", "nope"], 2),
    ]
    return cases
