"""Verdict-search designs with strategies left out, on instances away from and near thresholds.

Decides (cold, no hints, ``min_norm=False``) four sets with the default strategies and with the
designs ``--designs`` (each a comma-separated list of strategy names left out): the small
random instances and test-suite instances of ``compare_releases.py`` (n = 4 to 10), 36
phase-diagram lattice instances at n = 32 and 64, and the probes at the seven events around the
thresholds of the near-threshold set at n = 16 and 32. Prints and records, per set and design,
the CPU time (``time.process_time``), the verdicts that differ from the default's and the
strategies that decided. A strategy that decides nothing the others don't and saves no time is a
candidate for deletion (``bench_strategies.py`` measures the searches themselves).

Run: python benchmarks/leave_one_out.py [--designs crossover newton newton,crossover]
     [--out benchmarks/results/leave_one_out.json]
"""

from __future__ import annotations

import argparse
import collections
import json
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
from compare_releases import _generate
from near_threshold_set import samples

from tensegrity_rigidity import Instance, decide, find_threshold, lattice_instance, load_instance
from tensegrity_rigidity.ensemble.thresholds import EventPath
from tensegrity_rigidity.solver.core import SolverOptions
from tensegrity_rigidity.solver.stages import DEFAULT_STRATEGIES

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
#: (p_r, p_t) of the phase-diagram instances, each at f_c = 0, 0.5 and 1
PHASE_POINTS = [(0.3, 0.2), (0.5, 0.3), (0.7, 0.2), (0.9, 0.05), (0.4, 0.5), (0.6, 0.35)]


def instance_sets() -> dict[str, list[Instance]]:
    """The four sets of instances, by name."""
    sys.path.insert(0, str(ROOT))  # the generator reads tests/ and benchmarks/ as packages
    with tempfile.TemporaryDirectory() as tmp:
        _generate(Path(tmp), 300, 100, [], [])
        sets = {"small": [load_instance(f) for f in sorted(Path(tmp).glob("*.npz"))]}
    sets["phase"] = [
        lattice_instance(
            n,
            p_r,
            p_t,
            f_c,
            phi=0.0,
            theta=0.3 * i,
            seed=np.random.default_rng([n, i, int(2 * f_c)]),
        )  # fmt: skip
        for n in (32, 64)
        for i, (p_r, p_t) in enumerate(PHASE_POINTS)
        for f_c in (0.0, 0.5, 1.0)
    ]
    for n, count in ((16, 12), (32, 6)):
        near = []
        for _, _, (net, u, v, eps, p_t, f_c) in samples(n, count):
            th = find_threshold(net, u, v, eps, p_t, f_c)
            if not np.isfinite(th.s):
                continue
            path = EventPath(u, v, "p_r", p_t, f_c)
            mid = int(np.searchsorted(path.positions, th.s))
            for event in range(max(mid - 3, 0), min(mid + 4, path.n_events + 1)):
                near.append(Instance(net.with_kinds(path.kinds(event)), eps))
        sets[f"near{n}"] = near
    return sets


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", nargs="+", default=["newton", "affine"])
    ap.add_argument("--out", type=Path, default=RESULTS / "leave_one_out.json")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    designs = {"default": ()} | {f"-{d}": tuple(d.split(",")) for d in args.designs}
    out: dict[str, dict] = {}
    for name, insts in instance_sets().items():
        reference = None
        for design, left_out in designs.items():
            strategies = tuple(x for x in DEFAULT_STRATEGIES if x.name not in left_out)
            opts = SolverOptions(min_norm=False, stages=strategies)
            cpu, status, stages = 0.0, [], collections.Counter()
            for inst in insts:
                t0 = time.process_time()
                v = decide(inst, opts)
                cpu += time.process_time() - t0
                status.append(v.status)
                stages[v.stage] += 1
            reference = reference or status
            differ = sum(a != b for a, b in zip(reference, status, strict=True))
            row = {"instances": len(insts), "cpu": cpu, "differences": differ}
            out.setdefault(name, {})[design] = row | {"stages": dict(stages)}
            print(f"{name} ({len(insts)}) {design}: {cpu:.2f} s, {differ} verdicts differ, "
                  f"decided by {dict(stages)}", flush=True)  # fmt: skip
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps({"designs": designs, "sets": out}, indent=1))
    print(f"written {args.out}")


if __name__ == "__main__":
    main()
