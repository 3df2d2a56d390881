"""Our measurements beside the paper's claims: one typed row per claim.

:func:`compare` pairs each claim of :mod:`~tensegrity_rigidity.paper.claims` with what the
studies measured (the studies compute every statistic; this module only formats and judges) and
returns :class:`ComparisonRow` objects, which the report renders. Two numbers *agree* when they
differ by less than twice their combined standard error (the paper's error where it gives one,
else ours alone). Nothing here is tuned to agree.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
import pandas as pd

from .claims import CLAIMS, PCRIT_COMPRESSION, PCRIT_DILATION


@dataclass(frozen=True)
class ComparisonRow:
    """One claim of the paper beside our measurement.

    Attributes
    ----------
    key : str
        The claim's key in :data:`~tensegrity_rigidity.paper.claims.CLAIMS`.
    claim, paper : str
        The claim and the paper's value as printed.
    ours : str
        Our value with its uncertainty, formatted.
    system : str
        System size and sample counts behind our value.
    verdict : str
        "agree", "disagree" or "n/a" (no measurement).
    note : str
        How the two values are defined, where that matters.
    source : str
        Where in the paper the claim is made.
    """

    key: str
    claim: str
    paper: str
    ours: str
    system: str
    verdict: str
    note: str
    source: str


#: columns of the comparison table as the report shows it
TABLE_COLUMNS = ["claim", "paper", "ours", "system", "verdict", "note"]


def _verdict(ours, err, paper, paper_err=0.0):
    if ours is None or not np.isfinite(ours):
        return "n/a"
    sigma = math.hypot(err if np.isfinite(err) else 0.0, paper_err)
    if sigma == 0:
        return "agree" if abs(ours - paper) < 1e-12 else "disagree"
    return "agree" if abs(ours - paper) <= 2 * sigma else "disagree"


def fmt(value, err=None, digits=3) -> str:
    """``value ± err`` to ``digits`` decimals ("n/a" for a missing or non-finite value)."""
    if value is None or (isinstance(value, float) and not np.isfinite(value)):
        return "n/a"
    if err is None or not np.isfinite(err):
        return f"{value:.{digits}f}"
    return f"{value:.{digits}f} ± {err:.{digits}f}"


def compare(results: dict) -> list[ComparisonRow]:
    """One row per claim measured by the studies in ``results`` (study name -> result)."""
    rows = []

    def add(key, ours, system, verdict, note=""):
        c = CLAIMS[key]
        rows.append(ComparisonRow(key, c.text, c.paper, ours, system, verdict, note, c.source))

    if "fig1c" in results:
        r = results["fig1c"]
        sys_ = f"n = {r.n}, {r.samples} samples x 4 p_t"
        for strain in ("dilation", "shear", "compression", "average"):
            v, e = r.lam(0.5, strain)
            add(f"st_sr_half_{strain}", fmt(v, e), sys_, _verdict(v, e, 0.5))
        v, e = r.lam(1.0, "compression")
        c = CLAIMS["st_sr_cables_compression"]
        add(c.key, fmt(v, e), sys_, _verdict(v, e, c.value, c.error))
        v, e = r.lam(0.0, "dilation")
        c = CLAIMS["st_sr_struts_dilation"]
        add(
            c.key,
            fmt(v, e),
            sys_,
            _verdict(v, e, c.value, c.error),
            "identical to rods + cables under compression by an exact symmetry: compression is "
            "minus dilation, and e -> -e swaps cables and struts sample by sample",
        )
        v, e = r.lam(1.0, "dilation")
        c = CLAIMS["st_sr_cables_dilation"]
        add(c.key, fmt(v, e), sys_, _verdict(v, e, c.value), "paper gives no error bar")
        c = CLAIMS["rods_only_pc"]
        add(
            c.key,
            fmt(r.rods_only_pc, r.rods_only_pc_err),
            f"n = {r.n}, {r.rods_only_samples} thresholds",
            _verdict(r.rods_only_pc, r.rods_only_pc_err, c.value),
            "finite-size threshold (median of per-sample thresholds)",
        )
    if "fig1b" in results:
        r = results["fig1b"]
        xs = r.half_x
        spread = float(np.std(xs)) if xs.size else float("nan")
        mean = float(np.mean(xs)) if xs.size else float("nan")
        add(
            "collapse_shear_half",
            f"p_r + p_t/2 at P = 1/2: mean {mean:.3f}, spread {spread:.3f} over "
            f"{xs.size} values of p_t",
            f"n = {r.n}, {r.samples} samples per p_t",
            "agree" if spread < 0.02 else "disagree",
            "spread below 0.02 counts as agreement",
        )
    if "fig2" in results:
        r = results["fig2"]
        sys_ = f"n = {r.n}, {r.samples} samples per point"
        fits = r.fits
        for strain, table in (("compression", PCRIT_COMPRESSION), ("dilation", PCRIT_DILATION)):
            for p_t in table:
                row = fits[(fits.strain == strain) & np.isclose(fits.p_t, p_t)].iloc[0]
                c = CLAIMS[f"p_crit_{strain}_{p_t}"]
                add(
                    c.key,
                    fmt(row.p_crit, row.p_crit_err),
                    sys_,
                    _verdict(row.p_crit, row.p_crit_err, c.value, 0.005),
                    "ours: P = 1/2; paper: first positive energy (reads off to 0.01)",
                )
                c = CLAIMS[f"alpha_{strain}_{p_t}"]
                add(
                    c.key,
                    fmt(row.alpha, row.alpha_err),
                    f"{sys_}; {row.n_points} fit points",
                    _verdict(row.alpha, row.alpha_err, c.value, c.error),
                )
        if r.taut_at_transition is not None:
            v, e, _ = r.taut_at_transition
            c = CLAIMS["taut_cables_transition"]
            add(
                c.key,
                f"{100 * v:.1f} % ± {100 * e:.1f} %",
                sys_ + "; rigid samples at p_r nearest p_crit, mean over p_t = 0.1, 0.2, 0.3",
                _verdict(v, e, c.value),
                "paper gives no error bar",
            )
        peaks = r.crit[np.isclose(r.crit.phi, math.pi)]
        offset = peaks.gamma_peak_p_r - peaks.p_crit
        add(
            "gamma_peak",
            "peak - p_crit: " + ", ".join(f"{d:+.3f}" for d in offset),
            sys_,
            "agree" if (np.abs(offset) <= 0.1 + 1e-9).all() else "disagree",
            "agreement: every peak within 0.1 of p_crit",
        )
    if "fig4" in results:
        r = results["fig4"]
        sys_ = f"n = {r.n}, {r.samples} samples per point"
        for key, name, sign in (
            ("fig4a_dilation_rises", "dilation", 1),
            ("fig4a_compression_falls", "compression", -1),
        ):
            slope = r.slopes[name]
            add(
                key,
                f"slope dP/df_c = {slope:+.3f}",
                sys_,
                "agree" if slope * sign > 0 else "disagree",
            )
        a = r.average
        dev = a.sum_rel - 1.0
        add(
            "fig4c_sum_one",
            ", ".join(f"{v:.2f}±{e:.2f}" for v, e in zip(a.sum_rel, a.sum_rel_err, strict=False)),
            sys_,
            "agree" if (np.abs(dev) <= 2 * a.sum_rel_err + 1e-12).all() else "disagree",
            "per f_c = 0, 1/8, ..., 1; dP/df_c by central differences, second-order one-sided "
            "at f_c = 0 and 1, where P(f_c) is steep and the estimate is least reliable",
        )
    if "fig3" in results:
        r = results["fig3"]
        zmax = float(np.nanmax(np.abs(r.sim.z)))
        add(
            "single_node",
            f"max |z| = {zmax:.2f} over {len(r.sim)} points",
            f"{r.trials} trials per point",
            "agree" if zmax < 3.5 else "disagree",
            "z = (simulated - analytic) / binomial standard error",
        )
    return rows


def comparison_frame(rows: list[ComparisonRow]) -> pd.DataFrame:
    """The rows as a table (every field, one column each)."""
    return pd.DataFrame([asdict(r) for r in rows])
