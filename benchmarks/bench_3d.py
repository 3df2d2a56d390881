"""Three dimensions beside two at about the same number of unknowns: solve() and thresholds.

Pairs (FCC n, triangular n) with ``3 n_fcc^3 ~ 2 n_tri^2`` displacement unknowns: (8, 27),
(12, 51), (16, 78). For each pair and sample, on the same kind of sample (delta = 0.2, p_t =
0.3, f_c = 0.5, compression; principal axes from the SO(3) sequence in 3D, the golden angle in
2D): one ``solve()`` at p_r = 0.45 (3D) and 0.5 (2D), near both thresholds, and one threshold
along p_r, the two dimensions interleaved per sample so that a slow spell of the machine falls
on both. Times are also given in numeric factorisations of each lattice's full Newton matrix,
measured in the same run. Raw results go to ``benchmarks/results/bench_3d.json``.

Run: python benchmarks/bench_3d.py [--pairs 8:27 12:51] [--samples 2]
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import subprocess
import time
import warnings
from pathlib import Path

import numpy as np
from bench_threshold import refactor_seconds

from tensegrity_rigidity import SolverOptions, UndecidedWarning, solve
from tensegrity_rigidity.ensemble.spec import strain_angle
from tensegrity_rigidity.ensemble.thresholds import find_threshold
from tensegrity_rigidity.model.elements import place_elements
from tensegrity_rigidity.model.network import Instance
from tensegrity_rigidity.model.sampling import lattice_geometry
from tensegrity_rigidity.model.strain import sequence_rotation, strain_tensor

RESULTS = Path(__file__).with_name("results") / "bench_3d.json"
#: p_r of the timed solve(), near each lattice's threshold at p_t = 0.3
P_R = {"fcc": 0.45, "triangular": 0.5}
P_T, F_C, PHI, DELTA = 0.3, 0.5, "compression", 0.2


def one(lattice: str, n: int, k: int) -> dict:
    """Solve and threshold of sample ``k`` of one lattice."""
    rng = np.random.default_rng([n, k, 3])
    net, u, v = lattice_geometry(n, DELTA, rng, lattice)
    if net.dim == 3:
        strain = strain_tensor(PHI, rotation_matrix=sequence_rotation(k))
    else:
        strain = strain_tensor(PHI, strain_angle(k, 1))
    inst = Instance(net.with_kinds(place_elements(u, v, P_R[lattice], P_T, F_C)), strain)
    fact = refactor_seconds(net, strain)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UndecidedWarning)
        t0 = time.perf_counter()
        res = solve(inst)
        t_solve = time.perf_counter() - t0
        t0 = time.perf_counter()
        th = find_threshold(net, u, v, strain, P_T, F_C, "p_r", SolverOptions(min_norm=False))
        t_th = time.perf_counter() - t0
    return {
        "lattice": lattice,
        "n": n,
        "sample": k,
        "unknowns": net.dim * net.n_nodes,
        "sites": net.n_sites,
        "factorisation_s": fact,
        "solve_s": t_solve,
        "solve_status": res.status,
        "threshold_s": t_th,
        "threshold_p_r": th.s,
        "threshold_interval": [th.s_low, th.s_high],
        "undecided_probes": th.undecided,
        "probes": th.solves,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pairs", nargs="+", default=["8:27", "12:51"])
    ap.add_argument("--samples", type=int, default=2)
    args = ap.parse_args()
    runs = []
    for pair in args.pairs:
        n3, n2 = (int(x) for x in pair.split(":"))
        for k in range(1, args.samples + 1):
            runs.append(one("fcc", n3, k))
            runs.append(one("triangular", n2, k))
    rows = []
    for pair in args.pairs:
        n3, n2 = (int(x) for x in pair.split(":"))
        a = [r for r in runs if r["lattice"] == "fcc" and r["n"] == n3]
        b = [r for r in runs if r["lattice"] == "triangular" and r["n"] == n2]
        ratio = [x["threshold_s"] / y["threshold_s"] for x, y in zip(a, b, strict=True)]
        rows.append(
            [
                f"FCC {n3} / tri {n2}",
                f"{a[0]['unknowns']} / {b[0]['unknowns']}",
                f"{statistics.median(r['solve_s'] for r in a):.2f} / "
                f"{statistics.median(r['solve_s'] for r in b):.2f}",
                f"{statistics.median(r['threshold_s'] for r in a):.1f} / "
                f"{statistics.median(r['threshold_s'] for r in b):.1f}",
                f"{statistics.median(r['threshold_s'] / r['factorisation_s'] for r in a):.0f} / "
                f"{statistics.median(r['threshold_s'] / r['factorisation_s'] for r in b):.0f}",
                f"{statistics.median(ratio):.2f} ({min(ratio):.2f}-{max(ratio):.2f})",
            ]
        )
    header = ["pair", "unknowns", "solve s", "threshold s", "threshold / fact.", "3D/2D threshold"]
    widths = [max(len(str(x)) for x in col) for col in zip(header, *rows, strict=True)]
    for line in [header, *rows]:
        print("  ".join(str(x).ljust(w) for x, w in zip(line, widths, strict=True)))
    commit = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=False
    ).stdout.strip()
    RESULTS.parent.mkdir(exist_ok=True)
    entry = {
        "date": time.strftime("%Y-%m-%d"),
        "commit": commit,
        "command": "python benchmarks/bench_3d.py " + " ".join(f"--pairs {p}" for p in args.pairs),
        "runs": runs,
    }
    history = json.loads(RESULTS.read_text()) if RESULTS.exists() else []
    RESULTS.write_text(json.dumps([*history, entry], indent=1, default=float) + "\n")
    if not all(math.isfinite(r["threshold_p_r"]) for r in runs):
        print("note: some samples were never rigid on the path")


if __name__ == "__main__":
    main()
