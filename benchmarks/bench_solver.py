"""Solver speed and verdict agreement on identical instances across the phase diagram.

Instances per size: f_c in {0, 0.5, 1} x strain in {dilation, shear, compression} x regime in
{near the transition (p_r, p_t) = (0.55, 0.2), rigid (0.8, 0.1), floppy (0.4, 0.2)}.

Methods (all on the same instances, in one run):
  ours        tensegrity_rigidity.solve, verdict only (min_norm=False)
  ours-qdldl  the same with QDLDL's simplicial LDL^T instead of CHOLMOD, n <= 64
  ours+u      solve with minimum-norm displacements (the default)
  clarabel    generic interior-point QP (reference.qp_solve), n <= 64
  highs-lp    verdict LP (reference.lp_verdict), n <= 64
  l-bfgs-b    SciPy L-BFGS-B on E(u) from u = 0 with the exact gradient, verdict "E > 1e-10 E_aff";
              its wrong verdicts are counted against the LP, n <= 64
  factor      one sparse Cholesky (CHOLMOD, supernodal, AMD ordering) of R^T R + mu I over the
              non-empty sites: symbolic + numeric (factor) and numeric only (refactor)
  *-qdldl     the same with QDLDL's LDL^T (the backend before CHOLMOD)

Run: python benchmarks/bench_solver.py [--sizes 16 32 64 128] [--max-baseline 64]
"""

from __future__ import annotations

import argparse
import time
import zlib

import numpy as np
from _record import machine, record, table
from scipy.optimize import minimize

from tensegrity_rigidity import SolverOptions, lattice_instance, solve
from tensegrity_rigidity.model.mechanics import affine_extensions, rigidity_matrix
from tensegrity_rigidity.model.network import Element
from tensegrity_rigidity.solver.linalg import PatternFactor
from tensegrity_rigidity.solver.reference import lp_verdict, qp_solve

REGIMES = {"near": (0.55, 0.2), "rigid": (0.8, 0.1), "floppy": (0.4, 0.2)}


def instances(n):
    out = []
    for f_c in (0.0, 0.5, 1.0):
        for phi in ("dilation", "shear", "compression"):
            for name, (p_r, p_t) in REGIMES.items():
                seed = zlib.crc32(repr((n, f_c, phi, name)).encode())
                out.append(
                    (
                        (f_c, phi, name),
                        lattice_instance(n, p_r, p_t, f_c, phi=phi, theta=0.4, seed=seed),
                    )
                )
    return out


def lbfgs(inst):
    net = inst.network
    on = net.kinds != Element.EMPTY
    R = rigidity_matrix(net)[on]
    e0 = affine_extensions(net, inst.strain)[on]
    kinds = net.kinds[on]
    sig = np.where(kinds == Element.CABLE, 1.0, np.where(kinds == Element.STRUT, -1.0, 0.0))
    rod = kinds == Element.ROD

    def f(u):
        e = e0 + R @ u
        t = np.where(rod | (sig * e > 0), e, 0.0)
        return 0.5 * float(t @ e), R.T @ t

    res = minimize(
        f,
        np.zeros(R.shape[1]),
        jac=True,
        method="L-BFGS-B",
        options={"maxiter": 20000, "ftol": 1e-15, "gtol": 1e-12},
    )
    e_aff = f(np.zeros(R.shape[1]))[0]
    return res.fun > 1e-10 * max(e_aff, 1e-300)


def factor_times(inst, backend):
    """Seconds of the first factorisation (symbolic + numeric) and of one more numeric one."""
    from tensegrity_rigidity.solver.core import _Problem

    p = _Problem(inst, 1e-12, backend)
    data = p.values(p.k)
    f = PatternFactor(p._indptr, p._indices, p.n2, backend)
    t0 = time.perf_counter()
    f.factor(data)
    t1 = time.perf_counter()
    f.factor(data * 1.5)
    t2 = time.perf_counter()
    return t1 - t0, t2 - t1


