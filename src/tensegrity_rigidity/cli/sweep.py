"""The ``sweep`` command (registered by :mod:`~tensegrity_rigidity.cli`)."""

from __future__ import annotations

import sys

from .common import check_out, interrupt_status


def add_parser(sub) -> None:
    p = sub.add_parser(
        "sweep",
        help="run a parameter sweep (TOML spec) into a Parquet dataset",
        description="Run every sample of a TOML spec, in chunks saved as they finish, and print "
        "P with 95% Wilson intervals per grid point. Re-running the same command resumes; a "
        "larger spec (more samples, more grid values) into the same directory computes only "
        "what is new. One sweep at a time may write a directory.",
    )
    p.add_argument(
        "spec", help="TOML spec file (examples/sweep.toml; docs/guide/sweeps.md lists its keys)"
    )
    p.add_argument("--out", required=True, help="results directory")
    p.add_argument(
        "--workers",
        type=int,
        default=None,
        help="local worker processes (default and most: the usable cores; never more than chunks)",
    )
    p.add_argument(
        "--scheduler",
        default=None,
        help="address of a running Dask scheduler, e.g. tcp://host:8786",
    )
    p.add_argument(
        "--wait-workers",
        type=float,
        default=60.0,
        metavar="SECONDS",
        help="how long to wait for a first worker of a Dask scheduler that has none (default 60)",
    )
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(handler=_run)


def _run(args) -> int:
    from ..ensemble.executors import check_workers
    from ..ensemble.summary import format_table, probability_table
    from ..ensemble.sweep import SweepInterrupted, load_results, run_sweep
    from ..errors import SpecError

    check_out(args.out)
    if args.workers is not None:
        check_workers(args.workers, "--workers")
    if not args.wait_workers >= 0:
        raise SpecError(f"--wait-workers must be a non-negative number, got {args.wait_workers}")
    try:
        rep = run_sweep(
            args.spec,
            args.out,
            executor=args.workers,
            scheduler=args.scheduler,
            progress=False if args.no_progress else None,
            wait_for_workers=args.wait_workers,
        )
    except SweepInterrupted as exc:
        r = exc.report
        word = "terminated" if interrupt_status(exc.cause) == 143 else "interrupted"
        print(
            f"{word}: {r.samples_saved} of {r.samples_total} samples saved in {args.out}; run "
            "the same command again to resume",
            file=sys.stderr,
        )
        return interrupt_status(exc.cause)
    if rep.samples_run == 0:
        print(f"{args.out}: all {rep.samples_total} samples already done")
    else:
        rate = rep.samples_run / rep.seconds if rep.seconds else float("inf")
        print(
            f"{args.out}: ran {rep.samples_run} samples in {rep.chunks_run} chunks "
            f"({rate:.1f} samples/s), reused {rep.samples_reused} already done"
        )
    print(format_table(probability_table(load_results(args.out))))
    return 0
