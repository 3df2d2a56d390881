"""What an exact rational verdict on the support of a self-stress costs (python-flint).

An instance given in doubles is an exact rational instance. Scaling each row of the rigidity
matrix by its bond length (a positive factor, so signs are kept) makes it rational: the
forces of tensions ``t'`` are ``sum_b t'_b d_b`` with the bond vectors ``d_b`` exact, and the
work ``sum_b t'_b d_b . eps d_b``. An exact self-stress on a support is a rational null
vector of that matrix; with admissible signs and positive work it proves rigidity outright,
whatever the resolution model's tolerances.

For each size n: near-threshold samples (benchmarks/near_threshold_set.py), the configuration
at the first certified rigid event of the threshold search, its certified self-stress. On that
self-stress's support: the nullity (rank modulo a 62-bit prime, ``nmod_mat``), and the exact
null space (``fmpz_mat.nullspace``) with the time it takes, and whether the null vector
nearest the certificate (exact least squares in the null space) is an exact rigid certificate.
The cost's growth with the support gives the extrapolation to the n = 64 supports.

Run: python benchmarks/bench_exact.py [--sizes 6 8 10 12] [--samples 3] [--max-seconds 300]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
import warnings
from fractions import Fraction
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks._record import record, table  # noqa: E402
from benchmarks.near_threshold_set import samples  # noqa: E402
from tensegrity_rigidity import Instance, decide, find_threshold  # noqa: E402
from tensegrity_rigidity.ensemble.thresholds import EventPath  # noqa: E402
from tensegrity_rigidity.model.network import Element  # noqa: E402

#: the prime of the modular rank (the largest below 2^62)
PRIME = 2**62 - 57


def exact_matrix(net, strain, sites):
    """Integer force matrix (d * nodes, sites) of ``sites`` with rows scaled by bond length, a
    common power of two cleared, and the exact work coefficients ``d_b . eps d_b`` (sites,)."""
    pos = [[Fraction(float(x)) for x in row] for row in net.positions]
    box = [[Fraction(float(x)) for x in row] for row in net.box]
    eps = [[Fraction(float(x)) for x in row] for row in strain]
    dim = net.dim
    bonds, shifts = net.bonds[sites], net.shifts[sites]
    nodes = sorted(set(bonds.ravel().tolist()))
    index = {v: k for k, v in enumerate(nodes)}
    vectors = []
    for (i, j), s in zip(bonds.tolist(), shifts.tolist(), strict=True):
        d = [pos[j][a] - pos[i][a] + sum(s[c] * box[c][a] for c in range(dim)) for a in range(dim)]
        vectors.append(d)
    scale = math.lcm(*(x.denominator for d in vectors for x in d))
    rows = [[0] * len(sites) for _ in range(dim * len(nodes))]
    for b, ((i, j), d) in enumerate(zip(bonds.tolist(), vectors, strict=True)):
        for a in range(dim):
            x = int(d[a] * scale)
            rows[dim * index[j] + a][b] -= x  # a tension pulls node j towards i
            rows[dim * index[i] + a][b] += x
    work = [sum(d[a] * eps[a][c] * d[c] for a in range(dim) for c in range(dim)) for d in vectors]
    return rows, work, nodes


def exact_certificate(rows, work, t, sigma):
    """Nullity, seconds of the exact null space, and whether the null vector nearest ``t`` (in
    the scaled variables) has admissible signs and positive exact work."""
    import flint

    A = flint.fmpz_mat(rows)
    nullity = A.ncols() - flint.nmod_mat(rows, PRIME).rank()
    start = time.perf_counter()
    X, k = A.nullspace()
    seconds = time.perf_counter() - start
    basis = [[int(X[r, c]) for r in range(A.ncols())] for c in range(k)]
    # exact least squares of t in the null space: (B^T B) c = B^T t, t rounded to rationals
    tq = [Fraction(float(x)) for x in t]

    def q(x: Fraction):
        return flint.fmpq(x.numerator, x.denominator)

    dot = [[sum(a * b for a, b in zip(u, v, strict=True)) for v in basis] for u in basis]
    G = flint.fmpq_mat(dot)
    rhs = flint.fmpq_mat(
        [[q(sum(Fraction(a) * b for a, b in zip(u, tq, strict=True)))] for u in basis]
    )
    c = G.solve(rhs)
    coef = [Fraction(int(c[r, 0].p), int(c[r, 0].q)) for r in range(k)]
    tx = [sum(coef[r] * basis[r][b] for r in range(k)) for b in range(A.ncols())]
    signs_ok = all(s == 0 or s * x >= 0 for s, x in zip(sigma, tx, strict=True))
    positive = sum(x * w for x, w in zip(tx, work, strict=True)) > 0
    return nullity, k, seconds, signs_ok and positive


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--sizes", type=int, nargs="+", default=[6, 8, 10, 12])
    ap.add_argument("--samples", type=int, default=3)
    ap.add_argument("--max-seconds", type=float, default=300.0, help="stop growing n beyond")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    raw, out = [], []
    for n in args.sizes:
        slowest = 0.0
        for c, k, (net, u, v, strain, p_t, f_c) in samples(n, args.samples):
            th = find_threshold(net, u, v, strain, p_t, f_c)
            if not np.isfinite(th.s_high):
                continue
            ev = EventPath(u, v, "p_r", p_t, f_c)
            kinds = ev.kinds(int(np.searchsorted(ev.positions, th.s_high)) + 1)
            verdict = decide(Instance(net.with_kinds(kinds), strain))
            if verdict.status != "rigid":
                continue
            nonempty = np.flatnonzero(kinds != Element.EMPTY)
            t = np.asarray(verdict.rigid.t, dtype=float)
            support = nonempty[t != 0]
            rows, work, nodes = exact_matrix(net, strain, support)
            sigma = np.where(
                kinds[support] == Element.CABLE, 1, np.where(kinds[support] == Element.STRUT, -1, 0)
            )
            # scaled variables t'_b = t_b / |d_b| keep the signs: nearest null vector to t / |d|
            lengths = np.linalg.norm(
                net.positions[net.bonds[support, 1]]
                - net.positions[net.bonds[support, 0]]
                + net.shifts[support] @ net.box,
                axis=1,
            )
            nullity, k_basis, seconds, exact = exact_certificate(
                rows, work, t[t != 0] / lengths, sigma.tolist()
            )
            slowest = max(slowest, seconds)
            raw.append(
                {"n": n, "config": c, "sample": k, "support": int(support.size),
                 "nodes": len(nodes), "nullity": nullity, "seconds": seconds, "exact": exact}
            )  # fmt: skip
            out.append([n, c, k, support.size, len(nodes), nullity, f"{seconds:.2f}", exact])
            print(out[-1], flush=True)
        if slowest > args.max_seconds:
            break
    sizes = np.array([r["support"] for r in raw], float)
    secs = np.array([r["seconds"] for r in raw], float)
    fit = ""
    if len(raw) >= 3 and np.ptp(np.log(sizes)) > 0:
        slope, icpt = np.polyfit(np.log(sizes), np.log(np.maximum(secs, 1e-6)), 1)
        fit = (
            f"\n\nExact null space: time ~ support^{slope:.2f}; extrapolated to a support of "
            f"10,000 sites (an n = 64 probe): {math.exp(icpt) * 1e4**slope:.3g} s."
        )
    header = ["n", "config", "k", "support", "nodes", "nullity", "null space s", "exact rigid"]
    record("exact", "Exact verdicts on a self-stress's support (benchmarks/bench_exact.py)",
           table(header, out) + fit, raw)  # fmt: skip


if __name__ == "__main__":
    main()
