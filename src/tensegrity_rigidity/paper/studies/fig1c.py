"""Fig. 1C: S_t/S_r versus the cable fraction f_c, per strain and averaged over strains.

A maximum-likelihood fit of P = F(p_r + lam p_t) to the exact per-sample thresholds along p_r
at p_t = 0 and :data:`~.rows.COLLAPSE_PT`
(:func:`~tensegrity_rigidity.analysis.fits.fit_collapse_thresholds`: no grid; a threshold left
as an interval by undecided probes enters as its interval), bootstrap errors over samples. The
strain average pools the samples of five strains, a sample under every strain being one unit of
the bootstrap. The slope of the P = 1/2 contour is the
model-free alternative.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ...analysis import estimators as an
from ..claims import Measurement
from ..study import Result, Scale, Study
from ..style import (
    COLUMN,
    STRAIN_COLOURS,
    WORDS,
    counts,
    errorbar,
    legend_below,
    paper_legend,
    paper_point,
    save,
    unresolved,
)
from ..template import load
from .rows import COLLAPSE_PT, FC5, PHI5, Rows, strain_name, threshold_bounds

NAME = "fig1c"
T = load(NAME)
#: f_c of the headline claims (``samples``) and of the rest of the curve (``curve``)
FIG1C_FC = [0.0, 0.5, 1.0]
FIG1C_FC_CURVE = [0.25, 0.75]
#: claim key -> (f_c, strain) of the fit it reads
CLAIM_FITS = {
    **{f"st_sr_half_{s}": (0.5, s) for s in ("dilation", "shear", "compression", "average")},
    "st_sr_cables_compression": (1.0, "compression"),
    "st_sr_struts_dilation": (0.0, "dilation"),
    "st_sr_cables_dilation": (1.0, "dilation"),
}
#: the paper's values drawn: (claim, f_c, strain)
PAPER_POINTS = (
    ("st_sr_cables_compression", 1.0, "compression"),
    ("st_sr_struts_dilation", 0.0, "dilation"),
    ("st_sr_cables_dilation", 1.0, "dilation"),
    ("st_sr_half_average", 0.5, "average"),
)


@dataclass(frozen=True, kw_only=True)
class Params:
    n: int = 32  # lattice size
    samples: int = 0  # samples at f_c = 0, 0.5, 1
    curve: int = 0  # samples at f_c = 0.25, 0.75


PARAMS = {"tiny": Params(n=5, samples=6, curve=6), "quick": Params(n=12, samples=48, curve=48),
          "paper": Params(n=32, samples=24, curve=12)}  # fmt: skip


@dataclass(frozen=True, eq=False)
class Fig1cResult(Result):
    """S_t/S_r versus f_c. ``fits``: per (f_c, strain) the fields of
    :class:`~tensegrity_rigidity.analysis.fits.CollapseFit` with ``f_c``, ``strain``, ``phi``
    (NaN for the average); ``contour``: per (f_c, strain) ``lam``, ``lam_err`` from the slope
    of the P = 1/2 contour; the rods-only P = 1/2 point (every strain; a sample's strains are
    one bootstrap unit) with its samples, units and strains; ``one_type``: reading ("shear",
    "average") -> (value, error) of :func:`one_type_contrast`."""

    fits: pd.DataFrame
    contour: pd.DataFrame
    rods_only_pc: float
    rods_only_pc_err: float
    rods_only_samples: int
    n: int
    samples: int
    rows: pd.DataFrame
    rods_only_units: int = 0
    rods_only_strains: int = 0
    one_type: dict = field(default_factory=dict)

    def lam(self, f_c: float, strain: str) -> tuple[float, float]:
        """(S_t/S_r, its error) of one fit."""
        row = self.fits[np.isclose(self.fits.f_c, f_c) & (self.fits.strain == strain)].iloc[0]
        return float(row.lam), float(row.lam_err)


def sweeps(scale: Scale) -> dict[str, dict]:
    """The rods-only thresholds (p_t = 0, where f_c does not matter) are one sweep shared by
    every f_c; the one-sided sweeps at p_t = COLLAPSE_PT share its samples (seed 12)."""
    p = scale[NAME]
    base = {"n": p.n, "phi": PHI5, "seed": 12, "threshold": {"path": "p_r"}, "p_t": COLLAPSE_PT}
    return {
        "fig1c_rods": base | {"p_t": 0.0, "f_c": 0.5, "samples": max(p.samples, p.curve)},
        "fig1c_mixed": base | {"f_c": FIG1C_FC, "samples": p.samples},
        "fig1c_curve": base | {"f_c": FIG1C_FC_CURVE, "samples": p.curve},
    }


def _fits(df: pd.DataFrame, f_c: float, scale: Scale) -> tuple[list[dict], list[dict]]:
    """The collapse fits and contour slopes at one f_c: per strain, then the average."""
    p_t, fits, contour = [0.0, COLLAPSE_PT], [], []
    pooled: list[list[np.ndarray]] = [[], [], []]
    units = []
    for phi in PHI5:
        sub = df[np.isclose(df.f_c, f_c) & np.isclose(df.phi, phi)]
        bounds = threshold_bounds(sub, p_t)
        for part, m in zip(pooled, bounds, strict=True):
            part.append(m)
        units.append(an.common_samples(sub))  # the rows of the matrices
        if phi in (0.0, math.pi / 2, math.pi):
            t, lo, hi = bounds
            fit = an.fit_collapse_thresholds(t, np.array(p_t), lo, hi, n_boot=scale.bootstrap,
                                             rng=scale.rng("collapse"))  # fmt: skip
            fits.append({"f_c": f_c, "strain": strain_name(phi), "phi": phi, **fit.__dict__})
            c = an.contour_slope(t, np.array(p_t), n_boot=scale.bootstrap,
                                 rng=scale.rng("contour"))  # fmt: skip
            contour.append(
                {"f_c": f_c, "strain": strain_name(phi), "lam": c.value, "lam_err": c.err}
            )
    # the strain average: a sample under every strain is one unit of the bootstrap
    groups = np.concatenate(units)
    t, lo, hi = (np.vstack(part) for part in pooled)
    fit = an.fit_collapse_thresholds(t, np.array(p_t), lo, hi, n_boot=scale.bootstrap,
                                     groups=groups, rng=scale.rng("collapse"))  # fmt: skip
    fits.append({"f_c": f_c, "strain": "average", "phi": np.nan, **fit.__dict__})
    c = an.contour_slope(t, np.array(p_t), n_boot=scale.bootstrap, groups=groups,
                         rng=scale.rng("contour"))  # fmt: skip
    contour.append({"f_c": f_c, "strain": "average", "lam": c.value, "lam_err": c.err})
    return fits, contour


#: the claim "one type of one-sided element beats a mixture"
ONE_TYPE_CLAIM = "st_sr_shear_one_type_beats_mixture"
#: its contrast: lam at f_c = 0 and 1 against f_c = 1/2
ONE_TYPE = {0.0: 0.5, 1.0: 0.5, 0.5: -1.0}
#: the claim's readings: the sentence's (shear) and the one its parenthesis allows (average)
ONE_TYPE_READINGS = {"shear": [math.pi / 2], "average": PHI5}


def one_type_contrast(
    df: pd.DataFrame, fits: pd.DataFrame, reading: str, scale: Scale
) -> tuple[float, float]:
    """(lam(0) + lam(1))/2 - lam(1/2) of one reading, and its error.

    Parameters
    ----------
    df : DataFrame
        The study's threshold rows (rods only and one-sided, every f_c and strain).
    fits : DataFrame
        The study's collapse fits (:attr:`Fig1cResult.fits`).
    reading : str
        A key of :data:`ONE_TYPE_READINGS`: "shear" or "average" (the five strains pooled).
    scale : Scale
        Its bootstrap count and random streams.

    Returns
    -------
    value, err : float
        The contrast of the study's own fits, and the error of one bootstrap that refits the
        three systems on the same resampled samples (those present in all three, the strains
        of one sample one unit), so that their correlation through common random numbers is
        kept (:func:`~tensegrity_rigidity.analysis.fits.collapse_contrast`).
    """
    p_t, phis = [0.0, COLLAPSE_PT], ONE_TYPE_READINGS[reading]
    lam = {f: float(fits[np.isclose(fits.f_c, f) & (fits.strain == reading)].lam.iloc[0])
           for f in ONE_TYPE}  # fmt: skip
    value = sum(w * lam[f] for f, w in ONE_TYPE.items())
    systems: dict[float, list] = {f: [[], [], []] for f in ONE_TYPE}
    groups = []
    for phi in phis:
        subs = {f: df[np.isclose(df.f_c, f) & np.isclose(df.phi, phi)] for f in ONE_TYPE}
        common = set.intersection(*(set(an.common_samples(s)) for s in subs.values()))
        for f, sub in subs.items():
            bounds = threshold_bounds(sub[sub["sample"].isin(common)], p_t)
            for part, m in zip(systems[f], bounds, strict=True):
                part.append(m)
        groups.append(np.array(sorted(common)))
    parts = [(np.vstack(t), np.vstack(lo), np.vstack(hi)) for t, lo, hi in systems.values()]
    est = an.collapse_contrast(
        parts,
        list(ONE_TYPE.values()),
        np.array(p_t),
        n_boot=scale.bootstrap,
        rng=scale.rng("collapse"),
        groups=np.concatenate(groups) if len(phis) > 1 else None,
    )
    return value, est.err


def analyse(rows: Rows, scale: Scale) -> Fig1cResult:
    """S_t/S_r versus f_c for each strain and the strain average (collapse fits)."""
    parts = {name: frame for name, (frame, _) in rows.items()}
    rods = parts["fig1c_rods"]
    mixed = pd.concat([parts["fig1c_mixed"], parts["fig1c_curve"]], ignore_index=True)
    # every f_c pairs the rods-only thresholds with its own samples at p_t = COLLAPSE_PT
    df = pd.concat([rods.assign(f_c=f_c) for f_c in FC5] + [mixed], ignore_index=True)
    fits: list[dict] = []
    contour: list[dict] = []
    for f_c in FC5:
        a, b = _fits(df, f_c, scale)
        fits, contour = fits + a, contour + b
    frame = pd.DataFrame(fits)
    one_type = {reading: one_type_contrast(df, frame, reading, scale)
                for reading in ONE_TYPE_READINGS}  # fmt: skip
    rods_only = rods.drop_duplicates(["phi", "sample"])
    pc, pc_err = an.critical_point(
        rods_only.threshold_p_r.to_numpy(), groups=rods_only["sample"].to_numpy(),
        rng=scale.rng("critical_point"),
    )  # fmt: skip
    return Fig1cResult(
        fits=frame, contour=pd.DataFrame(contour), rods_only_pc=pc, one_type=one_type,
        rods_only_pc_err=pc_err, rods_only_samples=len(rods_only), n=scale[NAME].n,
        samples=scale[NAME].samples, rows=df,
        excluded={name: count for name, (_, count) in rows.items()},
        rods_only_units=int(rods_only["sample"].nunique()),
        rods_only_strains=int(rods_only.phi.nunique()),
    )  # fmt: skip


def numbers(r: Fig1cResult) -> dict:
    return {"n": r.n, "samples": r.samples, "p_t": COLLAPSE_PT, "pc": r.rods_only_pc,
            "pc_err": r.rods_only_pc_err, "units": r.rods_only_units,
            "strains": r.rods_only_strains}  # fmt: skip


def claims(r: Fig1cResult) -> tuple[Measurement, ...]:
    """The efficacy claims (collapse fit; the contour slope as the estimator's evidence) and
    the rods-only threshold at this size."""
    v, n = numbers(r), r.n
    system, out = T.label("system", **v), []
    for key, (f_c, strain) in CLAIM_FITS.items():
        lam, err = r.lam(f_c, strain)
        note = T.labels.get(f"note.{key}") or T.label("note", **v)
        out.append(Measurement.scalar(key, lam, err, system, note=note, size=n))
        row = r.contour[np.isclose(r.contour.f_c, f_c) & (r.contour.strain == strain)].iloc[0]
        out.append(Measurement.scalar(key, row.lam, row.lam_err, system, factor="estimator",
                                      label=T.label("contour"), size=n))  # fmt: skip
    # one type beats a mixture: shear as the sentence says, the strain average as the
    # reading its parenthesis allows (the claim's declared factor "reading")
    value, err = r.one_type["shear"]
    out.append(Measurement.scalar(ONE_TYPE_CLAIM, value, err, system, size=n,
                                  note=T.label("note.one_type")))  # fmt: skip
    value, err = r.one_type["average"]
    out.append(Measurement.scalar(ONE_TYPE_CLAIM, value, err, system, factor="reading", size=n,
                                  label=T.label("one_type.average")))  # fmt: skip
    out.append(Measurement.scalar("rods_only_pc", v["pc"], v["pc_err"], T.label("pc", **v),
                                  note=T.label("note.pc"), size=n))  # fmt: skip
    return tuple(out)


def figures(r: Fig1cResult, figdir) -> dict:
    fig, ax = plt.subplots(figsize=(COLUMN, 3.0))
    for strain, sub in r.fits.groupby("strain", sort=False):
        errorbar(ax, sub.f_c, sub.lam, sub.lam_err, color=STRAIN_COLOURS[strain], label=strain)
    ax.axhline(0.5, color="grey", ls=":", lw=1)
    for key, f_c, strain in PAPER_POINTS:
        paper_point(ax, f_c, key, STRAIN_COLOURS[strain], dx=0.02)
    paper_legend(ax)
    unresolved(ax)
    average = r.fits[r.fits.strain == "average"]
    counts(ax, average.f_c, average.n_samples)
    ax.set(xlabel=WORDS.label("f_c"), ylabel=WORDS.label("st_sr"))
    ax.set_title(T.label("title", n=r.n))
    legend_below(ax)
    return {"1C": save(fig, figdir, "1C")}


def cost(scale: Scale, costs) -> float:
    return costs.analysis(NAME) * scale.bootstrap / 100


def errors(scale: Scale) -> list[tuple]:
    """S_t/S_r per claim (the average pooled over five strains, whose errors are independent)
    and the rods-only P = 1/2 point."""
    p = scale[NAME]
    out = [(k, NAME, "st_sr", p.n, p.samples, 5 if s == "average" else 1)
           for k, (_, s) in CLAIM_FITS.items()]  # fmt: skip
    return out + [("rods_only_pc", NAME, "p_crit", p.n, p.samples)]


STUDY = Study(
    name=NAME, params=PARAMS, default=Params(), sweeps=sweeps, analyse=analyse, claims=claims,
    cost=cost, numbers=numbers, figures=figures, errors=errors,
    tables=lambda r: {"efficacy_fits": r.fits},
)  # fmt: skip
