"""How fast the command line answers: each command's wall time against the bare import.

What a user types first, each run as a fresh process the way the shell runs it (the installed
``tensegrity-rigidity`` script): ``--help``, ``--version``, ``sweep --help``, ``reproduce
--help``, ``sample`` of the README's sample (n = 16) and ``solve`` of it, beside
``python -c "import tensegrity_rigidity"`` and beside the import of the libraries ``solve``
needs (NumPy, SciPy's sparse matrices and BLAS, CVXOPT, QDLDL: the floor of its start). Like
hyperfine: one warm-up run of each command,
then ``--repeats`` rounds in which the commands take turns; per command the median, the
fastest and the slowest run, and the median minus the bare import's median (the target: at
most 0.5 s for ``--help`` and ``solve``).

``--against REV`` runs the same commands on the package's sources at a git revision (``git
archive REV src``, put first on ``PYTHONPATH``) in the same rounds, old against new: a command
that fails there (``--version`` before it existed) is shown as failed.

Run: python benchmarks/bench_cli_start.py [--repeats 10] [--against REV]
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _record import ROOT, machine, probe, record, table

#: the README's sample (n = 16, the shear strain), drawn once and solved by every tree
SAMPLE = ["--n", "16", "--p-r", "0.55", "--p-t", "0.3", "--f-c", "0.5", "--phi", "shear"]
#: the libraries ``solve`` cannot start without (sparse matrices, SciPy's BLAS, CHOLMOD): the
#: floor of its start, whatever the package does
LIBRARIES = "import numpy, scipy.sparse, scipy.linalg, cvxopt, qdldl"
#: name -> arguments of the command line (a string: Python code run with ``python -c``)
COMMANDS: dict[str, list[str] | str] = {
    'python -c "import tensegrity_rigidity"': "import tensegrity_rigidity",
    f'python -c "{LIBRARIES}"': LIBRARIES,
    "tensegrity-rigidity --help": ["--help"],
    "tensegrity-rigidity --version": ["--version"],
    "tensegrity-rigidity sweep --help": ["sweep", "--help"],
    "tensegrity-rigidity reproduce --help": ["reproduce", "--help"],
    "tensegrity-rigidity sample demo.npz ...": ["sample", "demo.npz", *SAMPLE, "--seed", "1"],
    "tensegrity-rigidity solve demo.npz": ["solve", "demo.npz"],
}
BARE = next(iter(COMMANDS))
#: the issue's bound on ``--help`` and ``solve`` above the bare import (seconds)
TARGET = 0.5


def script() -> str:
    """The installed ``tensegrity-rigidity`` of this interpreter's environment."""
    found = Path(sys.executable).with_name("tensegrity-rigidity")
    return str(found) if found.exists() else shutil.which("tensegrity-rigidity") or ""


def sources_at(rev: str, into: Path) -> Path:
    """The package's sources at git revision ``rev``, unpacked under ``into``; returns src/."""
    archive = subprocess.run(
        ["git", "archive", rev, "src"], cwd=ROOT, capture_output=True, check=True
    ).stdout
    into.mkdir(parents=True)
    subprocess.run(["tar", "-x", "-C", str(into)], input=archive, check=True)
    return into / "src"


def run_once(args: list[str] | str, env: dict, cwd: Path) -> float | None:
    """Wall seconds of one fresh process (None when it fails)."""
    cmd = [sys.executable, "-c", args] if isinstance(args, str) else [script(), *args]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, env=env, cwd=cwd, capture_output=True)
    seconds = time.perf_counter() - t0
    return seconds if proc.returncode == 0 else None


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=10, help="rounds after the warm-up")
    ap.add_argument("--against", default=None, metavar="REV", help="also time this revision")
    args = ap.parse_args()
    if not script():
        sys.exit("tensegrity-rigidity is not installed in this environment (pip install -e .)")
    work = Path(tempfile.mkdtemp())
    try:
        trees = {"this checkout": dict(os.environ)}
        if args.against:
            old = sources_at(args.against, work / "old")
            path = os.pathsep.join([str(old), os.environ.get("PYTHONPATH", "")]).rstrip(":")
            trees[args.against] = dict(os.environ, PYTHONPATH=path)
        dirs = {tree: work / f"tree{i}" for i, tree in enumerate(trees)}
        for tree, env in trees.items():  # each tree its own sample file: the same draw
            dirs[tree].mkdir()
            run_once(COMMANDS["tensegrity-rigidity sample demo.npz ..."], env, dirs[tree])
        times: dict[str, dict[str, list]] = {t: {c: [] for c in COMMANDS} for t in trees}
        for round_ in range(args.repeats + 1):  # round 0 warms the caches, not recorded
            probe()
            for command, argv in COMMANDS.items():
                for tree, env in trees.items():
                    seconds = run_once(argv, env, dirs[tree])
                    if round_:
                        times[tree][command].append(seconds)
    finally:
        shutil.rmtree(work)
    body, raw = report(times, args)
    record("cli_start", "Command-line start (benchmarks/bench_cli_start.py)", body, raw)


def report(times: dict[str, dict[str, list]], args) -> tuple[str, dict]:
    """The table (per command and tree: median, range, median above the bare import)."""
    header = ["command"]
    for tree in times:
        header += [f"{tree}: median s", "range s", "above import s"]
    rows = []
    for command in COMMANDS:
        row = [f"`{command}`"]
        for runs in times.values():
            ok = [t for t in runs[command] if t is not None]
            if len(ok) < len(runs[command]):
                row += ["fails", "-", "-"]
                continue
            median = statistics.median(ok)
            above = median - statistics.median(runs[BARE])
            row += [
                f"{median:.3f}",
                f"{min(ok):.3f} to {max(ok):.3f}",
                "-" if command == BARE else f"{above:+.3f}",
            ]
        rows.append(row)
    body = (
        f"Machine: {machine()}.\n\n"
        f"Wall seconds of a fresh process per command, {args.repeats} rounds after one warm-up "
        f"round, the commands taking turns; 'above import' is the median minus the median of "
        f"the bare import (target: at most {TARGET} s for `--help` and `solve`); the libraries' "
        f"line is the floor of `solve`'s start.\n\n" + table(header, rows)
    )
    return body, {"repeats": args.repeats, "target_seconds": TARGET, "seconds": times}


if __name__ == "__main__":
    main()
