"""The report's sections on finite size, the rigid clusters and node disorder; renders only.

The studies (:mod:`~tensegrity_rigidity.paper.studies.fss`,
:mod:`~tensegrity_rigidity.paper.studies.delta`) compute every number; this module words them.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..model.lattice import DEFAULT_DELTA
from .claims import CLAIMS, REFERENCES
from .comparison import fmt
from .render import Section
from .studies.fss import NU_CHECK, PC_CHECK, nu_dependent


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
