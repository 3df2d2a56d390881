"""Shared fixtures, and the Hypothesis profiles.

The default profile is derandomised: every run (CI included) draws the same examples, so a
property test fails on a commit or not at all, never at random. ``HYPOTHESIS_PROFILE=explore``
draws fresh examples (ten times as many where a test does not set its own count) to look
for new counterexamples.
"""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import settings

settings.register_profile("repeatable", derandomize=True, database=None)
settings.register_profile("explore", max_examples=10 * settings.default.max_examples)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "repeatable"))


@pytest.fixture
def rng():
    return np.random.default_rng(12345)
