"""The claims' numbers are those of the release before the paper layer was split by figure.

``data/release_claims.json`` holds every measurement of every study at the tiny scale as the
release at 5454841 computed it (``data/make_release_claims.py`` says how it was generated: that
release's sources, run once in a subprocess). The same samples and the same estimators must give
the same values and, the bootstrap streams being the ones those estimators always drew, the same
error bars, except where an estimator was changed on purpose since (:func:`_changed`): those
measurements must still be there, and their numbers are pinned by their own tests.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from tensegrity_rigidity.paper.registry import STUDIES
from tensegrity_rigidity.paper.studies import STORED

from .conftest import TINY

RELEASE = json.loads((Path(__file__).with_name("data") / "release_claims.json").read_text())
#: relative tolerance of a value or an error against the release's (the arithmetic is the same;
#: only the order of floating-point sums may differ)
RTOL = 1e-9
#: relative tolerance, of the value's magnitude, of the end points of iterative fits (the scaling
#: collapse, the extrapolations to n -> infinity, the per-size transitions): scipy's least squares
#: and minimize stop at relative tolerances of 1e-8, so a CPU whose BLAS kernels round otherwise
#: (AVX2 against the release's AVX-512) moves them, and their bootstrap errors, within that
FIT_RTOL = 1e-6


def _fitted(m) -> bool:
    """Whether the measurement ``m`` is the end point of an iterative fit."""
    label, claim = m["label"], m["claim"]
    return claim.startswith(("collapse", "st_sr")) or "extrapolated to n -> infinity" in label


def _changed(m) -> bool:
    """Whether ``m`` comes from an estimator changed on purpose since the release: the collapse
    fit of S_t/S_r reads the exact per-sample thresholds by maximum likelihood instead of
    outcomes binned on the p_r grid (every ``st_sr`` and ``collapse`` value, their
    extrapolations and their chi-square labels; tests/paper/test_fig1c_collapse.py), and
    Fig. 4C is measured on each system's transition (tests/paper/test_fig4_point.py), its
    surface at the paper's point kept as the factor "point" and the paired differences no
    longer a measurement. The energy grids start at 0.025 below n = 16, every tiny size, so the
    finite-size and node-disorder studies' energy exponents and taut fractions fit points the
    release's grid (from 0.45) did not have (tests/paper/test_finite_size.py pins the grids).
    The finite-size evidence of every claim but the rods-only p_c is its own limit by the laws,
    not an extrapolation with the rods-only nu (tests/paper/test_finite_size.py)."""
    claim = m["claim"]
    energy = claim.startswith("alpha_") or claim == "taut_cables_transition"
    own_limit = m["factor"] == "finite size" and claim != "rods_only_pc"
    return (claim.startswith(("st_sr", "collapse")) or claim == "fig4c_sum_one"
            or (m["study"] in ("fss", "delta") and energy) or own_limit)  # fmt: skip


def _kept(ms):
    return [m for m in ms if not _changed(m)]


@pytest.fixture(scope="module")
def measured(tiny_out):
    stored = dict(workers=STORED, scheduler=None, progress=False)
    results = {name: STUDIES[name](tiny_out, TINY, **stored) for name in TINY.studies}
    return [
        {
            "study": study,
            "claim": m.claim,
            "factor": m.factor,
            "label": m.label,
            "value": np.asarray(m.value, float),
            "err": np.asarray(m.err, float),
        }
        for study, result in sorted(results.items())
        for m in result.measured
    ]


def test_the_fixture_is_the_release_at_the_tiny_scale():
    assert RELEASE["release"] == "5454841" and RELEASE["scale"] == "tiny"
    assert len(RELEASE["measurements"]) > 200


def test_the_same_claims_are_measured_in_the_same_order(measured):
    def key(m):
        return (m["study"], m["claim"], m["factor"], m["label"])

    assert [key(m) for m in _kept(measured)] == [key(m) for m in _kept(RELEASE["measurements"])]
    # the changed estimators still measure every claim they measured, in every study
    changed = {(m["study"], m["claim"]) for m in RELEASE["measurements"] if _changed(m)}
    assert changed <= {(m["study"], m["claim"]) for m in measured if _changed(m)}


def test_every_value_and_error_is_the_release_s(measured):
    differ = []
    for ours, theirs in zip(_kept(measured), _kept(RELEASE["measurements"]), strict=True):
        for field in ("value", "err"):
            a, b = ours[field], np.asarray(theirs[field], float)
            if a.shape != b.shape:
                differ.append((ours["study"], ours["claim"], ours["label"], field, a, b))
                continue
            scale = np.abs(np.asarray(theirs["value"], float)) if _fitted(ours) else 0.0
            tol = np.maximum(RTOL * np.abs(b), FIT_RTOL * scale)
            if not np.all((np.abs(a - b) <= tol) | (np.isnan(a) & np.isnan(b))):
                differ.append((ours["study"], ours["claim"], ours["label"], field, a, b))
    assert not differ, differ[:5]
