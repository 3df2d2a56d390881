"""The documentation builds warning-free and the tutorial notebook runs (issue 16, items 1-2).

Both need the docs toolchain, which ``pip install -e ".[test]"`` installs (the ``test`` extra
includes ``docs``); without it they are skipped, saying so.
"""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest

import tensegrity_rigidity

DOCS = Path(__file__).resolve().parents[1] / "docs"
TUTORIAL = DOCS / "tutorial.ipynb"
REASON = "the docs toolchain is not installed (pip install -e '.[test]' or '.[docs]')"


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """The HTML site, built as the README says: ``sphinx-build -W`` (warnings are errors)."""
    for module in ("sphinx", "numpydoc", "myst_nb", "furo"):
        pytest.importorskip(module, reason=REASON)
    out = tmp_path_factory.mktemp("docs") / "html"
    start = time.perf_counter()
    proc = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-E", "-q", "-b", "html"]
        + [str(DOCS), str(out)],
        capture_output=True,
        text=True,
    )
    print(f"docs built in {time.perf_counter() - start:.1f} s")
    assert proc.returncode == 0, f"sphinx-build -W failed:\n{proc.stderr[-5000:]}"
    return out


def test_docs_build_warning_free_with_every_page(built):
    for page in (
        "index",
        "getting-started",
        "tutorial",
        "model",
        "solver",
        "results",
        "guide/sweeps",
        "guide/thresholds",
        "guide/dask-clusters",
        "guide/rigid-clusters",
        "guide/three-dimensions",
        "guide/reproduction",
        "reliability",
        "benchmarks",
        "changelog",
        "api/index",
        "api/model",
        "api/solver",
        "api/analysis",
        "api/ensemble",
        "api/paper",
    ):
        assert (built / f"{page}.html").is_file(), page


def test_api_reference_documents_the_whole_top_level(built):
    page = (built / "api" / "index.html").read_text()
    missing = [
        n for n in tensegrity_rigidity.__all__ if f'id="tensegrity_rigidity.{n}"' not in page
    ]
    assert not missing


def test_benchmark_tables_and_the_resolution_model_are_in_the_site(built):
    assert "<table" in (built / "benchmarks.html").read_text()
    model = (built / "model.html").read_text()
    for words in ("resolution model", "violation", "Deliberate departures from the paper"):
        assert words in model


def test_the_built_tutorial_shows_its_executed_outputs(built):
    page = (built / "tutorial.html").read_text()
    assert page.count("<img") >= 3  # the network, P with Wilson intervals, P from thresholds
    assert "S_t / S_r =" in page and "interval [" in page
    assert "Traceback" not in page and "IProgress" not in page


def _outputs(nb) -> str:
    text = []
    for cell in nb.cells:
        for out in cell.get("outputs", []):
            if out.output_type == "stream":
                text.append(out.text)
            elif out.output_type == "error":
                text.append(f"ERROR {out.ename}: {out.evalue}")
            else:
                text.append(out.get("data", {}).get("text/plain", ""))
    return "\n".join(text)


def test_the_tutorial_ran_in_the_build_with_every_result(built):
    """The notebook the docs build executed (myst-nb writes it beside the site): no error, its
    three figures and its results; the committed notebook carries no outputs."""
    nbformat = pytest.importorskip("nbformat", reason=REASON)
    committed = nbformat.read(TUTORIAL, as_version=4)
    assert not any(c.get("outputs") for c in committed.cells if c.cell_type == "code"), (
        "commit the tutorial without outputs: the docs build executes it"
    )
    nb = nbformat.read(built.parent / "jupyter_execute" / TUTORIAL.name, as_version=4)
    text = _outputs(nb)
    assert "ERROR" not in text
    images = sum(
        "image/png" in out.get("data", {}) for c in nb.cells for out in c.get("outputs", [])
    )
    assert images == 3
    for expected in ("verdict         rigid", "P [95% Wilson]", "interval [", "S_t / S_r ="):
        assert expected in text, expected


def test_every_promise_of_the_reliability_page_names_a_test_that_exists():
    """docs/reliability.md backs each promise with test names in brackets: each must be a test
    function of the suite (a renamed or deleted test leaves a promise unbacked)."""
    import re

    root = Path(__file__).resolve().parents[1]
    page = (root / "docs" / "reliability.md").read_text()
    named = set(re.findall(r"`(test_\w+)`", page))
    defined = set()
    for path in (root / "tests").rglob("test_*.py"):
        defined.update(re.findall(r"^def (test_\w+)", path.read_text(), flags=re.M))
    assert len(named) >= 20
    assert not sorted(named - defined)
