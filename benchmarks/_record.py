"""Add a benchmark run's tables to its own section of BENCHMARKS.md (between markers), above the
earlier runs."""

from __future__ import annotations

import platform
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import scipy

ROOT = Path(__file__).resolve().parents[1]


def machine() -> str:
    """One line naming what a run's timings and last bits depend on: the CPU, the libraries,
    and each BLAS with the kernel it picked for this CPU and its thread count (a verdict
    within resolution of the boundary can change with any of these; docs/model.md), then how
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
        f"{np.__version__}, SciPy {scipy.__version__}, HiGHS {highs}, BLAS: {blas}, "
        f"{time.strftime('%Y-%m-%d')}" + (f". {STEADINESS.summary()}" if STEADINESS.times else "")
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


def record(section: str, title: str, body: str) -> None:
    """Add a run's ``body`` at the top of its section of BENCHMARKS.md, above the earlier runs.

    The section is the text between ``<!-- bench:{section} -->`` and ``<!-- /bench:{section} -->``
    under the heading ``## {title}``; a missing section is appended to the file. The new entry
    opens with the date, the commit (``+ changes`` when tracked files differ from it) and the
    command line, so that every table names what produced it. Earlier entries, and the
    analyses written between them, stay as they are: a re-run adds to the record, never
    replaces it. A second call for the same section from the same process (a script that
    records after each part of its run) updates the entry it wrote, unless that entry was
    edited in between (then the run gets a second entry). The commit is the one checked out
    when this module was imported, at the start of the run.
    """
    path = ROOT / "BENCHMARKS.md"
    text = (
        path.read_text()
        if path.exists()
        else "# Benchmarks\n\nTables written by the scripts in `benchmarks/`, each run added "
        "at the top of its section above the earlier ones.\n"
    )
    opening, closing = f"<!-- bench:{section} -->", f"<!-- /bench:{section} -->"
    previous = _written.get(section)
    command = " ".join(["python", *sys.argv]) if sys.argv and sys.argv[0] else "python"
    date = time.strftime("%Y-%m-%d")
    entry = f"**Run of {date} at {_STARTED_AT}:** `{command}`.\n\n{body.strip()}"
    pattern = re.compile(rf"{re.escape(opening)}(.*?){re.escape(closing)}", re.S)
    match = pattern.search(text)
    if match and previous is not None and previous in match.group(1):
        # this process wrote the section's newest entry already (a script that records after
        # each part of its run): that entry is brought up to date
        at = match.start(1) + match.group(1).index(previous)
        text = text[:at] + entry + text[at + len(previous) :]
    elif match:
        earlier = match.group(1).strip()
        if earlier.startswith("## "):  # the heading, written anew
            earlier = earlier.split("\n", 1)[1].strip() if "\n" in earlier else ""
        block = f"{opening}\n## {title}\n\n{entry}\n\n" + (f"{earlier}\n" if earlier else "")
        text = text[: match.start()] + block + closing + text[match.end() :]
    else:
        block = f"{opening}\n## {title}\n\n{entry}\n{closing}"
        text = text.rstrip() + "\n\n" + block + "\n"
    path.write_text(text)
    _written[section] = entry
    print(entry)


#: The entry this process last wrote in each section (see :func:`record`).
_written: dict[str, str] = {}


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
