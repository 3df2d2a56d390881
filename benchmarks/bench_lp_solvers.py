"""LP solvers on the verdict LP at the threshold: is HiGHS the bottleneck of issue 13?

The `lp` stage decides the hard probes of a threshold search from the verdict LP
``max e0 . t`` over admissible self-stresses with ``|t_b| <= 1`` (``R^T t = 0``; columns the
elements' tensions, rows the nodes' forces), solved by HiGHS's interior point with crossover
(``stages.LinearProgram.verdict_lp``). This script takes that LP, built exactly as the stage
builds it, on the two configurations each threshold search of the near-threshold set decides
between (``bench_solver.at_threshold``: the first certified rigid one and the last certified
floppy one below it), and times it in every LP solver it finds installed, each on one thread,
to the end (without the stage's iteration limits; ``--time-limit`` per LP, default 600 s):

* HiGHS (``highspy``, a dependency): the interior point with crossover (the stage's solver)
  and the dual simplex;
* when installed: COPT (``coptpy``), Gurobi (``gurobipy``) and FICO Xpress (``xpress``), each
  by its barrier (with its default crossover) and its dual simplex. Without a licence they
  run as size-limited free editions (COPT: LPs up to about 10,000 columns; Gurobi: 2,000 rows
  and 2,000 columns; Xpress: 5,000 rows plus columns); an LP a solver refuses for its size is
  counted, not timed.

None of these is a dependency of the package, and nothing here is used by it: the numbers say
whether a better LP solver would meet issue 13's targets. ``pip install coptpy gurobipy
xpress`` brings their size-limited free editions.

Every solver is asked for a vertex (crossover on) in the stage's normalised units, and 'optimal'
is its own status, within its own default tolerances (COPT's and Xpress's dual simplex reach
optima up to 19 % above the others' on an n = 32 LP with bounds violated by up to 9e-7). Its
optimum is compared with HiGHS's interior point's (the largest relative difference, in units of
``max(|optimum|, 1e-3)``). Times are single runs. Each method is compared with HiGHS's interior
point on the LPs both solved to optimality ('paired'), so that a solver's size limit picks the
same instances for both sides of its ratio.
"""

from __future__ import annotations

import argparse
import functools
import json
import time
import warnings
from pathlib import Path

import numpy as np
from _record import machine, probe, record, table
from bench_solver import at_threshold

from tensegrity_rigidity.errors import UndecidedWarning
from tensegrity_rigidity.solver.problem import Problem


class TooLarge(Exception):
    """The instance exceeds a solver's free size limit."""


def verdict_lp(inst):
    """(A (2N, m) CSC, cost (m,), lo (m,), hi (m,)) of the `lp` stage's verdict LP."""
    p = Problem(inst)
    lo = np.where(p.sigma > 0, 0.0, -1.0)
    hi = np.where(p.sigma < 0, 0.0, 1.0)
    return p.RT.tocsc(), -p.e0, lo, hi


def _timed(run) -> float:
    """Seconds that ``run()`` takes."""
    t0 = time.perf_counter()
    run()
    return time.perf_counter() - t0


def highs(A, c, lo, hi, mode, limit):
    import highspy

    h = highspy.Highs()
    options = {"output_flag": False, "threads": 1, "time_limit": limit}
    if mode == "barrier":
        options |= {"solver": "ipx", "run_crossover": "on"}
    else:
        options |= {"solver": "simplex", "simplex_strategy": 1}
    for key, value in options.items():
        h.setOptionValue(key, value)
    lp = highspy.HighsLp()
    lp.num_col_, lp.num_row_ = A.shape[1], A.shape[0]
    lp.col_cost_, lp.col_lower_, lp.col_upper_ = c, lo, hi
    lp.row_lower_ = lp.row_upper_ = np.zeros(A.shape[0])
    lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
    lp.a_matrix_.start_, lp.a_matrix_.index_, lp.a_matrix_.value_ = A.indptr, A.indices, A.data
    h.passModel(lp)
    seconds = _timed(h.run)
    ok = h.getModelStatus() == highspy.HighsModelStatus.kOptimal
    return seconds, ok, h.getInfo().objective_function_value if ok else np.nan


