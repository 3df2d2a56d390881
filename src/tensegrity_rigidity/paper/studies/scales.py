"""System sizes, sample counts and bootstrap seeds of a reproduction: the scales."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: the bootstrap stream of each estimator (:meth:`Scale.rng`): the seeds each estimator has
#: always drawn from, so the error bars are those of the earlier releases (a few estimators of
#: different quantities share a seed)
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
    "disagreement": 1,
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
    n_method: int = 5  # the paper's method beside ours (studies.method)
    samples_method: int = 4
    method_step: float = 0.1
    fss_sizes: tuple[int, ...] = (4, 5, 6, 8)  # finite-size study (studies.fss)
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

    def rng(self, estimator: str, offset: int = 0) -> np.random.Generator:
        """A fresh generator for one estimator's bootstrap replicas.

        Parameters
        ----------
        estimator : str
            A key of :data:`BOOTSTRAP_STREAMS`.
        offset : int
            Added to the seed: one estimator applied to several subsets (one per smallest
            size, say) draws one stream per subset.

        Returns
        -------
        numpy.random.Generator
            Seeded with the estimator's stream plus :attr:`bootstrap_seed`, so that every
            estimate of a scale is reproducible and the estimators draw independent replicas.
        """
        return stream(estimator, self.bootstrap_seed + offset)

    @property
    def curve_samples(self) -> int:
        return self.samples_threshold if self.samples_curve is None else self.samples_curve

    @property
    def fig1b_samples(self) -> int:
        return self.samples_threshold if self.samples_fig1b is None else self.samples_fig1b


FIGURES = ("fig1b", "fig1c", "fig2", "fig3", "fig4")
# The counts of the large scales follow from target error bars: a headline estimator's
# bootstrap error is sigma_1(n) / sqrt(S) (sigma_1 measured, paper.budget), with at least 24
# samples wherever an error bar is compared. Targets: S_t/S_r +-0.013 (the paper's), p_crit
# and p_c +-0.005, the taut-cable fraction +-0.02, Fig. 4C +-0.1 (not met at n = 32: its
# middle is 0/0 there). docs/guide/reproduction.md derives each count.

#: FCC sizes of the 3d scale and their samples per point: the sizes cost about the same
SIZES_3D = (4, 6, 8, 10)
SAMPLES_3D = (160, 64, 24, 6)
#: (n, samples) of the 3d scale's rods-only thresholds
PC_3D = ((4, 640), (6, 320), (8, 160), (10, 48), (12, 16))
#: (n, samples) of the rods-only thresholds of the p_c extrapolation at the fss scales: the
#: median's error is about 1.25 x the threshold spread / sqrt(S), 0.0007 to 0.0011 per size
FSS_PC = ((8, 4000), (16, 1200), (32, 400), (64, 100), (128, 64))
FSS_PC_NO_128 = FSS_PC[:-1]
#: (n, samples) of the pc scale's pebble-game thresholds: errors 1.1e-4 to 2.2e-4 per size
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
