"""Table bugs 1 and 2: the Fig. 1C collapse fit must respond to the thresholds it is given.

The data are real per-sample thresholds of the paper scale (n = 32, seed 12, delta 0.2),
recomputed (outside the test suite) with the sweep specs of ``paper.studies.fig1c.sweeps``; on them
today's ``fig1c.analyse`` reproduces the committed rows of
``reports/paper-n32/tables/efficacy_fits.csv`` to every digit (f_c = 1 dilation and shear
0.537502063558762 +- 0.00773103553097755, f_c = 0.75 compression 0.500000000662733).

Cause: the collapse fit reads the exact thresholds only through the outcomes they imply on the
p_r grid ``FIT_P_R`` (step 0.01), twice the n = 32 transition width (w = 0.005). Thresholds that
differ by less than a grid step give identical outcome matrices (bug 1), and the binned
likelihood locks lam to the values where lam * 0.3 is a whole number of grid steps, k / 30
(bug 2: 0.5 = 15/30; f_c = 0 shear 0.53333333 = 16/30).
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from tensegrity_rigidity.paper.studies import SCALES, fig1c
from tensegrity_rigidity.paper.studies.rows import COLLAPSE_PT, FC5, PHI5

#: per-sample thresholds of the paper scale (the file says how they were computed)
THRESHOLDS = json.loads((Path(__file__).parent / "data" / "fig1c_n32_thresholds.json").read_text())

#: rods-only thresholds (p_t = 0, the same under every strain), samples 1..24
RODS = THRESHOLDS["rods"]
#: rods + cables (f_c = 1), p_t = 0.3, under dilation and under shear, samples 1..24
CABLES_DILATION = THRESHOLDS["cables_dilation"]
CABLES_SHEAR = THRESHOLDS["cables_shear"]
#: f_c = 0.75, p_t = 0.3, compression, samples 1..12 (the curve sweep's 12 samples)
FC075_COMPRESSION = THRESHOLDS["fc075_compression"]

SCALE = dataclasses.replace(SCALES["tiny"], bootstrap=4)
P_T = COLLAPSE_PT


def _frame(thresholds, p_t, f_c, phi):
    return pd.DataFrame(
        {
            "sample": np.arange(1, len(thresholds) + 1),
            "p_t": p_t,
            "f_c": f_c,
            "phi": phi,
            "threshold_p_r": np.asarray(thresholds, float),
        }
    )


def _lam(mixed: dict[tuple[float, float], list[float]], f_c: float, strain: str) -> float:
    """S_t/S_r of the study at (f_c, strain) from rods-only thresholds RODS and the p_t = 0.3
    thresholds ``mixed[(f_c, phi)]`` (the same dilation data elsewhere, so that the study runs)."""
    return analyse(mixed).lam(f_c, strain)[0]


def analyse(mixed: dict[tuple[float, float], list[float]]):
    """The Fig. 1C study on RODS and ``mixed`` (see :func:`_lam`)."""
    filler = CABLES_DILATION
    rods = pd.concat([_frame(RODS, 0.0, 0.5, phi) for phi in PHI5], ignore_index=True)
    parts = {"fig1c_mixed": [], "fig1c_curve": []}
    for f in FC5:
        name = "fig1c_mixed" if f in fig1c.FIG1C_FC else "fig1c_curve"
        for phi in PHI5:
            t = next(
                (v for (ff, pp), v in mixed.items() if ff == f and math.isclose(pp, phi)), filler
            )
            parts[name].append(_frame(t, P_T, f, phi))
    rows = {"fig1c_rods": (rods, 0)} | {
        name: (pd.concat(frames, ignore_index=True), 0) for name, frames in parts.items()
    }
    return fig1c.analyse(rows, SCALE)


def test_the_data_differ_sample_by_sample_but_never_by_a_grid_step():
    """The premise of the next test (holds today): shear thresholds of rods + cables are never
    below the dilation ones, 8 of 24 are above (by 0.0003 to 0.0021), none across a 0.01 bin."""
    d, s = np.array(CABLES_DILATION), np.array(CABLES_SHEAR)
    assert np.all(s >= d) and np.sum(s > d) == 8
    assert np.all(np.floor(d / 0.01) == np.floor(s / 0.01))


def test_distinct_systems_get_distinct_efficacies():
    """Bug 1: the fit of rods + cables under shear equals that under dilation to all digits.

    Every p_t = 0.3 threshold under shear is at least the dilation one and 8 are higher, on the
    same rods-only data: any estimator of P = F(p_r + lam p_t) must give shear a lower lam. The
    binned fit returns 0.537502063558762 for both (today's failure)."""
    mixed = {(1.0, 0.0): CABLES_DILATION, (1.0, math.pi / 2): CABLES_SHEAR}
    dilation, shear = _lam(mixed, 1.0, "dilation"), _lam(mixed, 1.0, "shear")
    assert dilation - shear > 2e-4, (dilation, shear)


def test_an_exact_symmetry_still_gives_identical_fits():
    """Guard (passes today and must pass after the fix): identical thresholds, as rods + struts
    under compression and rods + cables under dilation are by e -> -e, give identical fits."""
    mixed = {(1.0, 0.0): CABLES_DILATION, (0.0, math.pi): CABLES_DILATION}
    assert _lam(mixed, 1.0, "dilation") == _lam(mixed, 0.0, "compression")


@pytest.mark.parametrize("delta", [0.001, 0.002, 0.003])
def test_lambda_follows_a_shift_of_the_one_sided_thresholds(delta):
    """Bug 2: f_c = 0.75 compression sits at lam = 0.500000000662733 = 15/30.

    The collapse P = F((p_r + lam p_t - x0)/w) is equivariant: moving every p_t = 0.3
    threshold by delta is the same data with lam - delta/0.3 (x0 and w unchanged). The binned
    fit stays locked at 1/2 (its two count profiles are the same up to a shift of 15 grid
    steps, so its likelihood is symmetric about lam = 1/2) and misses the shift."""
    base = _lam({(0.75, math.pi): FC075_COMPRESSION}, 0.75, "compression")
    moved = _lam({(0.75, math.pi): list(np.add(FC075_COMPRESSION, delta))}, 0.75, "compression")
    expected = -delta / P_T
    assert moved - base == pytest.approx(expected, rel=0.05), (base, moved)
