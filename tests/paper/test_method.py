"""The paper's method beside ours: both verdicts on the same samples, and what moves."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from tensegrity_rigidity.paper import method
from tensegrity_rigidity.paper.claims import CLAIMS
from tensegrity_rigidity.paper.comparison import compare

from .conftest import SERIAL, TINY


@pytest.fixture(scope="module")
def result(tiny_out):
    """The method study on the session's tiny reproduction (its sweeps resume)."""
    return method.study_method(tiny_out, TINY, **SERIAL)


def test_both_verdicts_on_every_sample(result):
    rows = result.rows
    p_r = method.p_r_grid(TINY.method_step, *method.P_R_RANGE)
    points = sum(len([p for p in p_r if p + p_t <= 1 + 1e-12]) for p_t in method.PT4)
    assert len(rows) == points * 2 * TINY.samples_method
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
    d = method._disagreement(rows).set_index(["threshold", "region"])
    # at 1e-8: sample 3 (floppy, stopped at 1e-7) is called rigid, sample 4 (rigid) floppy
    row = d.loc[(1e-8, "all")]
    assert (row.differ, row.exact_floppy_paper_rigid, row.exact_rigid_paper_floppy) == (2, 1, 1)
    assert d.loc[(1e-10, "all")].exact_floppy_paper_rigid == 2
    assert d.loc[(1e-6, "all")].differ == 1


def test_claims_move_by_a_shift_handed_to_the_comparison(result):
    c = result.claims
    assert set(c.key) <= set(CLAIMS)
    assert {"st_sr_cables_compression", "st_sr_cables_dilation", "rods_only_pc"} <= set(c.key)
    ok = np.isfinite(c.exact) & np.isfinite(c.paper)
    assert np.allclose(c["shift"][ok], (c.paper - c.exact)[ok])
    assert all(m.factor == "method" and m.shift for m in result.measured)
    # no row of its own: the shifts only explain rows measured by the figure studies
    assert compare({"method": result}) == []
