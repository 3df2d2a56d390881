"""The report's section on the 3D study beyond the paper (the FCC lattice); renders only.

The study (:mod:`~tensegrity_rigidity.paper.studies.three_d`) computes every number; this
module words them beside their 2D counterparts: ours extrapolated from the finite-size study
(:data:`~tensegrity_rigidity.paper.claims.TWO_D_OURS`, the committed ``reports/fss`` tables)
and the paper's (:data:`~tensegrity_rigidity.paper.claims.CLAIMS`).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..analysis import estimators as an
from ..model.lattice import DEFAULT_DELTA
from .claims import REFERENCES, TWO_D_OURS
from .comparison import fmt
from .render import Section
from .studies.fss import misfit
from .studies.three_d import (
    FIG1C_PT,
    KEYS_3D,
    PC_3D_CHECK,
    PC_3D_MAXWELL,
    beside_2d,
)

#: how the 3D section names each quantity (the 2D claims' texts name the paper's values)
QUANTITY_TEXT = {
    "rods_only_pc": "rods only: P = 1/2 point p_c",
    "st_sr_half_dilation": "S_t/S_r at f_c = 0.5, dilation",
    "st_sr_half_shear": "S_t/S_r at f_c = 0.5, shear",
    "st_sr_half_compression": "S_t/S_r at f_c = 0.5, compression",
    "st_sr_cables_compression": "rods + cables, compression: S_t/S_r",
    "st_sr_cables_dilation": "rods + cables, dilation: S_t/S_r",
}
#: the scales' floor (paper.studies.scales): at least 24 samples wherever an error bar is
#: compared, so that the bootstrap's own error of the error bar, 1 / sqrt(2 (S - 1)), stays below
#: 15 %; a size with fewer is flagged
ERROR_FLOOR_SAMPLES = 24
#: |z| below which two values are called consistent (two standard errors of the difference)
CONSISTENT_Z = 2.0


def _z_text(z: float) -> str:
    if not np.isfinite(z):
        return "no error to compare with"
    word = "consistent with" if z < CONSISTENT_Z else "different from"
    return f"{word} it (z = {z:.2f})"


def _two_d_text(key: str) -> str:
    two = TWO_D_OURS[key]
    return fmt(two.value, two.error)


def three_d_tables(r) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The section's tables: each quantity per size, and each beside its 2D values."""
    wide = pd.DataFrame({"quantity": [QUANTITY_TEXT[k] for k in KEYS_3D]})
    sizes = sorted(set(r.by_size.n))
    for n in sizes:
        col = []
        for key in KEYS_3D:
            s = r.by_size[(r.by_size.key == key) & (r.by_size.n == n)]
            col.append(
                f"{fmt(s.value.iloc[0], s.err.iloc[0])} ({int(s.samples.iloc[0])})"
                if len(s)
                else ""
            )
        wide[f"n = {n}"] = col
    b = beside_2d(r)
    side = pd.DataFrame(
        {
            "quantity": [QUANTITY_TEXT[k] for k in b.key],
            "3D, largest n": [
                f"{fmt(v, e)} (n = {n})"
                for v, e, n in zip(b.largest, b.largest_err, b.n_max, strict=True)
            ],
            "3D, n -> inf (nu fitted)": [
                fmt(v, e) for v, e in zip(b.y_inf, b.y_inf_err, strict=True)
            ],
            "3D, n -> inf (1/nu = 3)": [
                fmt(v, e) for v, e in zip(b.y_inf_first_order, b.y_inf_first_order_err, strict=True)
            ],
            "2D ours, n -> inf (reports/fss)": [_two_d_text(k) for k in b.key],
            "2D paper": list(b.paper_2d),
            "z: 3D largest n vs 2D ours": [f"{z:.2f}" for z in b.z_2d],
            "z: 3D n -> inf vs 2D ours": [f"{z:.2f}" for z in b.z_2d_inf],
        }
    )
    return wide, side


