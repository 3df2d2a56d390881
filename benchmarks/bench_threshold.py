"""Per-sample threshold bisection: cold solves against warm starts from the nearest solved
configuration on the path.

Samples: n x n lattices (delta = 0.2), path "p_r" at p_t = 0.2, f_c in {0, 0.5, 1}, strains
dilation / shear / compression (theta = 0.4), the same geometry and uniforms for both variants.
Both must find identical thresholds (checked). Run: python benchmarks/bench_threshold.py
[--sizes 16 32] [--samples K]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from _record import machine, record, table

from tensegrity_rigidity.ensemble.thresholds import find_threshold
from tensegrity_rigidity.model.sampling import lattice_geometry
from tensegrity_rigidity.model.strain import strain_tensor


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--sizes", type=int, nargs="+", default=[16, 32])
    ap.add_argument("--samples", type=int, default=4)
    args = ap.parse_args()
    rows = []
    for n in args.sizes:
        times = {True: [], False: []}
        solves = {True: [], False: []}
        for f_c in (0.0, 0.5, 1.0):
            for phi in ("dilation", "shear", "compression"):
                for k in range(args.samples):
                    rng = np.random.default_rng([n, int(f_c * 2), k])
                    net, u, v = lattice_geometry(n, 0.2, rng)
                    eps = strain_tensor(phi, 0.4)
                    found = {}
                    for warm in (False, True):
                        t0 = time.perf_counter()
                        th = find_threshold(net, u, v, eps, 0.2, f_c, warm_start=warm)
                        times[warm].append(time.perf_counter() - t0)
                        solves[warm].append(th.solves)
                        found[warm] = (th.s, th.decided)
                    same = found[True] == found[False] or (
                        np.isnan(found[True][0]) and np.isnan(found[False][0])
                    )
                    assert same, (n, f_c, phi, k, found)
                    print(
                        n,
                        f_c,
                        phi,
                        k,
                        found[True],
                        f"{times[False][-1]:.2f} s -> {times[True][-1]:.2f} s",
                        flush=True,
                    )
        for warm in (False, True):
            t = np.asarray(times[warm])
            rows.append(
                [
                    n,
                    "warm" if warm else "cold",
                    t.size,
                    f"{np.median(t):.3f}",
                    f"{t.mean():.3f}",
                    f"{t.max():.3f}",
                    f"{np.mean(solves[warm]):.1f}",
                ]
            )
    body = (
        f"Machine: {machine()}. Seconds per sample threshold (bisection over the path's events), "
        "the same samples for both variants; identical thresholds (checked).\n\n"
        + table(["n", "start", "samples", "median s", "mean s", "max s", "solves"], rows)
    )
    record("threshold", "Threshold bisection: warm starts (benchmarks/bench_threshold.py)", body)


if __name__ == "__main__":
    main()
