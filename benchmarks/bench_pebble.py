"""One pebble-game threshold pass against one sparse factorisation of the same lattice.

For each size n: samples of the disordered triangular lattice (delta = DEFAULT_DELTA, seeds
``[n, k]``), the rods-only path ``p_r`` (p_t = 0). A *pass* is
``find_threshold(..., method="pebble")``: the rods added in the path's order, one incremental
pass of the fixed-torus pebble game up to the threshold event. Its unit of cost is one sparse
factorisation of the full lattice's Newton matrix (all sites rods,
``Problem(instance).factor(ones)``), measured in the same run on the same sample (median of
``--repeats``; the weights change by 1e-12 between repeats so that every call factorises).
The kernel is compiled (and cached) before any timing. Also timed: ``rigid_clusters`` of the
configuration at the threshold (rank, overconstrained bonds and labels of the sample at p_c), at
n <= ``--clusters-max``.

Run: python benchmarks/bench_pebble.py [--sizes 64 128 256 512] [--samples 5 5 3 2]
     [--clusters-max 256]

Writes the raw results to benchmarks/results/pebble.json and prints the table.
"""

from __future__ import annotations

import argparse
import json
import platform
import time
from pathlib import Path

import numpy as np

from tensegrity_rigidity import find_threshold, rigid_clusters
from tensegrity_rigidity.ensemble.thresholds import EventPath
from tensegrity_rigidity.model.lattice import DEFAULT_DELTA
from tensegrity_rigidity.model.network import Element, Instance
from tensegrity_rigidity.model.sampling import lattice_geometry
from tensegrity_rigidity.model.strain import strain_tensor
from tensegrity_rigidity.solver.problem import Problem

OUT = Path(__file__).resolve().parent / "results" / "pebble.json"
#: relative change of the weights between timed factorisations (defeats the factor cache)
WEIGHT_NUDGE = 1e-12
#: the issue's bound: a pass at n = 256 costs at most this many factorisations
TARGET_RATIO = 20.0


def factor_seconds(net, repeats: int) -> float:
    """Median time of ``Problem(full lattice).factor(weights)`` (numeric factorisation)."""
    full = Instance(net.with_kinds(np.full(net.n_sites, Element.ROD)), strain_tensor("dilation"))
    p = Problem(full)
    ones = np.ones(p.sites.size)
    p.factor(ones)  # the first call may set up the pattern
    times = []
    for k in range(repeats):
        w = ones * (1.0 + WEIGHT_NUDGE * (k + 1))
        t0 = time.perf_counter()
        p.factor(w)
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def one_sample(n: int, k: int, repeats: int, clusters: bool) -> dict:
    rng = np.random.default_rng([n, k])
    net, u, v = lattice_geometry(n, DEFAULT_DELTA, rng)
    eps = strain_tensor(float(rng.uniform(0, 2 * np.pi)), float(rng.uniform(0, 2 * np.pi)))
    t0 = time.perf_counter()
    th = find_threshold(net, u, v, eps, 0.0, 0.5, method="pebble")
    pass_s = time.perf_counter() - t0
    clusters_s, overconstrained, n_clusters = float("nan"), -1, -1
    if clusters:
        ev = EventPath(u, v, "p_r", 0.0, 0.5)
        at = int(np.searchsorted(ev.positions, th.s)) + 1  # the first rigid configuration
        t0 = time.perf_counter()
        r = rigid_clusters(net.with_kinds(ev.kinds(at)))
        clusters_s = time.perf_counter() - t0
        overconstrained, n_clusters = int(np.count_nonzero(r.overconstrained)), r.n_clusters
    fact = factor_seconds(net, repeats)
    return {
        "n": n,
        "sample": k,
        "threshold": th.s,
        "pass_seconds": pass_s,
        "clusters_seconds": clusters_s,
        "factor_seconds": fact,
        "ratio": pass_s / fact,
        "overconstrained_at_threshold": overconstrained,
        "clusters_at_threshold": n_clusters,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[64, 128, 256, 512])
    ap.add_argument("--samples", type=int, nargs="+", default=[5, 5, 3, 2])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--clusters-max", type=int, default=256)
    args = ap.parse_args()
    padded = args.samples + [args.samples[-1]] * len(args.sizes)
    counts = dict(zip(args.sizes, padded[: len(args.sizes)], strict=True))
    # compile (or load) the kernel before any timing
    net, u, v = lattice_geometry(4, DEFAULT_DELTA, np.random.default_rng(0))
    find_threshold(net, u, v, np.eye(2), 0.0, 0.5, method="pebble")
    rigid_clusters(net.with_kinds(np.full(net.n_sites, Element.ROD)))
    rows = []
    for n in args.sizes:
        for k in range(counts[n]):
            row = one_sample(n, k, args.repeats, n <= args.clusters_max)
            rows.append(row)
            print(
                f"n={n:4d} sample {k}: pass {row['pass_seconds']:.3f} s, factorisation "
                f"{row['factor_seconds']:.3f} s, ratio {row['ratio']:.2f}, clusters at p_c "
                f"{row['clusters_seconds']:.2f} s",
                flush=True,
            )
    summary = []
    for n in args.sizes:
        sel = [r for r in rows if r["n"] == n]
        summary.append(
            {
                "n": n,
                "samples": len(sel),
                "median_pass_seconds": float(np.median([r["pass_seconds"] for r in sel])),
                "max_pass_seconds": float(np.max([r["pass_seconds"] for r in sel])),
                "median_factor_seconds": float(np.median([r["factor_seconds"] for r in sel])),
                "median_ratio": float(np.median([r["ratio"] for r in sel])),
                "max_ratio": float(np.max([r["ratio"] for r in sel])),
                "median_clusters_seconds": float(np.median([r["clusters_seconds"] for r in sel])),
            }
        )
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(
        json.dumps(
            {
                "machine": f"{platform.processor() or platform.machine()}, "
                f"python {platform.python_version()}",
                "target_ratio_at_256": TARGET_RATIO,
                "summary": summary,
                "samples": rows,
            },
            indent=1,
        )
        + "\n"
    )
    print()
    print(
        "| n | samples | pass (median, max) | factorisation | ratio (median, max) "
        "| clusters at p_c |"
    )
    print("|---|---|---|---|---|---|")
    for s in summary:
        print(
            f"| {s['n']} | {s['samples']} | {s['median_pass_seconds']:.3f} s, "
            f"{s['max_pass_seconds']:.3f} s | {s['median_factor_seconds']:.3f} s | "
            f"{s['median_ratio']:.2f}, {s['max_ratio']:.2f} | "
            f"{s['median_clusters_seconds']:.2f} s |"
        )
    print(f"\nraw results: {OUT}")


if __name__ == "__main__":
    main()
