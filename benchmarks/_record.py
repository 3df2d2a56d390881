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
    import os

    return (
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, Python "
        f"{platform.python_version()}, NumPy {np.__version__}, SciPy {scipy.__version__}, "
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
