"""Table bug 4: Fig. 4B/4C at (p_r, p_t) = (0.3, 0.6) lie deep in the floppy phase.

The efficacies are derivatives of P; their ratios exist only where P varies. At n = 32 the
transition is w ~ 0.005 wide in x = p_r + lam p_t (Fig. 1C fits) while (0.3, 0.6) sits at
x = 0.6 for f_c = 1/2, eleven widths below x_c = 0.657: all 8 samples are floppy at every design
point for f_c = 1/4 ... 3/4 under every strain, S_r is 0 and (S_c + S_s)/S_r is 0/0 (+-100 in
reports/paper-n32/tables/fig4_average.csv).

The test runs the study on a synthetic ensemble that has the n = 32 transition (x_c = 0.657,
w = 0.005) and a known answer, generated from the study's own sweep specs (grid rows or
threshold rows, whichever the study asks for, so it also drives a redesigned study):

* sample s of (f_c, phi) becomes rigid where p_r + lam(f_c, phi) p_t = x_c + w (e_s + 0.3 h_sfk),
  e_s, h_sfk standard logistic (common random numbers over points; h also varies with f_c and
  phi), with lam(f, phi) = 1/2 + cos(phi) (0.1 y + 0.2 y^3), y = f - 1/2;
* on each strain's transition S_t/S_r = lam, dP/df_c / S_r = p_t lam', so
  (S_c + S_s)/S_r = 2 lam - (2 f - 1) lam' = 1 - 0.8 cos(phi) y^3, whose mean over the five
  strains phi in {0, pi/4, pi/2, 3pi/4, pi} is exactly 1 at every f_c (the paper's claim), and
  P rises with f_c under dilation and falls under compression.

A study that measures the efficacies where each system is critical recovers 1 within the Fig. 4C
target (0.1) at every f_c; the fixed point (0.3, 0.6) cannot (P = 0 there for 1/4 <= f_c <= 3/4).
"""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
import pandas as pd

from tensegrity_rigidity.paper.claims import TARGETS
from tensegrity_rigidity.paper.studies import SCALES, fig4

X_C, W = 0.657, 0.005
SCALE = dataclasses.replace(SCALES["paper"], bootstrap=40)


def lam(f_c, phi):
    y = f_c - 0.5
    return 0.5 + math.cos(phi) * (0.1 * y + 0.2 * y**3)


def _critical_x(sample: int, f_c: float, phi: float) -> float:
    """x_c + w (e_s + 0.3 h_sfk): where the sample becomes rigid in x = p_r + lam p_t."""
    e = np.random.default_rng([7, sample]).logistic()
    key = [8, sample, int(round(f_c * 1000)), int(round(phi * 1000))]
    h = np.random.default_rng(key).logistic()
    return X_C + W * (e + 0.3 * h)


def _as_list(v):
    return list(v) if isinstance(v, (list, tuple)) else [v]


def fake_rows(spec: dict) -> pd.DataFrame:
    """Rows of one sweep spec of the study from the synthetic ensemble (grid or threshold)."""
    rows = []
    threshold = spec.get("threshold")
    p_rs = [np.nan] if threshold else _as_list(spec["p_r"])
    for p_r, p_t, f_c, phi, k in itertools.product(
        p_rs,
        _as_list(spec["p_t"]),
        _as_list(spec["f_c"]),
        _as_list(spec["phi"]),
        range(1, spec["samples"] + 1),
    ):
        lm, xc = lam(f_c, phi), _critical_x(k, f_c, phi)
        row = {"n": spec["n"], "p_r": p_r, "p_t": p_t, "f_c": f_c, "phi": phi, "sample": k,
               "decided": True}  # fmt: skip
        if threshold is None:
            row["rigid"] = bool(p_r + lm * p_t > xc)
        elif threshold["path"] == "p_r":  # p_r in [0, 1 - p_t] at fixed p_t
            s = xc - lm * p_t
            row["threshold_p_r"] = s if 0 <= s <= 1 - p_t else np.nan
            row["threshold_p_t"] = p_t
        elif threshold["path"] == "total":  # p_r = s, p_t = T - s, T = the spec's p_t
            s = (xc - lm * p_t) / (1 - lm)
            row["threshold_p_r"] = min(max(s, 0.0), p_t)
            row["threshold_p_t"] = p_t - row["threshold_p_r"]
        else:
            raise NotImplementedError(threshold)
        rows.append(row)
    return pd.DataFrame(rows)


def test_the_synthetic_ensemble_is_floppy_at_the_paper_s_point():
    """Premise (holds today): at (0.3, 0.6) every sample is floppy for 1/4 <= f_c <= 3/4."""
    for f_c, phi, k in itertools.product([0.25, 0.5, 0.75], fig4.FIG4_PHI, range(1, 9)):
        assert 0.3 + lam(f_c, phi) * 0.6 < _critical_x(k, f_c, phi)


def test_fig4c_is_measured_where_the_systems_are_critical():
    rows = {name: (fake_rows(spec), 0) for name, spec in fig4.sweeps(SCALE).items()}
    result = fig4.analyse(rows, SCALE)
    (ours,) = [m for m in fig4.claims(result) if m.claim == "fig4c_sum_one" and m.factor == "ours"]
    value, err = np.asarray(ours.value, float), np.asarray(ours.err, float)
    assert value.size >= 5  # f_c = 0 ... 1 (every other f_c of Fig. 4A on the threshold paths)
    assert ours.points[0] == "f_c = 0.000" and ours.points[-1] == "f_c = 1.000"
    assert np.all(np.isfinite(value)) and np.all(np.isfinite(err)), (value, err)
    assert np.all(err < TARGETS["fig4c"]), err
    assert np.all(np.abs(value - 1) < np.maximum(3 * err, 0.02)), (value, err)


def test_the_point_s_unresolved_values_are_counted_among_its_own():
    """The paper's point has one value per f_c of its surface (9), the transition average one
    per f_c of its paths (5): each count is of its own values (the report once said '6 of its
    5'); a missing value counts as unresolved."""
    from types import SimpleNamespace

    est = SimpleNamespace(value=0.5, err=0.1)
    average = pd.DataFrame({"sum_rel": [1.0] * 5, "sum_rel_err": [0.1] * 5})
    point = pd.DataFrame({"sum_rel": [1.0, 0.1, np.nan] + [1.0] * 6,
                          "sum_rel_err": [0.1, 0.5, np.nan] + [0.1] * 6})  # fmt: skip
    path = pd.DataFrame({"p_r": [0.2, 0.4]})
    differences = pd.DataFrame({"sum_rel": [0.1, np.nan, np.nan, 1.1], "S_r": [0.5, 0, 0, 0.4]})
    r = SimpleNamespace(n=32, samples=8, transition_samples=8, average=average, point=point,
                        dilation=path, compression=path, differences=differences,
                        slopes={"dilation": est, "compression": est})  # fmt: skip
    v = fig4.numbers(r)
    assert (v["points"], v["unresolved"]) == (5, 0)
    assert (v["point_values"], v["point_unresolved"]) == (9, 2)
    # the paired differences' values missing because S_r = 0 there are counted, or none named
    assert v["differences_missing"] == 2
    r.differences = differences.assign(S_r=0.5)
    assert fig4.numbers(r)["differences_missing"] is None
