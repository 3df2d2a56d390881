"""The ``reproduce`` command (registered by :mod:`~tensegrity_rigidity.cli`)."""

from __future__ import annotations

from .common import check_out, interrupt_status


def add_parser(sub) -> None:
    from ..paper.reproduce import EXPECTED

    p = sub.add_parser(
        "reproduce",
        help="run every study of the paper and write the report",
        description="Run the paper's studies through the sweep engine and write report.html, "
        "report.md, figures (PNG, SVG) and tables (CSV) into DIR. Expected run times on 2 cores: "
        + "; ".join(f"{k}: {v}" for k, v in EXPECTED.items())
        + ". Re-running resumes.",
    )
    p.add_argument(
        "--scale",
        default="quick",
        choices=sorted(EXPECTED),
        help="system sizes and sample counts (default quick)",
    )
    p.add_argument("--out", required=True, help="output directory")
    p.add_argument("--workers", type=int, default=None, help="local processes (default: all)")
    p.add_argument("--scheduler", default=None, help="Dask scheduler address")
    p.add_argument("--no-progress", action="store_true", help="no progress bars")
    p.set_defaults(handler=_run)


def _run(args) -> int:
    from ..ensemble.sweep import SweepInterrupted
    from ..paper.reproduce import reproduce

    check_out(args.out)
    try:
        res = reproduce(
            args.out,
            args.scale,
            workers=args.workers,
            scheduler=args.scheduler,
            progress=False if args.no_progress else None,
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
