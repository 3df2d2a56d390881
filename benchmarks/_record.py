"""Write a benchmark run's current table into its own section of BENCHMARKS.md (between markers)
and append its raw results to ``benchmarks/results/<script>.json``."""

from __future__ import annotations

import json
import platform
import re
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import scipy

ROOT = Path(__file__).resolve().parents[1]


def machine(dated: bool = True) -> str:
    """One line naming what a run's timings and last bits depend on: the CPU, the libraries,
    and each BLAS with the kernel it picked for this CPU and its thread count (a verdict
    within resolution of the boundary can change with any of these; docs/model.md), the date
    unless not ``dated`` (the package's data files carry none: git dates them), then how
    steady the machine was where the script probed it (:func:`probe`)."""
    import os

    import highspy
    from threadpoolctl import threadpool_info

    import tensegrity_rigidity.solver.linalg  # noqa: F401 (loads CVXOPT's BLAS too)

    cpu = platform.processor() or platform.machine()
    try:
        info = Path("/proc/cpuinfo").read_text()
        cpu = re.search(r"model name\s*:\s*(.*)", info).group(1).strip()  # type: ignore[union-attr]
        cpu += " (AVX-512)" if " avx512f" in info else " (no AVX-512)"
    except (OSError, AttributeError):
        pass
    blas = "; ".join(
        f"{Path(d['filepath']).name.split('-')[0]} {d.get('version')} "
        f"{d.get('architecture')} x{d['num_threads']}"
        for d in threadpool_info()
        if d["user_api"] == "blas"
    )
    h = highspy.Highs()
    highs = f"{h.versionMajor()}.{h.versionMinor()}.{h.versionPatch()}"
    return (
        f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, NumPy "
        f"{np.__version__}, SciPy {scipy.__version__}, HiGHS {highs}, BLAS: {blas}"
        + (f", {time.strftime('%Y-%m-%d')}" if dated else "")
        + (f". {STEADINESS.summary()}" if STEADINESS.times else "")
    )


class Steadiness:
    """How steady the machine was during a run: a fixed workload timed between measurements.

    The workload (sorting the same 100,000 random numbers, about 5 ms; no BLAS, so the thread
    settings do not enter) should take the same time at every probe. A spread says that the
    machine slowed down in passing, and by how much; this machine was measured to slow down
    tenfold for seconds at a time (2026-11-30), which shifts any timing taken through it.
    """

    def __init__(self, size: int = 100_000) -> None:
        self._data = np.random.default_rng(0).random(size)
        self.times: list[float] = []

    def probe(self) -> float:
        """Time the workload once; returns the time (seconds)."""
        t0 = time.perf_counter()
        np.sort(self._data)
        self.times.append(time.perf_counter() - t0)
        return self.times[-1]

    def summary(self) -> str:
        """One clause for a run's entry: the probes' median, range and spread."""
        if not self.times:
            return "Steadiness not probed"
        t = np.asarray(self.times) * 1e3
        return (
            f"Steadiness: a fixed workload timed {t.size} times through the run took "
            f"{np.median(t):.2f} ms median, {t.min():.2f} to {t.max():.2f} ms "
            f"(max / min {t.max() / t.min():.1f})"
        )


#: The probes of this process (:func:`probe`), summarised by :func:`machine`.
STEADINESS = Steadiness()


def probe() -> float:
    """Time the steadiness workload once (the timing scripts call it before each instance, and
    `bench_sweep.py` before each sweep); returns that time in seconds."""
    return STEADINESS.probe()


def record(section: str, title: str, body: str, raw: Any = None) -> None:
    """Write a run's ``body`` as the current table of its section of BENCHMARKS.md, and append
    its raw results to ``benchmarks/results/<script>.json``.

    The section is the text between ``<!-- bench:{section} -->`` and ``<!-- /bench:{section} -->``
    under the heading ``## {title}``; it is replaced as a whole (a missing section is appended
    to the file), so BENCHMARKS.md holds the newest run of each script and its history lives in
    git. The entry opens with the date, the commit (``+ changes`` when tracked files differ from
    it) and the command line, so that every table names what produced it.

    ``raw`` (anything JSON can hold; numbers NumPy or not) is appended, with the same date,
    commit and command, to the JSON list in ``benchmarks/results/<script>.json``, ``<script>``
    the running script's name without ``.py``: the per-instance numbers behind the table, kept
    as data. A second call for the same section from the same process (a script that records
    after each part of its run) replaces what this process wrote, in both files. The commit is
    the one checked out when this module was imported, at the start of the run.
    """
    path = ROOT / "BENCHMARKS.md"
    text = (
        path.read_text()
        if path.exists()
        else "# Benchmarks\n\nThe current tables of the scripts in `benchmarks/`, one section "
        "each; raw results in `benchmarks/results/`.\n"
    )
    opening, closing = f"<!-- bench:{section} -->", f"<!-- /bench:{section} -->"
    command = _command()
    date = time.strftime("%Y-%m-%d")
    entry = f"**Run of {date} at {_STARTED_AT}:** `{command}`.\n\n{body.strip()}"
    block = f"{opening}\n## {title}\n\n{entry}\n{closing}"
    pattern = re.compile(rf"{re.escape(opening)}.*?{re.escape(closing)}", re.S)
    if pattern.search(text):
        text = pattern.sub(lambda _: block, text, count=1)
    else:
        text = text.rstrip() + "\n\n" + block + "\n"
    path.write_text(text)
    if raw is not None:
        _append_raw(section, {"date": date, "commit": _STARTED_AT, "command": command}, raw)
    print(entry)


def _command() -> str:
    return " ".join(["python", *sys.argv]) if sys.argv and sys.argv[0] else "python"


def results_path() -> Path:
    """``benchmarks/results/<script>.json`` of the running script (``run.json`` without one)."""
    script = Path(sys.argv[0]).stem if sys.argv and sys.argv[0] else "run"
    return ROOT / "benchmarks" / "results" / f"{script}.json"


def _append_raw(section: str, head: dict, raw: Any) -> None:
    """Append one run's raw results to :func:`results_path` (or replace this process's own)."""
    path = results_path()
    path.parent.mkdir(parents=True, exist_ok=True)
    runs = json.loads(path.read_text()) if path.exists() else []
    run = head | {"section": section, "results": raw}
    at = _appended.get(section)
    if at is not None and at < len(runs) and runs[at].get("command") == head["command"]:
        runs[at] = run
    else:
        runs.append(run)
        _appended[section] = len(runs) - 1
    path.write_text(json.dumps(runs, indent=1, default=_plain) + "\n")


def _plain(value: Any) -> Any:
    """JSON for what ``json`` does not know: NumPy scalars and arrays, anything else as text."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    return str(value)


#: Per section, the index in its results file of the run this process appended (see :func:`record`).
_appended: dict[str, int] = {}


def _commit() -> str:
    """The checkout's short commit, with ``+ changes`` when tracked files differ from it
    (``no git checkout`` outside one)."""
    try:
        head = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True
        )
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no"],
            cwd=ROOT,
            capture_output=True,
            text=True,
        )
    except OSError:
        return "no git checkout"
    if head.returncode != 0:
        return "no git checkout"
    return head.stdout.strip() + (" + changes" if dirty.stdout.strip() else "")


#: The commit the run started from (a commit made during a long run must not be named).
_STARTED_AT = _commit()


def table(header: list[str], rows: list[list]) -> str:
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)
