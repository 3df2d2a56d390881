"""One tiny end-to-end reproduction per test session, shared by the paper's tests.

Tests that need study results call the study functions on its output directory: every sweep
resumes (no new samples), so only the analysis runs again.
"""

from __future__ import annotations

import pytest

from tensegrity_rigidity.cli.main import main
from tensegrity_rigidity.paper.studies import SCALES

TINY = SCALES["tiny"]
SERIAL = dict(workers="serial", scheduler=None, progress=False)


@pytest.fixture(scope="session")
def tiny_out(tmp_path_factory):
    """Output directory of ``tensegrity-rigidity reproduce --scale tiny`` (run once)."""
    out = tmp_path_factory.mktemp("repro")
    assert (
        main(["reproduce", "--scale", "tiny", "--out", str(out), "--workers", "2", "--no-progress"])
        == 0
    )
    return out


@pytest.fixture(scope="session")
def tiny_results(tiny_out):
    """Every study of the tiny scale analysed once from the session's reproduction (its
    sweeps resume): shared by the tests that read results and change nothing."""
    from tensegrity_rigidity.paper.registry import STUDIES

    return {name: STUDIES[name](tiny_out, TINY, **SERIAL) for name in TINY.studies}