def copt(A, c, lo, hi, mode, limit):
    import coptpy

    m = _copt_env().createModel()
    for key, value in {"Logging": 0, "Threads": 1, "TimeLimit": limit}.items():
        m.setParam(key, value)
    m.setParam("LpMethod", 2 if mode == "barrier" else 1)
    x = m.addMVar(A.shape[1], lb=lo, ub=hi, obj=c)
    m.addMConstr(A, x, "E", np.zeros(A.shape[0]))
    try:
        seconds = _timed(m.solve)
    except coptpy.CoptError as e:
        if e.retcode == 4:  # the licence: without one, the size-limited edition
            raise TooLarge from e
        raise
    ok = m.status == coptpy.COPT.OPTIMAL
    return seconds, ok, m.objval if ok else np.nan


def gurobi(A, c, lo, hi, mode, limit):
    import gurobipy

    m = gurobipy.Model(env=_gurobi_env())
    m.Params.Threads, m.Params.TimeLimit = 1, limit
    m.Params.Method = 2 if mode == "barrier" else 1
    x = m.addMVar(A.shape[1], lb=lo, ub=hi, obj=c)
    m.addConstr(A @ x == np.zeros(A.shape[0]))
    m.update()  # build the model before the clock starts, as for the others
    try:
        seconds = _timed(m.optimize)
    except gurobipy.GurobiError as e:
        if e.errno == 10010:  # the size-limited licence
            raise TooLarge from e
        raise
    ok = m.Status == gurobipy.GRB.OPTIMAL
    return seconds, ok, m.ObjVal if ok else np.nan


def xpress(A, c, lo, hi, mode, limit):
    import xpress as xp

    with warnings.catch_warnings():  # its licence notice and deprecations
        warnings.simplefilter("ignore")
        p = xp.problem()
        p.setOutputEnabled(False)
        p.controls.threads, p.controls.timelimit = 1, int(limit)
        rows = A.shape[0]
        starts = A.indptr[:-1]
        p.loadproblem(
            "", ["E"] * rows, np.zeros(rows), None, c, starts, np.diff(A.indptr), A.indices, A.data,
            lo, hi,
        )  # fmt: skip
        try:
            seconds = _timed(lambda: p.lpoptimize("b" if mode == "barrier" else "d"))
        except xp.SolverError as e:
            if "too many rows and columns" in str(e):  # the community licence's limit
                raise TooLarge from e
            raise
    ok = int(p.attributes.lpstatus) == 1
    return seconds, ok, p.attributes.lpobjval if ok else np.nan


@functools.cache
def _copt_env():
    """One COPT environment for the whole run (each prints its licence banner once)."""
    import coptpy

    return coptpy.Envr()


@functools.cache
def _gurobi_env():
    """One silent Gurobi environment for the whole run."""
    import gurobipy

    return gurobipy.Env(params={"OutputFlag": 0})


#: name -> (the package it needs, or None for a dependency; the function timing one LP)
SOLVERS = {
    "HiGHS": (None, highs),
    "COPT": ("coptpy", copt),
    "Gurobi": ("gurobipy", gurobi),
    "Xpress": ("xpress", xpress),
}


