"""Command line: a thin layer over the API.

``tensegrity-rigidity sample``  draw a random lattice instance and write it to .npz
``tensegrity-rigidity solve``   relax an instance file and print the certified verdict
                                (``--plot FIGURE`` also draws the network and its tensions)
``tensegrity-rigidity sweep``   run a TOML parameter sweep into a Parquet dataset
``tensegrity-rigidity info``    say what a results directory holds
``tensegrity-rigidity reproduce``  run every study of the paper and write the report
``tensegrity-rigidity jamming`` test whether a packing (GSD frame or instance file) is jammed

Exit status and messages:

* 0: done;
* 2: the user's to fix (bad input, a busy or unusable directory, a full disk): one line
  ``error: ...`` on stderr, never a traceback;
* 1: work failed (a chunk raised, a worker or the Dask scheduler died): one line ``error: ...``
  with a resume hint, finished work saved;
* 130 / 143: interrupted by Ctrl-C / SIGTERM, finished work saved;
* 141: the output pipe closed early (``info DIR | head``), silently, as the shell's own tools.

Warnings are printed as one line each, ``warning: ...``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import signal
import sys
import threading
import warnings
from collections.abc import Sequence
from pathlib import Path

from .. import interrupts
from ..errors import TensegrityError
from . import info as info_cli
from . import jamming as jamming_cli
from . import reproduce as reproduce_cli
from . import sweep as sweep_cli
from .common import Terminated, check_out, on_sigterm


def _add_sample(sub) -> None:
    p = sub.add_parser(
        "sample",
        help="write a random lattice instance (.npz)",
        description="Draw a random strained lattice sample and save it as .npz.",
    )
    p.add_argument("out", help="output file (.npz; a regular file or a new name)")
    p.add_argument(
        "--n",
        type=int,
        default=16,
        help="linear size: n x n nodes, n^3 nodes with --lattice fcc (default 16)",
    )
    p.add_argument("--delta", type=float, default=None, help="node disorder (default 0.2)")
    p.add_argument("--p-r", type=float, required=True, help="rod probability")
    p.add_argument(
        "--p-t", type=float, default=0.0, help="one-sided element probability (default 0)"
    )
    p.add_argument(
        "--f-c", type=float, default=0.5, help="cable fraction of one-sided elements (default 0.5)"
    )
    p.add_argument(
        "--phi",
        default="shear",
        help="strain type: angle or dilation|shear|compression (default shear)",
    )
    p.add_argument(
        "--theta",
        type=float,
        default=None,
        help="principal-axis angle in radians (default 0); 2D lattices only",
    )
    p.add_argument("--gamma", type=float, default=1.0, help="strain magnitude (default 1)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument(
        "--lattice",
        default="triangular",
        choices=["triangular", "square", "fcc"],
        help="lattice builder (default triangular; fcc: the 3D face-centred cubic lattice)",
    )


def _add_solve(sub) -> None:
    p = sub.add_parser(
        "solve",
        help="relax an instance and print the verdict",
        description="Find the exact relaxed state of an instance file and "
        "print energy, verdict and certificate residuals.",
    )
    p.add_argument("file", help="instance file (.npz)")
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    p.add_argument(
        "--plot",
        metavar="FIGURE",
        default=None,
        help="also draw the network to FIGURE (.png, .svg, .pdf; a regular file or a new name): "
        "rods solid, cables dashed, "
        "struts hollow, coloured by tension (vermillion pulls, blue pushes), line width |t|, "
        "displacements as arrows",
    )


def _cmd_sample(args) -> int:
    from ..model.io import check_output_file, save_instance

    check_out(args.out, "the output file")
    check_output_file(args.out, "the output file")  # before any work: a device, a FIFO, a link
    from ..model.lattice import DEFAULT_DELTA
    from ..model.network import Element
    from ..model.sampling import lattice_instance

    inst = lattice_instance(
        args.n,
        args.p_r,
        args.p_t,
        args.f_c,
        phi=args.phi,
        theta=0.0 if args.theta is None else args.theta,
        gamma=args.gamma,
        delta=DEFAULT_DELTA if args.delta is None else args.delta,
        seed=args.seed,
        lattice=args.lattice,
    )
    save_instance(args.out, inst)
    net = inst.network
    print(
        f"wrote {args.out}: {net.n_nodes} nodes, {net.n_sites} sites "
        f"({net.count(Element.ROD)} rods, {net.count(Element.CABLE)} cables, "
        f"{net.count(Element.STRUT)} struts)"
    )
    return 0


def _cmd_solve(args) -> int:
    from ..model.io import load_instance
    from ..solver.core import solve

    if args.plot is not None:  # refuse a bad figure path before any work
        from ..paper.plotting import check_plot_path

        check_plot_path(args.plot)
    instance = load_instance(args.file)
    result = solve(instance)
    summary = result.summary()
    if args.json:  # JSON has no NaN or Infinity: a non-finite number is null
        safe = {
            k: None if isinstance(v, float) and not math.isfinite(v) else v
            for k, v in summary.items()
        }
        print(json.dumps(safe, indent=2, allow_nan=False))
    else:
        print(solve_text(result))
    if args.plot is not None:
        from ..model.io import atomic_output
        from ..paper.plotting import plot_solution

        with atomic_output(
            args.plot, "the figure path", "network.png"
        ) as tmp:  # whole, or no file at all
            plot_solution(instance, result, tmp)
        print(f"wrote {args.plot}", file=sys.stderr)
    return 0


def _g(x: float) -> str:
    return f"{x:.6g}" if math.isfinite(x) else "none"


def solve_text(result) -> str:
    """``solve``'s text form: the verdict, the certificate that decided it, then the other
    side's best candidate, named as such (a rigid sample has no floppy certificate, so its
    best displacement is rejected by construction, and the other way round).

    Energies are in units of stiffness x length^2 and displacements in the positions' units:
    with unit stiffness, a lattice constant 1 and strain magnitude gamma, E scales as gamma^2
    and u as gamma.
    """
    stress = f"work {_g(result.work)}, force residual {_g(result.force_residual)}"
    if not math.isfinite(result.force_residual):
        stress = "none found"
    shift = f"violation {_g(result.violation)}, size {_g(result.displacement_size)}"
    if not math.isfinite(result.violation):
        shift = "none found"
    status = result.status
    lines = [("status", status + (f" ({result.reason})" if result.reason else ""))]
    if status == "rigid":
        lines.append(("certificate", f"self-stress from the {result.method} stage: {stress}"))
        if math.isfinite(result.violation):
            shift += " (the best displacement found, rejected: the sample is rigid)"
        lines.append(("floppy candidate", shift))
    elif status == "floppy":
        lines.append(("certificate", f"displacement from the {result.method} stage: {shift}"))
        if math.isfinite(result.force_residual):
            stress += " (the best self-stress found, rejected: the sample is floppy)"
        lines.append(("rigid candidate", stress))
    else:
        lines += [
            ("certificate", "none accepted (see message)"),
            ("rigid candidate", stress),
            ("floppy candidate", shift),
        ]
    displacements = (
        "minimum-norm, certified" if result.min_norm_ok else "not certified minimum-norm"
    )
    lines += [
        ("energy", f"{_g(result.energy)} (certified lower bound {_g(result.energy_lower)})"),
        ("affine_energy", _g(result.affine_energy)),
        ("displacements", displacements),
        (
            "work spent",
            f"{result.iterations} Newton iterations, {result.factorizations} "
            f"factorizations, {result.seconds:.3g} s",
        ),
    ]
    if result.message:
        lines.append(("message", result.message))
    width = max(len(key) for key, _ in lines)
    return "\n".join(f"{key:<{width}}  {value}" for key, value in lines)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every command. It imports no numerical library (each command
    imports what it needs when it runs), so that ``--help`` answers at once."""
    import tensegrity_rigidity

    parser = argparse.ArgumentParser(
        prog="tensegrity-rigidity",
        description="Exact rigidity of random periodic tensegrity networks.",
    )
    parser.add_argument(
        "--version",
        action="version",
        version=f"tensegrity-rigidity {tensegrity_rigidity.__version__}",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    _add_sample(sub)
    _add_solve(sub)
    sweep_cli.add_parser(sub)
    info_cli.add_parser(sub)
    reproduce_cli.add_parser(sub)
    jamming_cli.add_parser(sub)
    return parser


COMMANDS = {"sample": _cmd_sample, "solve": _cmd_solve}


def _one_line_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Print a warning on one line. The package's own warnings (``UserWarning``s) explain
    themselves; any other (a NumPy ``RuntimeWarning``, say) also names its category and
    where it was raised, so that it can be traced (forked workers print theirs the same way)."""
    text = " ".join(str(message).split())
    if not issubclass(category, UserWarning):
        where = Path(filename)
        package = Path(__file__).resolve().parents[1]
        if where.is_absolute() and where.resolve().is_relative_to(package):
            where = where.resolve().relative_to(package.parent)
        text = f"{text} ({category.__name__} at {where}:{lineno})"
    print(f"warning: {text}", file=sys.stderr if file is None else file)


#: Exit status when the output pipe closed early: 128 + SIGPIPE, as a shell reports a process
#: that SIGPIPE killed.
CLOSED_PIPE = 141

#: Signals held back while the command line starts (see :func:`main`).
_START_SIGNALS = {signal.SIGINT, signal.SIGTERM}


#: what each command imports before it runs (modules of this package, relative to it)
_PRELOAD = {
    "sample": (".model.io", ".model.sampling"),
    "solve": (".model.io", ".solver.core"),
    "info": (".ensemble.sweep",),
    "sweep": (".ensemble.sweep", ".solver.core"),
    "reproduce": (".paper.reproduce",),
}


def _preload(args: argparse.Namespace) -> None:
    """Import what the command needs (run while :data:`_START_SIGNALS` are blocked).

    A signal that lands inside a C extension's initialisation comes out as a ``SystemError``
    with a traceback, not as an interrupt; blocked, it waits until the imports are done. Only
    the command's own modules are imported: ``solve`` needs neither pandas nor matplotlib
    (unless it plots).
    """
    import importlib

    modules = list(_PRELOAD.get(args.command, ()))
    if getattr(args, "plot", None) is not None:
        modules.append(".paper.plotting")
    for name in modules:
        importlib.import_module(name, __name__.partition(".")[0])


def _interrupt_behind(exc: BaseException) -> BaseException | None:
    """The KeyboardInterrupt (or SIGTERM) behind an import failure, if there is one."""
    seen = exc.__cause__ or exc.__context__
    while seen is not None:
        if isinstance(seen, KeyboardInterrupt):
            return seen
        seen = seen.__cause__ or seen.__context__
    return None


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point; returns the exit status (see the module docstring).

    SIGINT and SIGTERM are blocked from the first line until the arguments are parsed and the
    numerical stack is imported (:func:`_preload`); a signal that arrived meanwhile is then
    handled like any other, in one line.
    """
    for name in ("stdout", "stderr"):
        if getattr(sys, name) is None:  # closed by the caller (">&-"): the output goes nowhere
            setattr(sys, name, open(os.devnull, "w"))
    in_main_thread = threading.current_thread() is threading.main_thread()
    start_mask = (
        signal.pthread_sigmask(signal.SIG_BLOCK, _START_SIGNALS) if in_main_thread else None
    )
    previous = signal.signal(signal.SIGTERM, on_sigterm) if in_main_thread else None
    previous_hook = sys.unraisablehook
    sys.unraisablehook = interrupts.quiet_unraisable(previous_hook)
    interrupts.reset()
    try:
        try:
            args = build_parser().parse_args(argv)
            handler = getattr(args, "handler", None) or COMMANDS[args.command]
            _preload(args)
        finally:
            if start_mask is not None:  # delivers a signal that arrived meanwhile
                signal.pthread_sigmask(signal.SIG_SETMASK, start_mask)
        with warnings.catch_warnings():
            warnings.showwarning = _one_line_warning
            status = int(handler(args) or 0)
            sys.stdout.flush()  # a closed pipe shows here, not at interpreter exit
            return status
    except TensegrityError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return int(getattr(exc, "exit_status", 2))
    except BrokenPipeError:
        # stdout was closed early (``... | head``): the reader has what it wanted; silence the
        # final flush and end as a process killed by SIGPIPE would (128 + 13)
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
        return CLOSED_PIPE
    except OSError as exc:  # a full disk, a read-only file system, ... while writing output
        where = f" ({exc.filename})" if exc.filename else ""
        print(f"error: {exc.strerror or exc}{where}", file=sys.stderr)
        return 2
    except Terminated:
        print("terminated", file=sys.stderr)
        return 143
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except (SystemError, ImportError) as exc:
        cause = _interrupt_behind(exc)
        if cause is None:
            raise
        print("terminated" if isinstance(cause, Terminated) else "interrupted", file=sys.stderr)
        return 143 if isinstance(cause, Terminated) else 130
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
        sys.unraisablehook = previous_hook
        interrupts.reset()


if __name__ == "__main__":
    sys.exit(main())
