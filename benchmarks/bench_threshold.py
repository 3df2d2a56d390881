"""Per-sample thresholds on the near-threshold set of issue 13, n = 32, 64, 128.

Samples: the six configurations of ``near_threshold_set`` (triangular lattice, delta = 0.2,
path "p_r", random strain angle), cycled over the sample count of each size. For every
threshold: wall time (also in units of one numeric factorisation of the full lattice's
``R^T R + mu I``, measured in the same run on the same sample), probes (certified verdicts),
undecided probes and the width of the interval in events. At n <= ``--lp-max`` the two
configurations that straddle each threshold (an interval's two ends) are checked against the
verdict LP (HiGHS, no time limit): the one below must be floppy, the one above rigid. Each
threshold is computed twice, the second time with BLAS set to 2 threads; the two results must
be identical (a deterministic search whatever the thread settings).

Run: python benchmarks/bench_threshold.py [--sizes 32 64 128] [--samples 12 6 3]
     [--lp-time-limit SECONDS]

``--lp-time-limit`` bounds each verdict LP of the check (HiGHS, no limit by default); a
configuration whose LP reaches it is counted as unchecked ('LP limit'), never as agreeing.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from _record import machine, probe, record, table
from near_threshold_set import interval_events, samples
from reference import lp_verdict
from threadpoolctl import threadpool_limits

from tensegrity_rigidity.ensemble.thresholds import EventPath, find_threshold
from tensegrity_rigidity.model.network import Element, Instance
from tensegrity_rigidity.solver.problem import Problem


def refactor_seconds(net, eps) -> float:
    """Median time of one numeric refactorisation of the full lattice (all sites rods)."""
    full = Instance(net.with_kinds(np.full(net.n_sites, Element.ROD)), eps)
    p = Problem(full)
    values = p.values(np.ones(p.sites.size))
    p.factor_values(values)  # symbolic analysis once
    times = []
    for _ in range(5):
        t0 = time.perf_counter()
        p.factor_values(values)
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def straddle_check(net, u, v, eps, p_t, f_c, th, time_limit=None) -> str:
    """'ok', 'WRONG', 'limit' (an LP reached ``time_limit`` seconds) or '-' (never rigid on
    the path): the verdict LP on the last certified floppy configuration and the first
    certified rigid one (the two sides of a decided threshold; the two ends of an
    interval)."""
    if not np.isfinite(th.s) or th.s == 0 or not np.isfinite(th.s_low):
        return "-"
    ev = EventPath(u, v, "p_r", p_t, f_c)
    low = int(np.searchsorted(ev.positions, th.s_low)) + 1
    high = int(np.searchsorted(ev.positions, th.s_high)) + 1
    verdicts = []
    for i in (high, low - 1):
        t0 = time.perf_counter()
        lp = lp_verdict(Instance(net.with_kinds(ev.kinds(i)), eps), time_limit=time_limit)
        print(f"  verdict LP at event {i}: {lp.status}, {time.perf_counter() - t0:.1f} s")
        if lp.status == "time limit":
            return "limit"
        verdicts.append(lp.rigid)
    return "ok" if verdicts == [True, False] else "WRONG"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--sizes", type=int, nargs="+", default=[32, 64, 128])
    ap.add_argument("--samples", type=int, nargs="+", default=[12, 6, 3])
    ap.add_argument("--lp-max", type=int, default=64)
    ap.add_argument("--repeat-max", type=int, default=64, help="largest n searched twice")
    ap.add_argument("--lp-time-limit", type=float, default=None, help="seconds per check LP")
    args = ap.parse_args()
    rows, detail = [], []
    for n, count in zip(args.sizes, args.samples, strict=True):
        secs, units, solves, widths, checks = [], [], [], [], []
        undecided, unresolved, same = [], [], True
        for c, k, (net, u, v, eps, p_t, f_c) in samples(n, count):
            probe()
            t0 = time.perf_counter()
            th = find_threshold(net, u, v, eps, p_t, f_c)
            dt = time.perf_counter() - t0
            if n <= args.repeat_max:
                with threadpool_limits(limits=2, user_api="blas"):  # must not matter
                    same &= th == find_threshold(net, u, v, eps, p_t, f_c)
            ref = refactor_seconds(net, eps)
            width = interval_events(u, v, p_t, f_c, th)
            check = (
                straddle_check(net, u, v, eps, p_t, f_c, th, args.lp_time_limit)
                if n <= args.lp_max
                else "-"
            )
            secs.append(dt)
            units.append(dt / ref)
            solves.append(th.solves)
            undecided.append(th.undecided)
            unresolved.append(th.not_resolved)
            widths.append(width)
            checks.append(check)
            detail.append(
                [n, c, k, f"{th.s:.6f}", f"[{th.s_low:.6f}, {th.s_high:.6f}]", width,
                 th.solves, th.undecided, th.not_resolved, f"{dt:.2f}", check]
            )  # fmt: skip
            print(*detail[-1], flush=True)
        s = np.asarray(secs)
        rows.append(
            [
                n,
                len(secs),
                f"{np.median(s):.2f}",
                f"{s.max():.2f}",
                f"{np.median(units):.0f}",
                f"{np.median(solves):.0f}",
                int(np.sum(undecided)),
                int(np.sum(unresolved)),
                sum(w > 0 for w in widths),
                max(widths),
                sum(c == "ok" for c in checks),
                sum(c == "WRONG" for c in checks),
                sum(c == "limit" for c in checks),
                ("yes" if same else "NO") if n <= args.repeat_max else "-",
            ]
        )
        _write(rows, detail)


def _write(rows, detail) -> None:
    """Record the table so far (after every size: a long run keeps what it measured)."""
    body = (
        f"Machine: {machine()}. Seconds per threshold on the near-threshold set (six "
        "configurations of issue 13, cycled); 'refactorisations' is the median of each "
        "threshold's time over one numeric factorisation of its full lattice. 'intervals': "
        "thresholds reported as an interval because probes were undecided (within resolution "
        "of the boundary, or not resolved by the stages), with the widest interval in events. "
        "LP check: the configurations "
        "on both sides of each threshold (an interval's two ends: the last certified floppy "
        "and the first certified rigid configuration) against the HiGHS verdict LP ('LP limit': "
        "not checked, an LP reached --lp-time-limit). 'same': a "
        "second search, with BLAS set to 2 threads, returned the identical result.\n\n"
        + table(
            [
                "n",
                "samples",
                "median s",
                "max s",
                "refactorisations",
                "probes",
                "undecided probes",
                "not resolved",
                "intervals",
                "widest (events)",
                "LP ok",
                "LP wrong",
                "LP limit",
                "same",
            ],
            rows,
        )  # fmt: skip
        + "\n\nPer threshold:\n\n"
        + table(
            [
                "n",
                "config",
                "k",
                "s",
                "interval",
                "events",
                "probes",
                "undecided",
                "not resolved",
                "s",
                "LP check",
            ],
            detail,
        )  # fmt: skip
    )
    title = "Thresholds near the transition (benchmarks/bench_threshold.py)"
    record("threshold", title, body, raw={"sizes": rows, "thresholds": detail})


if __name__ == "__main__":
    main()
