"""The paper's method beside ours: both verdicts on the same samples, and what moves."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from tensegrity_rigidity.analysis import estimators as an
from tensegrity_rigidity.paper.claims import CLAIMS
from tensegrity_rigidity.paper.comparison import compare
from tensegrity_rigidity.paper.studies import method

from .conftest import SERIAL, TINY


@pytest.fixture(scope="module")
def result(tiny_out):
    """The method study on the session's tiny reproduction (its sweeps resume)."""
    return method.STUDY(tiny_out, TINY, **SERIAL)


def test_both_verdicts_on_every_sample(result):
    rows = result.rows
    params = TINY["method"]
    p_r = method.p_r_grid(params.step, *method.P_R_RANGE)
    points = sum(len([p for p in p_r if p + p_t <= 1 + 1e-12]) for p_t in method.PT4)
    assert len(rows) == points * 2 * params.samples
    assert not rows.duplicated(method.KEYS).any()
    # the paper's minimiser never goes below the exact minimum
    assert (rows.paper_energy >= rows.energy - 1e-9 * rows.affine_energy).all()


def test_disagreement_counts_add_up(result):
    d = result.disagreement
    assert set(d.threshold) == set(method.THRESHOLDS)
    assert (d.differ == d.exact_rigid_paper_floppy + d.exact_floppy_paper_rigid).all()
    main = d[(d.threshold == result.threshold) & (d.region == "all")].iloc[0]
    assert main.differ == int((result.rows.rigid != result.rows.paper_rigid).sum())


def test_disagreement_on_a_constructed_frame():
    rows = pd.DataFrame(
        {
            "phi": 0.0,
            "p_t": 0.0,
            "p_r": [0.5] * 4,
            "sample": [1, 2, 3, 4],
            "rigid": [True, False, False, True],
            "paper_energy": [1.0, 1e-9, 1e-7, 0.0],
            "affine_energy": [1.0] * 4,
        }
    )
    d = method._disagreement(rows, 1000, TINY).set_index(["threshold", "region"])
    # at 1e-8: sample 3 (floppy, stopped at 1e-7) is called rigid, sample 4 (rigid) floppy
    row = d.loc[(1e-8, "all")]
    assert (row.differ, row.exact_floppy_paper_rigid, row.exact_rigid_paper_floppy) == (2, 1, 1)
    assert d.loc[(1e-10, "all")].exact_floppy_paper_rigid == 2
    assert d.loc[(1e-6, "all")].differ == 1


def _frame(samples: int, points: int, differs) -> pd.DataFrame:
    """``samples`` disorders at ``points`` grid points; ``differs(sample)`` -> verdicts differ.

    Half the samples are rigid at every point (so P = 1/2 and every row is also in the
    "0.1 <= P <= 0.9" region); the paper's energy is 1 (rigid) or 0 (floppy) at every
    threshold, its verdict the exact one flipped where ``differs``.
    """
    s = np.repeat(np.arange(samples), points)
    rigid = s % 2 == 0
    flip = np.array([differs(i) for i in s], bool)
    return pd.DataFrame(
        {
            "phi": 0.0,
            "p_t": 0.0,
            "p_r": np.tile(np.linspace(0.4, 0.8, points), samples),
            "sample": s,
            "rigid": rigid,
            "paper_energy": np.where(rigid ^ flip, 1.0, 0.0),
            "affine_energy": 1.0,
        }
    )


def _main(d: pd.DataFrame, region: str = "all") -> pd.Series:
    return d[(d.threshold == method.PAPER_THRESHOLD) & (d.region == region)].iloc[0]


def test_disagreement_interval_resamples_whole_samples():
    # 2 of 10 samples disagree at all their 50 points, the others never: 100 of 500 rows, but
    # only 10 independent samples; the row-wise Wilson interval is far too narrow
    rows = _frame(10, 50, lambda i: i in (1, 4))
    d = method._disagreement(rows, 400, TINY)
    _, w_lo, w_hi = an.wilson(100, 500)
    for region in ("all", "0.1 <= P <= 0.9"):
        row = _main(d, region)
        assert (row.samples, row.units, row.differ, row.fraction) == (500, 10, 100, 0.2)
        assert row.lo <= 0.2 <= row.hi
        assert row.hi - row.lo > 3 * (w_hi - w_lo)
        assert (row.wilson_lo, row.wilson_hi) == pytest.approx((w_lo, w_hi))
        assert row.interval_note == ""


