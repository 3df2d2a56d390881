"""Shared fixtures, the Hypothesis profiles, and how pytest-xdist distributes the tests.

The default profile is derandomised: every run (CI included) draws the same examples, so a
property test fails on a commit or not at all, never at random. ``HYPOTHESIS_PROFILE=explore``
draws fresh examples (ten times as many where a test does not set its own count) to look
for new counterexamples.
"""

from __future__ import annotations

import os
from pathlib import Path


def _has_avx2() -> bool:
    try:
        return " avx2 " in f" {Path('/proc/cpuinfo').read_text()} "
    except OSError:
        return False


# OpenBLAS picks its kernels by CPU family, and the AVX-512 kernels round differently in the
# last bits. The tests pin work counts of round-off-level searches measured with the Haswell
# kernels, so the test processes (xdist workers inherit this) use them where the CPU has AVX2.
if _has_avx2():
    os.environ.setdefault("OPENBLAS_CORETYPE", "Haswell")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from hypothesis import settings  # noqa: E402

settings.register_profile("repeatable", derandomize=True, database=None)
settings.register_profile("explore", max_examples=10 * settings.default.max_examples)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "repeatable"))


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


@pytest.hookimpl(optionalhook=True)  # a hook of pytest-xdist: unknown without it
def pytest_xdist_make_scheduler(config, log):
    """Distribute the tests over pytest-xdist's workers (pyproject's default options: ``-n 2
    --dist loadfile``) by file, as ``loadfile`` does, except that tests/paper/ goes to one
    worker whole: its files share the session's tiny reproduction (``tiny_out``, about 80 s),
    which each worker running one of them would otherwise build again. (``--dist loadgroup``
    with ``xdist_group`` marks would say the same, but pytest-xdist 3.8 cannot group under
    pytest 9.2: it renames the items' private ``_nodeid``, which pytest 9.2 no longer reads.)
    """
    if config.getvalue("dist") != "loadfile":
        return None
    from xdist.scheduler import LoadFileScheduling

    class SharedFixtureScheduling(LoadFileScheduling):
        def _split_scope(self, nodeid: str) -> str:
            path = nodeid.split("::", 1)[0]
            return "tests/paper/" if path.startswith("tests/paper/") else path

    return SharedFixtureScheduling(config, log)
