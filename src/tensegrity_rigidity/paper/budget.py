"""What a reproduction costs, and which error bars its sample counts buy.

Two models, each with its constants in one place (this module).

Work and time (:func:`estimate`)
    Every study declares its sweeps (:data:`~tensegrity_rigidity.paper.registry.SWEEPS`, the
    specs the study itself runs). The estimate expands them with the sweep engine's own chunk
    planner (:func:`~tensegrity_rigidity.ensemble.sweep.plan_chunks`), so it counts exactly the
    rows the sweeps will compute: threshold searches, grid solves (minimum-norm displacements)
    and the paper's verdicts (L-BFGS-B), per study and size. Rows already stored under ``out``
    (a resumed run) and rows an earlier study of the same run computes into the same sweep (the
    finite-size and node-disorder studies share their sweeps at n_delta) are not counted again.
    Each row is priced by the per-sample costs below; a sweep's wall time is the makespan of its
    chunks on W workers in submission order (the engine runs one sweep at a time, each chunk on
    one worker); in-process work (Fig. 3's trials, the two drawn samples of Figs. 1A and 2A, the
    analysis) adds serially.

Error bars (:func:`expected_errors`)
    The headline estimators' bootstrap errors fall as ``sigma_1(n) / sqrt(S)`` with S the
    samples per point: ``sigma_1``, the error of one sample, is measured at a few sizes
    (:data:`SIGMA_1`) and interpolated as a power law in n. :func:`samples_for` inverts it for a
    target error. Which targets each scale meets, and which it cannot, is stated at
    :data:`~tensegrity_rigidity.paper.studies.SCALES`.

Sizes outside the measured ones are extrapolated with the power law of the nearest two
measured sizes (grid solves: the factorisation's N^1.3) and say so: the estimate's ``notes``
and the printed table name every extrapolated constant. Checked against the scales that were timed:
the model gives the quick scale as it was measured (Fig. 1C with three times today's threshold
searches) 10 min against about 8 min measured (on an older solver), and the tiny scale
1 min, as measured.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ..ensemble.spec import parse_spec
from ..ensemble.store import ResultStore
from ..ensemble.sweep import plan_chunks
from ..errors import InputError
from ..model.lattice import DEFAULT_DELTA
from .claims import CLAIMS
from .claims import TARGETS as CLAIM_TARGETS
from .studies import SCALES, Scale

# --------------------------------------------------------------------------- per-sample costs
#
# Mean seconds of one row on one process of the reference machine (x86_64, 2 cores). Means, not
# medians: a sweep's time is a sum. Sources:
#
# THRESHOLD_SECONDS: one exact threshold search along p_r (certified verdicts, an interval when
#   probes are undecided) at p_t = 0.3, the means of the p_t = 0.3 rows (f_c = 0, 0.5, 1; three
#   strains) of the first clean finite-size run (`reproduce --scale fss` from a clean clone at
#   a3eff61, 2 workers; benchmarks/calibrate_budget.py, BENCHMARKS.md): 0.080, 0.327, 2.90 and
#   73.2 s at n = 8, 16, 32, 64 over 3600, 1800, 864 and 92 rows (medians 0.067, 0.270,
#   1.86, 61.9 s). The constants before (0.01, 0.17, 1.56, 48 s, from the
#   near-threshold benchmark set before the refine stage, the LP stage's iterative refinement
#   and its primal simplex) priced that run's threshold rows 1.5 to 8 times too low. n = 128 is
#   extrapolated (x 25 per doubling, as from 32 to 64).
THRESHOLD_SECONDS = {8: 0.080, 16: 0.33, 32: 2.90, 64: 73.0}
# THRESHOLD_PT_FACTOR: cost relative to p_t = 0.3, by p_t (linear in between, 1 above 0.3), from
#   the 4,800 threshold rows of Fig. 1C of a quick run (n = 12, solve_seconds per row): means
#   0.029, 0.100, 0.158, 0.171 s at p_t = 0, 0.1, 0.2, 0.3. Rods only needs no active set.
#   Above 0.3 Fig. 1B's rows (p_t up to 0.8) averaged 0.081 s: 1 errs long. The finite-size
#   first clean run agrees: 0.52 and 0.82 at p_t = 0.1 and 0.2 (n = 32), 0.56 and 0.90 (16).
THRESHOLD_PT_FACTOR = ((0.0, 0.17), (0.1, 0.58), (0.2, 0.92), (0.3, 1.0))
# RODS_THRESHOLD_SECONDS: a rods-only threshold search (p_t = 0), measured directly because its
#   cost relative to a search at p_t = 0.3 falls with n: means of the rows of the rods-only p_c
#   sweeps (Scale.fss_pc, 4000, 1200, 400, 100 and 64 samples at n = 8 to 128) run on 2 workers
#   with the refine stage (`--scale pc`, 34 min 11 s): 113.0, 73.4, 117.9, 282.9
#   and 3395.7 s of search in all. The medians are lower (11.8 s at n = 128, max 219 s): a few
#   searches meet undecided probes (153 in 64 searches at n = 128), and an undecided probe runs
#   every stage. Before the refine stage (same day): 0.076, 0.40, 6.2 and 139 s at n = 16 to 128.
RODS_THRESHOLD_SECONDS = {8: 0.028, 16: 0.061, 32: 0.295, 64: 2.83, 128: 53.1}
# PEBBLE_SECONDS: a rods-only threshold by the pebble game with its spanning rigid cluster
#   (``[threshold] method = "pebble"``, the pc scale), wall seconds per sample of
#   ensemble.runner.threshold_chunk (geometry, one pass, the spanning cluster's labelling) on one
#   process of the reference machine under the other jobs' load (load average 8 on 2 cores):
#   200, 100, 30, 8 and 3 samples at n = 32, 64, 128, 256, 512. About N^1.5 in N = n^2 nodes
#   at the largest sizes (one pass costs about N^1.2 near threshold; the wrapping cluster's
#   labelling adds 5 to 10 %).
PEBBLE_SECONDS = {32: 0.0108, 64: 0.0268, 128: 0.142, 256: 1.11, 512: 8.07}
# GRID_SECONDS: one grid sample, solve() with the minimum-norm displacements (what grid sweeps
#   record), at the reference p_t = 0.15, from the rows of finished runs priced by
#   benchmarks/calibrate_budget.py (BENCHMARKS.md, "Budget model against finished runs"): the
#   quick run (n = 12, 24,952 grid rows: 0.0071 s) and the paper run (n = 32, 8,176 rows:
#   0.0705 s), both with the interior-point projection of the minimum-norm displacements. The
#   constants before it (0.025 s at n = 16, 0.152 s at n = 32) came from the benchmark's
#   instances and the older projection and priced the paper run's grid rows 2.2 x too high.
#   Beyond the measured sizes: N^1.3 (the factorisation) with N ~ n^2 unknowns.
GRID_SECONDS = {12: 0.0071, 32: 0.0705}
GRID_EXPONENT = 2.6
# GRID_WITHOUT_DISPLACEMENTS: a grid row solved without the minimum-norm displacements
#   (``solver.min_norm = false``, the energy sweeps of the finite-size study), relative to one
#   with them: 0.67, the CPU time of the four energy sweeps at n = 32 (4 samples, 528 rows,
#   both strains) without and with them, measured one after the other (29.2 s
#   against 43.4 s; with them 82 ms per row, the model above prices 70).
GRID_WITHOUT_DISPLACEMENTS = 0.67
# GRID_PT_FACTOR: cost relative to the reference p_t = 0.15, by p_t (linear in between, constant
#   beyond), from the grid rows of a quick run (n = 12): means of Fig. 2 at p_t = 0, 0.1, 0.2,
#   0.3: 4.4, 13.0, 16.2, 22.3 ms (reference: 14.6 ms between 0.1 and 0.2); Fig. 4 at p_t =
#   0.55 to 0.65: 40.2 ms over its 21,600 rows.
GRID_PT_FACTOR = ((0.0, 0.30), (0.1, 0.89), (0.2, 1.11), (0.3, 1.53), (0.6, 2.75))
# PAPER_VERDICT_SECONDS: one sample decided the paper's way (L-BFGS-B from u = 0, energy
#   threshold), means of the method study's rows of the same two runs: 0.0224 s at n = 12, 0.287
#   s at n = 32 (the benchmark's 27 near-transition instances gave means 3.6 x higher at n = 32:
#   a grid spans the transition, where most of those instances sit).
PAPER_VERDICT_SECONDS = {12: 0.0224, 32: 0.287}
# NODE_TRIAL_SECONDS: Fig. 3's single-node simulation, in-process: 7 s for 36 points x 4,000
#   trials (the quick run's study time).
NODE_TRIAL_SECONDS = 7.0 / (36 * 4000)
# SWEEP_OVERHEAD_SECONDS: a sweep with rows to compute starts its worker processes, plans,
#   writes and reloads its parts: about 1.2 s, from the tiny run (fss: 8 sweeps of 3 samples in
#   10 s, every row a few ms).
SWEEP_OVERHEAD_SECONDS = 1.2
# ANALYSIS_SECONDS: in-process analysis of a study per 100 bootstrap resamples, from the study
#   times of a resumed quick run (every sweep done: analysis only): fig1b 1 s, fig1c 9 s,
#   fig2 1 s, fig4 2 s, method 14 s. fss and delta: per size or delta, 6 collapse fits at the
#   fig1c rate (9 s for 20 fits and 20 contour slopes): 2.7 s.
ANALYSIS_SECONDS = {"fig1b": 1.0, "fig1c": 9.0, "fig2": 1.0, "fig3": 0.0, "fig4": 2.0}
ANALYSIS_SECONDS |= {"method": 14.0, "fss": 2.7, "delta": 2.7}
# THRESHOLD_SECONDS_3D, RODS_THRESHOLD_SECONDS_3D: one threshold search along p_r on the FCC
#   lattice (delta = 0.2, principal axes from the SO(3) sequence) at p_t = 0.3 (f_c = 0.5 under
#   dilation, shear, compression; f_c = 1 under compression, dilation) and at p_t = 0 (dilation,
#   shear), means of one run of 3, 2 and 1 samples at n = 4, 6, 8 (15, 10, 5 searches at p_t =
#   0.3; 6, 4, 2 rods only) on one process each, two at a time beside other jobs on the 2-core
#   machine. Beyond n = 8: the power law of n = 6 and 8 (n^4.7 at p_t = 0.3, n^2.5 rods only).
THRESHOLD_SECONDS_3D = {4: 0.338, 6: 2.16, 8: 8.37}
RODS_THRESHOLD_SECONDS_3D = {4: 0.148, 6: 0.485, 8: 0.99}
#: the 3D study's analysis: per size 5 collapse fits and one critical point (fss's rate per size)
ANALYSIS_SECONDS |= {"three_d": 2.7}

# --------------------------------------------------------------------------- error bars
#
# SIGMA_1[estimator][n]: the bootstrap error times sqrt(samples) (the error of one sample), the
# largest over the configurations measured. Sources (seed 12 unless said, delta = 0.2):
#
# "st_sr": S_t/S_r of one strain and f_c, collapse fit over p_t = 0 and 0.3 (Fig. 1C, the
#   finite-size study). n = 12: 0.0148 x sqrt 48 (quick run, rods + cables under dilation, fit
#   over p_t = 0 ... 0.3; compression 0.0118 x sqrt 48); n = 16: 0.0067 x sqrt 64 (dilation;
#   compression 0.0066); n = 32: 0.0071 x sqrt 32 (compression). Calibration sweeps of 64
#   (n = 16) and 32 (n = 32) samples, rods + cables at p_t = 0, 0.1, 0.2, 0.3.
# "p_crit": median threshold of one (strain, p_t) (Fig. 2, the rods-only p_c): the larger of
#   the bootstrap error x sqrt S and sqrt(pi / 2) x the thresholds' spread (the median's
#   asymptotic error), largest over p_t = 0 ... 0.3 and the strains: n = 12: 0.032 (spread
#   0.020 to 0.023), n = 16: 0.027 (0.018 to 0.021), n = 32: 0.0184 (0.011 to 0.0125), same
#   runs.
# "taut": fraction of taut cables in rigid samples at the grid p_r nearest p_crit (compression),
#   mean over p_t = 0.1, 0.2, 0.3. n = 12: 0.032 x sqrt 24 (quick run, p_r step 0.05, where
#   only 12 to 33 % of the samples were rigid). n = 32: the per-sample spread was 0.044 at
#   (p_r, p_t) = (0.525, 0.3) (P = 0.88) and 0.018 at (0.55, 0.3) (P = 1), 32 samples; with a
#   spread of 0.06 and at least 20 % rigid samples at the grid point nearest p_crit (half a
#   step of 0.025 is about one width, 0.011), 0.06 / sqrt(0.2) / sqrt(3) = 0.077.
# "fig4c": (S_c + S_s)/S_r, strain average, largest over f_c: n = 12: 0.091 x sqrt 96 (quick
#   run). Not measured at n = 32, where it cannot be: see SCALES["paper"].
# "st_sr_shift", "p_crit_shift": the method study's shifts (the paper's verdict minus ours on
#   the same samples, paired bootstrap): n = 12: 0.024 x sqrt 16 (S_t/S_r of rods + cables
#   under compression; dilation 0.015) and 0.006 x sqrt 16 (largest over p_t and strains), the
#   quick run. Other sizes follow S_t/S_r and p_crit (SIGMA_SCALING): a shift is the difference
#   of the same estimator on two verdicts of the same samples.
SIGMA_1 = {
    "st_sr": {12: 0.102, 16: 0.0536, 32: 0.0401},
    "p_crit": {12: 0.032, 16: 0.027, 32: 0.0184},
    "taut": {12: 0.157, 32: 0.077},
    "fig4c": {12: 0.89},
    "st_sr_shift": {12: 0.096},
    "p_crit_shift": {12: 0.024},
}
#: estimators measured at one size only that take their n-dependence from another
SIGMA_SCALING = {"st_sr_shift": "st_sr", "p_crit_shift": "p_crit"}
#: target standard errors: the claims' (:data:`~tensegrity_rigidity.paper.claims.TARGETS`), and
#: the method's shifts as precise as the claims they move
TARGETS = dict(CLAIM_TARGETS)
TARGETS |= {"st_sr_shift": 0.013, "p_crit_shift": 0.005}


# --------------------------------------------------------------------------- interpolation


def _power_law(
    table: dict[int, float], n: int, exponent: float | None = None
) -> tuple[float, bool]:
    """(value at n, extrapolated?) by piecewise power laws through ``table``.

    Between measured sizes: the power law through the two neighbours. Outside: the power law of
    the nearest two (``exponent`` instead when given; a single size: that exponent or none).
    """
    sizes = sorted(table)
    if n in table:
        return float(table[n]), False
    if len(sizes) == 1:
        k = sizes[0]
        return float(table[k] * (n / k) ** (exponent or 0.0)), True
    outside = n < sizes[0] or n > sizes[-1]
    if n < sizes[0]:
        lo, hi = sizes[0], sizes[1]
    elif n > sizes[-1]:
        lo, hi = sizes[-2], sizes[-1]
    else:
        lo, hi = next((a, b) for a, b in zip(sizes, sizes[1:], strict=False) if a < n < b)
    slope = math.log(table[hi] / table[lo]) / math.log(hi / lo)
    if outside and exponent is not None:
        slope = exponent
    ref = lo if n < hi else hi
    return float(table[ref] * (n / ref) ** slope), outside


def _factor(table, p_t: float) -> float:
    xs, ys = zip(*table, strict=True)
    return float(np.interp(p_t, xs, ys))


def row_seconds(mode: str, n: int, p_t: float) -> tuple[float, bool]:
    """(mean seconds of one row, extrapolated?) for a sweep of ``mode`` at size n and p_t.

    ``mode``: "threshold" (a threshold search), "pebble" (a rods-only threshold by the pebble
    game, with its spanning cluster), "grid" (an exact grid sample with its
    minimum-norm displacements), "energy" (the same without them) or "paper" (a grid sample
    decided the paper's way).
    """
    if mode == "pebble":
        return _power_law(PEBBLE_SECONDS, n)
    if mode == "threshold" and p_t == 0.0:
        return _power_law(RODS_THRESHOLD_SECONDS, n)
    if mode == "threshold":
        t, ext = _power_law(THRESHOLD_SECONDS, n)
        return t * _factor(THRESHOLD_PT_FACTOR, p_t), ext
    if mode in ("grid", "energy"):
        t, ext = _power_law(GRID_SECONDS, n, GRID_EXPONENT)
        t *= GRID_WITHOUT_DISPLACEMENTS if mode == "energy" else 1.0
        return t * _factor(GRID_PT_FACTOR, p_t), ext
    if mode == "paper":
        return _power_law(PAPER_VERDICT_SECONDS, n)
    raise InputError(
        f"unknown sweep mode {mode!r}; use 'threshold', 'pebble', 'grid', 'energy' or 'paper'"
    )


def row_seconds_3d(mode: str, n: int, p_t: float) -> tuple[float, bool]:
    """(mean seconds of one threshold row on the FCC lattice at size n and p_t, extrapolated?).

    Rods only (``p_t = 0``) from :data:`RODS_THRESHOLD_SECONDS_3D`, otherwise
    :data:`THRESHOLD_SECONDS_3D` scaled by the 2D :data:`THRESHOLD_PT_FACTOR` (1 at p_t = 0.3,
    the only one-sided p_t the 3D study runs). Only threshold sweeps are priced in 3D.
    """
    if mode != "threshold":
        raise InputError(f"no 3D cost model for {mode!r} sweeps; only 'threshold' is priced")
    if p_t == 0.0:
        return _power_law(RODS_THRESHOLD_SECONDS_3D, n)
    t, ext = _power_law(THRESHOLD_SECONDS_3D, n)
    return t * _factor(THRESHOLD_PT_FACTOR, p_t), ext


def sigma_1(estimator: str, n: int) -> tuple[float, bool]:
    """(error of one sample of ``estimator`` at size n, extrapolated?) from :data:`SIGMA_1`."""
    if estimator not in SIGMA_1:
        raise InputError(f"no error model for {estimator!r}; known: {', '.join(SIGMA_1)}")
    table = SIGMA_1[estimator]
    like = SIGMA_SCALING.get(estimator)
    if like is not None and n not in table:
        (k,) = table
        return table[k] * _power_law(SIGMA_1[like], n)[0] / _power_law(SIGMA_1[like], k)[0], True
    return _power_law(table, n)


def samples_for(estimator: str, n: int, target: float) -> int:
    """Samples per point for a bootstrap error of at most ``target`` at size n."""
    s, _ = sigma_1(estimator, n)
    return math.ceil((s / target) ** 2)


def expected_error(estimator: str, n: int, samples: int) -> float:
    """The error ``estimator`` is expected to have with ``samples`` samples per point at n."""
    s, _ = sigma_1(estimator, n)
    return s / math.sqrt(samples) if samples > 0 else math.inf


# --------------------------------------------------------------------------- the estimate


@dataclass(frozen=True)
class SweepCost:
    """The work of one sweep of a study.

    ``rows``: the rows its spec asks for; ``new_rows``: those still to compute (not stored under
    ``out``, not computed by an earlier sweep of the same name in this run). Seconds are for the
    new rows: ``cpu_seconds`` summed over rows, ``wall_seconds`` the makespan of the chunks on
    the estimate's workers.
    """

    study: str
    name: str
    mode: str
    n: int
    rows: int
    new_rows: int
    cpu_seconds: float
    wall_seconds: float
    extrapolated: bool


@dataclass(frozen=True)
class Estimate:
    """Work counts and estimated wall time of a scale (see the module docstring).

    Attributes
    ----------
    sweeps : tuple of SweepCost
        In the order the studies run them.
    serial : dict
        Study -> seconds of in-process work (trials, drawn samples, analysis).
    notes : tuple of str
        What the estimate extrapolates or cannot price.
    budget_minutes : float or None
        The scale's budget (wall minutes on 2 workers), None if it states none.
    """

    scale: str
    workers: int
    studies: tuple[str, ...]
    sweeps: tuple[SweepCost, ...]
    serial: dict[str, float] = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    budget_minutes: float | None = None

    @property
    def wall_seconds(self) -> float:
        return sum(s.wall_seconds for s in self.sweeps) + sum(self.serial.values())

    @property
    def cpu_seconds(self) -> float:
        return sum(s.cpu_seconds for s in self.sweeps) + sum(self.serial.values())

    @property
    def over_budget(self) -> bool:
        """True when the wall time exceeds the scale's budget (meant for an estimate on 2
        workers, the reference machine's)."""
        return self.budget_minutes is not None and self.wall_seconds > 60 * self.budget_minutes

    def table(self) -> pd.DataFrame:
        """Per study and size: threshold searches (pebble-game passes included), grid solves,
        paper verdicts (rows still to
        compute), CPU and wall minutes (in-process work on the study's first row)."""
        rows = []
        for study in self.studies:
            mine = [s for s in self.sweeps if s.study == study]
            sizes: list[int | None] = [*sorted({s.n for s in mine})] or [None]
            for i, n in enumerate(sizes):
                here = [s for s in mine if s.n == n]
                serial = self.serial.get(study, 0.0) if i == 0 else 0.0
                rows.append(
                    {
                        "study": study,
                        "n": n,
                        "thresholds": sum(
                            s.new_rows for s in here if s.mode in ("threshold", "pebble")
                        ),
                        "grid": sum(s.new_rows for s in here if s.mode in ("grid", "energy")),
                        "paper": sum(s.new_rows for s in here if s.mode == "paper"),
                        "cpu_min": (sum(s.cpu_seconds for s in here) + serial) / 60,
                        "wall_min": (sum(s.wall_seconds for s in here) + serial) / 60,
                        "extrapolated": any(s.extrapolated for s in here),
                    }
                )
        return pd.DataFrame(rows)


def _makespan(costs: list[float], workers: int) -> float:
    """Finish time of ``costs`` run in order, each on the first free of ``workers``."""
    free = [0.0] * max(1, workers)
    for c in costs:
        heapq.heapreplace(free, free[0] + c)
    return max(free)


def _stored_keys(path: Path) -> set:
    """(point_key, sample, theta) of the rows stored in a sweep directory (empty if none)."""
    if not path.is_dir():
        return set()
    df = ResultStore(path).read()
    if df.empty:
        return set()
    return set(zip(df.point_key, df["sample"], df.theta, strict=True))


def estimate(
    scale: Scale | str,
    workers: int = 2,
    studies: list[str] | None = None,
    out: str | Path | None = None,
) -> Estimate:
    """Count the work of a scale's studies and estimate its wall time on ``workers``.

    Parameters
    ----------
    scale : Scale or name of one in :data:`~tensegrity_rigidity.paper.studies.SCALES`
    workers : int
        Worker processes (2 on the reference machine; a Dask cluster's worker count).
    studies : list of str, optional
        These studies instead of the scale's own.
    out : path, optional
        An output directory of an earlier (interrupted) run: its stored rows are not counted.

    Raises
    ------
    InputError
        An unknown scale or study, or a study without a work model (nothing is left out
        silently).
    """
    from .registry import STUDIES, SWEEPS

    if isinstance(scale, str):
        if scale not in SCALES:
            raise InputError(f"unknown scale {scale!r}; choose from {', '.join(SCALES)}")
        scale = SCALES[scale]
    if workers < 1:
        raise InputError(f"workers must be at least 1, got {workers}")
    names = list(studies or scale.studies)
    for name in names:
        if name not in STUDIES:
            raise InputError(f"unknown study {name!r}; choose from {', '.join(STUDIES)}")
        if name not in SWEEPS or name not in ANALYSIS_SECONDS:
            raise InputError(f"study {name!r} has no work model: its run time cannot be estimated")
    planned: dict[str, set] = {}
    sweeps, serial, notes = [], {}, []
    for study in names:
        for name, raw in SWEEPS[study](scale).items():
            spec = parse_spec({"delta": DEFAULT_DELTA} | raw)
            if name not in planned:
                planned[name] = _stored_keys(Path(out) / "studies" / name) if out else set()
            done = planned[name]
            chunks = plan_chunks(spec, done)
            mode = "threshold" if spec.mode == "threshold" else spec.verdict
            if spec.threshold is not None and spec.threshold.get("method") == "pebble":
                mode = "pebble"
            mode = "grid" if mode == "exact" else mode
            if mode == "grid" and not spec.solver_options().min_norm:
                mode = "energy"
            costs, ext = [], False
            for point, ks in chunks:
                price = row_seconds_3d if spec.lattice == "fcc" else row_seconds
                sec, e = price(mode, point.n, point.p_t)
                ext |= e
                costs.append(sec * len(ks))
                pk = spec.point_key(point)
                done.update((pk, k, spec.angle(k)) for k in ks)
            n = max(spec.grid["n"])
            note = f"the {mode} cost at n = {n} is extrapolated in n from the measured sizes"
            if ext and note not in notes:
                notes.append(note)
            sweeps.append(
                SweepCost(
                    study,
                    name,
                    mode,
                    int(n),
                    spec.n_samples(),
                    sum(len(ks) for _, ks in chunks),
                    float(sum(costs)),
                    _makespan(costs, workers) + (SWEEP_OVERHEAD_SECONDS if chunks else 0.0),
                    ext,
                )
            )
        serial[study] = _serial_seconds(study, scale)
    return Estimate(
        scale.name,
        workers,
        tuple(names),
        tuple(sweeps),
        serial,
        tuple(notes),
        scale.budget_minutes,
    )


def _serial_seconds(study: str, scale: Scale) -> float:
    """In-process seconds of a study: its analysis, Fig. 3's trials, the two drawn samples."""
    per = {"fss": len(scale.fss_sizes), "delta": len(scale.deltas)}.get(study, 1)
    per = len(scale.sizes_3d) if study == "three_d" else per
    sec = ANALYSIS_SECONDS[study] * per * scale.bootstrap / 100
    if study == "fig3":
        sec += 36 * scale.node_trials * NODE_TRIAL_SECONDS
    if study == "fig2":
        n = max(scale.n_grid, 8)
        sec += row_seconds("grid", n, 0.2)[0] + row_seconds("grid", n, 0.4)[0]
    return sec


# --------------------------------------------------------------------------- error bars


def expected_errors(scale: Scale | str) -> pd.DataFrame:
    """The error bar each headline claim can expect at a scale, beside its target and the paper's.

    One row per claim a study of the scale measures with a calibrated estimator: ``claim``,
    ``study``, ``estimator`` (a key of :data:`SIGMA_1`), ``n``, ``samples``, ``expected``,
    ``target`` (:data:`TARGETS`), ``paper`` (the paper's error: stated, or the rounding of its
    printed value; 0 for an exact statement), ``meets`` (expected <= target) and
    ``extrapolated`` (sigma_1 extrapolated in n). The finite-size study gives one row per size.
    Claims whose error is not set by the sample count (the energy exponents: a least-squares
    error over 4 or 5 grid points; the nonaffinity peak: the p_r grid) are not listed.
    """
    if isinstance(scale, str):
        scale = SCALES[scale]
    rows = []

    def add(claim, study, est, n, samples, pool=1):
        s, ext = sigma_1(est, n)
        err = s / math.sqrt(samples * pool) if samples > 0 else math.inf
        c = CLAIMS.get(claim)
        rows.append(
            {
                "claim": claim,
                "study": study,
                "estimator": est,
                "n": n,
                "samples": samples,
                "expected": err,
                "target": TARGETS[est],
                "paper": c.error if c is not None else math.nan,
                "meets": err <= TARGETS[est],
                "extrapolated": ext,
            }
        )

    from .studies import FIG1C_PHI
    from .studies.headline import LAMBDA_CLAIMS

    if "fig1c" in scale.studies:
        for key, _, _ in LAMBDA_CLAIMS:
            add(key, "fig1c", "st_sr", scale.n_threshold, scale.samples_threshold)
        # pooled over the strains (their errors were independent: 0.011 per strain, 0.005
        # pooled over five at n = 12)
        add("st_sr_half_average", "fig1c", "st_sr", scale.n_threshold, scale.samples_threshold,
            len(FIG1C_PHI))  # fmt: skip
        add("rods_only_pc", "fig1c", "p_crit", scale.n_threshold, scale.samples_threshold)
    if "fig1b" in scale.studies:
        add("collapse_shear_half", "fig1b", "st_sr", scale.n_threshold, scale.fig1b_samples)
    if "fig2" in scale.studies:
        for strain in ("compression", "dilation"):
            for p_t in (0.0, 0.1, 0.2, 0.3):
                add(f"p_crit_{strain}_{p_t}", "fig2", "p_crit", scale.n_grid,
                    scale.samples_threshold)  # fmt: skip
        add("taut_cables_transition", "fig2", "taut", scale.n_grid, scale.samples_grid)
    if "fig4" in scale.studies:
        add("fig4c_sum_one", "fig4", "fig4c", scale.n_grid, scale.samples_fig4)
    if "method" in scale.studies:
        add("st_sr_cables_compression", "method", "st_sr_shift", scale.n_method,
            scale.samples_method)  # fmt: skip
        add("p_crit_compression_0.3", "method", "p_crit_shift", scale.n_method,
            scale.samples_method)  # fmt: skip
    if "fss" in scale.studies:
        # every S_t/S_r claim has the first's error, every p_crit the rods-only p_c's
        for n in scale.fss_sizes:
            add("st_sr_cables_compression", f"fss n={n}", "st_sr", n, scale.fss_samples(n))
        for n in scale.pc_sizes:
            add("rods_only_pc", f"fss n={n}", "p_crit", n, scale.pc_samples(n))
    if "delta" in scale.studies:
        add("st_sr_cables_compression", "delta", "st_sr", scale.n_delta, scale.samples_delta)
        add("rods_only_pc", "delta", "p_crit", scale.n_delta, scale.samples_delta)
    return pd.DataFrame(rows)


# --------------------------------------------------------------------------- text


def describe(est: Estimate, errors: pd.DataFrame | None = None) -> str:
    """The estimate as printed by ``reproduce --estimate``: counts, times, error bars."""
    lines = [
        f"scale {est.scale} on {est.workers} worker(s): estimated {est.wall_seconds / 60:.0f} "
        f"min wall ({est.cpu_seconds / 60:.0f} CPU min); an estimate from measured per-sample "
        "costs, not a measurement of this run",
    ]
    if est.budget_minutes is not None and est.workers == 2:
        verdict = "OVER BUDGET" if est.over_budget else "within"
        lines.append(f"budget: {est.budget_minutes:g} min on 2 workers ({verdict})")
    t = est.table()
    lines.append("")
    lines.append(
        f"{'study':<8} {'n':>4} {'thresholds':>11} {'grid':>8} {'paper':>7} "
        f"{'CPU min':>8} {'wall min':>9}"
    )
    for r in t.itertuples():
        n = "-" if r.n is None or (isinstance(r.n, float) and math.isnan(r.n)) else int(r.n)
        mark = "  (extrapolated)" if r.extrapolated else ""
        lines.append(
            f"{r.study:<8} {n!s:>4} {r.thresholds:>11,} {r.grid:>8,} {r.paper:>7,} "
            f"{r.cpu_min:>8.1f} {r.wall_min:>9.1f}{mark}"
        )
    lines.append(
        f"{'total':<8} {'':>4} {int(t.thresholds.sum()):>11,} {int(t.grid.sum()):>8,} "
        f"{int(t.paper.sum()):>7,} {est.cpu_seconds / 60:>8.1f} {est.wall_seconds / 60:>9.1f}"
    )
    for note in est.notes:
        lines.append(f"note: {note}")
    if errors is not None and len(errors):
        lines.append("")
        lines.append("expected error bars (bootstrap error of one sample / sqrt(samples)):")
        lines.append(
            f"{'claim':<28} {'study':<10} {'n':>4} {'samples':>8} {'expected':>9} "
            f"{'target':>7} {'paper':>7}"
        )
        for r in errors.itertuples():
            flag = "" if r.meets else "  exceeds target"
            flag += "  (extrapolated in n)" if r.extrapolated else ""
            lines.append(
                f"{r.claim:<28} {r.study:<10} {r.n:>4} {r.samples:>8} {r.expected:>9.4f} "
                f"{r.target:>7.3f} {r.paper:>7.4f}{flag}"
            )
    return "\n".join(lines)
