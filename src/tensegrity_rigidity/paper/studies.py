"""The paper's studies as sweep specs plus their analysis.

Each study is a set of sweep specs (run by :func:`tensegrity_rigidity.ensemble.sweep.run_sweep` into
``DIR/studies/<name>``, so an interrupted reproduction resumes) and a function that turns the
rows into a frozen result (:class:`Fig1bResult`, ...) holding the numbers the figures and the
comparison need. Sizes and sample counts come from a :class:`Scale`. Every result carries the
number of samples it excluded (``excluded``: sweep name -> count), so nothing is shared through
module state.

Estimators (documented in :mod:`~tensegrity_rigidity.analysis.estimators`):

* S_t/S_r (Fig. 1C): binomial-likelihood fit of P = F(p_r + lam p_t) to per-sample thresholds
  along p_r at p_t in {0, 0.1, 0.2, 0.3}; bootstrap errors over samples. The strain average
  pools the samples of five strains phi in {0, pi/4, pi/2, 3pi/4, pi}.
* S_r, S_t, dP/df_c (Fig. 4): a binomial-likelihood surface smooth in f_c, fitted to the
  outcomes at (p_r, p_t) = (0.3, 0.6) and at steps matched in x = p_r + p_t/2 (h_r = 0.025,
  h_t = 0.05) for f_c = 0, 1/8, ..., 1, on common random numbers; the strain average over phi
  in {0, pi/4, pi/2, 3pi/4, pi}; S_c = S_t + (1 - f_c) dP/df_c / p_t and
  S_s = S_t - f_c dP/df_c / p_t (from S_t = f_c S_c + (1 - f_c) S_s and
  dP/df_c = p_t (S_c - S_s)). Errors: bootstrap over samples.
* p_crit (Fig. 2): the median per-sample threshold (P = 1/2), bootstrap error.

Undecided samples: a grid sample whose verdict lies below double-precision resolution is dropped
and counted. A threshold sample whose bisection met such a configuration is dropped and counted
too, unless the rows carry the threshold's interval (``threshold_p_r_low``,
``threshold_p_r_high``): then it is kept at its estimate, and the samples whose interval
straddles a grid value are counted as a stated uncertainty of P.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ..analysis import estimators as an
from ..analysis.single_node import simulate_single_node, single_node_probability
from ..ensemble.runner import sample_geometry
from ..ensemble.spec import parse_spec
from ..ensemble.sweep import load_results, run_sweep
from ..model.elements import place_elements
from ..model.lattice import DEFAULT_DELTA
from ..model.network import Instance
from ..model.strain import NAMED_STRAINS, strain_tensor
from ..solver.core import SolveResult, energy_certified, solve
from .claims import Measurement

PHI5 = [0.0, math.pi / 4, math.pi / 2, 3 * math.pi / 4, math.pi]
FC5 = [0.0, 0.25, 0.5, 0.75, 1.0]
PT4 = [0.0, 0.1, 0.2, 0.3]
#: the names of the strains in :data:`~tensegrity_rigidity.model.strain.NAMED_STRAINS`, by phi
STRAIN_NAMES = {phi: name for name, phi in NAMED_STRAINS.items()}


#: most samples per point of the finite-size study's energy grids by default (its threshold
#: sweeps have up to 400): the paper scale's count at n = 32 (:meth:`Scale.fss_energy_samples`)
ENERGY_SAMPLES = 24


@dataclass(frozen=True)
class Scale:
    """System sizes and sample counts of a reproduction, and which studies it runs.

    ``studies`` lists the studies (keys of :data:`tensegrity_rigidity.paper.registry.STUDIES`)
    that ``reproduce`` runs at this scale. The work each study does at a scale, its run time
    and the error bar each headline claim can expect are computed by
    :mod:`tensegrity_rigidity.paper.budget` (``tensegrity-rigidity reproduce --scale NAME
    --estimate``); the comments at :data:`SCALES` say where the counts of the large scales come
    from.
    """

    name: str
    n_threshold: int  # lattice size of threshold studies (Figs. 1, 2 p_crit)
    n_grid: int  # lattice size of grid studies (Figs. 2, 4)
    samples_threshold: int  # Fig. 1C at f_c = 0, 0.5, 1 and Fig. 2's thresholds
    samples_grid: int
    samples_fig4: int
    p_r_step: float
    node_trials: int
    bootstrap: int
    n_method: int = 5  # the paper's method beside ours (paper.method)
    samples_method: int = 4
    method_step: float = 0.1
    fss_sizes: tuple[int, ...] = (4, 5, 6, 8)  # finite-size study (paper.finite_size)
    samples_fss: int | tuple[int, ...] = 6  # one count, or one per size of fss_sizes
    # (n, samples) of the rods-only thresholds extrapolated to p_c: dedicated one-strain sweeps
    # (the rods-only threshold does not depend on the strain); () reads the headline sweeps
    fss_pc: tuple[tuple[int, int], ...] = ()
    deltas: tuple[float, ...] = (0.1, 0.2, 0.3)  # node-disorder study
    n_delta: int = 5
    samples_delta: int = 6
    studies: tuple[str, ...] = ("fig1b", "fig1c", "fig2", "fig3", "fig4")
    samples_curve: int | None = None  # Fig. 1C at f_c = 0.25, 0.75 (None: samples_threshold)
    samples_fig1b: int | None = None  # Fig. 1B (None: samples_threshold)
    # energy grids of the finite-size study per size: one count, or one per size of fss_sizes
    # (None: the first ENERGY_SAMPLES of the size's samples_fss at most)
    samples_energy: int | tuple[int, ...] | None = None
    budget_minutes: float | None = None  # the estimated wall time on 2 workers stays below

    def __post_init__(self):
        if isinstance(self.samples_fss, tuple) and len(self.samples_fss) != len(self.fss_sizes):
            raise ValueError(
                f"scale {self.name}: samples_fss has {len(self.samples_fss)} counts for "
                f"{len(self.fss_sizes)} sizes"
            )
        if isinstance(self.samples_energy, tuple) and len(self.samples_energy) != len(
            self.fss_sizes
        ):
            raise ValueError(
                f"scale {self.name}: samples_energy has {len(self.samples_energy)} counts for "
                f"{len(self.fss_sizes)} sizes"
            )

    @property
    def pc_sizes(self) -> tuple[int, ...]:
        """Sizes of the rods-only p_c extrapolation (``fss_pc``'s, else ``fss_sizes``)."""
        return tuple(n for n, _ in self.fss_pc) if self.fss_pc else tuple(self.fss_sizes)

    def pc_samples(self, n: int) -> int:
        """Samples of the rods-only threshold at size ``n`` of :attr:`pc_sizes`."""
        return dict(self.fss_pc)[n] if self.fss_pc else self.fss_samples(n)

    def fss_samples(self, n: int) -> int:
        """Samples per point of the finite-size study at size ``n``."""
        if isinstance(self.samples_fss, int):
            return self.samples_fss
        return self.samples_fss[self.fss_sizes.index(n)]

    def fss_energy_samples(self, n: int) -> int:
        """Samples per point of the finite-size study's energy grids at size ``n``
        (:attr:`samples_energy`; by default the first :data:`ENERGY_SAMPLES` of
        :meth:`fss_samples` at most)."""
        if self.samples_energy is None:
            return min(self.fss_samples(n), ENERGY_SAMPLES)
        if isinstance(self.samples_energy, int):
            return self.samples_energy
        return self.samples_energy[self.fss_sizes.index(n)]

    @property
    def delta_energy_samples(self) -> int:
        """Samples per point of the node-disorder study's energy grids: the first
        :data:`ENERGY_SAMPLES` of :attr:`samples_delta` at most."""
        return min(self.samples_delta, ENERGY_SAMPLES)

    @property
    def curve_samples(self) -> int:
        return self.samples_threshold if self.samples_curve is None else self.samples_curve

    @property
    def fig1b_samples(self) -> int:
        return self.samples_threshold if self.samples_fig1b is None else self.samples_fig1b


FIGURES = ("fig1b", "fig1c", "fig2", "fig3", "fig4")
#: Sample counts of the large scales, from target error bars (paper.budget states every constant):
#: a headline estimator's bootstrap error is sigma_1(n) / sqrt(S), sigma_1 measured (SIGMA_1).
#: Targets: S_t/S_r +-0.013 (the paper's), p_crit and p_c +-0.005, the fraction of taut cables
#: +-0.02, Fig. 4C +-0.1 (no printed error bar; a third of the 0.28 deviation seen at n = 12).
#: Floor: S >= 24 wherever an error bar is compared, so that the bootstrap's own error of the
#: error bar, 1 / sqrt(2 (S - 1)), stays below 15 %.
#:
#: paper (n = 32; 50 min on 2 workers, estimate 44 min; per-sample CPU costs in brackets):
#:   Fig. 1C headline f_c = 0, 0.5, 1 x 5 strains: the target needs (0.0401 / 0.013)^2 = 10
#:     samples; the floor gives 24: +-0.0082 per strain, +-0.0037 for the 5-strain average
#:     (24.7 s). The rest of the curve (f_c = 0.25, 0.75): 12 samples, +-0.0116 (15.6 s).
#:   Fig. 1B (collapse over p_t = 0 ... 0.8, 9 threshold searches): 10 needed, floor 24 (12.8 s).
#:   Fig. 2 thresholds: p_crit needs (0.0184 / 0.005)^2 = 14, floor 24: +-0.0038 (8.3 s);
#:     grid: the taut fraction needs (0.077 / 0.02)^2 = 15, floor 24: +-0.016 (24.2 s).
#:   Fig. 4 (225 grid points per sample at p_t ~ 0.6, 94 s): its middle cannot be measured at
#:     n = 32 with any count. Thresholds along p_r at p_t = 0.6 (n = 32, 6 samples, seed 41,
#:     dilation, shear, compression) lie in 0.330 ... 0.393 for every f_c in 0.25 ... 0.75:
#:     all 18 samples are floppy at (0.3, 0.6) and none changes between p_r = 0.275 and 0.325,
#:     so S_r = S_t = 0 there and (S_c + S_s)/S_r is 0/0. Only at f_c <= 0.125 and >= 0.875 do
#:     samples change in that window (2 to 5 of 6). Under dilation P(0.3, 0.6) is 0 up to
#:     f_c = 0.875 and 1 at f_c = 1 (all 6): Fig. 4A's signs need few samples. 8 samples; the
#:     ends of 4C then exceed the +-0.1 target (0.89 / sqrt 8 = 0.31 on the n = 12 calibration).
#:   Method (the paper's verdict beside ours) at the claims' own n = 32, p_r step 0.025 (128
#:     grid points, L-BFGS-B 1.04 s each: 151 s): 16 samples; the shifts' errors, scaled from
#:     n = 12 (0.096 and 0.024 per sample) by the S_t/S_r and p_crit calibrations (x 0.39 and
#:     x 0.58): +-0.009 on S_t/S_r, +-0.0035 on p_crit.
#:   Fig. 3: 10,000 trials per point, binomial error <= 0.5 / 100 = 0.005 (17 s in-process).
#:   Exceeding the paper's error bars: none of the S_t/S_r and p_crit claims; Fig. 4C (above).
#:   Energy exponents alpha and the nonaffinity peak are not set by S (least-squares errors over
#:   4-5 grid points; the p_r grid).
#:
#: fss (119 min on 2 workers by the estimate, 109 of them the threshold sweeps): per size 12.5
#:   threshold searches per sample (in units of one at p_t = 0.3: 3 rods-only, cheap, 9 at p_t =
#:   0.3, 4 at p_t = 0.1, 0.2 x 0.75), priced by the costs measured in the finite-size run of
#:   2026-11-26 (paper.budget): 1.0, 4.1, 36 and about 880 CPU s per sample at n = 8, 16, 32, 64.
#:   That run had the former counts (12 samples at n = 64, 200 at 16, 96 at 32, 32 per delta) and
#:   was stopped after 97 min with n = 64 two thirds done (about 150 min in all). The counts are now
#:   chosen from the error targets (S_t/S_r +-0.013, p_crit +-0.005; `budget.expected_errors`)
#:   within the budget: n = 64 takes 8 samples (S_t/S_r +-0.0106, p_crit +-0.0044), n = 32 64
#:   (+-0.0050), node disorder 24 per delta (S_t/S_r +-0.0082, p_c +-0.0038); n = 8: 400 (S_t/S_r
#:   +-0.0126), n = 16: 160 (+-0.0042), which cost little. The extrapolations rest most on the
#:   largest sizes; with 12 samples at n = 64 a synthetic extrapolation p_c(n) = p_c + a n^(-1/nu)
#:   (nu fitted) scattered by +-0.010 around the true p_c (60 draws): only n = 128 (fss-cluster, pc)
#:   narrows it. delta = 0.2 reads the first 24 samples of the fss sweeps at n = 32.
#:   The energy grids of alpha and the taut-cable fraction (2026-11-27,
#:   finite_size.energy_sweeps: 24 samples per point, no minimum-norm displacements) add 20
#:   CPU min, 10 min on 2 workers by the estimate (about 15 measured: the model errs short on
#:   them): 119 in all. n = 64 had 8 until 2026-11-29 (its threshold count), and bootstrap
#:   errors from 8 samples came out implausibly small (the taut-cable fraction's 0.003) and
#:   dominated the extrapolations; 16 more cost about 9 CPU min (the 8 took 4.5 in the run of
#:   2026-11-28; 6.5 min on 2 workers alone on 2026-11-29). The budget is 120 min, the limit;
#:   the measured pieces add to about 113 min (the threshold sweeps' estimate was 109 min,
#:   their clean run took 97, 2026-11-26).
#:
#: fss-cluster: fss plus n = 128 (8 samples: one threshold search there is extrapolated to
#:   30 min at p_t = 0.3; 62 CPU hours in all with the energy grids, 24 samples at every size)
#:   and 32 samples at n = 64 (S_t/S_r +-0.0053, p_crit +-0.0022); meant for a Dask cluster
#:   (--scheduler; --estimate --workers N gives the wall time). Its sweeps extend those of fss in
#:   the same output directory.
#: (n, samples) of the rods-only thresholds of the p_c extrapolation at the fss scales: the
#: median's error is about 1.25 x the spread of the thresholds / sqrt(S), spreads 0.037,
#: 0.019, 0.010 and about 0.006 at n = 8 to 64 (the fss run), 0.003 expected at 128; these
#: counts give 0.0007 to 0.0010 at n <= 64 (against 0.0012 to 0.0023 from the headline sweeps,
#: errors counted by sample) and 0.0011 at n = 128. Measured on 2026-11-25 (`--scale pc`,
#: reports/pc): spreads 0.037, 0.019, 0.010, 0.0057, 0.0030 and errors 0.0007 to 0.0008 with
#: 12 samples at n = 128, whose searches took 139 s each; with the refine stage of the verdict
#: search they take 53 s on average (median 12 s), and n = 128 has 64 samples (error 0.00045;
#: 57 min of CPU). n = 128 stays out of the fss scale, which stays within its budget without
#: it, and is in pc and fss-cluster.
FSS_PC = ((8, 4000), (16, 1200), (32, 400), (64, 100), (128, 64))
FSS_PC_NO_128 = FSS_PC[:-1]
SCALES = {
    "tiny": Scale(
        "tiny", 5, 5, 6, 4, 6, 0.1, 300, 10,
        fss_sizes=(4, 5, 6, 8), samples_fss=3, n_delta=5, samples_delta=3,
        fss_pc=((4, 6), (5, 6), (6, 6), (8, 4), (10, 3)),
        studies=(*FIGURES, "method", "fss", "delta"), budget_minutes=2,
    ),
    "quick": Scale(
        "quick", 12, 12, 48, 24, 96, 0.05, 4000, 100,
        n_method=12, samples_method=16, method_step=0.05,
        studies=(*FIGURES, "method"), budget_minutes=10,
    ),
    "paper": Scale(
        "paper", 32, 32, 24, 24, 8, 0.025, 10000, 200,
        n_method=32, samples_method=16, method_step=0.025,
        studies=(*FIGURES, "method"), samples_curve=12, budget_minutes=50,
    ),
    "fss": Scale(
        "fss", 32, 32, 0, 0, 0, 0.025, 0, 200,
        fss_sizes=(8, 16, 32, 64), samples_fss=(400, 160, 64, 8), samples_energy=24,
        fss_pc=FSS_PC_NO_128,
        deltas=(0.1, 0.2, 0.3), n_delta=32, samples_delta=24,
        studies=("fss", "delta"), budget_minutes=120,
    ),
    "pc": Scale(
        "pc", 32, 32, 0, 0, 0, 0.025, 0, 200,
        fss_sizes=(), samples_fss=(), fss_pc=FSS_PC,
        studies=("fss",), budget_minutes=40,
    ),
    "fss-cluster": Scale(
        "fss-cluster", 32, 32, 0, 0, 0, 0.025, 0, 200,
        fss_sizes=(8, 16, 32, 64, 128), samples_fss=(400, 200, 96, 32, 8), samples_energy=24,
        fss_pc=FSS_PC,
        deltas=(0.1, 0.2, 0.3), n_delta=32, samples_delta=32,
        studies=("fss", "delta"),
    ),
}  # fmt: skip

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
#: n = 64, p_t = 0.3, dilation, p_r = 0.5 (the fss run of 2026-11-29) 5 of 24 samples are
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
    parsed = parse_spec({"delta": DEFAULT_DELTA} | spec)
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


# --------------------------------------------------------------------------- Fig. 1


@dataclass(frozen=True, eq=False)
class Fig1bResult:
    """P(p_r, p_t) at f_c = 0.5 under shear.

    Attributes
    ----------
    p_r : (K,) float
        Grid of p_r.
    p_t : (J,) float
        Values of p_t (one threshold sweep each).
    P : (J, K) float
        Fraction of rigid samples; NaN where p_r + p_t > 1.
    half_x : (H,) float
        p_r + p_t/2 where P crosses 1/2, for each p_t whose P reaches 1/2 (linear
        interpolation on the grid).
    collapse : CollapseFit
        Fit of P = F(p_r + lam p_t) to every p_t: lam = S_t/S_r under shear at f_c = 0.5.
    rows : DataFrame
        The threshold rows analysed.
    excluded : dict
        Sweep name -> samples excluded as undecided.
    straddling : int or None
        Samples whose threshold interval straddles a grid value (see :func:`interval_straddles`;
        None when the rows do not record intervals). The other results' ``straddling`` alike.
    """

    p_r: np.ndarray
    p_t: np.ndarray
    P: np.ndarray
    half_x: np.ndarray
    collapse: an.CollapseFit
    n: int
    samples: int
    rows: pd.DataFrame
    excluded: dict[str, int]
    straddling: int | None = None
    measured: tuple[Measurement, ...] = ()


#: p_t of Fig. 1B's threshold sweeps
FIG1B_PT = [round(x, 3) for x in np.arange(0.0, 0.81, 0.1)]


def fig1b_sweeps(scale: Scale) -> dict[str, dict]:
    """Sweep name -> spec of Fig. 1B (the work :mod:`~tensegrity_rigidity.paper.budget` counts)."""
    return {
        "fig1b": {
            "n": scale.n_threshold,
            "p_t": FIG1B_PT,
            "f_c": 0.5,
            "phi": "shear",
            "samples": scale.fig1b_samples,
            "seed": 11,
            "threshold": {"path": "p_r"},
        }
    }


def study_fig1b(out, scale: Scale, **kw) -> Fig1bResult:
    """P(p_r, p_t) at f_c = 0.5 under shear, from per-sample thresholds along p_r."""
    p_t = FIG1B_PT
    df, excluded = sweep_rows(out, "fig1b", fig1b_sweeps(scale)["fig1b"], **kw)
    p_r = np.linspace(0, 1, 101)
    P = np.full((len(p_t), p_r.size), np.nan)
    for i, pt in enumerate(p_t):
        t = df[np.isclose(df.p_t, pt)].threshold_p_r.to_numpy()
        ok = p_r + pt <= 1 + 1e-12
        P[i, ok] = an.probability_from_thresholds(t, p_r[ok])
    halves = []
    for i, pt in enumerate(p_t):
        ok = np.isfinite(P[i])
        if ok.sum() > 2 and P[i, ok].max() >= 0.5:
            halves.append(float(np.interp(0.5, P[i, ok], p_r[ok])) + pt / 2)
    y, pr, pt = an.outcomes_from_thresholds(df, np.arange(0.0, 1.0001, 0.01))
    collapse = an.fit_collapse(y, pr, pt, n_boot=scale.bootstrap)
    system = f"n = {scale.n_threshold}, {collapse.n_samples} samples x {len(p_t)} p_t"
    half = np.array(halves)
    note = (
        f"collapse fit over p_t = 0 ... 0.8; p_r + p_t/2 at P = 1/2: mean {half.mean():.3f}, "
        f"spread {half.std():.3f} over {half.size} values of p_t"
        if half.size
        else "collapse fit over p_t = 0 ... 0.8"
    )
    measured = (
        Measurement.scalar(
            "collapse_shear_half",
            collapse.lam,
            collapse.lam_err,
            system,
            note=note,
            size=scale.n_threshold,
        ),
    )
    return Fig1bResult(
        p_r=p_r,
        p_t=np.array(p_t),
        P=P,
        half_x=half,
        collapse=collapse,
        n=scale.n_threshold,
        samples=scale.fig1b_samples,
        rows=df,
        excluded={"fig1b": excluded},
        straddling=interval_straddles(df, p_r),
        measured=measured,
    )


@dataclass(frozen=True, eq=False)
class Fig1cResult:
    """S_t/S_r versus f_c for each strain and the strain average.

    Attributes
    ----------
    fits : DataFrame
        One row per (f_c, strain): the fields of
        :class:`~tensegrity_rigidity.analysis.estimators.CollapseFit` plus ``f_c``, ``strain``,
        ``phi`` (NaN for the average).
    rods_only_pc, rods_only_pc_err : float
        Median threshold of the rods-only samples (p_t = 0, every strain) and its bootstrap error.
    rods_only_samples : int
        Number of rods-only thresholds.
    contour : DataFrame
        Per (f_c, strain): ``lam``, ``lam_err`` from the slope of the P = 1/2 contour
        (:func:`~tensegrity_rigidity.analysis.estimators.contour_slope`), the model-free
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


def fig1c_sweeps(scale: Scale) -> dict[str, dict]:
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


def study_fig1c(out, scale: Scale, **kw) -> Fig1cResult:
    """S_t/S_r versus f_c for each strain and the strain average (collapse fits)."""
    parts, excluded = {}, {}
    for name, spec in fig1c_sweeps(scale).items():
        parts[name], excluded[name] = sweep_rows(out, name, spec, **kw)
    rods = parts["fig1c_rods"]
    mixed = pd.concat([parts["fig1c_mixed"], parts["fig1c_curve"]], ignore_index=True)
    # every f_c pairs the rods-only thresholds with its own samples at p_t = FIG1C_PT
    df = pd.concat([rods.assign(f_c=f_c) for f_c in FC5] + [mixed], ignore_index=True)
    p_t = [0.0, FIG1C_PT]
    grid = np.arange(0.3, 0.9001, 0.01)
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
                fit = an.fit_collapse(y, pr, pt, n_boot=scale.bootstrap)
                fits.append({"f_c": f_c, "strain": strain_name(phi), "phi": phi, **fit.__dict__})
                c = an.contour_slope(t, np.array(p_t), n_boot=scale.bootstrap)
                contour.append(
                    {"f_c": f_c, "strain": strain_name(phi), "lam": c.value, "lam_err": c.err}
                )
        # the strain average: a sample under every strain is one unit of the bootstrap
        groups = np.concatenate(units)
        fit = an.fit_collapse(np.vstack(pooled), pr, pt, n_boot=scale.bootstrap, groups=groups)
        fits.append({"f_c": f_c, "strain": "average", "phi": np.nan, **fit.__dict__})
        c = an.contour_slope(
            np.vstack(pooled_t), np.array(p_t), n_boot=scale.bootstrap, groups=groups
        )
        contour.append({"f_c": f_c, "strain": "average", "lam": c.value, "lam_err": c.err})
    rods_only = rods.drop_duplicates(["phi", "sample"])
    pc, pc_err = an.critical_point(
        rods_only.threshold_p_r.to_numpy(), groups=rods_only["sample"].to_numpy()
    )
    fits, contour = pd.DataFrame(fits), pd.DataFrame(contour)
    system = f"n = {scale.n_threshold}, {scale.samples_threshold} samples x 2 p_t"
    measured = []
    for key, f_c, strain in [
        *((f"st_sr_half_{s_}", 0.5, s_) for s_ in ("dilation", "shear", "compression", "average")),
        ("st_sr_cables_compression", 1.0, "compression"),
        ("st_sr_struts_dilation", 0.0, "dilation"),
        ("st_sr_cables_dilation", 1.0, "dilation"),
    ]:
        row = fits[np.isclose(fits.f_c, f_c) & (fits.strain == strain)].iloc[0]
        note = (
            "identical to rods + cables under compression by an exact symmetry: compression is "
            "minus dilation, and e -> -e swaps cables and struts sample by sample"
            if key == "st_sr_struts_dilation"
            else f"collapse fit P = F(p_r + lam p_t) over p_t = 0 and {FIG1C_PT}"
        )
        measured.append(
            Measurement.scalar(key, row.lam, row.lam_err, system, note=note, size=scale.n_threshold)
        )
        row = contour[np.isclose(contour.f_c, f_c) & (contour.strain == strain)].iloc[0]
        measured.append(
            Measurement.scalar(
                key,
                row.lam,
                row.lam_err,
                system,
                factor="estimator",
                label="slope of the P = 1/2 contour instead of the logistic collapse fit",
                size=scale.n_threshold,
            )
        )
    measured.append(
        Measurement.scalar(
            "rods_only_pc",
            pc,
            pc_err,
            f"n = {scale.n_threshold}, {rods_only['sample'].nunique()} samples x "
            f"{rods_only.phi.nunique()} strains",
            note="finite-size threshold (median of per-sample thresholds, every strain; a "
            "sample's strains are one unit of the bootstrap)",
            size=scale.n_threshold,
        )
    )
    return Fig1cResult(
        fits=fits,
        contour=contour,
        rods_only_pc=pc,
        rods_only_pc_err=pc_err,
        rods_only_samples=len(rods_only),
        n=scale.n_threshold,
        samples=scale.samples_threshold,
        rows=df,
        excluded=excluded,
        straddling=interval_straddles(pd.concat([rods, mixed], ignore_index=True), grid),
        measured=tuple(measured),
    )


# --------------------------------------------------------------------------- Fig. 2


@dataclass(frozen=True, eq=False)
class DisplacementField:
    """Samples drawn in Figs. 1A and 2A, rebuilt from sweep samples and solved.

    Attributes
    ----------
    instance, result : Instance, SolveResult
        A rods + cables sample under compression just above its own threshold (Fig. 2A), or
        None when no sample of the field sweep qualified.
    p_r, p_t : float
        Where that sample was solved.
    mixed_instance, mixed_result : Instance, SolveResult
        A rigid sample of rods, cables and struts under shear (Fig. 1A), or None.
    """

    instance: Instance | None
    result: SolveResult | None
    p_r: float
    p_t: float
    mixed_instance: Instance | None
    mixed_result: SolveResult | None


@dataclass(frozen=True, eq=False)
class Fig2Result:
    """Rods + cables (f_c = 1): energies, nonaffinity, engaged cables versus p_r.

    Attributes
    ----------
    curves : DataFrame
        Per (phi, p_t, p_r): energy and nonaffinity: mean with standard error, median and
        quartiles (``*_median``, ``*_q25``, ``*_q75``; both are heavy-tailed near the
        transition), the number of samples with a nonaffinity (``gamma_n``), P, N; and the
        median nonaffinity over all N samples bracketed (``gamma_median_low``,
        ``gamma_median_high``: :func:`~tensegrity_rigidity.analysis.estimators.median_bracket`
        with the rows' certified lower bounds ``nonaffinity_lower``), with the number of
        samples known only from such a bound (``gamma_bounded``).
    taut : DataFrame
        Per (phi, p_t, p_r): fraction of cables under tension in rigid samples (mean, sem, size).
    fits : DataFrame
        Per (phi, p_t): the power-law fit of the mean energy above p_crit
        (:class:`~tensegrity_rigidity.analysis.estimators.PowerLawFit` fields of
        :func:`energy_exponent`: ``alpha_err`` from a bootstrap over samples that re-estimates
        p_crit, ``alpha_ls_err`` the least-squares error that does not) and ``p_crit_err``.
    crit : DataFrame
        Per (phi, p_t): ``p_crit`` (median threshold) and ``gamma_peak_p_r`` (grid p_r of the
        largest mean nonaffinity).
    paper_estimators : DataFrame
        Per (phi, p_t): the paper's estimators on our grid rows: ``p_crit`` where the mean
        energy first becomes positive and ``alpha`` fitted from it (with errors).
    peaks : dict
        Under compression, per p_t: where the mean and the median Gamma peak, with their joint
        covariance (see ``_gamma_peaks``).
    at_pcrit : DataFrame
        Per-sample Gamma and energy at the grid p_r nearest p_crit under compression, per p_t.
    tails : DataFrame
        :func:`tail_statistics` of ``at_pcrit``.
    worst_tail : dict or None
        Its Gamma row with the largest ``top_share`` (:func:`worst_tail`).
    min_norm_failed : int or None
        Grid samples whose displacements are not the verified minimum-norm minimiser (their
        Gamma is NaN); None when the rows do not record it.
    tensions_uncertified : int or None
        Rigid grid samples whose relaxed energy is not certified, so that their tensions need
        not be t* (their taut fractions are NaN, :func:`mask_uncertified_tensions`); None when
        the rows do not record the energy's lower bound.
    taut_at_transition : tuple
        (mean, error, [(p_t, p_r), ...]): the fraction of taut cables in rigid samples at the grid
        p_r nearest p_crit under compression, averaged over p_t = 0.1, 0.2, 0.3; None when no
        such sample exists.
    field : DisplacementField
    """

    curves: pd.DataFrame
    taut: pd.DataFrame
    fits: pd.DataFrame
    crit: pd.DataFrame
    paper_estimators: pd.DataFrame
    peaks: dict
    at_pcrit: pd.DataFrame
    tails: pd.DataFrame
    worst_tail: dict | None
    min_norm_failed: int | None
    tensions_uncertified: int | None
    taut_at_transition: tuple | None
    n: int
    samples: int
    rows: pd.DataFrame
    field: DisplacementField
    excluded: dict[str, int]
    straddling: int | None = None
    measured: tuple[Measurement, ...] = ()
    # sweep name -> undecided rows excluded from P, Gamma and the taut cables but kept in the
    # energy analyses (:func:`energy_bracketed`; counted in ``excluded`` too; the curves'
    # ``energy_n`` counts them, ``N`` does not)
    bracketed: dict[str, int] = dataclasses.field(default_factory=dict)


def fig2_sweeps(scale: Scale) -> dict[str, dict]:
    """Sweep name -> spec of Fig. 2: a grid per p_t, the thresholds on the same samples
    (seed 21) and the two small sweeps that supply the drawn samples of Figs. 2A and 1A."""
    p_r = p_r_grid(scale.p_r_step, 0.3, 0.95)
    base = {"n": scale.n_grid, "f_c": 1.0, "phi": ["compression", "dilation"], "seed": 21}
    out = {
        f"fig2_pt{p_t:.1f}": base
        | {
            "p_r": [p for p in p_r if p + p_t <= 1 + 1e-12],
            "p_t": p_t,
            "samples": scale.samples_grid,
        }
        for p_t in PT4
    }
    out["fig2_thresholds"] = base | {
        "p_t": PT4,
        "samples": scale.samples_threshold,
        "threshold": {"path": "p_r"},
    }
    field = {"n": max(scale.n_grid, 8), "samples": FIELD_SAMPLES, "f_c": 1.0, "seed": 1000}
    out["fig2_field"] = field | {
        "p_t": FIELD_P_T,
        "phi": "compression",
        "threshold": {"path": "p_r"},
    }
    out["fig1a_field"] = field | {
        "p_r": 0.55,
        "p_t": 0.4,
        "f_c": 0.5,
        "phi": "shear",
        "seed": 2000,
    }
    return out


def study_fig2(out, scale: Scale, **kw) -> Fig2Result:
    """Rods + cables (f_c = 1): nonaffinity, energies and engaged cables versus p_r."""
    sweeps = fig2_sweeps(scale)
    p_r = p_r_grid(scale.p_r_step, 0.3, 0.95)
    grids, excluded, bracketed = [], {}, {}
    for p_t in PT4:
        name = f"fig2_pt{p_t:.1f}"
        rows, excluded[name] = sweep_rows(out, name, sweeps[name], energy=True, **kw)
        bracketed[name] = int((~rows.decided.astype(bool)).sum())
        grids.append(rows)
    # the energy analyses read every row kept, the others only the decided ones
    energy_rows = pd.concat(grids, ignore_index=True)
    rows = energy_rows[energy_rows.decided.astype(bool)].reset_index(drop=True)
    rows, min_norm_failed = mask_min_norm(rows)
    rows, tensions_uncertified = mask_uncertified_tensions(rows)
    th, excluded["fig2_thresholds"] = sweep_rows(
        out, "fig2_thresholds", sweeps["fig2_thresholds"], **kw
    )
    energies = (
        energy_rows.groupby(["phi", "p_t", "p_r"])
        .agg(
            energy=("energy", "mean"),
            energy_sem=("energy", "sem"),
            energy_median=("energy", "median"),
            energy_q25=("energy", _q25),
            energy_q75=("energy", _q75),
            energy_n=("energy", "size"),
        )
        .reset_index()
    )
    curves = (
        rows.groupby(["phi", "p_t", "p_r"])
        .agg(
            gamma=("nonaffinity", "mean"),
            gamma_sem=("nonaffinity", "sem"),
            gamma_median=("nonaffinity", "median"),
            gamma_q25=("nonaffinity", _q25),
            gamma_q75=("nonaffinity", _q75),
            gamma_n=("nonaffinity", "count"),
            P=("rigid", "mean"),
            N=("rigid", "size"),
        )
        .reset_index()
    )
    curves = energies.merge(curves, on=["phi", "p_t", "p_r"], how="left")
    curves = curves.merge(gamma_median_brackets(rows), on=["phi", "p_t", "p_r"], how="left")
    taut = (
        rows[rows.rigid]
        .groupby(["phi", "p_t", "p_r"])
        .frac_cables_taut.agg(["mean", "sem", "size"])
        .reset_index()
    )
    fits, crit, paper_est = [], [], []
    for (phi, p_t), sub in curves.groupby(["phi", "p_t"]):
        one = np.isclose(th.phi, phi) & np.isclose(th.p_t, p_t)
        grid = energy_rows[np.isclose(energy_rows.phi, phi) & np.isclose(energy_rows.p_t, p_t)]
        pc, pc_err = an.critical_point(th[one].threshold_p_r.to_numpy())
        fit = energy_exponent(grid, th[one], scale.bootstrap)
        fits.append(
            {
                "phi": phi,
                "strain": strain_name(phi),
                "p_t": p_t,
                "p_crit_err": pc_err,
                **fit.__dict__,
            }
        )
        g = sub.set_index("p_r").gamma
        crit.append({"phi": phi, "p_t": p_t, "p_crit": pc, "gamma_peak_p_r": float(g.idxmax())})
        # the paper's estimators on the decided grid rows: p_crit where the mean energy first
        # becomes positive, and the power law fitted from that p_crit (an undecided row's
        # bracketed energy could make a mean positive that is not)
        decided = rows[np.isclose(rows.phi, phi) & np.isclose(rows.p_t, p_t)]
        e, x = per_sample(decided, "energy")
        first = an.first_positive(e, x, n_boot=scale.bootstrap)
        pfit = an.fit_energy_exponent(
            x, e, lambda idx, e=e, x=x: an.first_positive(e[idx], x, n_boot=0).value,
            n_boot=scale.bootstrap,
        )  # fmt: skip
        paper_est.append(
            {
                "phi": phi,
                "strain": strain_name(phi),
                "p_t": p_t,
                "p_crit": first.value,
                "p_crit_err": first.err,
                "alpha": pfit.alpha,
                "alpha_err": pfit.alpha_err,
                "n_points": pfit.n_points,
            }
        )
    crit, fits, paper_est = pd.DataFrame(crit), pd.DataFrame(fits), pd.DataFrame(paper_est)
    peaks = _gamma_peaks(rows, crit, scale.bootstrap)
    at_pcrit = _at_transition(rows, crit)
    tails = tail_statistics(at_pcrit)
    taut_tr = taut_with_error(rows, th, scale.bootstrap)
    field_, excluded["fig2_field"], excluded["fig1a_field"] = _displacement_field(out, scale, **kw)
    return Fig2Result(
        curves=curves,
        taut=taut,
        fits=fits,
        crit=crit,
        paper_estimators=paper_est,
        peaks=peaks,
        at_pcrit=at_pcrit,
        tails=tails,
        worst_tail=worst_tail(tails),
        min_norm_failed=min_norm_failed,
        tensions_uncertified=tensions_uncertified,
        taut_at_transition=taut_tr,
        n=scale.n_grid,
        samples=scale.samples_grid,
        rows=rows,
        field=field_,
        excluded=excluded,
        bracketed=bracketed,
        straddling=interval_straddles(th, p_r),
        measured=_fig2_measurements(scale, fits, paper_est, peaks, taut_tr),
    )


def gamma_median_brackets(rows: pd.DataFrame) -> pd.DataFrame:
    """Per (phi, p_t, p_r): the median nonaffinity over every sample, bracketed.

    Samples without a certified nonaffinity (NaN after :func:`mask_min_norm`) enter at their
    certified lower bound ``nonaffinity_lower`` (at 0 where the row has none) for
    ``gamma_median_low`` and at ``+inf`` for ``gamma_median_high``
    (:func:`~tensegrity_rigidity.analysis.estimators.median_bracket`); ``gamma_bounded``
    counts those known from a bound. Rows written before the bound existed have none.
    """
    lower = rows["nonaffinity_lower"] if "nonaffinity_lower" in rows else np.nan
    rows = rows.assign(_lower=lower)
    out = []
    for (phi, p_t, p_r), g in rows.groupby(["phi", "p_t", "p_r"]):
        gamma, low = g.nonaffinity.to_numpy(), g._lower.to_numpy(dtype=float)
        lo, hi = an.median_bracket(gamma, low)
        bounded = int(np.sum(np.isnan(gamma) & np.isfinite(low)))
        out.append((phi, p_t, p_r, lo, hi, bounded))
    columns = ["phi", "p_t", "p_r", "gamma_median_low", "gamma_median_high", "gamma_bounded"]
    return pd.DataFrame(out, columns=columns)


def _q25(x: pd.Series) -> float:
    return float(x.quantile(0.25))


def _q75(x: pd.Series) -> float:
    return float(x.quantile(0.75))


def mask_min_norm(rows: pd.DataFrame) -> tuple[pd.DataFrame, int | None]:
    """Nonaffinity NaN where the displacements are not the verified minimum-norm minimiser.

    Rows with ``min_norm_ok == False`` carry whatever minimiser the solver stopped at, whose
    Gamma can be off by orders of magnitude (issue 14): their ``nonaffinity`` becomes NaN and
    they are counted. Returns (rows, count); the count is None when the rows have no
    ``min_norm_ok`` column (written before it existed), and missing values in it count as ok.
    """
    if "min_norm_ok" not in rows:
        return rows, None
    bad = rows["min_norm_ok"].eq(False).to_numpy()
    if bad.any():
        rows = rows.copy()
        rows.loc[bad, "nonaffinity"] = np.nan
    return rows, int(bad.sum())


def mask_uncertified_tensions(rows: pd.DataFrame) -> tuple[pd.DataFrame, int | None]:
    """Taut fractions NaN where the relaxed tensions are not certified to be t*.

    A rigid row's ``frac_cables_taut`` and ``frac_struts_taut`` count the elements its relaxed
    tensions engage. Where the relaxation has not converged (not
    :func:`~tensegrity_rigidity.solver.core.energy_certified`: near a sample's own threshold)
    those tensions need not be
    t*, and engage more elements: at the paper scale's grid p_r nearest p_crit (p_t = 0.1,
    compression, 2026-11-26) two such samples had 0.43 and 0.50 where the four certified ones
    averaged 0.31. Their fractions become NaN and they are counted. Returns (rows, count); the
    count is None when the rows have no ``energy_lower`` column.
    """
    if "energy_lower" not in rows:
        return rows, None
    certified = energy_certified(
        rows["energy"].to_numpy(dtype=float), rows["energy_lower"].to_numpy(dtype=float)
    )
    bad = rows["rigid"].to_numpy(dtype=bool) & ~certified
    if bad.any():
        rows = rows.copy()
        rows.loc[bad, ["frac_cables_taut", "frac_struts_taut"]] = np.nan
    return rows, int(bad.sum())


def _at_transition(rows: pd.DataFrame, crit: pd.DataFrame) -> pd.DataFrame:
    """Per-sample Gamma and energy at the grid p_r nearest p_crit (compression), per p_t."""
    parts = []
    for _, c in crit[np.isclose(crit.phi, math.pi)].sort_values("p_t").iterrows():
        sub = rows[np.isclose(rows.phi, math.pi) & np.isclose(rows.p_t, c.p_t)]
        grid = np.unique(sub.p_r)
        if not grid.size or not np.isfinite(c.p_crit):
            continue
        p_r = grid[int(np.argmin(np.abs(grid - c.p_crit)))]
        at = sub[np.isclose(sub.p_r, p_r)]
        parts.append(at[["p_t", "p_r", "sample", "nonaffinity", "energy", "rigid"]])
    cols = ["p_t", "p_r", "sample", "nonaffinity", "energy", "rigid"]
    return pd.concat(parts, ignore_index=True) if parts else pd.DataFrame(columns=cols)


def tail_statistics(at_pcrit: pd.DataFrame) -> pd.DataFrame:
    """What a mean over samples at the transition is sensitive to, per p_t and observable.

    For Gamma and the energy at p_crit: the number of samples, mean, median, quartiles,
    largest value, the share of the sum carried by the largest sample (``top_share``) and the
    mean with that sample left out (``mean_without_top``).
    """
    out = []
    for p_t, sub in at_pcrit.groupby("p_t"):
        for name, col in (("Gamma", "nonaffinity"), ("energy", "energy")):
            v = sub[col].to_numpy(float)
            v = v[np.isfinite(v)]
            if not v.size:
                continue
            total = v.sum()
            out.append(
                {
                    "p_t": p_t,
                    "p_r": float(sub.p_r.iloc[0]),
                    "observable": name,
                    "N": v.size,
                    "mean": v.mean(),
                    "median": float(np.median(v)),
                    "q25": float(np.quantile(v, 0.25)),
                    "q75": float(np.quantile(v, 0.75)),
                    "max": v.max(),
                    "top_share": v.max() / total if total > 0 else np.nan,
                    "mean_without_top": np.sort(v)[:-1].mean() if v.size > 1 else np.nan,
                }
            )
    return pd.DataFrame(out)


def worst_tail(tails: pd.DataFrame) -> dict | None:
    """The row of :func:`tail_statistics` (Gamma) whose largest sample carries most of the sum."""
    g = tails[tails.observable == "Gamma"] if len(tails) else tails
    g = g[np.isfinite(g.top_share)] if len(g) else g
    if not len(g):
        return None
    return g.loc[g.top_share.idxmax()].to_dict()


def _gamma_peaks(rows: pd.DataFrame, crit: pd.DataFrame, n_boot: int) -> dict:
    """Where the mean (and the median) nonaffinity peaks under compression, per p_t.

    Returns {"p_t": (J,), "p_crit": (J,), "p_crit_err": (J,), "mean": (peaks, cov),
    "median": (peaks, cov)}; the peaks' covariance comes from one bootstrap over samples shared
    by every p_t (common random numbers correlate the curves).
    """
    comp = crit[np.isclose(crit.phi, math.pi)].sort_values("p_t")
    samples = np.arange(1, int(rows["sample"].max()) + 1)
    vals, xs = [], []
    for p_t in comp.p_t:
        sub = rows[np.isclose(rows.phi, math.pi) & np.isclose(rows.p_t, p_t)]
        v, x = per_sample(sub, "nonaffinity", samples)
        vals.append(v)
        xs.append(x)
    out = {"p_t": comp.p_t.to_numpy(), "p_crit": comp.p_crit.to_numpy()}
    for stat in ("mean", "median"):
        out[stat] = an.peak_locations(vals, xs, stat, n_boot=n_boot)
    return out


def _fig2_measurements(scale, fits, paper_est, peaks, taut_tr) -> tuple[Measurement, ...]:
    system = f"n = {scale.n_grid}, {scale.samples_grid} samples per point"
    out = []
    for _, row in fits.iterrows():
        alt = paper_est[np.isclose(paper_est.phi, row.phi) & np.isclose(paper_est.p_t, row.p_t)]
        alt = alt.iloc[0]
        key = f"p_crit_{row.strain}_{row.p_t}"
        out.append(
            Measurement.scalar(
                key,
                row.p_crit,
                row.p_crit_err,
                f"n = {scale.n_grid}, {scale.samples_threshold} thresholds",
                note="ours: median threshold (P = 1/2); paper: first positive mean energy",
                size=scale.n_grid,
            )
        )
        out.append(
            Measurement.scalar(
                key,
                alt.p_crit,
                alt.p_crit_err,
                system,
                factor="estimator",
                label="the paper's p_crit (first grid p_r with positive mean energy)",
                size=scale.n_grid,
            )
        )
        key = f"alpha_{row.strain}_{row.p_t}"
        out.append(
            Measurement.scalar(
                key,
                row.alpha,
                row.alpha_err,
                f"{system}; {row.n_points} fit points",
                note="least squares of ln(mean E) over ln(p_r - p_crit), p_crit = P = 1/2; "
                "error: bootstrap over samples, p_crit re-estimated in each replica",
                size=scale.n_grid,
            )
        )
        out.append(
            Measurement.scalar(
                key,
                alt.alpha,
                alt.alpha_err,
                f"{system}; {alt.n_points} fit points",
                factor="estimator",
                label="fitted from the paper's p_crit (first positive mean energy)",
                size=scale.n_grid,
            )
        )
    if taut_tr is not None:
        v, e, _ = taut_tr
        out.append(
            Measurement.scalar(
                "taut_cables_transition",
                v,
                e,
                system + "; rigid samples with certified tensions at p_r nearest p_crit, mean over "
                "p_t = 0.1, 0.2, 0.3 (error: bootstrap over samples, p_crit re-estimated)",
                size=scale.n_grid,
            )
        )
    labels = tuple(f"p_t = {p:.1f}" for p in peaks["p_t"])
    pc_var = np.diag(
        fits[np.isclose(fits.phi, math.pi)].sort_values("p_t").p_crit_err.to_numpy() ** 2
    )
    for stat, factor, label in (
        ("mean", "ours", ""),
        ("median", "estimator", "peak of the median Gamma instead of the mean"),
    ):
        at, cov = peaks[stat]
        out.append(
            Measurement(
                "gamma_peak",
                at - peaks["p_crit"],
                cov + pc_var,
                system,
                factor=factor,
                label=label,
                points=labels,
                note="peak of the mean Gamma on the p_r grid minus the median threshold; error: "
                "bootstrap over samples, grid resolution, p_crit's error",
                size=scale.n_grid,
            )
        )
    return tuple(out)


def thresholds_by_sample(
    thresholds: pd.DataFrame, ids: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Per-sample thresholds lined up with the sample ids ``ids`` (S,).

    Returns ``t`` (S,) float (NaN: never rigid, or no threshold row) and ``known`` (S,) bool
    (the sample has a threshold row): a threshold sweep and a grid sweep of the same seed,
    n and delta hold the same disorder as sample k (common random numbers), so a bootstrap
    that redraws samples must redraw a sample's threshold and its grid rows together.
    """
    by = thresholds.set_index("sample").threshold_p_r
    known = np.isin(ids, by.index.to_numpy())
    return by.reindex(ids).to_numpy(float), known


def energy_exponent(grid: pd.DataFrame, thresholds: pd.DataFrame, n_boot: int) -> an.PowerLawFit:
    """alpha of the mean energy of ``grid`` above the median threshold of ``thresholds``.

    Parameters
    ----------
    grid : DataFrame
        Decided grid rows of one (phi, p_t) curve: ``sample``, ``p_r``, ``energy``.
    thresholds : DataFrame
        Threshold rows of the same (phi, p_t) and seed: ``sample``, ``threshold_p_r``.
    n_boot : int
        Bootstrap replicas.

    Returns
    -------
    PowerLawFit
        :func:`~tensegrity_rigidity.analysis.estimators.fit_energy_exponent`: its errors
        redraw whole samples (a sample's energies at every p_r and its threshold together) and
        re-estimate p_crit in every replica.
    """
    ids = np.union1d(grid["sample"].unique(), thresholds["sample"].unique())
    e, x = per_sample(grid, "energy", samples=ids)
    t, known = thresholds_by_sample(thresholds, ids)
    return an.fit_energy_exponent(
        x, e, lambda idx: an.median_threshold(t[idx][known[idx]]), n_boot=n_boot
    )


#: p_t averaged by the taut-cable fraction at the transition (the paper's Fig. 2 inset)
TAUT_PT = (0.1, 0.2, 0.3)


def taut_with_error(rows: pd.DataFrame, thresholds: pd.DataFrame, n_boot: int):
    """:func:`taut_at_transition` from grid and threshold rows, with a bootstrap error.

    Parameters
    ----------
    rows : DataFrame
        Grid rows (``phi``, ``p_t``, ``p_r``, ``sample``, ``rigid``, ``frac_cables_taut``;
        NaN where the tensions are not certified).
    thresholds : DataFrame
        Threshold rows of the same samples (``phi``, ``p_t``, ``sample``, ``threshold_p_r``).
    n_boot : int
        Bootstrap replicas.

    Returns
    -------
    tuple or None
        (mean, error, [(p_t, p_r), ...]) as :func:`taut_at_transition`, with the error a
        bootstrap over samples: a replica redraws whole samples (the same disorders at every
        p_t and p_r and in the thresholds, so the three p_t averaged are not independent),
        re-estimates p_crit per p_t and so may pick another grid p_r. None without a point.

    Notes
    -----
    The error of :func:`taut_at_transition` alone adds the three p_t's standard errors as if
    independent and takes the grid point as known: 0.005 at n = 32 where the same claim
    measured at other sizes and delta had 0.016.
    """
    comp = rows[np.isclose(rows.phi, math.pi)]
    th = thresholds[np.isclose(thresholds.phi, math.pi)]
    ids = np.union1d(comp["sample"].unique(), th["sample"].unique())
    blocks = []
    for p_t in TAUT_PT:
        sub = comp[np.isclose(comp.p_t, p_t)]
        if not len(sub):
            continue
        sub = sub.assign(_taut=np.where(sub.rigid.astype(bool), sub.frac_cables_taut, np.nan))
        f, x = per_sample(sub, "_taut", samples=ids)
        blocks.append((p_t, f, x, *thresholds_by_sample(th[np.isclose(th.p_t, p_t)], ids)))

    def at(idx):
        taut, crit = [], []
        for p_t, f, x, t, known in blocks:
            v = f[idx]
            size = np.isfinite(v).sum(axis=0)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)  # points without a rigid sample
                mean = np.nanmean(v, axis=0)
                sem = np.nanstd(v, axis=0, ddof=1) / np.sqrt(size)
            table = {"p_r": x, "mean": mean, "sem": sem, "size": size}
            taut.append(pd.DataFrame(table).assign(phi=math.pi, p_t=p_t))
            pc = an.median_threshold(t[idx][known[idx]])
            crit.append({"phi": math.pi, "p_t": p_t, "p_crit": pc})
        if not taut:
            return None
        return taut_at_transition(pd.concat(taut, ignore_index=True), pd.DataFrame(crit))

    best = at(np.arange(ids.size))
    if best is None:
        return None
    rng = np.random.default_rng(6)
    boots = [at(rng.integers(0, ids.size, ids.size)) for _ in range(n_boot)]
    vals = np.array([b[0] for b in boots if b is not None])
    err = float(np.std(vals, ddof=1)) if vals.size > 1 else float("nan")
    return best[0], err, best[2]


def taut_at_transition(taut: pd.DataFrame, crit: pd.DataFrame):
    """Fraction of taut cables at the grid p_r nearest p_crit (compression), mean over p_t.

    Only grid points with a rigid sample whose tensions are certified (a finite mean) count:
    at n = 64 the point just below p_crit can have no rigid sample of 8 (p_t = 0.1 in the fss
    energy grids), and the next one is used. A p_t without such a point is left out; the
    returned list says which (p_t, p_r) were averaged.
    """
    vals = []
    for p_t in TAUT_PT:
        pc = crit[np.isclose(crit.phi, math.pi) & np.isclose(crit.p_t, p_t)].p_crit
        sub = taut[np.isclose(taut.phi, math.pi) & np.isclose(taut.p_t, p_t)]
        sub = sub[np.isfinite(sub["mean"].to_numpy(float))]
        if len(pc) and len(sub) and np.isfinite(pc.iloc[0]):
            row = sub.iloc[int(np.argmin(np.abs(sub.p_r - float(pc.iloc[0]))))]
            vals.append((row["mean"], row["sem"], p_t, row.p_r))
    if not vals:
        return None
    v = float(np.mean([x[0] for x in vals]))
    e = float(np.sqrt(np.nansum([x[1] ** 2 for x in vals])) / len(vals))
    return v, e, [(x[2], x[3]) for x in vals]


#: samples of the sweeps that supply the drawn samples of Figs. 1A and 2A
FIELD_SAMPLES = 8
#: Fig. 2A's sample: rods + cables under compression at p_t = 0.2, solved at its own threshold
#: plus this step in p_r (rigid there by monotonicity)
FIELD_P_T, FIELD_STEP = 0.2, 0.02


def _displacement_field(out, scale: Scale, **kw) -> tuple[DisplacementField, int, int]:
    """The samples drawn in Figs. 2A and 1A, taken from small sweeps and solved again.

    Fig. 2A: the first sample of a threshold sweep (rods + cables, compression, p_t = 0.2) whose
    threshold s* is positive and leaves room for s* + 0.02 <= 1 - p_t; it is rigid at
    p_r = s* + 0.02. Fig. 1A: the first rigid sample of a grid sweep at (p_r, p_t, f_c) =
    (0.55, 0.4, 0.5) under shear. Each is rebuilt with the sweep's own sample geometry and solved
    with the minimum-norm displacements. Returns (field, excluded 2A, excluded 1A).
    """
    sweeps = fig2_sweeps(scale)
    spec_2a = sweeps["fig2_field"]
    th, ex_2a = sweep_rows(out, "fig2_field", spec_2a, **kw)
    inst = res = None
    p_r = float("nan")
    ok = th[(th.threshold_p_r > 0) & (th.threshold_p_r + FIELD_STEP <= 1 - FIELD_P_T)]
    if len(ok):
        row = ok.iloc[0]
        p_r = float(row.threshold_p_r) + FIELD_STEP
        inst = _rebuild(spec_2a, row, p_r)
        res = solve(inst)
    spec_1a = sweeps["fig1a_field"]
    grid, ex_1a = sweep_rows(out, "fig1a_field", spec_1a, **kw)
    inst2 = res2 = None
    rigid = grid[grid.rigid]
    if len(rigid):
        row = rigid.iloc[0]
        inst2 = _rebuild(spec_1a, row, float(row.p_r))
        res2 = solve(inst2)
    field_ = DisplacementField(inst, res, p_r, FIELD_P_T, inst2, res2)
    return field_, ex_2a, ex_1a


def _rebuild(spec: dict, row: pd.Series, p_r: float) -> Instance:
    """The instance of one sweep row's sample at ``p_r`` (its geometry, uniforms and strain)."""
    sp = parse_spec({"delta": DEFAULT_DELTA} | spec)
    point = next(
        q for q in sp.points() if np.isclose(q.p_t, row.p_t) and np.isclose(q.phi, row.phi)
    )
    net, u, v, theta = sample_geometry(sp, point, int(row["sample"]))
    kinds = place_elements(u, v, p_r, point.p_t, point.f_c)
    return Instance(net.with_kinds(kinds), strain_tensor(point.phi, theta, sp.gamma))


# --------------------------------------------------------------------------- Fig. 3


@dataclass(frozen=True, eq=False)
class Fig3Result:
    """Single node: analytic P_N versus f_c and its simulation.

    Attributes
    ----------
    f_c : (F,) float
        Grid of the analytic curves.
    analytic : dict
        p_r -> (F,) analytic P_N.
    sim : DataFrame
        Simulated points: p_r, f_c, P with its Wilson interval (lo, hi), the analytic value and
        ``z = (P - analytic) / binomial standard error`` (the error from the Wilson interval).
    trials : int
        Trials per simulated point.
    """

    f_c: np.ndarray
    analytic: dict
    sim: pd.DataFrame
    trials: int
    excluded: dict[str, int] = field(default_factory=dict)
    measured: tuple[Measurement, ...] = ()


def study_fig3(out, scale: Scale, **kw) -> Fig3Result:
    """Single node: analytic P_N versus f_c, and simulation with Wilson intervals."""
    rng = np.random.default_rng(31)
    f_c = np.linspace(0, 1, 41)
    p_rs = [0.1, 0.3, 0.5, 0.7]
    analytic = {
        p: np.array([single_node_probability(p, f * (1 - p), (1 - f) * (1 - p)) for f in f_c])
        for p in p_rs
    }
    sim = []
    for p in p_rs:
        for f in np.linspace(0, 1, 9):
            k, n = simulate_single_node(p, f * (1 - p), (1 - f) * (1 - p), scale.node_trials, rng)
            P, lo, hi = an.wilson(k, n)
            sim.append(
                {
                    "p_r": p,
                    "f_c": f,
                    "P": float(P),
                    "lo": float(lo),
                    "hi": float(hi),
                    "analytic": single_node_probability(p, f * (1 - p), (1 - f) * (1 - p)),
                }
            )
    sim = pd.DataFrame(sim)
    se = (sim.hi - sim.lo) / (2 * 1.96)
    sim["z"] = (sim.P - sim.analytic) / se
    # the test of "simulation = formula" uses the binomial variance under the formula
    var = sim.analytic * (1 - sim.analytic) / scale.node_trials
    measured = (
        Measurement(
            "single_node",
            sim.P.to_numpy(),
            np.diag(var.to_numpy()),
            f"{scale.node_trials} trials per point",
            points=tuple(
                f"p_r = {a}, f_c = {b:.3f}" for a, b in zip(sim.p_r, sim.f_c, strict=True)
            ),
            reference=sim.analytic.to_numpy(),
            note="simulated against analytic P_N at every point; binomial errors at the "
            "analytic value",
        ),
    )
    return Fig3Result(
        f_c=f_c, analytic=analytic, sim=sim, trials=scale.node_trials, measured=measured
    )


# --------------------------------------------------------------------------- Fig. 4

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
        (:func:`~tensegrity_rigidity.analysis.estimators.fit_efficacies`).
    curves : EfficacyCurves
        The strain average with covariances over f_c.
    differences : DataFrame
        The strain average from paired central differences (one-sided at f_c = 0 and 1), the
        estimator the surface replaces, kept as evidence of what the estimator changes.
    slopes : dict
        Strain name ("dilation", "compression") -> least-squares slope of P over f_c with its
        error (:func:`~tensegrity_rigidity.analysis.estimators.paired_slope`).
    """

    per_phi: pd.DataFrame
    average: pd.DataFrame
    dilation: pd.DataFrame
    compression: pd.DataFrame
    curves: an.EfficacyCurves
    differences: pd.DataFrame
    slopes: dict[str, an.Derivative]
    n: int
    samples: int
    excluded: dict[str, int]
    measured: tuple[Measurement, ...] = ()


def _ratio_frame(c: an.EfficacyCurves) -> pd.DataFrame:
    cols = {"f_c": c.f_c, "S_r": c.values["S_r"], "S_r_err": c.err("S_r")}
    for name in ("S_c_rel", "S_s_rel", "sum_rel"):
        cols[name], cols[f"{name}_err"] = c.values[name], c.err(name)
    return pd.DataFrame(cols)


def fig4_sweeps(scale: Scale) -> dict[str, dict]:
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


def study_fig4(out, scale: Scale, **kw) -> Fig4Result:
    """P versus f_c at (p_r, p_t) = (0.3, 0.6) and the efficacies S_r, S_t, S_c, S_s.

    Three sweeps on the same samples (common random numbers): the centre, p_r +- H_R and
    p_t +- H_T, each at f_c = 0, 1/8, ..., 1 and five strains. The efficacies come from a
    binomial-likelihood surface smooth in f_c (see
    :func:`~tensegrity_rigidity.analysis.estimators.fit_efficacies`), fitted to all 45 points of
    each strain at once.
    """
    p_r0, p_t0 = FIG4_CENTRE
    frames, excluded = {}, {}
    for name, spec in fig4_sweeps(scale).items():
        frames[name], excluded[name] = sweep_rows(out, name, spec, **kw)
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
        y, pr, pt, fc, FIG4_CENTRE, np.array(FIG4_FC), FIG4_DEGREES, n_boot=scale.bootstrap
    )
    rows = []
    for phi, c in zip(FIG4_PHI, per_strain, strict=True):
        for i, f in enumerate(FIG4_FC):
            P = outcomes(centre, phi=phi, f_c=f)
            P = P[np.isfinite(P)]
            row = {"phi": phi, "f_c": f, "P": P.mean(), "N": P.size}
            for name in ("S_r", "S_t", "D_f", "S_c", "S_s"):
                row[name], row[f"{name}_err"] = c.values[name][i], c.err(name)[i]
            rows.append(row)
    per_phi = pd.DataFrame(rows)
    _, per_phi["lo"], per_phi["hi"] = an.wilson(per_phi.P * per_phi.N, per_phi.N)
    slopes = {
        name: an.paired_slope(
            np.column_stack([outcomes(centre, phi=phi, f_c=f) for f in FIG4_FC]),
            np.asarray(FIG4_FC),
        )
        for name, phi in (("dilation", 0.0), ("compression", math.pi))
    }
    differences = _fig4_differences(outcomes, centre, d_r, d_t)
    system = f"n = {scale.n_grid}, {scale.samples_fig4} samples per point"
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
    return Fig4Result(
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
        measured=tuple(measured),
    )


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


def fig3_sweeps(scale: Scale) -> dict[str, dict]:
    """Fig. 3 runs no sweep: its ``scale.node_trials`` single-node trials run in-process."""
    return {}


#: study name -> the sweeps it runs at a scale (name -> spec)
SWEEPS = {
    "fig1b": fig1b_sweeps,
    "fig1c": fig1c_sweeps,
    "fig2": fig2_sweeps,
    "fig3": fig3_sweeps,
    "fig4": fig4_sweeps,
}

STUDIES = {
    "fig1b": study_fig1b,
    "fig1c": study_fig1c,
    "fig2": study_fig2,
    "fig3": study_fig3,
    "fig4": study_fig4,
}
