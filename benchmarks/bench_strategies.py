"""Per strategy of the default verdict search: the probes it alone decides and its time.

Searches the thresholds of the near-threshold set (``near_threshold_set.py``; ``--rods-only``:
the rods-only thresholds) with the default options, each strategy wrapped so that the time it
spends and the probes it decides are counted. Then every probe of those searches is decided
again cold (no hints) by the default strategies and by the default less each one strategy: a
probe that the default decides and the default less ``X`` does not is one that ``X`` alone
decides. A strategy that decides nothing the others don't and saves no time is a candidate for
deletion (issue 74, item 4). Writes a JSON record under ``benchmarks/results/`` (not
BENCHMARKS.md).

Run: python benchmarks/bench_strategies.py [--sizes 16 32 64] [--samples 6 6 2] [--rods-only]
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from collections import Counter
from pathlib import Path

from near_threshold_set import CONFIGS, RODS_ONLY, samples

from tensegrity_rigidity.ensemble import thresholds
from tensegrity_rigidity.ensemble.thresholds import find_threshold
from tensegrity_rigidity.solver.core import SolverOptions, decide
from tensegrity_rigidity.solver.stages import DEFAULT_STRATEGIES

RESULTS = Path(__file__).resolve().parent / "results"


class _Timed:
    """A strategy that runs another and counts its seconds and the probes it decides."""

    def __init__(self, inner, seconds: Counter, decided: Counter):
        self.inner, self.name = inner, inner.name
        self.seconds, self.decided = seconds, decided

    def run(self, search) -> None:
        t0 = time.process_time()
        self.inner.run(search)
        self.seconds[self.name] += time.process_time() - t0
        self.decided[self.name] += search.stage == self.name


def measure(n: int, count: int, configs) -> dict:
    """One size: the threshold searches, then the cold probes by leave-one-out designs."""
    seconds: Counter = Counter()
    decided: Counter = Counter()
    timed = tuple(_Timed(x, seconds, decided) for x in DEFAULT_STRATEGIES)
    opts = SolverOptions(min_norm=False, stages=timed)
    probes = []
    original = thresholds.decide

    def recording(instance, options=None, *args, **kwargs):
        probes.append(instance)
        return original(instance, options, *args, **kwargs)

    thresholds.decide = recording
    try:
        t0 = time.process_time()
        for _, _, (net, u, v, eps, p_t, f_c) in samples(n, count, configs):
            find_threshold(net, u, v, eps, p_t, f_c, options=opts)
        search_seconds = time.process_time() - t0
    finally:
        thresholds.decide = original
    base = SolverOptions(min_norm=False)
    alone: Counter = Counter()
    without_seconds: Counter = Counter()
    base_seconds = base_decided_seconds = 0.0
    for inst in probes:
        t0 = time.process_time()
        ref = decide(inst, base)
        base_seconds += time.process_time() - t0
        if not ref.decided:
            continue
        base_decided_seconds += time.process_time() - t0
        for x in DEFAULT_STRATEGIES:
            less = SolverOptions(
                min_norm=False, stages=tuple(y for y in DEFAULT_STRATEGIES if y is not x)
            )
            t0 = time.process_time()
            v = decide(inst, less)
            without_seconds[x.name] += time.process_time() - t0
            alone[x.name] += not v.decided
    return {
        "n": n,
        "samples": count,
        "probes": len(probes),
        "search_seconds": search_seconds,
        "strategy_seconds": dict(seconds),
        "strategy_decided": dict(decided),
        "cold_default_seconds": base_seconds,
        # the leave-one-out designs run on the decided probes only: compare with this
        "cold_default_seconds_decided": base_decided_seconds,
        "decides_alone": {x.name: alone[x.name] for x in DEFAULT_STRATEGIES},
        "cold_seconds_without": dict(without_seconds),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[16])
    ap.add_argument("--samples", type=int, nargs="+", default=[6])
    ap.add_argument("--rods-only", action="store_true")
    ap.add_argument("--out", type=Path, default=None)
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    configs = RODS_ONLY if args.rods_only else CONFIGS
    rows = [measure(n, k, configs) for n, k in zip(args.sizes, args.samples, strict=True)]
    for r in rows:
        print(f"n = {r['n']}: {r['probes']} probes, searches {r['search_seconds']:.1f} s")
        for x in DEFAULT_STRATEGIES:
            name = x.name
            print(
                f"  {name:10s} decides {r['strategy_decided'].get(name, 0):4d} in the searches, "
                f"{r['decides_alone'][name]:3d} alone; {r['strategy_seconds'].get(name, 0):7.2f} s"
                f" in the searches; cold probes without it {r['cold_seconds_without'][name]:.2f}"
                f" s against {r['cold_default_seconds_decided']:.2f} s"
            )
    out = args.out or RESULTS / ("bench_strategies-rods.json" if args.rods_only else
                                 "bench_strategies.json")  # fmt: skip
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"rods_only": args.rods_only, "sizes": rows}, indent=1))
    print(f"written {out}")


if __name__ == "__main__":
    main()