def test_disagreement_interval_of_independent_rows_is_close_to_wilson():
    # one row per sample: the cluster bootstrap is the ordinary one, close to Wilson
    rows = _frame(400, 1, lambda i: i % 5 == 0)
    row = _main(method._disagreement(rows, 1000, TINY))
    assert row.units == 400 and row.fraction == pytest.approx(0.2)
    ratio = (row.hi - row.lo) / (row.wilson_hi - row.wilson_lo)
    assert 0.7 < ratio < 1.3
    assert row.lo == pytest.approx(row.wilson_lo, abs=0.02)
    assert row.hi == pytest.approx(row.wilson_hi, abs=0.02)


def test_disagreement_interval_is_reproducible():
    rows = _frame(12, 7, lambda i: i in (0, 3, 5))
    a, b = method._disagreement(rows, 200, TINY), method._disagreement(rows, 200, TINY)
    pd.testing.assert_frame_equal(a, b)


def test_disagreement_interval_without_any_difference_bounds_over_samples():
    # the percentiles would collapse to [0, 0]: the bound counts samples, not rows
    d = method._disagreement(_frame(20, 30, lambda i: False), 100, TINY)
    row = _main(d)
    assert (row.differ, row.units, row.lo) == (0, 20, 0.0)
    assert row.hi == pytest.approx(1 - 0.05 ** (1 / 20))  # 0.139, against Wilson's 0.006
    assert row.hi > 10 * row.wilson_hi
    assert "no verdict differs" in row.interval_note
    # every verdict differs: the mirror image
    row = _main(method._disagreement(_frame(20, 30, lambda i: True), 100, TINY))
    assert (row.lo, row.hi) == (pytest.approx(0.05 ** (1 / 20)), 1.0)


def test_disagreement_interval_of_one_sample_or_none():
    row = _main(method._disagreement(_frame(1, 40, lambda i: False), 100, TINY))
    assert (row.units, row.lo, row.hi) == (1, 0.0, 1.0)
    assert "one sample" in row.interval_note
    # one sample, P is 0 or 1 at every point: the near-transition region is empty
    row = _main(method._disagreement(_frame(1, 40, lambda i: True), 100, TINY), "0.1 <= P <= 0.9")
    assert row.units == 0 and np.isnan(row.lo) and np.isnan(row.hi)
    assert row.interval_note == "no samples in the region"


def test_method_section_quotes_the_study_s_numbers(result):
    """The section's numbers are the disagreement table's at the paper's threshold, and its
    table shows the cluster interval beside the row-wise Wilson one."""
    v = method.numbers(result)
    d = result.disagreement
    main = d[(d.threshold == result.threshold) & (d.region == "all")].iloc[0]
    assert (v["differ"], v["verdicts"], v["units"]) == (main.differ, main.samples, main.units)
    assert v["all_lo"] == 100 * main.lo and v["iterations"] == result.iterations["median"]
    tables = method.report_tables(result)
    assert {"units", "wilson_lo", "wilson_hi", "interval_note"} <= set(tables["disagreement"])
    assert list(tables["claims"].columns) == ["claim", "exact", "paper", "shift", "note"]


def test_claims_move_by_a_shift_handed_to_the_comparison(result):
    c = result.claims
    assert set(c.key) <= set(CLAIMS)
    assert {"st_sr_cables_compression", "st_sr_cables_dilation", "rods_only_pc"} <= set(c.key)
    ok = np.isfinite(c.exact) & np.isfinite(c.paper)
    assert np.allclose(c["shift"][ok], (c.paper - c.exact)[ok])
    assert all(m.factor == "method" and m.shift for m in result.measured)
    # no row of its own: the shifts only explain rows measured by the figure studies
    assert compare({"method": result}) == []