def _target_line(n, ours, T, facts, wrong, undecided, max_baseline):
    """One line per size checking issue 5's targets against this run's numbers."""
    med, mx = np.median(ours), ours.max()
    ok = "met" if undecided == 0 and not (n <= max_baseline and wrong["ours"]) else "not met"
    agree = (
        f"{wrong['ours']} wrong verdicts against the LP, {undecided} undecided"
        if n <= max_baseline
        else f"{undecided} undecided (the LP is not run at this size)"
    )
    if n == 64 and T["clarabel"]:
        ratio = np.median(T["clarabel"]) / med
        per_f = med / np.median(T["refactor"])
        return (
            f"n = 64: median {med * 1e3:.0f} ms, {ratio:.1f}x faster than Clarabel's median "
            f"(target 10x: {'met' if ratio >= 10 else 'not met'}); median "
            f"{np.median(facts):.0f} factorisations and {per_f:.1f} refactorisation-times "
            f"(target about 10); {agree}."
        )
    if n == 128:
        return (
            f"n = 128: median {med:.2f} s (target < 1 s: {'met' if med < 1 else 'not met'}), "
            f"max {mx:.1f} s (target < 10 s: {'met' if mx < 10 else 'not met'}); {agree}."
        )
    if n <= max_baseline:
        return f"n = {n}: {agree} (target none: {ok})."
    return ""


def timed(fn, *a):
    t0 = time.perf_counter()
    out = fn(*a)
    return out, time.perf_counter() - t0


