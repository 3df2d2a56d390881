"""The reproduction report: our numbers beside the paper's, figures, tables.

The report renders; it computes nothing. The studies (:mod:`~tensegrity_rigidity.paper.studies`)
compute every statistic, :mod:`~tensegrity_rigidity.paper.comparison` pairs them with the
paper's claims (:mod:`~tensegrity_rigidity.paper.claims`) into typed rows.

:func:`write_report` writes ``report.md``, a self-contained ``report.html`` (figures embedded as
base64 PNG; no external reference of any kind) and the tables as CSV.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..analysis.single_node import class_weights, qbar_table
from ..model.lattice import DEFAULT_DELTA
from .claims import CLAIMS, REFERENCES
from .comparison import (
    RULE,
    compare,
    comparison_frame,
    evidence_frame,
    fmt,
    paper_against_itself,
    shared_measurements,
    summary_frame,
)
from .finite_size import NU_CHECK, PC_CHECK, nu_dependent
from .render import to_html, to_markdown
from .report_3d import three_d_section
from .studies import ENERGY_BRACKETED
from .studies.rows import undecided_by_kind

FIGURE_CAPTIONS = {
    "1A": "A force-balanced rigid sample: rods solid, cables dashed, struts hollow; colour from "
    "red (pulling) through green (zero) to blue (pushing).",
    "1B": "Probability of rigidity under shear at f_c = 0.5 with the mean-field line.",
    "1C": "S_t/S_r versus f_c for dilation, shear, compression and the strain average.",
    "2A": "Nonaffine displacement field of a rods-and-cables network under compression: arrows "
    "of equal length give the direction, their colour and the background |u| on a log scale.",
    "2B": "Nonaffinity versus p_r for several p_t (rods + cables, compression): median with the "
    "interquartile band, the mean as open markers; where some samples' minimum norm is known "
    "only from below, a bar brackets the median over all samples.",
    "2E": "Not in the paper: the distribution (complementary CDF) of Gamma over samples at the "
    "grid p_r nearest p_crit (rods + cables, compression).",
    "2C": "Energy versus p_r under compression; inset: log-log with power-law fits.",
    "2D": "Energy versus p_r under dilation; inset: log-log with power-law fits.",
    "3B": "Single three-coordinated node: P_N versus f_c.",
    "4A": "P versus f_c for strains from dilation (phi = 0) to compression (phi = pi).",
    "4B": "Efficacies of cables and struts relative to rods, averaged over strains.",
    "4C": "Combined efficacy (S_c + S_s)/S_r versus f_c.",
    "RC": "Not in the paper: rigid clusters at the threshold (pebble game). Left: one rods-only "
    "sample just after its threshold event, its spanning rigid cluster in blue, that cluster's "
    "stressed (overconstrained) rods in vermillion (thicker), other rigid clusters sky blue, "
    "lone (floppy) rods grey; rods leaving the box are drawn whole to their neighbour's image. "
    "Right: mean masses (nodes) of the spanning cluster and of its stressed part at each "
    "sample's threshold against n, log-log, with the fitted n^d (dashed).",
    "FS": "Not in the paper: finite size. Against n (log axis), with the fitted "
    "y_inf + a n^(-1/nu) (dashed), the extrapolation to n -> infinity (squares at 'inf') and "
    "the paper's or the literature's value (dotted): the "
    "rods-only P = 1/2 point; then (not at the pc scale) S_t/S_r of rods + cables "
    "(compression, dilation) and of f_c = 0.5 under shear, the energy exponent alpha of "
    "rods + cables under compression and under dilation (one line per p_t), and the fraction "
    "of taut cables at p_crit. Beside the rods-only point, log-log, the standard deviation of "
    "the rods-only thresholds against n with its fitted n^(-1/nu), and p_c from the P = 1/2 "
    "point against that width.",
    "3D": "Not in the paper: the FCC lattice in 3D against n (log axis). The rods-only P = 1/2 "
    "point (grey: the literature's 3D value, dashed, and Maxwell's 1/2, dotted; the 2D values "
    "written in the panel), S_t/S_r at f_c = 0.5 per strain, and S_t/S_r of rods + cables under "
    "compression and dilation; fits y_inf + a n^(-1/nu) with nu fitted to the rods-only "
    "points (dashed, squares at 'inf') and with 1/nu = 3 (dotted, open diamonds); dash-dot "
    "lines with grey bands: ours in 2D extrapolated (reports/fss); open stars: the paper's 2D "
    "values. Last panel: the widths of the rods-only threshold distributions, log-log.",
}


#: what the table of undecided verdicts by kind shows
UNDECIDED_KINDS = (
    "Undecided verdicts by kind. Within resolution: the best candidates prove that the sample "
    "lies within the resolution model's tolerances of the boundary. Not resolved: the search "
    'stopped before either side (docs/model.md, "Undecided verdicts").'
)


def excluded_samples(results: dict) -> dict[str, int]:
    """Sweep name -> samples excluded as undecided, over every study result."""
    out: dict[str, int] = {}
    for r in results.values():
        out.update(r.excluded)
    return out


def bracketed_rows(results: dict) -> dict[str, int]:
    """Sweep name -> undecided grid rows that enter the energy analyses
    (:func:`~tensegrity_rigidity.paper.studies.energy_bracketed`), over every study result."""
    out: dict[str, int] = {}
    for r in results.values():
        out.update(getattr(r, "bracketed", {}))
    return out


def straddling_of(results: dict) -> dict[str, int | None]:
    """Study name -> threshold samples whose interval straddles a grid value (None: the
    threshold rows do not record intervals), for the studies that record it."""
    return {k: r.straddling for k, r in results.items() if hasattr(r, "straddling")}


def tables_of(results: dict) -> dict[str, pd.DataFrame]:
    """The CSV tables written beside the report (name -> frame), from the study results."""
    extra = {}
    if "fig1c" in results:
        extra["efficacy_fits"] = results["fig1c"].fits
    if "fig2" in results:
        extra["energy_fits"] = results["fig2"].fits
        extra["energy_fits_paper_estimators"] = results["fig2"].paper_estimators
        extra["fig2_curves"] = results["fig2"].curves
        extra["fig2_tails"] = results["fig2"].tails
        extra["fig2_at_pcrit"] = results["fig2"].at_pcrit
    if "fig3" in results:
        extra["single_node_qbar"] = pd.DataFrame(qbar_table())
        extra["single_node_simulation"] = results["fig3"].sim
        extra["single_node_class_weights"] = pd.DataFrame([class_weights()])
    if "fss" in results:
        extra["fss_by_size"] = results["fss"].by_size
        extra["fss_extrapolated"] = results["fss"].extrapolated
        if results["fss"].pc_by_smallest is not None:
            extra["fss_pc_by_smallest_size"] = results["fss"].pc_by_smallest
        if results["fss"].fractal is not None:
            extra["pc_fractal_dimensions"] = results["fss"].fractal
            extra["pc_cluster_masses"] = results["fss"].fractal_by_size
    if "delta" in results:
        extra["delta_by_delta"] = results["delta"].by_delta
    if "three_d" in results:
        from .studies.three_d import beside_2d

        extra["three_d_by_size"] = results["three_d"].by_size
        extra["three_d_extrapolated"] = results["three_d"].extrapolated
        extra["three_d_beside_2d"] = beside_2d(results["three_d"])
    if "method" in results:
        extra["method_disagreement"] = results["method"].disagreement
        extra["method_claims"] = results["method"].claims
    if "fig4" in results:
        extra["fig4_average"] = results["fig4"].average
        extra["fig4_per_strain"] = results["fig4"].per_phi
        extra["fig4_differences"] = results["fig4"].differences
    return extra


@dataclass(frozen=True)
class Section:
    """A section of the report: a title, paragraphs and tables, rendered to Markdown and HTML."""

    title: str
    paragraphs: tuple[str, ...]
    tables: tuple[pd.DataFrame, ...] = ()


def _g(x: float) -> str:
    return f"{x:.3g}" if np.isfinite(x) else "n/a"


def _bracket_sentence(curves: pd.DataFrame) -> str:
    """What the certified lower bounds of the samples without a nonaffinity say about the
    median Gamma under compression (empty where no row has such a bound)."""
    if "gamma_bounded" not in curves or not int(curves.gamma_bounded.sum()):
        return ""
    k = int(curves.gamma_bounded.sum())
    comp = curves[np.isclose(curves.phi, np.pi)]
    open_ = comp[comp.gamma_median_high > comp.gamma_median_low]
    text = (
        f" {k} of them have a certified lower bound on Gamma instead (their minimum-norm "
        "projection ran but stalled, near their own threshold; rows' nonaffinity_lower): "
        "counting every sample, the median Gamma of a grid point lies between its median with "
        "those samples at their bounds (at 0 where a sample has none) and at infinity. Under "
        f"compression the two agree at {len(comp) - len(open_)} of {len(comp)} grid points"
    )
    if len(open_):
        w = open_.loc[(open_.gamma_median_high / open_.gamma_median_low).idxmax()]
        high = "inf" if np.isposinf(w.gamma_median_high) else _g(w.gamma_median_high)
        text += (
            f"; the widest bracket is [{_g(w.gamma_median_low)}, {high}] "
            f"(p_t = {w.p_t:.1f}, p_r = {w.p_r:g}; median over the certified samples "
            f"{_g(w.gamma_median)})"
        )
    return text + "."


def tails_section(r) -> Section:
    """Heavy tails of Gamma and the energy at the transition (from Fig. 2's study)."""
    if r.min_norm_failed is None:
        mn = (
            "The sweep rows do not record whether the displacements are the verified "
            "minimum-norm minimiser (min_norm_ok, absent in rows written before it existed): "
            "every stored Gamma is used."
        )
    else:
        mn = (
            f"{r.min_norm_failed} grid samples have no verified minimum-norm displacements "
            "(min_norm_ok = False); their Gamma is left out (NaN), their verdict and energy kept."
        )
    mn += _bracket_sentence(r.curves)
    if r.tensions_uncertified:
        mn += (
            f" {r.tensions_uncertified} rigid grid samples have no certified relaxed energy, so "
            "their tensions need not be t*: their fractions of taut cables and struts are left "
            "out (NaN)."
        )
    paragraphs = [mn]
    w = r.worst_tail
    if w is not None:
        paragraphs.append(
            f"Near the transition Gamma is heavy-tailed, so a mean over samples (what the paper "
            f"plots in Fig. 2B) is set by its few largest samples. At p_crit "
            f"(p_t = {w['p_t']:.1f}, p_r = {w['p_r']:g}) the largest of {w['N']} samples carries "
            f"{100 * w['top_share']:.0f} % of the summed Gamma: leaving it out moves the mean "
            f"from {_g(w['mean'])} to {_g(w['mean_without_top'])}, while the median is "
            f"{_g(w['median'])} (quartiles {_g(w['q25'])}, {_g(w['q75'])}). The paper's mean is "
            "therefore sensitive to the number of samples (a larger sample meets larger "
            "outliers), to how far the minimiser is from the minimum-norm one along floppy "
            "directions (an unconverged or non-minimum-norm displacement inflates exactly these "
            "samples), and to the position of the grid point relative to p_crit; the median and "
            "quartiles (Fig. 2B band, Fig. 2E) are not."
        )
    table = r.tails.copy()
    for col in ("mean", "median", "q25", "q75", "max", "mean_without_top"):
        if col in table:
            table[col] = table[col].map(_g)
    if "top_share" in table:
        table["top_share"] = table["top_share"].map(
            lambda x: f"{100 * x:.0f} %" if np.isfinite(x) else "n/a"
        )
    return Section(
        "Heavy tails: Gamma and the energy at the transition", tuple(paragraphs), (table,)
    )


def method_section(r) -> Section:
    """The paper's verdict beside ours on the same samples (from the method study)."""
    it = r.iterations
    main = r.disagreement[
        (r.disagreement.threshold == r.threshold) & (r.disagreement.region == "all")
    ].iloc[0]
    near = r.disagreement[
        (r.disagreement.threshold == r.threshold) & (r.disagreement.region != "all")
    ].iloc[0]
    paragraphs = (
        "The paper decided each sample by minimising the energy (Mathematica's FindMinimum) and "
        "calling it rigid when the energy is above 0. Here the same grid (rods + cables, "
        f"compression and dilation, p_t = 0 to 0.3, p_r = 0.40 to 0.80, n = {r.n}, {r.samples} "
        "samples per point) is decided twice on identical samples: by our certificates, and by "
        "SciPy's L-BFGS-B with its default tolerances and the exact gradient from u = 0, rigid "
        f"when the energy it stops at exceeds {r.threshold:g} of the affine energy. That "
        "threshold is the resolution of a minimiser stopped at default tolerances (about half "
        "the machine digits relative to the energy scale; FindMinimum's default precision goal "
        "is 8 digits); 100x above and below it are shown too.",
        f"At that threshold {main.differ} of {main.samples} verdicts differ "
        f"({100 * main.fraction:.1f} %, 95 % interval {100 * main.lo:.1f} to "
        f"{100 * main.hi:.1f} %); where the exact P lies between 0.1 and 0.9, {near.differ} of "
        f"{near.samples} ({100 * near.fraction:.1f} %). The verdicts are {main.units} samples "
        "(disorders) decided at every grid point, so one sample's verdicts are correlated: the "
        "intervals (lo, hi) come from a bootstrap over whole samples (each replica draws the "
        "samples with replacement and pools all their verdicts; 2.5 and 97.5 percentiles), "
        "where no verdict differs from the exact 95 % upper bound 1 - 0.05^(1/samples) on the "
        "share of samples with a disagreement (interval_note says which). The Wilson interval "
        "that counts every verdict as independent (wilson_lo, wilson_hi) is shown for "
        f"comparison only; it is too narrow. {main.exact_floppy_paper_rigid} floppy "
        f"samples are called rigid (the minimiser stopped above the threshold) and "
        f"{main.exact_rigid_paper_floppy} rigid samples floppy. L-BFGS-B took a median of "
        f"{it['median']:.0f} iterations (at most {it['max']}); {it['not_converged']} runs "
        "stopped without meeting its tolerances.",
        "How each claim moves (same samples, same estimator; shift = paper's verdict - ours, "
        "with a paired bootstrap error). The comparison table's explanation column adds these "
        "shifts to our values as the evidence for the factor 'method'.",
    )
    dis = r.disagreement.copy()
    for col in ("fraction", "lo", "hi", "wilson_lo", "wilson_hi"):
        dis[col] = dis[col].map(lambda x: f"{100 * x:.1f} %" if np.isfinite(x) else "n/a")
    claims = r.claims.copy()
    claims.insert(1, "claim", [CLAIMS[k].text for k in claims.key])
    for col in ("exact", "paper", "shift"):
        claims[col] = [fmt(v, e) for v, e in zip(claims[col], claims[f"{col}_err"], strict=True)]
    claims = claims[["claim", "exact", "paper", "shift", "note"]]
    return Section("The paper's method beside ours", paragraphs, (dis, claims))


def _pc_widths(r) -> str:
    """The second reading of the rods-only extrapolation: the threshold distributions' widths."""
    w = r.pc_widths
    if w is None or not np.isfinite(w.nu):
        return ""
    dof = w.n.size - 2
    return (
        " Without a fitted exponent (the widths of the threshold distributions, standard "
        "deviations "
        + ", ".join(f"{x:.4f}" for x in w.width)
        + " at n = "
        + ", ".join(str(int(n)) for n in w.n)
        + ", scale as n^(-1/nu); the P = 1/2 point is a "
        f"straight line in the width whose intercept is p_c): nu = {fmt(w.nu, w.nu_err)} "
        f"(chi-square {w.nu_chi2:.2f} with {dof} degrees of freedom), z = "
        f"{r.pc_widths_nu_z:.2f} against "
        f"{NU_CHECK.value}; p_c = {fmt(w.p_c, w.p_c_err)} (chi-square {w.p_c_chi2:.2f} with "
        f"{dof}), z = {r.pc_widths_z:.2f} against {PC_CHECK.value}."
    )


def _pc_smallest(r) -> tuple[str, tuple[pd.DataFrame, ...]]:
    """The rods-only extrapolation without the smallest sizes: a sentence and its table."""
    t = r.pc_by_smallest
    if t is None or len(t) < 2:
        return "", ()
    fitted = t[np.isfinite(t.p_c)]
    # a fit with nu at its bound or without a degree of freedom passes through its points
    # whatever the form: its p_c is not a reading of the threshold
    loose = fitted.nu_at_bound.astype(bool) | (fitted.dof <= 0)
    free = fitted[~loose]
    text = (
        " The second table refits the rods-only point without the smallest sizes, "
        "where corrections to scaling are largest (a reading that moves by more than its error "
        "is not determined by these sizes)."
    )
    left_out = ""
    if loose.any():
        n_bound = int(fitted.nu_at_bound.astype(bool).sum())
        n_dof = int((loose & ~fitted.nu_at_bound.astype(bool)).sum())
        why = [
            f"{n_bound} with nu at the bound of its allowed range (0.5 to 3: the sizes do not "
            "determine it)"
            if n_bound
            else "",
            f"{n_dof} with 0 degrees of freedom (three parameters through three points)"
            if n_dof
            else "",
        ]
        left_out = f"{int(loose.sum())} of the {len(fitted)} free fits left out: " + " and ".join(
            w for w in why if w
        )
    if len(free) > 1:
        text += (
            f" Fitted freely, p_c ranges from {free.p_c.min():.4f} to {free.p_c.max():.4f} as "
            "the smallest sizes are dropped" + (f" ({left_out})." if left_out else ".")
        )
    elif left_out:
        text += f" Fitted freely, no range of p_c is quoted: {left_out}, which leaves {len(free)}."
    table = pd.DataFrame(
        [
            {
                "sizes used": f"n >= {int(row.n_min)} ({int(row.sizes)})",
                "p_c, nu fitted": fmt(row.p_c, row.p_c_err),
                "nu": fmt(row.nu, row.nu_err) + (" (at bound)" if row.nu_at_bound else ""),
                "chi-square / dof, nu fitted": f"{row.chi2:.2f} / {row.dof}",
                "z, nu fitted": f"{row.z:.2f}",
                f"p_c, nu = {NU_CHECK.value}": fmt(row.p_c_fixed, row.p_c_fixed_err),
                "chi-square / dof, nu fixed": f"{row.chi2_fixed:.2f} / {row.dof_fixed}",
                "z, nu fixed": f"{row.z_fixed:.2f}",
            }
            for row in t.itertuples()
        ]
    )
    return text, (table,)


def _pc_intervals(r) -> str:
    """The rods-only thresholds reported as intervals (undecided probes), per size."""
    pc = r.by_size[r.by_size.key == "rods_only_pc"].sort_values("n")
    if "intervals" not in pc or not np.nansum(pc.intervals.to_numpy(float)):
        return ""
    parts = [
        f"{int(row.intervals)} of {int(row.samples)} at n = {int(row.n)} "
        f"(mean width {row.width:.1e})"
        for row in pc.itertuples()
        if row.intervals > 0
    ]
    return (
        " Rods-only thresholds that are intervals (undecided probes on their paths; "
        "the median uses their midpoints): " + ", ".join(parts) + "."
    )


def fss_section(r) -> Section:
    """Finite size: the headline claims per n and extrapolated to n -> infinity."""
    ex = r.extrapolated.set_index("key")
    pc = ex.loc["rods_only_pc"]
    smallest, smallest_tables = _pc_smallest(r)
    changed, compared = nu_dependent(r.extrapolated)
    paragraphs = (
        (
            f"The headline claims at n = {', '.join(map(str, r.sizes))} "
            f"({', '.join(map(str, r.samples))} samples per point at these sizes; exact "
            f"per-sample thresholds, node disorder delta = {DEFAULT_DELTA}; the energy "
            "exponents alpha and the taut-cable fraction from grids of energies on "
            f"{', '.join(map(str, r.energy_samples))} samples, sample k with the disorder of "
            "threshold sample k), "
            "each extrapolated with y(n) = y_inf + a n^(-1/nu). "
            if r.sizes
            else "Only the rods-only P = 1/2 point (exact per-sample thresholds, node disorder "
            f"delta = {DEFAULT_DELTA}), extrapolated with y(n) = y_inf + a n^(-1/nu). "
        )
        + (
            "The rods-only P = 1/2 point comes from its own sweeps, one strain (in a "
            "finite-size run the rods-only thresholds were identical under dilation, shear and "
            "compression for all 400 samples at n = 8 and 96 % at n = 32), at n = "
            f"{', '.join(map(str, r.pc_sizes))} with {', '.join(map(str, r.pc_samples))} "
            "samples. "
            if r.pc_sizes and tuple(r.pc_sizes) != tuple(r.sizes)
            else "Its errors resample samples, all strains of one sample together. "
        )
        + "For the "
        f"rods-only P = 1/2 point nu is fitted: p_c = {fmt(pc.y_inf, pc.y_inf_err)}, "
        f"nu = {fmt(pc.nu, pc.nu_err)} (chi-square {pc.chi2:.2f} with {pc.dof} degree(s) of "
        "freedom; errors from a parametric bootstrap). Checks, not inputs: nu against "
        f"{NU_CHECK.value} ± {NU_CHECK.error} ({NU_CHECK.citation.split(',')[0]}): "
        f"z = {r.nu_z:.2f}; p_c against {PC_CHECK.value} ({PC_CHECK.citation.split(',')[0]}): "
        f"z = {r.pc_z:.2f} (within its error when z < 1)."
        + (
            " The fitted nu sits at the bound of its allowed range (0.5 to 3): these sizes and "
            "errors do not determine it, and p_c moves with it."
            if r.nu_at_bound
            else ""
        )
        + (
            f" With nu fixed at the literature's {NU_CHECK.value} ± {NU_CHECK.error} instead, "
            f"p_c = {fmt(r.pc_at_check_nu.y_inf, r.pc_at_check_nu.y_inf_err)} (chi-square "
            f"{r.pc_at_check_nu.chi2:.2f} with {r.pc_at_check_nu.dof} degrees of freedom), "
            f"z = {r.pc_at_check_nu_z:.2f} against {PC_CHECK.value}."
            if r.pc_at_check_nu is not None
            else ""
        )
        + _pc_widths(r)
        + _pc_intervals(r)
        + smallest
        + (
            " The other claims are extrapolated with nu fixed at the fitted value, its error added."
            if r.sizes
            else ""
        )
        + (
            f" Each claim is also extrapolated with nu fixed at the literature's {NU_CHECK.value}"
            f' ± {NU_CHECK.error} (columns "n -> infinity, nu = {NU_CHECK.value}" and '
            f'"z_paper, nu = {NU_CHECK.value}"; the comparison shows both readings): '
            f"{len(changed)} of {compared} extrapolated claims change verdict between the two nu"
            + (
                ": the extrapolation is nu-dependent there ("
                + "; ".join(CLAIMS[k].text for k in changed)
                + ")."
                if changed
                else "."
            )
            if compared
            else ""
        )
        + " z_paper is the comparison's statistic of the extrapolation against the "
        "paper's value; where the chi-square is above its 99th percentile the form does not "
        "fit the sizes, and the comparison says so beside the extrapolated value.",
    )
    wide = r.by_size.pivot_table(index="key", columns="n", values="value")
    err = r.by_size.pivot_table(index="key", columns="n", values="err")
    table = pd.DataFrame({"claim": [CLAIMS[k].text for k in wide.index]})
    table["paper"] = [CLAIMS[k].paper for k in wide.index]
    for n in wide.columns:
        table[f"n = {n}"] = [fmt(v, e) for v, e in zip(wide[n], err[n], strict=True)]
    table["n -> infinity"] = [fmt(ex.loc[k].y_inf, ex.loc[k].y_inf_err) for k in wide.index]
    table["chi-square / dof"] = [f"{ex.loc[k].chi2:.1f} / {ex.loc[k].dof}" for k in wide.index]
    table["z_paper"] = [f"{ex.loc[k].z_paper:.2f}" for k in wide.index]
    table[f"n -> infinity, nu = {NU_CHECK.value}"] = [
        fmt(ex.loc[k].y_inf_nu_check, ex.loc[k].y_inf_nu_check_err) for k in wide.index
    ]
    table[f"z_paper, nu = {NU_CHECK.value}"] = [
        f"{ex.loc[k].z_paper_nu_check:.2f}" for k in wide.index
    ]
    return Section("Finite size", paragraphs, (table, *smallest_tables))


def _against(value: float, err: float, key: str) -> tuple[str, str, str]:
    """(literature value with its error, citation's first part, z) of one reference."""
    ref = REFERENCES[key]
    ref_err = ref.error or 0.0
    z = abs(value - ref.value) / np.hypot(err, ref_err) if err > 0 or ref_err > 0 else np.nan
    quoted = f"{ref.value} ± {ref.error:g}" if ref.error else f"about {ref.value} (no error)"
    return quoted, ref.citation.split(",")[0].split(" (")[0], f"{z:.2f}"


def clusters_section(r) -> Section:
    """The rods-only study by the pebble game against the literature: p_c, nu and the fractal
    dimensions of the spanning rigid cluster and its stressed part at the threshold."""
    pc = r.extrapolated.set_index("key").loc["rods_only_pc"]
    w, fixed = r.pc_widths, r.pc_at_check_nu
    fits = r.fractal
    rows = []

    def add(quantity, how, value, err, keys):
        for key in keys:
            quoted, who, z = _against(value, err, key)
            rows.append(
                {"quantity": quantity, "ours": fmt(value, err), "how": how,
                 "literature": quoted, "source": who, "z": z}
            )  # fmt: skip

    pc_refs = ("pc_javerzat_notarmuzi", "pc_jacobs_thorpe")
    nu_refs = ("nu_javerzat_notarmuzi", "nu_moukarzel_duxbury", "nu_jacobs_thorpe")
    add("p_c", "P = 1/2 points, y + a n^(-1/nu), nu fitted", pc.y_inf, pc.y_inf_err, pc_refs)
    if fixed is not None:
        add("p_c", f"the same, nu fixed at {NU_CHECK.value}", fixed.y_inf, fixed.y_inf_err,
            pc_refs)  # fmt: skip
    if w is not None and np.isfinite(w.p_c):
        add("p_c", "centre against width (no exponent)", w.p_c, w.p_c_err, pc_refs)
    add("nu", "P = 1/2 points, fitted", pc.nu, pc.nu_err, nu_refs)
    if w is not None and np.isfinite(w.nu):
        add("nu", "widths of the threshold distributions", w.nu, w.nu_err, nu_refs)
    n_min = int(fits.n_min.min())
    refs = {"rigid": ("df_rigid_javerzat_notarmuzi", "df_rigid_jacobs_thorpe"),
            "stressed": ("df_stressed_jacobs_thorpe",)}  # fmt: skip
    for row in fits[fits.mass == "nodes"].itertuples():  # sites: tables/pc_fractal_dimensions
        name = "spanning rigid cluster" if row.cluster == "rigid" else "its stressed part"
        sizes = "all sizes" if row.n_min == n_min else f"n >= {row.n_min}"
        add(f"d_f, {name}", f"mean {row.mass} at threshold, {sizes} (chi-square "
            f"{row.chi2:.1f} / {row.dof})", row.d, row.d_err, refs[row.cluster])  # fmt: skip
    table = pd.DataFrame(rows)
    by = r.fractal_by_size
    masses = pd.DataFrame(
        {
            "n": by.n,
            "samples": by.samples,
            **{
                f"{lab}, {mass}": [
                    fmt(v, e) for v, e in zip(by[f"{c}_{mass}"], by[f"{c}_{mass}_err"], strict=True)
                ]
                for c, lab in (("rigid", "spanning cluster"), ("stressed", "stressed part"))
                for mass in ("nodes", "sites")
            },
        }
    )
    free = fits[(fits.n_min == n_min) & (fits.mass == "nodes")].set_index("cluster")
    paragraph = (
        "The rods-only thresholds here are combinatorial: one pass of the periodic pebble game "
        "per sample, rods added in the order of their site uniforms (Newman-Ziff), the "
        "threshold being the rod that closes the first unbalanced circuit (a stressed cluster "
        "that wraps the torus and resists a generic strain; docs/guide/rigid-clusters.md); on "
        "the cross-validation set they equal the certified bisection's thresholds. Just after "
        "that rod, the rigid cluster that holds it is the spanning rigid cluster, and its "
        "overconstrained rods are its stressed part; their masses at each sample's own "
        "threshold scale as n^d_f, fitted in log-log (errors resample each size's samples). "
        f"Spanning rigid cluster: d_f = {fmt(free.loc['rigid'].d, free.loc['rigid'].d_err)}; "
        f"stressed part: d_f = {fmt(free.loc['stressed'].d, free.loc['stressed'].d_err)} "
        "(masses in nodes, all sizes; in bond sites, a second reading of the same exponent, "
        "in tables/pc_fractal_dimensions.csv). A z above 2 with a chi-square well above its "
        "degrees of freedom points at corrections to scaling at the smallest sizes rather "
        "than at the exponent: the rows without the smallest sizes say how far the fits move. The "
        "literature values with their provenance are in paper/claims.py (REFERENCES); the "
        "values and errors the brief quoted for Javerzat & Notarmuzi (2025) and the fractal "
        "dimensions of Jacobs & Thorpe were not verified against the papers (their errors are "
        "then counted as 0)."
    )
    return Section("Rigid clusters at the threshold", (paragraph,), (table, masses))


def delta_section(r) -> Section:
    """The headline claims at each node disorder delta."""
    paragraphs = (
        f"The paper does not state its node disorder delta; ours is {DEFAULT_DELTA}. The headline "
        f"claims at delta = {', '.join(f'{d:g}' for d in r.deltas)} (n = {r.n}, {r.samples} "
        "samples per point); z_paper against the paper's value.",
    )
    wide = r.by_delta.pivot_table(index="key", columns="delta", values="value")
    err = r.by_delta.pivot_table(index="key", columns="delta", values="err")
    z = r.by_delta.pivot_table(index="key", columns="delta", values="z_paper")
    table = pd.DataFrame({"claim": [CLAIMS[k].text for k in wide.index]})
    table["paper"] = [CLAIMS[k].paper for k in wide.index]
    for d in wide.columns:
        table[f"delta = {d:g}"] = [
            f"{fmt(v, e)} (z = {zz:.1f})" for v, e, zz in zip(wide[d], err[d], z[d], strict=True)
        ]
    return Section("Node disorder delta", paragraphs, (table,))


def sections_of(results: dict) -> list[Section]:
    """The report's sections after the comparison table, for the studies that ran."""
    out = []
    if "fig2" in results:
        out.append(tails_section(results["fig2"]))
    if "method" in results:
        out.append(method_section(results["method"]))
    if "fss" in results:
        out.append(fss_section(results["fss"]))
        if results["fss"].fractal is not None:
            out.append(clusters_section(results["fss"]))
    if "delta" in results:
        out.append(delta_section(results["delta"]))
    if "three_d" in results:
        out.append(three_d_section(results["three_d"]))
    return out


def _section_blocks(sec: Section) -> list[tuple]:
    return (
        [("h2", sec.title)]
        + [("p", p) for p in sec.paragraphs]
        + [("table", table) for table in sec.tables]
    )


def _replication_sentence(rows) -> str:
    """The verdicts that a replication at the same size contradicts, counted and named:
    agreements it turns into disagreements and disagreements it turns into agreements
    (empty when there is none)."""
    cases = (
        ("agree", "disagree", "agreements", ("holds", "hold"), "only at our precision or on our "
         "samples"),
        ("disagree", "agree", "disagreements", ("is", "are"), "not replicated"),
    )  # fmt: skip
    text = ""
    for ours, theirs, noun, verbs, what in cases:
        named = [r.claim for r in rows if r.verdict == ours and r.replication == theirs]
        if named:
            text += (
                f"{len(named)} of the {noun} ({'; '.join(named)}) "
                f"{verbs[len(named) > 1]} {what}: the same claim at the same size on the "
                f"finite-size study's samples {theirs}s (explanation column). "
            )
    return text


def _shared_sentence(rows, total: int) -> str:
    """How many rows restate another claim about the same system, with the paper's own z."""
    pairs = shared_measurements(rows)
    if not pairs:
        return ""
    text = {r.key: r.claim for r in rows}
    each = "; ".join(
        f"'{text[a]}' is '{text[b]}'"
        + (
            f" (the paper's two values differ by z = {z:.1f} with the errors used below)"
            if np.isfinite(z)
            else ""
        )
        for a, b, z in pairs
    )
    return (
        f"{len(pairs)} of the {total} rows measure a system identical to another row's by an "
        f"exact symmetry (rods only under compression and dilation; e -> -e swapping cables and "
        f"struts), so our value is one number compared with two of the paper's: {each}. The "
        f"independent comparisons are {total - len(pairs)}. "
    )


#: the report's title
TITLE = "Tensegrity rigidity: reproduction report"

#: the start of the finite-size extrapolations' labels, said once in the evidence section
_EXTRAPOLATED = re.compile(
    r"extrapolated to n -> infinity from n = [0-9, ]+(?:\(rods-only p_c: n = [0-9, ]+\) )?"
)


def _said_once(frames: list[pd.DataFrame]) -> tuple[list[pd.DataFrame], str]:
    """The evidence tables with the repeated "extrapolated to n -> infinity from n = ..."
    shortened to "n -> inf", and the sentence that says it once ("" when absent)."""
    found: list[str] = []
    out = []
    for df in frames:
        df = df.copy()
        for col in ("changed", "system"):
            for s in df[col]:
                found += [m.group(0).strip() for m in _EXTRAPOLATED.finditer(str(s))]
            df[col] = [_EXTRAPOLATED.sub("n -> inf ", str(s)).strip() for s in df[col]]
        out.append(df)
    said = sorted(set(found))
    if not said:
        return out, ""
    return out, (
        "Finite size: 'n -> inf' is "
        + " or ".join(said)
        + ", with y(n) = y_inf + a n^(-1/nu), nu fitted or fixed at the literature's value."
    )


def _exclusions(results: dict) -> tuple[str, pd.DataFrame]:
    """What the undecided samples did to the analyses: a sentence and a table per sweep."""
    undecided = excluded_samples(results)
    bracketed = bracketed_rows(results)
    table = pd.DataFrame(
        [
            {"sweep": k, "excluded": v, "still in the energies": bracketed.get(k, 0)}
            for k, v in undecided.items()
            if v
        ],
        columns=["sweep", "excluded", "still in the energies"],
    )
    text = (
        f"{sum(undecided.values())} samples are excluded because a configuration's verdict lay "
        "below double-precision resolution (no certificate to tolerance)."
    )
    if any(bracketed.values()):
        text += (
            f" {sum(bracketed.values())} of them still enter the mean energies and the alpha "
            "fits from p_crit at P = 1/2 (not P, Gamma, the taut cables or the paper's "
            "first-positive estimator), their E* being bracketed without a verdict: at E = 0 "
            f"where their relaxed energy is at most {ENERGY_BRACKETED:g} of the affine energy, "
            "else at their certified energy."
        )
    straddling = straddling_of(results)
    recorded = {k: v for k, v in straddling.items() if v is not None}
    if straddling and not recorded:
        text += (
            " The threshold rows do not record the interval of each threshold, so samples with "
            "an undecided configuration on their bisection path are excluded."
        )
    elif recorded:
        text += (
            " Threshold samples kept at their estimate whose interval straddles a grid value "
            "(P there uncertain by one sample each): "
            + ", ".join(f"{k}: {v}" for k, v in recorded.items())
            + "."
        )
    return text, table


def report_blocks(
    results: dict, figures: dict, scale_name: str, timings: dict[str, float], extra: dict
) -> list[tuple]:
    """The report as blocks (:mod:`~tensegrity_rigidity.paper.render`), top down: the summary
    table, the evidence for each disagreement, how claims are compared, what was excluded, the
    studies' sections, the figures."""
    rows = compare(results)
    n_agree = sum(r.verdict == "agree" for r in rows)
    n_dis = sum(r.verdict == "disagree" for r in rows)
    n_inc = sum(r.verdict == "inconclusive" for r in rows)
    shared = len(shared_measurements(rows))
    intro = (
        "Reproduction of *Rigidity of generic random tensegrity structures* at scale "
        f"**{scale_name}**. Every verdict is certified (an admissible self-stress or a "
        "zero-energy displacement), so a difference from the paper is statistical, finite-size "
        "or definitional, not solver noise. "
    )
    if rows:
        intro += (
            f"{n_agree} claims agree, {n_dis} do not"
            + (f", {n_inc} are inconclusive at this precision" if n_inc else "")
            + f" ({len(rows) - shared} independent comparisons of {len(rows)})."
        )
    elif set(results) == {"three_d"}:
        intro += (
            "This scale runs the 3D study beyond the paper only: the paper's questions asked "
            "of the FCC lattice, beside the 2D values, in its section below."
        )
    else:
        intro += (
            "This scale runs none of the paper's figure studies: its claims are compared in the "
            "finite-size and node-disorder tables below (z_paper), claim by claim in the report "
            "of --scale quick or paper."
        )
    blocks: list[tuple] = [("p", intro)]
    if rows:
        blocks += [("h2", "Comparison with the paper"), ("table", summary_frame(rows))]
        said = _replication_sentence(rows) + _shared_sentence(rows, len(rows))
        if said:
            blocks.append(("p", said.replace("(explanation column)", "(evidence below)")))
        with_evidence = [
            r
            for r in rows
            if r.evidence
            and (r.verdict == "disagree" or (r.verdict == "agree" and r.replication == "disagree"))
        ]
        if with_evidence:
            frames, once = _said_once([evidence_frame(r) for r in with_evidence])
            blocks += [
                ("h2", "Evidence for each disagreement"),
                (
                    "p",
                    "For each disagreement, and each agreement that other samples of the same "
                    "size contradict: our value, then the same claim replicated at the same size "
                    "or measured with one factor changed (finite size, node disorder delta, the "
                    "paper's method, the estimator), and how each reads against the paper. " + once,
                ),
            ]
            for r, frame in zip(with_evidence, frames, strict=True):
                blocks += [("h3", r.claim), ("table", frame)]
        itself = paper_against_itself(results)
        if len(itself):
            blocks += [
                ("h2", "The paper against itself"),
                (
                    "p",
                    "The paper states the efficacy of cables twice. Under P = F(p_r + lambda "
                    "p_t) its own p_crit tables give lambda = (p_crit(0) - p_crit(0.3)) / 0.3: "
                    "0.50 under compression and 0.63 under dilation, against its headline "
                    "S_t/S_r of 0.372 and about 0.67. Ours from the same p_crit estimator and "
                    "from the collapse fit, beside both.",
                ),
                ("table", itself),
            ]
        blocks += [("h2", "How claims are compared"), ("p", RULE)]
    text, table = _exclusions(results)
    blocks += [("h2", "Samples excluded"), ("p", text)]
    if len(table):
        blocks.append(("table", table))
    kinds = extra.get("undecided_by_kind")
    if kinds is not None and len(kinds):
        blocks += [("p", UNDECIDED_KINDS), ("table", kinds)]
    blocks += [
        ("h2", "Conventions"),
        (
            "p",
            f"Conventions (docs/model.md): node disorder delta = {DEFAULT_DELTA}; f_c is the "
            "cable fraction (rods + cables is f_c = 1; the supplement's tables say 0.0); "
            "energies are totals at gamma = 1, so the intercept beta depends on system size and "
            "is not compared; p_crit is the median per-sample threshold (P = 1/2) while the "
            "paper takes the first p_r with positive mean energy; the single-node class labels "
            "follow the table, not the prose. Study wall times of this invocation (samples "
            "stored by an earlier one are reused, not timed): "
            + ", ".join(f"{k} {v:.0f} s" for k, v in timings.items())
            + ".",
        ),
    ]
    for sec in sections_of(results):
        blocks += _section_blocks(sec)
    if figures:
        blocks.append(("h2", "Figures"))
        for fid, paths in figures.items():
            blocks += [
                ("h3", f"Figure {fid}"),
                ("figure", fid, paths[0], FIGURE_CAPTIONS.get(fid, "")),
            ]
    blocks += [
        ("h2", "Tables"),
        ("ul", [f"`tables/{n}.csv`" for n in ["comparison", *extra]]),
    ]
    return blocks


def write_report(
    out: Path,
    results: dict,
    figures: dict,
    scale_name: str,
    timings: dict[str, float],
) -> dict[str, Path]:
    """Write report.md, report.html and the CSV tables; returns their paths.

    ``results`` maps study names to the studies' frozen results; the samples each study
    excluded travel inside them.
    """
    out = Path(out)
    tables = out / "tables"
    tables.mkdir(parents=True, exist_ok=True)
    comparison_frame(compare(results)).to_csv(tables / "comparison.csv", index=False)
    extra = tables_of(results)
    if (out / "studies").is_dir():
        extra["undecided_by_kind"] = undecided_by_kind(out / "studies")
    for name, df in extra.items():
        df.to_csv(tables / f"{name}.csv", index=False)
    blocks = report_blocks(results, figures, scale_name, timings, extra)
    (out / "report.md").write_text(to_markdown(TITLE, blocks))
    (out / "report.html").write_text(to_html(TITLE, blocks))
    return {
        "md": out / "report.md",
        "html": out / "report.html",
        "comparison": tables / "comparison.csv",
    }
