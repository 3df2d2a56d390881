"""The jamming study's computation: the sample loop, its estimates on data with a known answer,
the cost estimate and the figures."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from tensegrity_rigidity import InputError, jamming
from tensegrity_rigidity.analysis.bootstrap import Estimate
from tensegrity_rigidity.analysis.jamming import (
    JammingPoint,
    finite_size_shift,
    jamming_points,
    jamming_table,
)
from tensegrity_rigidity.ensemble.jamming import (
    COLUMNS,
    estimate_cost,
    jamming_row,
    jamming_samples,
    load_costs,
)
from tensegrity_rigidity.model.softdisks import soft_packing
from tensegrity_rigidity.paper.jamming_figures import plot_jamming_probability, plot_packing


def test_sample_loop_rows_are_functions_of_their_coordinates():
    rows = jamming_samples([16], [0.80, 0.88], 2, seed=3, progress=False)
    assert list(rows.columns) == list(COLUMNS) and len(rows) == 4
    assert set(rows["collective"]) <= {"jammed", "unjammed", "undecided"}
    more = jamming_samples([16], [0.80, 0.84, 0.88], 3, seed=3, progress=False)
    same = more[more["phi"].isin([0.80, 0.88]) & (more["sample"] < 2)].reset_index(drop=True)
    cols = ["n", "phi", "sample", "energy", "contacts", "collective", "strict"]
    pd.testing.assert_frame_equal(same[cols], rows[cols])
    assert jamming_row(16, 0.88, 1, seed=3)["contacts"] == rows["contacts"].iloc[3]
    with pytest.raises(InputError):
        jamming_samples([], [0.8], 1, progress=False)


def _synthetic(rng, sizes, phi_j, width, phis, samples):
    """Outcomes drawn from a logistic P with a known centre per size."""
    rows = []
    for n in sizes:
        for phi in phis:
            p = 1 / (1 + np.exp(-(phi - phi_j[n]) / width))
            for k in range(samples):
                status = "jammed" if rng.random() < p else "unjammed"
                rows.append({"n": n, "phi": phi, "sample": k, "collective": status,
                             "strict": status})  # fmt: skip
    return pd.DataFrame(rows)


def test_jamming_points_recover_a_known_centre():
    rng = np.random.default_rng(1)
    phis = np.round(np.linspace(0.80, 0.88, 9), 3)
    truth = {64: 0.835, 256: 0.840}
    rows = _synthetic(rng, [64, 256], truth, 0.01, phis, 150)
    table = jamming_table(rows)
    assert table["decided"].eq(150).all() and table["undecided"].eq(0).all()
    points = jamming_points(rows, np.random.default_rng(2), replicas=100)
    for p in points:
        assert abs(p.phi_j.value - truth[p.n]) < 4 * p.phi_j.err + 1e-3
        # width of the 1/4..3/4 band of a logistic of scale w is 2 ln 3 w
        assert abs(p.width.value - 2 * np.log(3) * 0.01) < 4 * p.width.err + 2e-3


def test_finite_size_shift_reports_every_form_and_their_spread():
    sizes = np.array([64, 128, 256, 512, 1024])
    phi = 0.842 - 0.3 * sizes**-0.7
    err = np.full(sizes.size, 2e-4)
    points = [JammingPoint(int(n), Estimate(float(v), float(e)), Estimate(0.01, 0.001), 100)
              for n, v, e in zip(sizes, phi, err, strict=True)]  # fmt: skip
    fit = finite_size_shift(points)
    assert {f.free for f in fit.fits} == {True, False} and len(fit.fits) == 3
    exact = [f for f in fit.fits if not f.free and f.exponent == 0.7][0]
    assert abs(exact.phi_inf.value - 0.842) < 1e-6 and exact.chi2_dof < 1e-6
    assert any(f.phi_inf.value != exact.phi_inf.value for f in fit.fits)
    assert fit.accepted and abs(fit.phi_inf - 0.842) <= fit.spread
    with pytest.raises(InputError):
        finite_size_shift(points[:1])


def test_cost_estimate_grows_with_size_and_samples():
    costs = load_costs()
    assert {"2", "3"} <= set(costs) and costs["measured"]
    small = estimate_cost([64], [0.84], 10)
    big = estimate_cost([64, 1024], [0.84, 0.85], 10, workers=2)
    assert 0 < small["cpu_seconds"] < big["cpu_seconds"]
    assert big["samples"] == 40 and big["wall_seconds"] >= big["cpu_seconds"] / 2
    assert big["per_size"][1024] > big["per_size"][64]


def test_figures_draw(tmp_path):
    sp = soft_packing(32, 0.9, np.random.default_rng(4))
    net = sp.packing.contact_network(tolerance=0)
    result = jamming(net)
    plot_packing(sp.packing, net, result, tmp_path / "packing.png")
    assert (tmp_path / "packing.png").stat().st_size > 1000
    rows = _synthetic(np.random.default_rng(1), [64], {64: 0.84}, 0.01, [0.82, 0.84, 0.86], 20)
    plot_jamming_probability(jamming_table(rows), tmp_path / "p.png")
    assert (tmp_path / "p.png").stat().st_size > 1000
