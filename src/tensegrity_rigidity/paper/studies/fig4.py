"""Fig. 4: P versus f_c at (p_r, p_t) = (0.3, 0.6), and the efficacies of cables and struts.

Estimator: S_r, S_t and dP/df_c from a binomial-likelihood surface smooth in f_c, fitted to the
outcomes at (0.3, 0.6) and at steps matched in x = p_r + p_t/2 (h_r = 0.025, h_t = 0.05) for
f_c = 0, 1/8, ..., 1, on common random numbers; the strain average over phi in {0, pi/4, pi/2,
3pi/4, pi}; S_c = S_t + (1 - f_c) dP/df_c / p_t and S_s = S_t - f_c dP/df_c / p_t (from
S_t = f_c S_c + (1 - f_c) S_s and dP/df_c = p_t (S_c - S_s)). Errors: bootstrap over samples.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ...analysis import estimators as an
from ..claims import Measurement
from .rows import PHI5, Rows, load_sweeps
from .scales import Scale

FIG4_PHI = PHI5
FIG4_FC = [i / 8 for i in range(9)]
FIG4_CENTRE = (0.3, 0.6)
#: steps around the centre, matched in the mean-field variable x = p_r + p_t / 2 (both move x
#: by +-0.025): near the edge of the transition P is strongly curved and a secant is steeper
#: the wider it is, so unmatched spans would bias S_t / S_r.
H_R, H_T = 0.025, 0.05
#: polynomial degrees in f_c of the efficacy surface (logit at the centre; its slopes)
FIG4_DEGREES = (4, 2)


@dataclass(frozen=True, eq=False)
class Fig4Result:
    """P versus f_c at (p_r, p_t) = (0.3, 0.6) and the efficacies of cables and struts.

    Attributes
    ----------
    per_phi : DataFrame
        Per (phi, f_c): the measured P, N, its Wilson interval (lo, hi), and from the fitted
        surface S_r, S_t, D_f = dP/df_c, S_c, S_s with errors (``<name>_err``).
    average, dilation, compression : DataFrame
        Per f_c: S_r, S_c/S_r (``S_c_rel``), S_s/S_r, (S_c + S_s)/S_r (``sum_rel``) with errors,
        for the strain average and the two pure strains, from the fitted surface
        (:func:`~tensegrity_rigidity.analysis.fits.fit_efficacies`).
    curves : EfficacyCurves
        The strain average with covariances over f_c.
    differences : DataFrame
        The strain average from paired central differences (one-sided at f_c = 0 and 1), the
        estimator the surface replaces, kept as evidence of what the estimator changes.
    slopes : dict
        Strain name ("dilation", "compression") -> least-squares slope of P over f_c with its
        error (:func:`~tensegrity_rigidity.analysis.fits.paired_slope`).
    """

    per_phi: pd.DataFrame
    average: pd.DataFrame
    dilation: pd.DataFrame
    compression: pd.DataFrame
    curves: an.EfficacyCurves
    differences: pd.DataFrame
    slopes: dict[str, an.Estimate]
    n: int
    samples: int
    excluded: dict[str, int]
    measured: tuple[Measurement, ...] = ()


def _ratio_frame(c: an.EfficacyCurves) -> pd.DataFrame:
    cols = {"f_c": c.f_c, "S_r": c.values["S_r"], "S_r_err": c.err("S_r")}
    for name in ("S_c_rel", "S_s_rel", "sum_rel"):
        cols[name], cols[f"{name}_err"] = c.values[name], c.err(name)
    return pd.DataFrame(cols)


def sweeps(scale: Scale) -> dict[str, dict]:
    """Sweep name -> spec of Fig. 4: the centre and the steps in p_r and in p_t (seed 41)."""
    p_r0, p_t0 = FIG4_CENTRE
    base = {
        "n": scale.n_grid,
        "f_c": FIG4_FC,
        "phi": FIG4_PHI,
        "samples": scale.samples_fig4,
        "seed": 41,
    }
    return {
        "fig4_centre": base | {"p_r": p_r0, "p_t": p_t0},
        "fig4_dpr": base | {"p_r": [p_r0 - H_R, p_r0 + H_R], "p_t": p_t0},
        "fig4_dpt": base | {"p_r": p_r0, "p_t": [p_t0 - H_T, p_t0 + H_T]},
    }


def analyse(rows: Rows, scale: Scale) -> Fig4Result:
    """P versus f_c at (p_r, p_t) = (0.3, 0.6) and the efficacies S_r, S_t, S_c, S_s.

    Three sweeps on the same samples (common random numbers): the centre, p_r +- H_R and
    p_t +- H_T, each at f_c = 0, 1/8, ..., 1 and five strains. The efficacies come from a
    binomial-likelihood surface smooth in f_c (see
    :func:`~tensegrity_rigidity.analysis.fits.fit_efficacies`), fitted to all 45 points of
    each strain at once.
    """
    p_r0, p_t0 = FIG4_CENTRE
    frames = {name: frame for name, (frame, _) in rows.items()}
    excluded = {name: count for name, (_, count) in rows.items()}
    centre, d_r, d_t = frames["fig4_centre"], frames["fig4_dpr"], frames["fig4_dpt"]
    samples = np.arange(1, scale.samples_fig4 + 1)

    def outcomes(df, **sel):
        """Rigidity per sample index (nan where the sample was undecided and dropped)."""
        m = np.ones(len(df), bool)
        for key, val in sel.items():
            m &= np.isclose(df[key], val)
        return df[m].set_index("sample").rigid.astype(float).reindex(samples).to_numpy()

    design = [(centre, p_r0, p_t0)]
    design += [(d_r, p_r0 + s * H_R, p_t0) for s in (-1, 1)]
    design += [(d_t, p_r0, p_t0 + s * H_T) for s in (-1, 1)]
    pr, pt, fc = (
        np.array([p for _, p, _ in design for _ in FIG4_FC]),
        np.array([t for _, _, t in design for _ in FIG4_FC]),
        np.array(FIG4_FC * len(design)),
    )
    y = np.array(
        [
            np.column_stack(
                [outcomes(df, phi=phi, f_c=f, p_r=a, p_t=b) for df, a, b in design for f in FIG4_FC]
            )
            for phi in FIG4_PHI
        ]
    )
    per_strain, average = an.fit_efficacies(
        y,
        pr,
        pt,
        fc,
        FIG4_CENTRE,
        np.array(FIG4_FC),
        FIG4_DEGREES,
        n_boot=scale.bootstrap,
        rng=scale.rng("efficacies"),
    )
    table = []
    for phi, c in zip(FIG4_PHI, per_strain, strict=True):
        for i, f in enumerate(FIG4_FC):
            P = outcomes(centre, phi=phi, f_c=f)
            P = P[np.isfinite(P)]
            row = {"phi": phi, "f_c": f, "P": P.mean(), "N": P.size}
            for name in ("S_r", "S_t", "D_f", "S_c", "S_s"):
                row[name], row[f"{name}_err"] = c.values[name][i], c.err(name)[i]
            table.append(row)
    per_phi = pd.DataFrame(table)
    _, per_phi["lo"], per_phi["hi"] = an.wilson(per_phi.P * per_phi.N, per_phi.N)
    slopes = {
        name: an.paired_slope(
            np.column_stack([outcomes(centre, phi=phi, f_c=f) for f in FIG4_FC]),
            np.asarray(FIG4_FC),
        )
        for name, phi in (("dilation", 0.0), ("compression", math.pi))
    }
    differences = _fig4_differences(outcomes, centre, d_r, d_t)
    result = Fig4Result(
        per_phi=per_phi,
        average=_ratio_frame(average),
        dilation=_ratio_frame(per_strain[0]),
        compression=_ratio_frame(per_strain[-1]),
        curves=average,
        differences=differences,
        slopes=slopes,
        n=scale.n_grid,
        samples=scale.samples_fig4,
        excluded=excluded,
    )
    return dataclasses.replace(result, measured=claims(result))


def claims(result: Fig4Result) -> tuple[Measurement, ...]:
    """Fig. 4A's signs (slopes of P over f_c) and Fig. 4C's sum (S_c + S_s)/S_r = 1 (the fitted
    surface; paired differences as the estimator's evidence)."""
    slopes, average, differences = result.slopes, result.curves, result.differences
    system = f"n = {result.n}, {result.samples} samples per point"
    measured = [
        Measurement.scalar(
            key,
            slopes[name].value,
            slopes[name].err,
            system,
            note="least-squares slope of P over f_c = 0, 1/8, ..., 1 (mean of per-sample slopes)",
        )
        for key, name in (
            ("fig4a_dilation_rises", "dilation"),
            ("fig4a_compression_falls", "compression"),
        )
    ]
    points = tuple(f"f_c = {f:.3f}" for f in FIG4_FC)
    measured.append(
        Measurement(
            "fig4c_sum_one",
            average.values["sum_rel"],
            average.cov["sum_rel"],
            system,
            points=points,
            note="binomial-likelihood surface smooth in f_c (logit quartic in f_c, slopes in p_r "
            "and p_t quadratic) over the 45 points of each strain; strain average of S_r, S_t, "
            "dP/df_c; covariance over f_c by a bootstrap over samples",
        )
    )
    measured.append(
        Measurement(
            "fig4c_sum_one",
            differences.sum_rel.to_numpy(float),
            np.diag(differences.sum_rel_err.to_numpy(float) ** 2),
            system,
            factor="estimator",
            label="paired central differences (one-sided at f_c = 0, 1)",
            points=points,
        )
    )
    return tuple(measured)


def _fig4_differences(outcomes, centre, d_r, d_t) -> pd.DataFrame:
    """The strain average of (S_c + S_s)/S_r from paired central differences.

    S_r, S_t by central differences over the steps H_R, H_T; dP/df_c by central differences
    inside and second-order one-sided differences at f_c = 0 and 1; errors from the per-sample
    differences, taken as independent across strains and f_c. Ratios where S_r = 0 are NaN.
    """
    p_r0, p_t0 = FIG4_CENTRE
    last = len(FIG4_FC) - 1
    rows = []
    for i, f in enumerate(FIG4_FC):
        parts = []
        for phi in FIG4_PHI:
            S_r = an.paired_derivative(
                outcomes(d_r, phi=phi, f_c=f, p_r=p_r0 - H_R),
                outcomes(d_r, phi=phi, f_c=f, p_r=p_r0 + H_R),
                H_R,
            )
            S_t = an.paired_derivative(
                outcomes(d_t, phi=phi, f_c=f, p_t=p_t0 - H_T),
                outcomes(d_t, phi=phi, f_c=f, p_t=p_t0 + H_T),
                H_T,
            )
            if 0 < i < last:
                coef = {i - 1: -1.0, i + 1: 1.0}
                step = FIG4_FC[i + 1] - FIG4_FC[i - 1]
            else:
                j = (1, 2) if i == 0 else (last - 1, last - 2)
                sign = 1.0 if i == 0 else -1.0
                coef = {i: -3.0 * sign, j[0]: 4.0 * sign, j[1]: -1.0 * sign}
                step = 2 * abs(FIG4_FC[j[0]] - FIG4_FC[i])
            diff = sum(c * outcomes(centre, phi=phi, f_c=FIG4_FC[k]) for k, c in coef.items())
            diff = diff[np.isfinite(diff)]
            D = diff.mean() / step
            D_e = diff.std(ddof=1) / np.sqrt(diff.size) / step
            parts.append((S_r.value, S_r.err, S_t.value, S_t.err, D, D_e))
        a = np.array(parts)
        k = len(a)
        S_r, S_t, D = a[:, 0].mean(), a[:, 2].mean(), a[:, 4].mean()
        S_r_e, S_t_e, D_e = (np.sqrt((a[:, c] ** 2).sum()) / k for c in (1, 3, 5))
        total = 2 * S_t + (1 - 2 * f) * D / p_t0
        total_e = np.hypot(2 * S_t_e, abs(1 - 2 * f) * D_e / p_t0)
        if S_r != 0:
            ratio = total / S_r
            err = np.hypot(total_e / S_r, ratio * S_r_e / S_r)
        else:
            ratio = err = np.nan
        rows.append({"f_c": f, "sum_rel": ratio, "sum_rel_err": abs(err)})
    return pd.DataFrame(rows)


def study(out, scale: Scale, **kw) -> Fig4Result:
    """Run (or resume) the sweeps of Fig. 4 into ``out`` and analyse them."""
    return analyse(load_sweeps(out, sweeps(scale), **kw), scale)
