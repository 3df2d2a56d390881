"""Undecided probes solved again, one design of the verdict search after another.

The probes are the ``.npz`` files that ``bench_stages.py --save-undecided FOLDER`` writes: the
element kinds of one configuration of a near-threshold sample and the hints its threshold search
passed. Every design (``bench_stages.py``'s syntax) decides every probe in the same run; the
table gives per design the probes decided rigid or floppy, those left within resolution or not
resolved, and the seconds per probe (wall: median, max; CPU: median, steadier when the machine is
shared). Certified verdicts of two designs must never
contradict each other ('contradictions': must be 0).

Run: python benchmarks/resolve_probes.py FOLDER [--designs DESIGN ...] [--rods-only]
"""

from __future__ import annotations

import argparse
import re
import time
import warnings
from collections import Counter
from pathlib import Path

import numpy as np
from _record import machine, probe, record, table
from bench_stages import DEFAULT_DESIGNS, design
from near_threshold_set import CONFIGS, RODS_ONLY, sample

from tensegrity_rigidity.model.network import Instance
from tensegrity_rigidity.solver.core import SolverOptions, decide
from tensegrity_rigidity.solver.linalg import one_blas_thread

HEADER = ["stages", "probes", "rigid", "floppy", "within resolution", "not resolved",
          "median s", "max s", "median cpu s", "contradictions", "decided by"]  # fmt: skip


def load(path: Path, configs) -> tuple[str, Instance, dict]:
    """(name, instance, hints) of one saved probe."""
    n, c, k = map(int, re.match(r"n(\d+)_c(\d+)_k(\d+)_", path.name).groups())  # type: ignore[union-attr]
    net, _, _, eps, _, _ = sample(n, c, k, configs)
    data = np.load(path)
    hints = {key: data[key] for key in ("initial_displacements", "initial_tensions") if key in data}
    return path.stem, Instance(net.with_kinds(data["kinds"]), eps), hints


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder", type=Path)
    ap.add_argument("--designs", nargs="+", default=DEFAULT_DESIGNS[:1])
    ap.add_argument("--rods-only", action="store_true")
    args = ap.parse_args()
    configs = RODS_ONLY if args.rods_only else CONFIGS
    probes = [load(p, configs) for p in sorted(args.folder.glob("*.npz"))]
    if not probes:
        raise SystemExit(f"no .npz probes in {args.folder}")
    verdicts: dict[str, dict[str, str]] = {}
    rows, per_probe = [], []
    for text in args.designs:
        stages, options = design(text)
        opts = SolverOptions(min_norm=False, stages=stages, **options)
        label = text.replace(",", " ")
        kinds: Counter = Counter()
        by: Counter = Counter()
        secs, cpus = [], []
        for name, inst, hints in probes:
            probe()
            t0, c0 = time.perf_counter(), time.process_time()
            with one_blas_thread(), warnings.catch_warnings():
                warnings.simplefilter("ignore")
                v = decide(inst, opts, **hints)
            secs.append(time.perf_counter() - t0)
            cpus.append(time.process_time() - c0)
            kinds[v.reason or v.status] += 1
            by[v.stage or "undecided"] += 1
            verdicts.setdefault(name, {})[label] = v.status
            per_probe.append(
                {"probe": name, "stages": label, "status": v.status, "reason": v.reason,
                 "stage": v.stage, "seconds": secs[-1], "cpu seconds": cpus[-1]}
            )  # fmt: skip
            print(name, label, v.status, v.reason, v.stage, f"{secs[-1]:.2f}", flush=True)
        clash = sum({"rigid", "floppy"} <= set(d.values()) for d in verdicts.values())
        s = np.asarray(secs)
        rows.append(
            [label, len(probes), kinds["rigid"], kinds["floppy"], kinds["within resolution"],
             kinds["not resolved"], f"{np.median(s):.2f}", f"{s.max():.2f}",
             f"{np.median(cpus):.2f}", clash,
             ", ".join(f"{k} {v}" for k, v in sorted(by.items()))]
        )  # fmt: skip
        body = (
            f"Machine: {machine()}. Probes left undecided by a threshold search "
            f"(`bench_stages.py --save-undecided`, {args.folder.name}), each decided again with "
            "its hints by every design in the same run.\n\n" + table(HEADER, rows)
        )
        raw = {"designs": [dict(zip(HEADER, r, strict=True)) for r in rows], "probes": per_probe}
        record("resolve-probes", "Undecided probes solved again (resolve_probes.py)", body, raw=raw)


if __name__ == "__main__":
    main()
