"""Sweep throughput: samples per second of a standard sweep, 1 and 2 workers.

The standard sweep: p_r in {0.45, 0.55, 0.65}, p_t = 0.2, f_c in {0, 0.5, 1}, phi in {dilation,
shear, compression}, nonaffinity (minimum-norm displacements) included; the same samples for
every worker count. Per size and worker count: wall time, samples per second, the median
``solve()`` time and Newton iterations, the stages that decided the verdicts, the undecided
samples and the samples whose minimum-norm displacements are certified (``min_norm_ok``), and
of the others those whose nonaffinity has a certified lower bound (``nonaffinity_lower``).
Run: python benchmarks/bench_sweep.py [--samples K] [--sizes 16 32 64]
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np
from _record import machine, probe, record, table

from tensegrity_rigidity.ensemble.spec import parse_spec
from tensegrity_rigidity.ensemble.sweep import load_results, run_sweep


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--samples", type=int, default=8)
    ap.add_argument("--sizes", type=int, nargs="+", default=[16, 32])
    args = ap.parse_args()
    rows = []
    for n in args.sizes:
        spec = parse_spec(
            {
                "n": n,
                "p_r": [0.45, 0.55, 0.65],
                "p_t": 0.2,
                "f_c": [0.0, 0.5, 1.0],
                "phi": ["dilation", "shear", "compression"],
                "samples": args.samples,
                "seed": 5,
                "output": {"chunk_size": 4},
            }
        )
        frames = {}
        for workers in (1, 2):
            probe()
            out = Path(tempfile.mkdtemp())
            try:
                start = time.perf_counter()
                run_sweep(spec, out / "s", executor=workers, progress=False)
                wall = time.perf_counter() - start
                df = load_results(out / "s")
                frames[workers] = df.drop(columns="solve_seconds")
            finally:
                shutil.rmtree(out)
            rows.append(
                [
                    n,
                    workers,
                    len(df),
                    f"{wall:.1f}",
                    f"{len(df) / wall:.1f}",
                    f"{df.solve_seconds.median() * 1e3:.1f}",
                    f"{df.iterations.median():.0f}",
                    ", ".join(f"{k} {v}" for k, v in sorted(df.method.value_counts().items())),
                    f"{int((~df.decided).sum())}",
                    f"{int(df.min_norm_ok.sum())}/{len(df)}",
                    f"{int((~df.min_norm_ok & np.isfinite(df.nonaffinity_lower)).sum())}",
                ]
            )
        assert frames[1].equals(frames[2]), "rows differ between worker counts"
    body = (
        f"Machine: {machine()}.\n\n"
        + table(
            [
                "n",
                "workers",
                "samples",
                "wall s",
                "samples/s",
                "median solve ms",
                "median Newton iterations",
                "decided by",
                "undecided",
                "min-norm certified",
                "bounded only",
            ],
            rows,
        )
        + "\n\nRows are identical for 1 and 2 workers (checked by the script)."
    )
    record("sweep", "Sweep throughput (benchmarks/bench_sweep.py)", body, raw=rows)


if __name__ == "__main__":
    main()
