"""Sweep rows as the studies read them: undecided samples, threshold intervals, grids.

Undecided samples: a grid sample whose verdict lies below double-precision resolution is dropped
and counted. A threshold sample whose bisection met such a configuration is dropped and counted
too, unless the rows carry the threshold's interval (``threshold_p_r_low``,
``threshold_p_r_high``): then it is kept at its estimate, and the samples whose interval
straddles a grid value are counted as a stated uncertainty of P.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

from ...ensemble.spec import Spec, parse_spec
from ...ensemble.sweep import load_results, run_sweep
from ...model.lattice import DEFAULT_DELTA
from ...model.strain import NAMED_STRAINS
from ...solver.core import energy_certified

PHI5 = [0.0, math.pi / 4, math.pi / 2, 3 * math.pi / 4, math.pi]
FC5 = [0.0, 0.25, 0.5, 0.75, 1.0]
PT4 = [0.0, 0.1, 0.2, 0.3]
#: p_t of the one-sided thresholds of the collapse fits of S_t/S_r (Fig. 1C, the finite-size and
#: 3D studies), beside p_t = 0: the thresholds at p_t = 0.1 and 0.2 add nothing measurable on
#: common random numbers (the fit's error over p_t = {0, 0.3} was 0.0067 and 0.0071 at n = 16
#: and 32 against 0.0068 and 0.0066 over p_t = {0, 0.1, 0.2, 0.3}, with the same S_t/S_r) for
#: half the threshold searches
COLLAPSE_PT = 0.3
#: the names of the strains in :data:`~tensegrity_rigidity.model.strain.NAMED_STRAINS`, by phi
STRAIN_NAMES = {phi: name for name, phi in NAMED_STRAINS.items()}

#: what :func:`load_sweeps` returns: sweep name -> (rows to analyse, samples excluded)
Rows = dict[str, tuple[pd.DataFrame, int]]

#: threshold-interval columns of threshold rows (absent in rows written before they existed)
INTERVAL = ("threshold_p_r_low", "threshold_p_r_high")


def strain_name(phi: float) -> str:
    """ "dilation", "shear" or "compression" for the named strains, else phi to 3 decimals."""
    for value, name in STRAIN_NAMES.items():
        if math.isclose(phi, value, abs_tol=1e-12):
            return name
    return f"{phi:.3f}"


#: An undecided grid configuration still enters the energy analyses (the mean energies and
#: the alpha fits from p_crit at P = 1/2) when its E* is known without its verdict: its relaxed
#: energy ``energy`` (of an actual displacement, an upper bound on E*) and the certified lower
#: bound ``energy_lower`` bracket E*. Two cases: ``energy`` at most this fraction of the affine
#: energy, where E* is zero to that precision and the row enters at E = 0 (at its ``energy``,
#: 1e-15 against a mean of 0 would put a grid point of floppy samples into the log-log fit);
#: and an energy certified to ``ENERGY_GAP`` (:func:`energy_certified`), where it enters at
#: ``energy`` as a decided row does. Its verdict, nonaffinity and taut cables stay unknown, so
#: P, Gamma, the taut fraction, the tails at p_crit and the paper's first-positive estimator
#: leave it out. Near a sample's own threshold such rows are the ones at the transition: at
#: n = 64, p_t = 0.3, dilation, p_r = 0.5 (a finite-size run) 5 of 24 samples are
#: undecided with energies of 8e-18 to 5e-13 (affine energy 5.2e3), and dropping them raised
#: that point's mean energy from 282 to 356.
ENERGY_BRACKETED = 1e-9


def energy_bracketed(df: pd.DataFrame) -> tuple[np.ndarray, np.ndarray]:
    """Undecided grid rows whose E* is bracketed (:data:`ENERGY_BRACKETED`).

    Returns
    -------
    near_zero, certified : (rows,) bool
        Undecided rows whose relaxed energy is at most :data:`ENERGY_BRACKETED` of the affine
        energy (they enter the energy analyses at E = 0), and the others whose relaxed energy
        is certified (they enter at it).
    """
    none = np.zeros(len(df), dtype=bool)
    if df.empty or not {"decided", "energy", "affine_energy"} <= set(df.columns):
        return none, none
    undecided = ~df["decided"].to_numpy(bool)
    energy, affine = df["energy"].to_numpy(float), df["affine_energy"].to_numpy(float)
    with np.errstate(invalid="ignore"):
        near_zero = undecided & (energy <= ENERGY_BRACKETED * affine)
    certified = none.copy()
    if "energy_lower" in df:
        lower = df["energy_lower"].to_numpy(float)
        with np.errstate(invalid="ignore"):
            certified = undecided & ~near_zero & energy_certified(energy, lower) & (energy > 0)
    return near_zero, certified


def keep_decided(df: pd.DataFrame, energy: bool = False) -> tuple[pd.DataFrame, int]:
    """Rows to analyse and the number of samples excluded as undecided.

    Grid rows: samples with ``decided == False`` are dropped and counted, except, with
    ``energy`` (rows for the energy analyses only), those whose E* is bracketed
    (:func:`energy_bracketed`): they are kept (still undecided; those near zero with
    ``energy`` set to 0) and still counted. Threshold rows with the interval columns
    (:data:`INTERVAL`): an undecided sample is kept when its interval is finite, at the row's
    estimate ``threshold_p_r`` (the interval's midpoint if the estimate is missing); without
    them every undecided sample is dropped.
    """
    if df.empty or "decided" not in df:
        return df.reset_index(drop=True), 0
    bad = ~df["decided"].astype(bool)
    count = int(bad.sum())
    if energy and "threshold_p_r" not in df:
        near_zero, certified = energy_bracketed(df)
        if near_zero.any():
            df = df.copy()
            df.loc[near_zero, "energy"] = 0.0
        return df[~(bad & ~(near_zero | certified))].reset_index(drop=True), count
    if "threshold_p_r" in df and all(c in df for c in INTERVAL):
        lo, hi = df[INTERVAL[0]].to_numpy(float), df[INTERVAL[1]].to_numpy(float)
        usable = bad.to_numpy() & np.isfinite(lo) & np.isfinite(hi)
        if usable.any():
            df = df.copy()
            est = df["threshold_p_r"].to_numpy(float, copy=True)
            fill = usable & ~np.isfinite(est)
            est[fill] = 0.5 * (lo[fill] + hi[fill])
            df["threshold_p_r"] = est
            bad = bad & ~usable
    return df[~bad].reset_index(drop=True), int(bad.sum())


def interval_straddles(df: pd.DataFrame, grid) -> int | None:
    """Samples whose threshold interval (when recorded) contains a value of ``grid``.

    Such a sample's outcome at that grid value is not determined by double precision; the
    count bounds the change of P there (count / samples). None when the rows do not record
    the interval (written before the columns existed).
    """
    if not all(c in df for c in INTERVAL):
        return None
    if df.empty:
        return 0
    lo = df[INTERVAL[0]].to_numpy(float)[:, None]
    hi = df[INTERVAL[1]].to_numpy(float)[:, None]
    g = np.asarray(grid, float)[None, :]
    with np.errstate(invalid="ignore"):
        hit = (lo < g) & (g <= hi)
    return int(hit.any(axis=1).sum())


def study_spec(spec: dict) -> Spec:
    """A study's sweep spec parsed: a lattice sweep with the default node disorder unless it
    names one, a packing sweep (``[packing]``, no lattice) as it is."""
    return parse_spec(spec if "packing" in spec else dict(delta=DEFAULT_DELTA) | spec)


#: ``workers`` value that reads stored rows only: nothing is computed or written (the caller has
#: checked that every row is stored, as :func:`~tensegrity_rigidity.paper.reproduce.read_evidence`)
STORED = "stored"


def sweep_rows(
    out: Path, name: str, spec: dict, workers, scheduler, progress, energy: bool = False
):
    """Run (or resume) one sweep; return its rows to analyse and the count excluded
    (:func:`keep_decided`; ``energy``: rows for the energy analyses, which keep undecided
    rows whose energy is bracketed near zero).

    With ``workers=STORED`` the rows of ``spec`` are read from ``out`` without running
    anything.
    """
    path = out / "studies" / name
    parsed = study_spec(spec)
    if workers == STORED:
        return keep_decided(load_results(path, parsed), energy)
    run_sweep(parsed, path, executor=workers, scheduler=scheduler, progress=progress)
    return keep_decided(load_results(path), energy)


def p_r_grid(step: float, lo: float = 0.2, hi: float = 0.95) -> list[float]:
    return [round(x, 6) for x in np.arange(lo, hi + 1e-9, step)]


def threshold_matrix(rows: pd.DataFrame, p_t: list[float]) -> np.ndarray:
    """(S, J) thresholds of the samples present at every p_t (NaN: never rigid).

    Rows of one strain and f_c from a threshold sweep along p_r; samples are matched by index.
    """
    groups = [rows[np.isclose(rows.p_t, pt)].set_index("sample").threshold_p_r for pt in p_t]
    common = sorted(set.intersection(*(set(g.index) for g in groups))) if groups else []
    return np.column_stack([g.reindex(common).to_numpy(float) for g in groups])


def per_sample(rows: pd.DataFrame, column: str, samples=None) -> tuple[np.ndarray, np.ndarray]:
    """(S, G) values of ``column`` by sample (rows) and p_r (columns) of one curve, and p_r (G,).

    ``samples`` (S,) fixes the rows (NaN for a sample missing from ``rows``), so that curves of
    the same samples line up row by row.
    """
    table = rows.pivot_table(index="sample", columns="p_r", values=column, dropna=False)
    if samples is not None:
        table = table.reindex(samples)
    return table.to_numpy(float), table.columns.to_numpy(float)


def load_sweeps(out: Path, sweeps: dict[str, dict], energy: tuple[str, ...] = (), **kw) -> Rows:
    """Run (or resume, or read with ``workers=STORED``) every sweep of a study.

    Parameters
    ----------
    out : path
        The reproduction's output directory (sweeps under ``out/studies/<name>``).
    sweeps : dict
        Sweep name -> spec, as a figure module's ``sweeps(scale)`` returns.
    energy : tuple of str
        Sweeps whose rows feed the energy analyses (:func:`keep_decided` with ``energy``).
    **kw
        ``workers``, ``scheduler``, ``progress`` of :func:`sweep_rows`.

    Returns
    -------
    Rows
        Sweep name -> (rows to analyse, samples excluded as undecided), in the order of
        ``sweeps``.
    """
    return {
        name: sweep_rows(out, name, spec, energy=name in energy, **kw)
        for name, spec in sweeps.items()
    }


#: columns of :func:`undecided_by_kind`
UNDECIDED_COLUMNS = ["sweep", "counted", "undecided", "within", "not_resolved"]


def undecided_by_kind(studies: Path) -> pd.DataFrame:
    """Undecided verdicts of every sweep under ``studies``, by kind.

    Grid sweeps count undecided rows, threshold sweeps undecided probes on the bisection
    paths; each is either within resolution of the boundary or not resolved by the search
    (:func:`~tensegrity_rigidity.solver.certificates.undecided_reason`). Rows stored before
    the kinds were recorded count as undecided only, so the last two columns may add up to
    less.

    Parameters
    ----------
    studies : path
        ``out/studies`` of a reproduction (one sweep directory each).

    Returns
    -------
    pandas.DataFrame
        :data:`UNDECIDED_COLUMNS`, one row per sweep with an undecided verdict.
    """
    out = []
    for path in sorted(p for p in Path(studies).glob("*") if p.is_dir()):
        rows = load_results(path)
        if rows.empty:
            continue
        if "threshold_undecided" in rows:
            counted, undecided = "probes", int(rows.threshold_undecided.sum())
            # rows stored before the kinds were recorded have no count: neither kind
            recorded = rows.get("threshold_not_resolved", pd.Series(np.nan, index=rows.index))
            known = recorded.notna()
            not_resolved = int(recorded[known].sum())
            within = int(rows.threshold_undecided[known].sum()) - not_resolved
        else:
            counted, undecided = "rows", int((~rows.decided.astype(bool)).sum())
            reason = rows.get("undecided_reason", pd.Series("", index=rows.index))
            within = int((reason == "within resolution").sum())
            not_resolved = int((reason == "not resolved").sum())
        if undecided:
            out.append([path.name, counted, undecided, within, not_resolved])
    return pd.DataFrame(out, columns=UNDECIDED_COLUMNS)


def threshold_bounds(rows: pd.DataFrame, p_t: list[float]) -> tuple[np.ndarray, ...]:
    """(S, J) thresholds, their lower and upper ends of the samples present at every p_t.

    As :func:`threshold_matrix`, with the interval (:data:`INTERVAL`) beside each threshold:
    equal to it where the threshold is exact, the events between a certified floppy and a
    certified rigid configuration where undecided probes left it open; rows written before
    the interval was recorded read as exact. The input of
    :func:`~tensegrity_rigidity.analysis.fits.fit_collapse_thresholds`.
    """
    t = threshold_matrix(rows, p_t)
    if not all(c in rows for c in INTERVAL):
        return t, t.copy(), t.copy()
    ends = [threshold_matrix(rows.assign(threshold_p_r=rows[c]), p_t) for c in INTERVAL]
    return t, ends[0], ends[1]