def three_d_section(r):
    """The 3D study's section: what was run, the rods-only threshold against the literature,
    the efficacies against 2D, and the tables."""
    ex = r.extrapolated.set_index("key")
    counts = ", ".join(f"{s} at n = {n}" for n, s in zip(r.sizes, r.samples, strict=True))
    pc_counts = ", ".join(f"{s} at n = {n}" for n, s in zip(r.pc_sizes, r.pc_samples, strict=True))
    pc = ex.loc["rods_only_pc"]
    n_max = max(r.pc_sizes)
    v_max, e_max = r.at("rods_only_pc", n_max)
    nu_text = f"nu = {pc.nu:.2f} ± {pc.nu_err:.2f}" if np.isfinite(pc.nu) else "nu not determined"
    at_bound = np.isfinite(pc.nu) and bool(np.any(np.isclose(1 / pc.nu, an.THETA, rtol=1e-6)))
    if at_bound:
        nu_text += ", at a bound of the fitted range"
    paragraphs = [
        "Not in the paper, which studies 2D lattices only. The same questions on the periodic "
        f"FCC lattice (12 neighbours, node disorder delta = {DEFAULT_DELTA}, principal strain "
        "axes rotated per sample by a low-discrepancy sequence on SO(3)), every verdict "
        "certified as in 2D. Exact per-sample thresholds along p_r: rods only under dilation "
        "and shear (rods only under compression is the dilation system, sample by sample), "
        f"and at p_t = {FIG1C_PT:g} f_c = 0.5 under dilation, shear and compression and rods + "
        "cables (f_c = 1) under compression and dilation; S_t/S_r from the collapse fit "
        "P = F(p_r + lambda p_t) over p_t = 0 and 0.3, as Fig. 1C in 2D. Samples per point: "
        f"{counts}; rods-only thresholds: {pc_counts}. Each quantity is extrapolated with "
        "y(n) = y_inf + a n^(-1/nu) in two readings: nu fitted to the rods-only points (used "
        "for every quantity, as in 2D) and 1/nu = 3 = d, the inverse-volume shift of a "
        "first-order transition, which is what the literature reports for this lattice. "
        f"Sizes are small (n = {max(r.sizes)} is {max(r.sizes) ** 3} nodes, as 2D n = "
        f"{round(max(r.sizes) ** 1.5)}), so the extrapolations rest on a short range in n: "
        "read the trend from the per-size table, not the extrapolation alone.",
        f"Rods-only threshold: {fmt(v_max, e_max)} at n = {n_max}; extrapolated "
        f"{fmt(pc.y_inf, pc.y_inf_err)} ({nu_text}) or "
        f"{fmt(pc.y_inf_first_order, pc.y_inf_first_order_err)} with 1/nu = 3"
        + (
            f", and {fmt(r.widths.p_c, r.widths.p_c_err)} from the centres against the widths "
            f"of the threshold distributions (no exponent; widths fall as n^(-1/nu) with nu = "
            f"{r.widths.nu:.2f} ± {r.widths.nu_err:.2f})"
            if r.widths is not None and np.isfinite(r.widths.p_c)
            else ""
        )
        + misfit(pc.chi2_first_order, pc.dof_first_order)
        + f". The literature's {PC_3D_CHECK.value:g} (Chubynsky & Thorpe 2007; quoted, not "
        "read in their text, so its precision is not known here): the first-order "
        f"extrapolation lies {PC_3D_CHECK.value - pc.y_inf_first_order:+.4f} from it, "
        + _z_text(
            an.agreement_z(
                pc.y_inf_first_order, pc.y_inf_first_order_err**2, PC_3D_CHECK.value, 0.0
            )
        )
        + " with the quoted value taken as exact"  # fmt: skip
        + f"; Maxwell's count gives {PC_3D_MAXWELL.value:g}. In 2D the threshold lies below "
        f"Maxwell's 2/3 (ours {_two_d_text('rods_only_pc')}, "
        f"Jacobs & Thorpe {REFERENCES['pc_jacobs_thorpe'].value:g}). The rods-only threshold "
        f"is the same under shear as under dilation for {100 * r.strain_free:.1f} % of the "
        "samples (a rods-only threshold depends on the strain only through finite-size "
        "coincidences).",
    ]
    few = [n for n, s in zip(r.sizes, r.samples, strict=True) if s < ERROR_FLOOR_SAMPLES]
    if few:
        paragraphs.append(
            f"Caution: n = {', '.join(map(str, few))} has fewer than {ERROR_FLOOR_SAMPLES} "
            "samples per point, so its bootstrap errors are themselves uncertain by 1 / "
            "sqrt(2 (S - 1)) or more and can come out implausibly small; a z that rests on "
            "such a size is marked below, and the extrapolations weigh it by that error."
        )
    for keys, what in (
        (("st_sr_half_dilation", "st_sr_half_shear", "st_sr_half_compression"),
         "With cables and struts in equal numbers (f_c = 0.5)"),
        (("st_sr_cables_compression", "st_sr_cables_dilation"),
         "Rods + cables (the paper's 37 % under compression and 67 % under dilation, in 3D)"),
    ):  # fmt: skip
        n_top = max(r.sizes)
        parts, z_top, z_inf, misfits = [], [], [], ""
        for key in keys:
            f = ex.loc[key]
            v, e = r.at(key, n_top)
            two = TWO_D_OURS[key]
            label = QUANTITY_TEXT[key].split(", ")[-1].split(":")[0]
            parts.append(f"{label} {fmt(f.y_inf, f.y_inf_err)}")
            z_top.append(an.agreement_z(v, e**2, two.value, two.error or np.nan))
            z_inf.append(an.agreement_z(f.y_inf, f.y_inf_err**2, two.value, two.error or np.nan))
            misfits += misfit(f.chi2, f.dof)
        mark = " (few samples)" if n_top in few else ""
        text = (
            f"{what}, extrapolated: " + ", ".join(parts) + f"{misfits}. Against ours in 2D "
            f"the largest z is {np.nanmax(z_inf):.2f} for the extrapolations and "
            f"{np.nanmax(z_top):.2f} at n = {n_top}{mark} (table below)."
        )
        if keys[0] == "st_sr_half_dilation" and np.isfinite(r.half_strain_free):
            text += (
                f" At f_c = 0.5 the threshold at p_t = {FIG1C_PT:g} is the same under the "
                f"three strains for {100 * r.half_strain_free:.1f} % of the samples: the "
                "three values are not independent measurements."
            )
        paragraphs.append(text)
    lam = r.by_size[r.by_size.key != "rods_only_pc"]
    dz = np.abs(lam.value - lam.contour) / np.hypot(lam.err, lam.contour_err)
    if len(lam) and np.isfinite(dz).any():
        paragraphs.append(
            "The model-free estimator, the slope of the P = 1/2 contour between p_t = 0 and 0.3, "
            f"gives S_t/S_r within {np.nanmax(dz):.1f} combined standard errors of the collapse "
            "fit at every size and quantity (largest difference "
            f"{np.nanmax(np.abs(lam.value - lam.contour)):.3f}; tables/three_d_by_size.csv, "
            "columns contour)."
        )
    wide, side = three_d_tables(r)
    paragraphs.append(
        "Tables: each quantity per size (value ± bootstrap error, samples in brackets), then "
        "each beside 2D (ours from reports/fss, extrapolated with nu fitted; the paper's as "
        "printed; z of the largest 3D size and of the extrapolation with nu fitted against "
        "ours in 2D)."
    )
    return Section("Beyond the paper: three dimensions (FCC)", tuple(paragraphs), (wide, side))