def available() -> list[tuple[str, str]]:
    """(solver, mode) pairs whose package imports, HiGHS's interior point first."""
    import importlib

    out = []
    for name, (module, _) in SOLVERS.items():
        if module is not None:
            try:
                importlib.import_module(module)
            except ImportError:
                print(f"{name}: {module} not installed, skipped")
                continue
        out += [(name, "barrier"), (name, "dual")]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--sizes", type=int, nargs="+", default=[16, 24, 32, 64])
    ap.add_argument(
        "--samples", type=int, default=6, help="threshold samples per size (two LPs each)"
    )
    ap.add_argument("--time-limit", type=float, default=600.0, help="seconds per LP")
    ap.add_argument("--json", help="also write every LP's (seconds, optimal, optimum) here")
    args = ap.parse_args()
    warnings.simplefilter("ignore", UndecidedWarning)
    methods = available()
    rows, raw, keys = [], {}, {}
    for n in args.sizes:
        cases = [(key, verdict_lp(inst)) for key, inst in at_threshold(n, args.samples)]
        keys[n] = [key for key, _ in cases]
        # every method on one LP before the next LP: a passing slowdown of the machine then
        # hits all methods on a few LPs, not one method on many (a run that took them one
        # method at a time read 3 to 13 times the usual time for three methods: one on three
        # LPs of one size, the two others on twelve consecutive LPs of the next)
        res = {}  # (method, instance index) -> (seconds, ok, optimum) or None (too large)
        for i, (key, lp) in enumerate(cases):
            probe()
            for method in methods:
                try:
                    res[method, i] = SOLVERS[method[0]][1](*lp, method[1], args.time_limit)
                except TooLarge:
                    res[method, i] = None
                r = res[method, i]
                shown = "too large" if r is None else f"{r[0]:.3f} s ok={r[1]} {r[2]:.6e}"
                print(n, key, lp[0].shape, *method, shown, flush=True)
        ref = methods[0]
        cols = [lp[0].shape[1] for _, lp in cases]
        shape = f"{cases[0][1][0].shape[0]} x {min(cols)}-{max(cols)}"
        for m in methods:
            took = [i for i in range(len(cases)) if res[m, i] is not None]
            ok = [i for i in took if res[m, i][1]]
            paired = [i for i in ok if res[ref, i] is not None and res[ref, i][1]]
            t = np.array([res[m, i][0] for i in paired])
            t_ref = sum(res[ref, i][0] for i in paired)
            diff = max(
                (
                    abs(res[m, i][2] - res[ref, i][2]) / max(abs(res[ref, i][2]), 1e-3)
                    for i in paired
                ),
                default=np.nan,
            )
            rows.append(
                [
                    n,
                    shape,
                    f"{m[0]} {m[1]}",
                    len(cases),
                    len(took),
                    len(ok),
                    len(paired),
                    f"{1e3 * np.median(t):.1f}" if t.size else "-",
                    f"{1e3 * t.max():.1f}" if t.size else "-",
                    f"{t.sum():.2f}" if t.size else "-",
                    f"{t_ref:.2f}" if t.size else "-",
                    f"{t_ref / t.sum():.2f}" if t.size else "-",
                    f"{diff:.1e}",
                ]
            )
        raw[n] = {f"{m[0]} {m[1]}": [res[m, i] for i in range(len(cases))] for m in methods}
    if args.json:
        Path(args.json).write_text(json.dumps({"keys": keys, "results": raw}, default=str))
    header = [
        "n", "LP rows x columns", "solver, method", "LPs", "within its size limit", "optimal",
        "paired", "median ms", "max ms", "sum s", "HiGHS barrier's sum s",
        "HiGHS barrier / this", "largest optimum difference",
    ]  # fmt: skip
    body = (
        f"Machine: {machine()}. `python benchmarks/bench_lp_solvers.py "
        f"--sizes {' '.join(map(str, args.sizes))} --samples {args.samples}`; each LP once, "
        "one thread. 'paired': the LPs that this method and HiGHS's interior point both "
        "solved to optimality; the times, the sums' ratio and the optimum difference are "
        "over those.\n\n" + table(header, rows)
    )
    record(
        "lp_solvers",
        "The verdict LP in other LP solvers (benchmarks/bench_lp_solvers.py)",
        body,
        raw={"keys": keys, "results": raw},
    )


if __name__ == "__main__":
    main()
