"""Stage by stage: what each stage of the verdict search leaves on near-threshold probes.

For each probe (a sample of the near-threshold set at one p_r) the default stages run in turn
on one search state; after each the best rigid candidate (work, force residual), the best
floppy candidate (violation, size), the lowest energy, the time and the factorisations are
printed and written to ``benchmarks/results/diagnose_stages.json``. It shows where a search
that ends undecided stalls (Newton's convergence, the interior point's accuracy, the LP's
budget).

Run: python benchmarks/diagnose_stages.py N CONFIG SAMPLE P_R [P_R ...]
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
import warnings
from pathlib import Path

from near_threshold_set import sample

from tensegrity_rigidity.model.elements import place_elements
from tensegrity_rigidity.model.network import Instance
from tensegrity_rigidity.solver.core import SolverOptions
from tensegrity_rigidity.solver.linalg import one_blas_thread
from tensegrity_rigidity.solver.problem import Problem
from tensegrity_rigidity.solver.stages import Search

RESULTS = Path(__file__).with_name("results") / "diagnose_stages.json"


def diagnose(n: int, c: int, k: int, p_r: float) -> list[dict]:
    """One probe's trace: a dict per stage run."""
    net, u, v, eps, p_t, f_c = sample(n, c, k)
    inst = Instance(net.with_kinds(place_elements(u, v, p_r, p_t, f_c)), eps)
    opts = SolverOptions()
    trace = []
    with one_blas_thread(), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        p = Problem(inst, opts.regularization, opts.factorization, True, tolerances=opts.tolerances)
        s = Search(p, opts.resolution, opts.refiner, opts.polish, opts.balance)
        for strategy in opts.stages:
            name = strategy.name
            t0, f0 = time.perf_counter(), p.factorizations
            strategy.run(s)
            r, fl = s.rigid, s.floppy
            trace.append(
                {
                    "stage": name,
                    "seconds": time.perf_counter() - t0,
                    "factorizations": p.factorizations - f0,
                    "work": None if r is None else float(r.work),
                    "residual": None if r is None else float(r.residual),
                    "violation": None if fl is None else float(fl.violation),
                    "size": None if fl is None else float(fl.size),
                    "energy": float(s.E),
                    "decided": s.stage,
                }
            )
            t = trace[-1]
            print(
                f"  {name:9s} {t['seconds']:7.1f} s {t['factorizations']:4d} fact.  "
                f"rigid w {t['work'] or 0:.2e} r {t['residual'] or 0:.2e}  "
                f"floppy viol {t['violation'] or 0:.2e} size {t['size'] or 0:.2e}  "
                f"E {t['energy']:.2e}  {s.stage or '-'}",
                flush=True,
            )
            if s.decided:
                break
    return trace


def main() -> None:
    n, c, k = (int(x) for x in sys.argv[1:4])
    runs = []
    for p_r in (float(x) for x in sys.argv[4:]):
        print(f"n = {n}, configuration {c}, sample {k}, p_r = {p_r}", flush=True)
        runs.append({"n": n, "config": c, "sample": k, "p_r": p_r, "trace": diagnose(n, c, k, p_r)})
    commit = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=False
    ).stdout.strip()
    RESULTS.parent.mkdir(exist_ok=True)
    history = json.loads(RESULTS.read_text()) if RESULTS.exists() else []
    entry = {"date": time.strftime("%Y-%m-%d"), "commit": commit, "command": sys.argv, "runs": runs}
    RESULTS.write_text(json.dumps([*history, entry], indent=1) + "\n")


if __name__ == "__main__":
    main()
