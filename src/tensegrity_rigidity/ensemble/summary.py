"""Short tables of a sweep's rows: P with Wilson intervals (grid mode; packing mode: P of the
collectively jammed), thresholds (threshold mode).

What ``tensegrity-rigidity sweep`` prints at the end and ``tensegrity-rigidity info`` shows.
Undecided samples (a verdict below double-precision resolution) are counted, never guessed:
P and its interval use the decided samples only.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..analysis.estimators import wilson
from ..model.strain import NAMED_STRAINS

GRID_COLUMNS = ["n", "delta", "p_r", "p_t", "f_c", "phi", "fraction", "seed"]


def probability_table(rows: pd.DataFrame) -> pd.DataFrame:
    """One line per grid point.

    Parameters
    ----------
    rows : pandas.DataFrame
        Sweep rows (:func:`~tensegrity_rigidity.ensemble.sweep.load_results`).

    Returns
    -------
    pandas.DataFrame
        The grid columns, then ``N`` (decided samples) and ``undecided``; in grid mode ``rigid``,
        ``P``, ``lo``, ``hi`` (95% Wilson interval); in threshold mode ``median_p_r`` (median
        threshold, a never-rigid sample counting as above every p_r) and ``never_rigid``; in
        packing mode ``rigid`` counts the collectively jammed packings (P is theirs) and
        ``strict`` the strictly jammed ones.
    """
    if rows.empty:
        return pd.DataFrame()
    threshold = "threshold_p_r" in rows
    by = [c for c in GRID_COLUMNS if c in rows and not (threshold and c == "p_r")]
    decided = rows["decided"].astype(bool)
    out = []
    for key, sub in rows.groupby(by, sort=True, dropna=False):
        ok = decided.loc[sub.index]
        line = dict(zip(by, key if isinstance(key, tuple) else (key,), strict=True))
        line |= {"N": int(ok.sum()), "undecided": int((~ok).sum())}
        good = sub[ok]
        if threshold:
            t = good["threshold_p_r"].to_numpy(dtype=float)
            line["median_p_r"] = (
                float(np.median(np.where(np.isnan(t), np.inf, t))) if t.size else math.nan
            )
            line["never_rigid"] = int(np.isnan(t).sum())
        else:
            packing = "collective" in good
            jammed = good["collective"] == "jammed" if packing else good["rigid"]
            k = int(jammed.astype(bool).sum())
            p, lo, hi = wilson(k, len(good))
            line |= {"rigid": k, "P": float(p), "lo": float(lo), "hi": float(hi)}
            if packing:  # strictly jammed; a strict test left undecided counts as not strict
                line["strict"] = int((good["strict"] == "jammed").sum())
        out.append(line)
    return pd.DataFrame(out)


def phi_name(phi: float) -> str:
    """A strain type for people.

    Parameters
    ----------
    phi : float
        Strain type.

    Returns
    -------
    str
        "dilation", "shear", "compression", or the angle to 12 significant digits (fewer
        merged grid points: 0.70001 and 0.70004 both read "0.7").
    """
    for name, value in NAMED_STRAINS.items():
        if math.isclose(phi, value, abs_tol=1e-12):
            return name
    return f"{phi:.12g}"


def format_table(table: pd.DataFrame, max_rows: int = 40) -> str:
    """A :func:`probability_table` as plain text; grid columns that do not vary are left out.

    Parameters
    ----------
    table : pandas.DataFrame
        From :func:`probability_table`.
    max_rows : int
        Grid points shown; a last line counts the others.

    Returns
    -------
    str
        Right-aligned columns: the varying grid values, ``N``, ``undecided``, then
        ``rigid`` and ``P [95% Wilson]`` (grid mode), ``jammed``, ``strict`` and ``P [95%
        Wilson]`` (packing mode) or ``median p_r*`` and ``never rigid`` (threshold mode); "(no
        rows)" for an empty table.
    """
    if table.empty:
        return "(no rows)"
    grid = [c for c in GRID_COLUMNS if c in table and table[c].nunique(dropna=False) > 1]
    cells = []
    for _, r in table.head(max_rows).iterrows():
        row = [phi_name(r[c]) if c == "phi" else f"{r[c]:g}" for c in grid]
        row += [str(int(r["N"])), str(int(r["undecided"]))]
        if "P" in table:
            row.append(str(int(r["rigid"])))
            if "strict" in table:
                row.append(str(int(r["strict"])))
            row.append("-" if r["N"] == 0 else f"{r['P']:.3f} [{r['lo']:.3f}, {r['hi']:.3f}]")
        else:
            m = r["median_p_r"]
            row.append("-" if not np.isfinite(m) else f"{m:.4f}")
            row.append(str(int(r["never_rigid"])))
        cells.append(row)
    head = grid + ["N", "undecided"]
    if "strict" in table:  # packing mode: P of the collectively jammed
        head += ["jammed", "strict", "P [95% Wilson]"]
    else:
        head += ["rigid", "P [95% Wilson]"] if "P" in table else ["median p_r*", "never rigid"]
    widths = [max([len(h)] + [len(c[i]) for c in cells]) for i, h in enumerate(head)]
    lines = ["  ".join(h.rjust(w) for h, w in zip(head, widths, strict=True))]
    lines += ["  ".join(c.rjust(w) for c, w in zip(row, widths, strict=True)) for row in cells]
    if len(table) > max_rows:
        lines.append(f"... {len(table) - max_rows} more grid points (load_results for all)")
    return "\n".join(lines)
