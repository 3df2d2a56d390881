"""The jamming test on random bidisperse packings: time per size, agreement with an independent LP.

For each dimension and size, ``--samples`` packings at each packing fraction near the jamming
point (soft packings minimised by FIRE, contacts = overlaps) are tested for collective and strict
jamming; wall and CPU times of the packing and of each test are recorded per instance, and at
sizes up to ``--oracle-max`` each verdict is compared with ``benchmarks/jamming_reference.py``
(a displacement LP by SciPy's HiGHS plus a dense SVD) where that oracle decides with a margin.
Writes its section of BENCHMARKS.md, appends the raw rows to
``benchmarks/results/bench_jamming.json`` and writes the per-sample cost model
``seconds = a N^b`` (per dimension, packing and tests, fitted to the CPU times) to
``src/tensegrity_rigidity/ensemble/data/jamming_costs.json``, which
:func:`tensegrity_rigidity.ensemble.jamming.estimate_cost` reads.

    python benchmarks/bench_jamming.py                 # 2D 64..1024, 3D 64..256
    python benchmarks/bench_jamming.py --quick         # a smoke run (not recorded)
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks._record import machine, probe, record, table  # noqa: E402
from benchmarks.jamming_reference import reference_jamming  # noqa: E402
from tensegrity_rigidity.ensemble.jamming import sample_rng  # noqa: E402
from tensegrity_rigidity.model.softdisks import soft_packing  # noqa: E402
from tensegrity_rigidity.solver.jamming import jamming  # noqa: E402

COSTS = ROOT / "src" / "tensegrity_rigidity" / "ensemble" / "data" / "jamming_costs.json"
PHIS = {2: (0.835, 0.845, 0.855), 3: (0.635, 0.645, 0.655)}


def _timed(fn, *args):
    w, c = time.perf_counter(), time.process_time()
    out = fn(*args)
    return out, time.perf_counter() - w, time.process_time() - c


def run_instance(dim: int, n: int, phi: float, sample: int, oracle: bool) -> dict:
    probe()
    sp, w_pack, c_pack = _timed(soft_packing, n, phi, sample_rng(7, n, phi, sample), dim)
    net = sp.packing.contact_network(tolerance=0.0)
    row = {"dim": dim, "n": n, "phi": phi, "sample": sample, "wall_packing": w_pack,
           "cpu_packing": c_pack, "contacts": net.n_sites}  # fmt: skip
    for kind in ("collective", "strict"):
        r, w, c = _timed(jamming, net, kind)
        row |= {
            kind: r.status,
            f"{kind}_reason": r.reason,
            f"wall_{kind}": w,
            f"cpu_{kind}": c,
            "rattlers": r.n_rattlers,
            f"excess_{kind}": r.excess_contacts,
        }
        if oracle:
            ref, w_ref, _ = _timed(reference_jamming, net, kind)
            row |= {f"oracle_{kind}": ref.status, f"wall_oracle_{kind}": w_ref}
    return row


def fit_cost(rows: list[dict], dim: int) -> dict:
    """``seconds = a N^b`` least squares in logs, for the packing and for both tests (CPU)."""
    sel = [r for r in rows if r["dim"] == dim]
    n = np.array([r["n"] for r in sel], dtype=float)
    out = {}
    for name, key in (("packing", lambda r: r["cpu_packing"]),
                      ("tests", lambda r: r["cpu_collective"] + r["cpu_strict"])):  # fmt: skip
        t = np.array([max(key(r), 1e-4) for r in sel])
        b, log_a = np.polyfit(np.log(n), np.log(t), 1)
        # a mean, not a median: the estimate's total is a sum
        a = float(np.mean(t / n**b))
        out[name] = [a, float(b)]
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes2", type=int, nargs="*", default=[64, 256, 1024])
    ap.add_argument("--sizes3", type=int, nargs="*", default=[64, 256])
    ap.add_argument("--samples", type=int, default=4)
    ap.add_argument("--oracle-max", type=int, default=256)
    ap.add_argument("--quick", action="store_true", help="one small size, nothing recorded")
    args = ap.parse_args(argv)
    if args.quick:
        args.sizes2, args.sizes3, args.samples = [32], [32], 1
    rows = []
    for dim, sizes in ((2, args.sizes2), (3, args.sizes3)):
        for n in sizes:
            for phi in PHIS[dim]:
                for k in range(args.samples):
                    rows.append(run_instance(dim, n, phi, k, n <= args.oracle_max))
                    r = rows[-1]
                    print(f"{dim}D n={n} phi={phi} #{k}: {r['collective']}/{r['strict']} "
                          f"pack {r['wall_packing']:.2f}s coll {r['wall_collective']:.2f}s "
                          f"strict {r['wall_strict']:.2f}s", flush=True)  # fmt: skip
    body_rows = []
    for dim, sizes in ((2, args.sizes2), (3, args.sizes3)):
        for n in sizes:
            sel = [r for r in rows if r["dim"] == dim and r["n"] == n]
            if not sel:
                continue

            def med(key, sel=sel):
                return f"{np.median([r[key] for r in sel]):.2f}"

            def mx(key, sel=sel):
                return f"{np.max([r[key] for r in sel]):.2f}"

            counts = {}
            for kind in ("collective", "strict"):
                c = [r[kind] for r in sel]
                counts[kind] = "/".join(
                    str(c.count(s)) for s in ("jammed", "unjammed", "undecided")
                )
            agree = compared = 0
            for r in sel:
                for kind in ("collective", "strict"):
                    o = r.get(f"oracle_{kind}")
                    if o in ("jammed", "unjammed") and r[kind] != "undecided":
                        compared += 1
                        agree += o == r[kind]
            oracle = f"{agree}/{compared}" if any("oracle_collective" in r for r in sel) else "-"
            body_rows.append([
                f"{dim}D", n, len(sel), counts["collective"], counts["strict"],
                med("wall_packing"), med("cpu_packing"), med("wall_collective"),
                med("cpu_collective"), mx("wall_collective"), med("wall_strict"),
                med("cpu_strict"), mx("wall_strict"), oracle,
            ])  # fmt: skip
    header = ["dim", "N", "packings", "collective J/U/undecided", "strict J/U/undecided",
              "packing wall s", "packing CPU s", "collective wall s", "collective CPU s",
              "collective max wall s", "strict wall s", "strict CPU s", "strict max wall s",
              "agree with oracle LP"]  # fmt: skip
    costs = {str(d): fit_cost(rows, d) for d in (2, 3) if any(r["dim"] == d for r in rows)}
    body = (
        f"Machine: {machine()}.\n\n"
        f"Packing fractions {PHIS[2]} (2D) and {PHIS[3]} (3D), {args.samples} packings each; "
        "medians over the packings of one size, times of one process (wall and CPU). "
        "Agreement counts every (packing, kind) the oracle decides with a margin.\n\n"
        + table(header, body_rows)
        + "\n\nPer-sample cost model (CPU seconds = a N^b, written to "
        "`ensemble/data/jamming_costs.json`): "
        + "; ".join(
            f"{d}D packing {c['packing'][0]:.3g} N^{c['packing'][1]:.2f}, tests "
            f"{c['tests'][0]:.3g} N^{c['tests'][1]:.2f}"
            for d, c in costs.items()
        )  # fmt: skip
    )
    if args.quick:
        print(body)
        return 0
    record("jamming", "Jamming test on random packings (benchmarks/bench_jamming.py)", body, rows)
    COSTS.parent.mkdir(parents=True, exist_ok=True)
    stamp = f"benchmarks/bench_jamming.py, {time.strftime('%Y-%m-%d')}, {machine().split(',')[0]}"
    COSTS.write_text(json.dumps({"measured": stamp, **costs}, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
