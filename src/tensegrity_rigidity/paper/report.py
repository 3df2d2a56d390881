"""The reproduction report: our numbers beside the paper's, figures, tables.

The report renders; it computes nothing. The studies (:mod:`~tensegrity_rigidity.paper.studies`)
compute every statistic, :mod:`~tensegrity_rigidity.paper.comparison` pairs them with the
paper's claims (:mod:`~tensegrity_rigidity.paper.claims`) into typed rows.

:func:`write_report` writes ``report.md``, a self-contained ``report.html`` (figures embedded as
base64 PNG; no external reference of any kind) and the tables as CSV.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd

from ..analysis.single_node import class_weights, qbar_table
from ..model.lattice import DEFAULT_DELTA
from .claims import CLAIMS
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
from .render import Section, to_html, to_markdown
from .report_3d import three_d_section
from .report_fss import clusters_section, delta_section, fss_section
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
