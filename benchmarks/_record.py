"""Write a benchmark's table into its own section of BENCHMARKS.md (between markers)."""

from __future__ import annotations

import platform
import re
import time
from pathlib import Path

import numpy as np
import scipy

ROOT = Path(__file__).resolve().parents[1]


def machine() -> str:
    """One line naming what a run's timings and last bits depend on: the CPU, the libraries,
    and each BLAS with the kernel it picked for this CPU and its thread count (a verdict
    within resolution of the boundary can change with any of these; docs/model.md)."""
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
        f"{time.strftime('%Y-%m-%d')}"
    )


def record(section: str, title: str, body: str) -> None:
    path = ROOT / "BENCHMARKS.md"
    text = (
        path.read_text()
        if path.exists()
        else "# Benchmarks\n\nTables written by the scripts in `benchmarks/`; "
        "re-run a script to refresh its section.\n"
    )
    block = f"<!-- bench:{section} -->\n## {title}\n\n{body.strip()}\n<!-- /bench:{section} -->"
    pattern = re.compile(rf"<!-- bench:{section} -->.*?<!-- /bench:{section} -->", re.S)
    text = (
        pattern.sub(block, text) if pattern.search(text) else text.rstrip() + "\n\n" + block + "\n"
    )
    path.write_text(text)
    print(block)


def table(header: list[str], rows: list[list]) -> str:
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)
