"""System sizes, sample counts and bootstrap seeds of a reproduction: the scales."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: the bootstrap stream of each estimator (:meth:`Scale.rng`): distinct, so that no two
#: estimators reuse one sequence of replicas; the values are the seeds each estimator has
#: always drawn from, so the error bars are those of the earlier releases
BOOTSTRAP_STREAMS = {
    "collapse": 0,
    "critical_point": 1,
    "peaks": 2,
    "contour": 3,
    "first_positive": 4,
    "efficacies": 5,
    "energy_exponent": 5,
    "taut": 6,
    "crossing": 6,
    "paired": 7,
    "finite_size": 8,
    "widths": 9,
    "fractal": 10,
}

#: most samples per point of the finite-size study's energy grids by default (its threshold
#: sweeps have up to 400): the paper scale's count at n = 32 (:meth:`Scale.fss_energy_samples`)
ENERGY_SAMPLES = 24


def stream(estimator: str, offset: int = 0) -> np.random.Generator:
    """A fresh generator on one estimator's bootstrap stream.

    Parameters
    ----------
    estimator : str
        A key of :data:`BOOTSTRAP_STREAMS`.
    offset : int
        Added to the stream's seed (:attr:`Scale.bootstrap_seed`).

    Returns
    -------
    numpy.random.Generator
    """
    return np.random.default_rng(BOOTSTRAP_STREAMS[estimator] + offset)


@dataclass(frozen=True, kw_only=True)
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
    n_threshold: int = 32  # lattice size of threshold studies (Figs. 1, 2 p_crit)
    n_grid: int = 32  # lattice size of grid studies (Figs. 2, 4)
    samples_threshold: int = 0  # Fig. 1C at f_c = 0, 0.5, 1 and Fig. 2's thresholds
    samples_grid: int = 0  # Fig. 2's grids
    samples_fig4: int = 0  # Fig. 4's grids
    p_r_step: float = 0.025  # p_r grid step of the grid studies
    node_trials: int = 0  # single-node trials per point (Fig. 3)
    bootstrap: int = 200  # bootstrap replicas of every error bar
    # added to each estimator's bootstrap stream (:data:`BOOTSTRAP_STREAMS`): 0 draws the
    # replicas every release so far drew
    bootstrap_seed: int = 0
    n_method: int = 5  # the paper's method beside ours (paper.method)
    samples_method: int = 4
    method_step: float = 0.1
    fss_sizes: tuple[int, ...] = (4, 5, 6, 8)  # finite-size study (paper.finite_size)
    samples_fss: int | tuple[int, ...] = 6  # one count, or one per size of fss_sizes
    # (n, samples) of the rods-only thresholds extrapolated to p_c: dedicated one-strain sweeps
    # (the rods-only threshold does not depend on the strain); () reads the headline sweeps
    fss_pc: tuple[tuple[int, int], ...] = ()
    # threshold method of the fss_pc sweeps: "lp" (certified bisection) or "pebble" (the pebble
    # game, which also measures the spanning rigid cluster and its stressed part at threshold)
    pc_method: str = "lp"
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
    # the 3D study (studies.three_d): sizes of the FCC lattice and samples per point at each
    # (one count per size), and (n, samples) of its rods-only thresholds (sizes may go beyond)
    sizes_3d: tuple[int, ...] = ()
    samples_3d: tuple[int, ...] = ()
    pc_3d: tuple[tuple[int, int], ...] = ()

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

    def samples_3d_at(self, n: int) -> int:
        """Samples per point of the 3D study at size ``n`` (0 for a size it has not)."""
        return dict(zip(self.sizes_3d, self.samples_3d, strict=True)).get(n, 0)

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

    def rng(self, estimator: str) -> np.random.Generator:
        """A fresh generator for one estimator's bootstrap replicas.

        Parameters
        ----------
        estimator : str
            A key of :data:`BOOTSTRAP_STREAMS`.

        Returns
        -------
        numpy.random.Generator
            Seeded with the estimator's stream plus :attr:`bootstrap_seed`, so that every
            estimate of a scale is reproducible and the estimators draw independent replicas.
        """
        return stream(estimator, self.bootstrap_seed)

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
#:   0.3, 4 at p_t = 0.1, 0.2 x 0.75), priced by the costs measured in the first clean
#:   fss run (paper.budget): 1.0, 4.1, 36 and about 880 CPU s per sample at n = 8, 16, 32, 64.
#:   That run had the former counts (12 samples at n = 64, 200 at 16, 96 at 32, 32 per delta) and
#:   was stopped after 97 min with n = 64 two thirds done (about 150 min in all). The counts are now
#:   chosen from the error targets (S_t/S_r +-0.013, p_crit +-0.005; `budget.expected_errors`)
#:   within the budget: n = 64 takes 8 samples (S_t/S_r +-0.0106, p_crit +-0.0044), n = 32 64
#:   (+-0.0050), node disorder 24 per delta (S_t/S_r +-0.0082, p_c +-0.0038); n = 8: 400 (S_t/S_r
#:   +-0.0126), n = 16: 160 (+-0.0042), which cost little. The extrapolations rest most on the
#:   largest sizes; with 12 samples at n = 64 a synthetic extrapolation p_c(n) = p_c + a n^(-1/nu)
#:   (nu fitted) scattered by +-0.010 around the true p_c (60 draws): only n = 128 (fss-cluster, pc)
#:   narrows it. delta = 0.2 reads the first 24 samples of the fss sweeps at n = 32.
#:   The energy grids of alpha and the taut-cable fraction (
#:   finite_size.energy_sweeps: 24 samples per point, no minimum-norm displacements) add 20
#:   CPU min, 10 min on 2 workers by the estimate (about 15 measured: the model errs short on
#:   them): 119 in all. n = 64 had 8 at first (its threshold count), and bootstrap
#:   errors from 8 samples came out implausibly small (the taut-cable fraction's 0.003) and
#:   dominated the extrapolations; 16 more cost about 9 CPU min (the 8 took 4.5 in the run of
#:   a finished run; 6.5 min on 2 workers alone). The budget is 120 min, the limit;
#:   the measured pieces add to about 113 min (the threshold sweeps' estimate was 109 min,
#:   their clean run took 97).
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
#: errors counted by sample) and 0.0011 at n = 128. Measured (`--scale pc`,
#: reports/pc): spreads 0.037, 0.019, 0.010, 0.0057, 0.0030 and errors 0.0007 to 0.0008 with
#: 12 samples at n = 128, whose searches took 139 s each; with the refine stage of the verdict
#: search they take 53 s on average (median 12 s), and n = 128 has 64 samples (error 0.00045;
#: 57 min of CPU). n = 128 stays out of the fss scale, which stays within its budget without
#: it, and is in pc and fss-cluster.
#: 3d (studies.three_d, the FCC lattice; 29 min on 2 workers by the estimate): per size 5
#:   threshold searches at p_t = 0.3 and 2 rods-only ones per sample, priced by paper.budget
#:   (0.34, 2.2, 8.4 s at p_t = 0.3 and n = 4, 6, 8; ~24 s at 10 extrapolated). Counts fall
#:   with n so that the sizes cost about the same. n = 10 has 6 samples per point: S_t/S_r's
#:   error there is about 0.02 if a 3D sample scatters as a 2D sample of as many nodes.
SIZES_3D = (4, 6, 8, 10)
SAMPLES_3D = (160, 64, 24, 6)
PC_3D = ((4, 640), (6, 320), (8, 160), (10, 48), (12, 16))
FSS_PC = ((8, 4000), (16, 1200), (32, 400), (64, 100), (128, 64))
FSS_PC_NO_128 = FSS_PC[:-1]
#: (n, samples) of the pc scale's pebble-game thresholds (one pass each, priced by
#: paper.budget's PEBBLE_SECONDS): the median's error is about 1.25 x the spread of the
#: thresholds / sqrt(S), spreads 0.0105, 0.0059, 0.0033, 0.0018 at n = 32 to 256 (measured), about
#: 0.001 at 512: 4000, 4000, 1000, 200 samples give 2.2e-4, 1.2e-4, 1.1e-4, 1.3e-4 (measured).
PC_PEBBLE = ((32, 4000), (64, 4000), (128, 1000), (256, 200), (512, 200))
SCALES = {
    "tiny": Scale(
        name="tiny", n_threshold=5, n_grid=5, samples_threshold=6, samples_grid=4,
        samples_fig4=6, p_r_step=0.1, node_trials=300, bootstrap=10,
        fss_sizes=(4, 5, 6, 8), samples_fss=3, n_delta=5, samples_delta=3,
        fss_pc=((4, 6), (5, 6), (6, 6), (8, 4), (10, 3)),
        studies=(*FIGURES, "method", "fss", "delta"), budget_minutes=2,
    ),
    "quick": Scale(
        name="quick", n_threshold=12, n_grid=12, samples_threshold=48, samples_grid=24,
        samples_fig4=96, p_r_step=0.05, node_trials=4000, bootstrap=100,
        n_method=12, samples_method=16, method_step=0.05,
        studies=(*FIGURES, "method"), budget_minutes=10,
    ),
    "paper": Scale(
        name="paper", n_threshold=32, n_grid=32, samples_threshold=24, samples_grid=24,
        samples_fig4=8, p_r_step=0.025, node_trials=10000, bootstrap=200,
        n_method=32, samples_method=16, method_step=0.025,
        studies=(*FIGURES, "method"), samples_curve=12, budget_minutes=50,
    ),
    "fss": Scale(
        name="fss", bootstrap=200,
        fss_sizes=(8, 16, 32, 64), samples_fss=(400, 160, 64, 8), samples_energy=24,
        fss_pc=FSS_PC_NO_128,
        deltas=(0.1, 0.2, 0.3), n_delta=32, samples_delta=24,
        studies=("fss", "delta"), budget_minutes=120,
    ),
    "pc": Scale(
        name="pc", bootstrap=200, fss_sizes=(), samples_fss=(), fss_pc=PC_PEBBLE,
        pc_method="pebble", studies=("fss",), budget_minutes=60,
    ),
    "3d": Scale(
        name="3d", bootstrap=200, fss_sizes=(), samples_fss=(),
        sizes_3d=SIZES_3D, samples_3d=SAMPLES_3D, pc_3d=PC_3D,
        studies=("three_d",), budget_minutes=60,
    ),
    "tiny-3d": Scale(
        name="tiny-3d", bootstrap=10, fss_sizes=(), samples_fss=(),
        sizes_3d=(2, 3, 4), samples_3d=(4, 3, 2), pc_3d=((2, 8), (3, 6), (4, 3)),
        studies=("three_d",), budget_minutes=1,
    ),
    "fss-cluster": Scale(
        name="fss-cluster", bootstrap=200,
        fss_sizes=(8, 16, 32, 64, 128), samples_fss=(400, 200, 96, 32, 8), samples_energy=24,
        fss_pc=FSS_PC,
        deltas=(0.1, 0.2, 0.3), n_delta=32, samples_delta=32,
        studies=("fss", "delta"),
    ),
}  # fmt: skip
