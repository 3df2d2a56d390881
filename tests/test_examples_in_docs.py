"""The Python examples of the README and the docs run as printed (no stale attribute names)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: pages whose Python blocks are self-contained (the sweeps guide's need a spec file on disk)
PAGES = [
    "README.md",
    "docs/getting-started.md",
    "docs/guide/thresholds.md",
    "docs/guide/three-dimensions.md",
    "docs/guide/rigid-clusters.md",
    "docs/guide/packings.md",
]


def _blocks(page: str) -> list[str]:
    return re.findall(r"```python\n(.*?)```", (ROOT / page).read_text(), flags=re.S)


@pytest.mark.parametrize("page", PAGES)
def test_python_examples_run(page, tmp_path, monkeypatch):
    blocks = _blocks(page)
    assert blocks, f"{page} has no Python example"
    monkeypatch.chdir(tmp_path)  # examples may write files (save_instance)
    for code in blocks:
        exec(compile(code, page, "exec"), {"__name__": "__example__"})
