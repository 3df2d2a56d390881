"""Fig. 1C: S_t/S_r versus the cable fraction f_c, per strain and averaged over strains.

Estimator: a binomial-likelihood fit of P = F(p_r + lam p_t) to per-sample thresholds along p_r
at p_t = 0 and 0.3 (:func:`~tensegrity_rigidity.analysis.fits.fit_collapse`); bootstrap errors
over samples. The strain average pools the samples of five strains phi in {0, pi/4, pi/2,
3pi/4, pi}, a sample under every strain being one unit of the bootstrap. The slope of the
P = 1/2 contour is the model-free alternative.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ...analysis import estimators as an
from ..claims import Measurement
from .rows import FC5, PHI5, Rows, interval_straddles, load_sweeps, strain_name, threshold_matrix
from .scales import Scale

#: p_r grid of the outcomes the collapse fits read from the thresholds
FIT_P_R = np.arange(0.3, 0.9001, 0.01)


@dataclass(frozen=True, eq=False)
class Fig1cResult:
    """S_t/S_r versus f_c for each strain and the strain average.

    Attributes
    ----------
    fits : DataFrame
        One row per (f_c, strain): the fields of
        :class:`~tensegrity_rigidity.analysis.fits.CollapseFit` plus ``f_c``, ``strain``,
        ``phi`` (NaN for the average).
    rods_only_pc, rods_only_pc_err : float
        Median threshold of the rods-only samples (p_t = 0, every strain) and its bootstrap error.
    rods_only_samples : int
        Number of rods-only thresholds.
    rods_only_units, rods_only_strains : int
        Distinct samples and strains behind them (a sample's strains are one bootstrap unit).
    contour : DataFrame
        Per (f_c, strain): ``lam``, ``lam_err`` from the slope of the P = 1/2 contour
        (:func:`~tensegrity_rigidity.analysis.fits.contour_slope`), the model-free
        alternative to the collapse fit.
    """

    fits: pd.DataFrame
    contour: pd.DataFrame
    rods_only_pc: float
    rods_only_pc_err: float
    rods_only_samples: int
    n: int
    samples: int
    rows: pd.DataFrame
    excluded: dict[str, int]
    straddling: int | None = None
    measured: tuple[Measurement, ...] = ()
    rods_only_units: int = 0
    rods_only_strains: int = 0

    def lam(self, f_c: float, strain: str) -> tuple[float, float]:
        """(S_t/S_r, its error) of one fit."""
        fits = self.fits
        row = fits[np.isclose(fits.f_c, f_c) & (fits.strain == strain)].iloc[0]
        return float(row.lam), float(row.lam_err)


#: Fig. 1C: S_t/S_r from a collapse fit over p_t = 0 (rods only) and p_t = FIG1C_PT, the ends of
#: the paper's range 0 ... 0.3. The thresholds at p_t = 0.1 and 0.2 add nothing measurable on
#: common random numbers: the collapse fit's bootstrap error over p_t = {0, 0.3} was 0.0067 and
#: 0.0066 (n = 16, 64 samples, rods + cables under dilation and compression) and 0.0071 (n = 32,
#: 32 samples, compression) against 0.0070, 0.0068 and 0.0066 over p_t = {0, 0.1, 0.2, 0.3},
#: with the same values of S_t/S_r (0.566, 0.447, 0.454 against 0.565, 0.449, 0.454), for half
#: the threshold searches.
FIG1C_PT = 0.3
#: f_c of the headline claims (samples_threshold) and of the rest of the curve (samples_curve)
FIG1C_FC = [0.0, 0.5, 1.0]
FIG1C_FC_CURVE = [0.25, 0.75]
FIG1C_PHI = PHI5


def sweeps(scale: Scale) -> dict[str, dict]:
    """Sweep name -> spec of Fig. 1C.

    The rods-only thresholds (p_t = 0, where f_c does not matter) are one sweep shared by every
    f_c; the one-sided sweeps at p_t = :data:`FIG1C_PT` share its samples (seed 12).
    """
    base = {"n": scale.n_threshold, "phi": FIG1C_PHI, "seed": 12, "threshold": {"path": "p_r"}}
    rods = max(scale.samples_threshold, scale.curve_samples)
    return {
        "fig1c_rods": base | {"p_t": 0.0, "f_c": 0.5, "samples": rods},
        "fig1c_mixed": base
        | {"p_t": FIG1C_PT, "f_c": FIG1C_FC, "samples": scale.samples_threshold},
        "fig1c_curve": base
        | {"p_t": FIG1C_PT, "f_c": FIG1C_FC_CURVE, "samples": scale.curve_samples},
    }


def analyse(rows: Rows, scale: Scale) -> Fig1cResult:
    """S_t/S_r versus f_c for each strain and the strain average (collapse fits)."""
    parts = {name: frame for name, (frame, _) in rows.items()}
    excluded = {name: count for name, (_, count) in rows.items()}
    rods = parts["fig1c_rods"]
    mixed = pd.concat([parts["fig1c_mixed"], parts["fig1c_curve"]], ignore_index=True)
    # every f_c pairs the rods-only thresholds with its own samples at p_t = FIG1C_PT
    df = pd.concat([rods.assign(f_c=f_c) for f_c in FC5] + [mixed], ignore_index=True)
    p_t = [0.0, FIG1C_PT]
    grid = FIT_P_R
    fits, contour = [], []
    for f_c in FC5:
        pooled, pooled_t, units = [], [], []
        for phi in FIG1C_PHI:
            sub = df[np.isclose(df.f_c, f_c) & np.isclose(df.phi, phi)]
            y, pr, pt = an.outcomes_from_thresholds(sub, grid)
            t = threshold_matrix(sub, p_t)
            pooled.append(y)
            pooled_t.append(t)
            units.append(an.common_samples(sub))  # the rows of y and of t

            if phi in (0.0, math.pi / 2, math.pi):
                fit = an.fit_collapse(y, pr, pt, n_boot=scale.bootstrap, rng=scale.rng("collapse"))
                fits.append({"f_c": f_c, "strain": strain_name(phi), "phi": phi, **fit.__dict__})
                c = an.contour_slope(
                    t, np.array(p_t), n_boot=scale.bootstrap, rng=scale.rng("contour")
                )
                contour.append(
                    {"f_c": f_c, "strain": strain_name(phi), "lam": c.value, "lam_err": c.err}
                )
        # the strain average: a sample under every strain is one unit of the bootstrap
        groups = np.concatenate(units)
        fit = an.fit_collapse(
            np.vstack(pooled), pr, pt, n_boot=scale.bootstrap, groups=groups,
            rng=scale.rng("collapse"),
        )  # fmt: skip
        fits.append({"f_c": f_c, "strain": "average", "phi": np.nan, **fit.__dict__})
        c = an.contour_slope(
            np.vstack(pooled_t), np.array(p_t), n_boot=scale.bootstrap, groups=groups,
            rng=scale.rng("contour"),
        )  # fmt: skip
        contour.append({"f_c": f_c, "strain": "average", "lam": c.value, "lam_err": c.err})
    rods_only = rods.drop_duplicates(["phi", "sample"])
    pc, pc_err = an.critical_point(
        rods_only.threshold_p_r.to_numpy(),
        groups=rods_only["sample"].to_numpy(),
        rng=scale.rng("critical_point"),
    )
    result = Fig1cResult(
        fits=pd.DataFrame(fits),
        contour=pd.DataFrame(contour),
        rods_only_pc=pc,
        rods_only_pc_err=pc_err,
        rods_only_samples=len(rods_only),
        n=scale.n_threshold,
        samples=scale.samples_threshold,
        rows=df,
        excluded=excluded,
        straddling=interval_straddles(pd.concat([rods, mixed], ignore_index=True), grid),
        rods_only_units=int(rods_only["sample"].nunique()),
        rods_only_strains=int(rods_only.phi.nunique()),
    )
    return dataclasses.replace(result, measured=claims(result))


#: claim key -> (f_c, strain) of the Fig. 1C fits it reads
CLAIM_FITS = {
    **{f"st_sr_half_{s}": (0.5, s) for s in ("dilation", "shear", "compression", "average")},
    "st_sr_cables_compression": (1.0, "compression"),
    "st_sr_struts_dilation": (0.0, "dilation"),
    "st_sr_cables_dilation": (1.0, "dilation"),
}


def claims(result: Fig1cResult) -> tuple[Measurement, ...]:
    """The efficacy claims (collapse fit; the contour slope as the estimator's evidence) and
    the rods-only threshold at this size."""
    fits, contour, n = result.fits, result.contour, result.n
    system = f"n = {n}, {result.samples} samples x 2 p_t"
    measured = []
    for key, (f_c, strain) in CLAIM_FITS.items():
        row = fits[np.isclose(fits.f_c, f_c) & (fits.strain == strain)].iloc[0]
        note = (
            "identical to rods + cables under compression by an exact symmetry: compression is "
            "minus dilation, and e -> -e swaps cables and struts sample by sample"
            if key == "st_sr_struts_dilation"
            else f"collapse fit P = F(p_r + lam p_t) over p_t = 0 and {FIG1C_PT}"
        )
        measured.append(Measurement.scalar(key, row.lam, row.lam_err, system, note=note, size=n))
        row = contour[np.isclose(contour.f_c, f_c) & (contour.strain == strain)].iloc[0]
        measured.append(
            Measurement.scalar(
                key,
                row.lam,
                row.lam_err,
                system,
                factor="estimator",
                label="slope of the P = 1/2 contour instead of the logistic collapse fit",
                size=n,
            )
        )
    measured.append(
        Measurement.scalar(
            "rods_only_pc",
            result.rods_only_pc,
            result.rods_only_pc_err,
            f"n = {n}, {result.rods_only_units} samples x {result.rods_only_strains} strains",
            note="finite-size threshold (median of per-sample thresholds, every strain; a "
            "sample's strains are one unit of the bootstrap)",
            size=n,
        )
    )
    return tuple(measured)


def study(out, scale: Scale, **kw) -> Fig1cResult:
    """Run (or resume) the sweeps of Fig. 1C into ``out`` and analyse them."""
    return analyse(load_sweeps(out, sweeps(scale), **kw), scale)
