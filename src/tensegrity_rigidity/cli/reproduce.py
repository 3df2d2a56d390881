"""The ``reproduce`` command (registered by :mod:`~tensegrity_rigidity.cli`)."""

from __future__ import annotations

from .common import check_out, interrupt_status


def add_parser(sub) -> None:
    from ..paper.run_times import EXPECTED

    p = sub.add_parser(
        "reproduce",
        help="run every study of the paper and write the report",
        description="Run the paper's studies through the sweep engine and write report.html, "
        "report.md, figures (PNG, SVG) and tables (CSV) into DIR. Run times on 2 cores: "
        + "; ".join(f"{k}: {v}" for k, v in EXPECTED.items())
        + ". Re-running resumes. --estimate prints the work of each study, the estimated run "
        "time and the error bar each headline claim can expect, and runs nothing.",
    )
    p.add_argument(
        "--scale",
        default="quick",
        choices=list(EXPECTED),
        help="system sizes and sample counts (default quick)",
    )
    p.add_argument("--out", default=None, help="output directory (required unless --estimate)")
    p.add_argument("--workers", type=int, default=None, help="local processes (default: all)")
    p.add_argument("--scheduler", default=None, help="Dask scheduler address")
    p.add_argument(
        "--no-progress", action="store_true", help="no progress bar (one line per study instead)"
    )
    p.add_argument(
        "--evidence",
        default=None,
        metavar="FSS_DIR",
        help="the output directory of a finished '--scale fss' run: its finite-size and "
        "node-disorder results join this report (read only), so that the explanation column "
        "gives their evidence for each disagreement",
    )
    p.add_argument(
        "--estimate",
        action="store_true",
        help="print the threshold searches and grid solves per study and size, the estimated "
        "wall time on --workers (default: all cores) and the expected error bars; with --out, "
        "count only what is not stored there yet. Exit status 1 when the estimate on 2 workers "
        "exceeds the scale's budget",
    )
    p.set_defaults(handler=_run)


def _estimate(args) -> int:
    from pathlib import Path

    from ..ensemble.executors import check_workers, usable_cores
    from ..errors import InputError
    from ..paper.budget import describe, estimate, expected_errors

    check_workers(args.workers, "--workers")  # nothing runs: any count is priced, not capped
    if args.out is not None and Path(args.out).exists() and not Path(args.out).is_dir():
        raise InputError(f"--out {args.out}: not a directory (a reproduction's output)")
    workers = usable_cores() if args.workers is None else args.workers
    est = estimate(args.scale, workers, out=args.out)
    print(describe(est, expected_errors(args.scale)))
    on_two = est if workers == 2 else estimate(args.scale, 2, out=args.out)
    if workers != 2 and on_two.budget_minutes is not None:
        verdict = "OVER BUDGET" if on_two.over_budget else "within"
        print(
            f"on 2 workers: {on_two.wall_seconds / 60:.0f} min, budget "
            f"{on_two.budget_minutes:g} min ({verdict})"
        )
    return 1 if on_two.over_budget else 0


def _run(args) -> int:
    from pathlib import Path

    from ..ensemble.executors import check_workers
    from ..ensemble.sweep import SweepInterrupted
    from ..errors import InputError
    from ..paper.reproduce import reproduce

    if args.evidence is not None and not Path(args.evidence).is_dir():
        raise InputError(f"--evidence {args.evidence}: no such directory")
    if args.estimate:
        return _estimate(args)  # which checks --workers
    check_workers(args.workers, "--workers")
    if args.out is None:
        raise InputError("reproduce needs --out DIR (or --estimate, which runs nothing)")
    check_out(args.out)
    try:
        res = reproduce(
            args.out,
            args.scale,
            workers=args.workers,
            scheduler=args.scheduler,
            progress=False if args.no_progress else None,
            evidence=args.evidence,
        )
    except SweepInterrupted as exc:
        import sys

        word = "terminated" if interrupt_status(exc.cause) == 143 else "interrupted"
        print(
            f"{word}; finished samples are kept in {args.out}/studies: run the same "
            "command again to resume",
            file=sys.stderr,
        )
        return interrupt_status(exc.cause)
    print(f"wrote {res['report']['html']} and {res['report']['md']}")
    return 0