def stats(ts):
    ts = np.asarray(ts)
    return f"{np.median(ts) * 1e3:.1f}", f"{ts.mean() * 1e3:.1f}", f"{ts.max() * 1e3:.1f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--sizes", type=int, nargs="+", default=[16, 32, 64, 128])
    ap.add_argument("--max-baseline", type=int, default=64)
    args = ap.parse_args()
    rows, agree_rows, targets = [], [], []
    for n in args.sizes:
        cases = instances(n)
        T = {
            k: []
            for k in (
                "ours",
                "ours-qdldl",
                "ours+u",
                "clarabel",
                "highs-lp",
                "l-bfgs-b",
                "factor",
                "refactor",
                "factor-qdldl",
                "refactor-qdldl",
            )
        }
        wrong = {"ours": 0, "clarabel": 0, "l-bfgs-b": 0}
        fallbacks, facts, general, undecided = 0, [], 0, 0
        # Each method runs over all instances in its own block, the BLAS-heavy L-BFGS-B last:
        # interleaved, the OpenBLAS threads that SciPy leaves spinning after L-BFGS-B halve the
        # speed of CHOLMOD's (a separate OpenBLAS) in the next solve (measured: 126 against
        # 67 ms median at n = 64).
        for backend, suffix in (("cholmod", ""), ("qdldl", "-qdldl")):
            for _, inst in cases:
                f1, f2 = factor_times(inst, backend)
                T["factor" + suffix].append(f1)
                T["refactor" + suffix].append(f2)
        ours_results = []
        for key, inst in cases:
            r, t = timed(solve, inst, SolverOptions(min_norm=False))
            T["ours"].append(t)
            ours_results.append(r)
            fallbacks += r.method != "newton"
            general += r.method.split("+")[-1] in ("lp-feasibility", "lp", "qp", "lp-certificate")
            undecided += not r.decided
            facts.append(r.factorizations)
            print(n, key, r.status, r.method, f"{t:.3f} s", flush=True)
        if n <= args.max_baseline:
            for _, inst in cases:
                _, t = timed(solve, inst, SolverOptions(min_norm=False, factorization="qdldl"))
                T["ours-qdldl"].append(t)
            for _, inst in cases:
                _, t = timed(solve, inst)
                T["ours+u"].append(t)
            verdicts = {"highs-lp": [], "clarabel": [], "l-bfgs-b": []}
            for name, fn in (
                ("highs-lp", lambda i: lp_verdict(i).rigid),
                ("clarabel", lambda i: qp_solve(i).rigid),
                ("l-bfgs-b", lbfgs),
            ):
                for _, inst in cases:
                    v, t = timed(fn, inst)
                    T[name].append(t)
                    verdicts[name].append(v)
            lp_rigid = np.asarray(verdicts["highs-lp"])
            wrong["ours"] = int(np.sum(np.array([r.rigid for r in ours_results]) != lp_rigid))
            for name in ("clarabel", "l-bfgs-b"):
                wrong[name] = int(np.sum(np.asarray(verdicts[name]) != lp_rigid))
        for k, ts in T.items():
            if ts:
                rows.append([n, k, len(ts), *stats(ts)])
        ours = np.asarray(T["ours"])
        per_refactor = np.median(ours / np.asarray(T["refactor"]))
        targets.append(_target_line(n, ours, T, facts, wrong, undecided, args.max_baseline))
        common = [
            n,
            len(cases),
            undecided,
            fallbacks,
            general,
            f"{np.median(facts):.0f} / {max(facts)}",
        ]
        if n <= args.max_baseline:
            q = np.asarray(T["clarabel"])
            agree_rows.append(
                common[:3]
                + [wrong["ours"], wrong["clarabel"], wrong["l-bfgs-b"]]
                + common[3:]
                + [
                    f"{np.median(q) / np.median(ours):.1f}x",
                    f"{np.median(q / ours):.1f}x",
                    f"{np.median(ours) / np.median(T['refactor']):.1f}",
                    f"{per_refactor:.1f}",
                ]
            )
        else:
            agree_rows.append(
                common[:3]
                + ["-", "-", "-"]
                + common[3:]
                + ["-", "-", f"{np.median(ours) / np.median(T['refactor']):.1f}"]
                + [f"{per_refactor:.1f}"]
            )
    body = (
        f"Machine: {machine()}. Times in ms over the same instances per size "
        "(27 per size: 3 f_c x 3 strains x 3 regimes).\n\n"
        + table(["n", "method", "instances", "median ms", "mean ms", "max ms"], rows)
        + "\n\nVerdicts against the HiGHS LP (wrong = disagreements); samples that left plain "
        "Newton, and those that needed the general path (HiGHS or Clarabel); our numeric "
        "factorisations (median / max); speed-up over Clarabel as a ratio of medians and as the "
        "median of per-instance ratios; our time in units of one numeric refactorisation, as a "
        "ratio of medians and as the median of per-instance ratios (the refactorisation time "
        "varies 2.5x with the density of the instance):\n\n"
        + table(
            [
                "n",
                "instances",
                "ours undecided",
                "ours wrong",
                "clarabel wrong",
                "l-bfgs-b wrong",
                "left Newton",
                "general path",
                "factorisations",
                "clarabel / ours (medians)",
                "clarabel / ours (per instance)",
                "ours / refactor (medians)",
                "ours / refactor (per instance)",
            ],
            agree_rows,
        )
        + "\n\nHow the verdicts of the generic methods are read: Clarabel's as E > 1e-14 E_ref "
        "from its interior-point minimiser, L-BFGS-B's as E > 1e-10 E_aff after convergence; "
        "both are energy thresholds on inexact minima. Ours rests on certificates. 'ours' decides "
        "only; 'ours+u' adds the minimum-norm displacements. 'general path' counts the samples "
        "certified by a HiGHS or Clarabel starting point (or the LP's own certificate).\n\n"
        "Issue 5 targets on this run (computed by the script):\n\n"
        + "\n".join(f"- {line}" for line in targets if line)
    )
    record("solver", "Solver: ours against generic solvers (benchmarks/bench_solver.py)", body)


if __name__ == "__main__":
    main()
