"""The ``sweep`` command (registered by :mod:`~tensegrity_rigidity.cli`)."""

from __future__ import annotations

import sys


def add_parser(sub) -> None:
    p = sub.add_parser(
        "sweep",
        help="run a parameter sweep (TOML spec) into a Parquet dataset",
        description="Run every sample of a TOML spec, in chunks saved as they finish. "
        "Re-running the same command resumes; a finished sweep does no work.",
    )
    p.add_argument("spec", help="TOML spec file (see tensegrity_rigidity.ensemble.spec)")
    p.add_argument("--out", required=True, help="results directory")
    p.add_argument(
        "--workers", type=int, default=None, help="local worker processes (default: all cores)"
    )
    p.add_argument(
        "--scheduler",
        default=None,
        help="address of a running Dask scheduler, e.g. tcp://host:8786",
    )
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(handler=_run)


def _run(args) -> int:
    from ..ensemble.spec import load_spec
    from ..ensemble.sweep import SweepInterrupted, run_sweep
    from ..errors import SpecError

    spec = load_spec(args.spec)  # validate before any work
    if args.workers is not None and args.workers < 1:
        raise SpecError(f"--workers must be at least 1, got {args.workers}")
    try:
        rep = run_sweep(
            args.spec,
            args.out,
            executor=args.workers,
            scheduler=args.scheduler,
            progress=False if args.no_progress else None,
        )
    except SweepInterrupted as exc:
        r = exc.report
        print(
            f"interrupted: {r.chunks_skipped + r.chunks_run} of {r.chunks_total} chunks saved "
            f"in {args.out}; run the same command again to resume",
            file=sys.stderr,
        )
        return 130
    if rep.chunks_run == 0:
        print(
            f"{args.out}: all {rep.chunks_total} chunks already done ({spec.n_samples()} samples)"
        )
    else:
        rate = rep.samples_run / rep.seconds if rep.seconds else float("inf")
        print(
            f"{args.out}: ran {rep.chunks_run} chunks ({rep.samples_run} samples, "
            f"{rate:.1f} samples/s), skipped {rep.chunks_skipped} already done"
        )
    return 0
