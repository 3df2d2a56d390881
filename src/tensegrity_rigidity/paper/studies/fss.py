"""Finite size: the headline claims at several n and their extrapolation to n -> infinity.

At the ``fss`` scale the study runs n = 8, 16, 32, 64 (:mod:`.headline` gives the sweeps
and the claims at one size). Where the scale gives ``fss_pc``, the rods-only point comes
from one-strain sweeps of its own (:func:`~.headline.rods_pc_sweep`) with more samples and
sizes: a rods-only threshold does not depend on the strain, and it is the one extrapolation
with a literature value precise to 3e-4; by the pebble game (the ``pc`` scale) they also give
the fractal dimensions of the spanning rigid cluster. Each claim is extrapolated with
``y(n) = y_inf + a n^(-1/nu)``
(:func:`~tensegrity_rigidity.analysis.scaling.fit_finite_size`): the rods-only point with nu
fitted (the literature's nu is a check, not an input), the others with nu fixed at that
value, and every claim a second time with nu fixed at the literature's :data:`NU_CHECK`.
The widths of the rods-only threshold distributions give a reading with no fitted exponent
(:func:`~tensegrity_rigidity.analysis.scaling.width_scaling`). The results are the
comparison's evidence for the factor "finite size", and every claim at every size is a
replication.

Like the figure modules: ``sweeps(scale)``, ``analyse(rows, scale)``, ``claims(result)`` and
``study(out, scale, **kw)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
from scipy import stats

from ...analysis import estimators as an
from ...model.lattice import DEFAULT_DELTA
from ..claims import CLAIMS, REFERENCES, REPLICATION, Measurement
from .headline import (
    ENERGY_KEYS,
    NU_CHECK,
    PC_CHECK,
    energy_names,
    energy_sweeps,
    headline,
    headline_sweeps,
    judged,
    rods_pc_sweep,
)
from .rows import Rows, load_sweeps
from .scales import Scale


@dataclass(frozen=True, eq=False)
class FiniteSizeResult:
    """The headline claims at several sizes and their extrapolation to n -> infinity.

    Attributes
    ----------
    by_size : DataFrame
        Per (n, key): value and err.
    extrapolated : DataFrame
        Per key: ``y_inf``, ``y_inf_err``, ``a``, ``nu``, ``nu_err``, ``nu_fixed``, ``chi2``,
        ``dof`` (:class:`~tensegrity_rigidity.analysis.scaling.FiniteSizeFit`; nu fitted
        for the rods-only threshold, fixed at its fitted value for the other claims),
        ``z_paper``, the agreement statistic of ``y_inf`` against the paper's claim, and
        ``verdict_paper``, the comparison's verdict on it
        (:func:`~tensegrity_rigidity.paper.comparison.verdict`). The same extrapolation with
        nu fixed at :data:`NU_CHECK` (value and error) for every key, the rods-only threshold
        included: ``y_inf_nu_check``, ``y_inf_nu_check_err``, ``chi2_nu_check``,
        ``dof_nu_check``, ``z_paper_nu_check`` and ``verdict_paper_nu_check``. A claim whose
        two verdicts differ has an extrapolation that depends on nu.
    nu_z : float
        The fitted nu against :data:`NU_CHECK`, in units of both errors.
    pc_z : float
        The extrapolated rods-only threshold against :data:`PC_CHECK`, in units of its error.
    pc_at_check_nu : FiniteSizeFit or None
        The rods-only extrapolation with nu fixed at :data:`NU_CHECK` (a second reading, shown
        beside the free fit; the other claims use the free fit's nu).
    pc_at_check_nu_z : float
        That extrapolation against :data:`PC_CHECK`.
    nu_at_bound : bool
        Whether the free fit's nu ended at a bound of its allowed range (the sizes do not
        determine it).
    energy_samples : tuple of int
        Samples per point of the energy grids at each of ``sizes``.
    excluded, bracketed : dict
        Sweep name -> undecided rows; -> of those, the rows whose E* is bracketed, which still
        enter the energy analyses
        (:func:`~tensegrity_rigidity.paper.studies.energy_bracketed`).
    pc_sizes, pc_samples : tuple of int
        Sizes of the rods-only extrapolation and its samples at each (the headline sweeps'
        unless the scale gives ``fss_pc``).
    pc_widths : WidthScaling or None
        The rods-only threshold distributions' widths and centres against size (where the
        scale gives ``fss_pc``): nu from the widths alone and p_c from the centre against the
        width, a second reading with no fitted exponent
        (:func:`~tensegrity_rigidity.analysis.scaling.width_scaling`).
    pc_widths_z, pc_widths_nu_z : float
        Its p_c against :data:`PC_CHECK` and its nu against :data:`NU_CHECK`.
    pc_by_smallest : DataFrame
        The rods-only extrapolation refitted from the sizes ``n >= n_min``, one row per
        ``n_min`` (:func:`pc_by_smallest_size`): how much the extrapolation rests on the
        smallest sizes, where corrections to scaling are largest.
    fractal : DataFrame or None
        Where the rods-only sweeps ran the pebble game: the fractal dimensions of the spanning
        rigid cluster and of its stressed part at the threshold (:func:`fractal_dimensions`).
    fractal_by_size : DataFrame or None
        Their mean masses per size (:func:`fractal_dimensions`).
    picture : ClusterPicture or None
        One pebble-game sample at its threshold, for the figure of its clusters
        (:func:`cluster_picture`).
    measured : tuple of Measurement
        The evidence for the comparison's factor "finite size": per claim, the extrapolation
        with the free fit's nu and the one with nu fixed at :data:`NU_CHECK`, labelled so; and
        every claim at every size as a replication (:func:`replications`).
    """

    by_size: pd.DataFrame
    extrapolated: pd.DataFrame
    nu_z: float
    pc_z: float
    sizes: tuple[int, ...]
    samples: tuple[int, ...]  # per size
    excluded: dict[str, int]
    energy_samples: tuple[int, ...] = ()  # per size, of the energy grids
    bracketed: dict[str, int] = field(default_factory=dict)
    measured: tuple[Measurement, ...] = ()
    pc_at_check_nu: an.FiniteSizeFit | None = None
    pc_at_check_nu_z: float = float("nan")
    nu_at_bound: bool = False
    pc_sizes: tuple[int, ...] = ()  # sizes of the rods-only extrapolation
    pc_samples: tuple[int, ...] = ()  # its samples per size
    pc_widths: an.WidthScaling | None = None
    pc_widths_z: float = float("nan")
    pc_widths_nu_z: float = float("nan")
    pc_by_smallest: pd.DataFrame | None = None
    fractal: pd.DataFrame | None = None
    fractal_by_size: pd.DataFrame | None = None
    picture: ClusterPicture | None = None


@dataclass(frozen=True, eq=False)
class ClusterPicture:
    """One rods-only sample just after its threshold event, with its rigid clusters.

    Attributes
    ----------
    network : PeriodicNetwork
        The sample's rods at the threshold (the threshold bond included).
    clusters : RigidClusters
        Its rigid clusters and overconstrained sites
        (:func:`~tensegrity_rigidity.combinatorics.clusters.rigid_clusters`).
    spanning : SpanningCluster
        The spanning rigid cluster (the threshold bond's) and its stressed sites.
    n, sample : int
        Its size and sample index (of :func:`rods_pc_sweep`'s pebble sweep).
    p_r : float
        Its threshold.
    """

    network: Any
    clusters: Any
    spanning: Any
    n: int
    sample: int
    p_r: float


#: the size and sample drawn at its threshold in the pc report (64: small enough to read)
PICTURE_N, PICTURE_SAMPLE = 64, 1


def cluster_picture(sizes: tuple[int, ...], delta: float = DEFAULT_DELTA) -> ClusterPicture | None:
    """Sample :data:`PICTURE_SAMPLE` of the pebble sweep at the size of ``sizes`` nearest
    :data:`PICTURE_N`, at its threshold (None if it never becomes rigid).

    Rebuilt from its seed, as the sweep built it (a second pass of the pebble game, then the
    full labelling of that one network).
    """
    from ...combinatorics.clusters import rigid_clusters
    from ...ensemble.runner import sample_geometry
    from ...ensemble.spec import parse_spec
    from ...ensemble.thresholds import pebble_pass
    from ...model.elements import place_elements

    n = min(sizes, key=lambda k: (abs(math.log(k / PICTURE_N)), k))
    ((_, raw),) = rods_pc_sweep(n, delta, PICTURE_SAMPLE, "pebble").items()
    spec = parse_spec(raw)
    point = spec.points()[0]
    net, u, v, _ = sample_geometry(spec, point, PICTURE_SAMPLE)
    th, spanning = pebble_pass(net, u, v)
    if not np.isfinite(th.s):
        return None
    # rods with u <= s: the threshold bond (u = s) included
    at = net.with_kinds(place_elements(u, v, np.nextafter(th.s, np.inf), 0.0, 0.5))
    return ClusterPicture(at, rigid_clusters(at), spanning, n, PICTURE_SAMPLE, th.s)


#: (name, mass column of the pebble-game rows, literature value) of the clusters whose fractal
#: dimension the pc scale measures at the threshold
FRACTAL_CLUSTERS = (
    ("rigid", "cluster_nodes", REFERENCES["df_rigid_javerzat_notarmuzi"]),
    ("stressed", "stressed_nodes", REFERENCES["df_stressed_jacobs_thorpe"]),
)
#: their masses counted in bond sites instead of nodes: a second reading of the same exponent
FRACTAL_SITES = {"rigid": "cluster_sites", "stressed": "stressed_sites"}


def fractal_dimensions(
    sizes: tuple[int, ...], rows: list[pd.DataFrame], scale: Scale
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Fractal dimensions of the spanning rigid cluster and its stressed part at threshold.

    Parameters
    ----------
    sizes : tuple of int
        The sizes of the rods-only sweeps.
    rows : list of DataFrame
        Their pebble-game rows, one frame per size (columns of
        :data:`FRACTAL_CLUSTERS` and :data:`FRACTAL_SITES`; samples never rigid are left out).
    scale : Scale
        Bootstrap replicas and generators.

    Returns
    -------
    fits : DataFrame
        One row per (``cluster``, ``mass`` = "nodes" or "sites", ``n_min``: the smallest size
        fitted, all sizes and without the smallest): ``d``, ``d_err``, ``chi2``, ``dof``, the
        literature value ``reference`` with ``reference_err`` and ``z`` against it
        (:func:`~tensegrity_rigidity.analysis.scaling.fractal_dimension`: ``M ~ n^d``, the mass
        of each sample at its own threshold, the wrapping event).
    by_size : DataFrame
        Per size: ``n``, ``samples`` and, per cluster and mass, the mean and its error
        (``<cluster>_<mass>``, ``<cluster>_<mass>_err``).
    """
    n = np.asarray(sizes, float)
    rigid = [r[np.isfinite(r.threshold_p_r)] for r in rows]
    by_size = pd.DataFrame({"n": np.asarray(sizes, int), "samples": [len(r) for r in rigid]})
    fits = []
    for name, nodes_col, ref in FRACTAL_CLUSTERS:
        for mass, col in (("nodes", nodes_col), ("sites", FRACTAL_SITES[name])):
            masses = [r[col].to_numpy(float) for r in rigid]
            for k, n_min in enumerate(n[: max(1, n.size - 2)]):
                fit = an.fractal_dimension(
                    n[k:], masses[k:], scale.bootstrap, rng=scale.rng("fractal", k)
                )
                if k == 0:
                    by_size[f"{name}_{mass}"] = fit.mass
                    by_size[f"{name}_{mass}_err"] = fit.mass_err
                ref_err = ref.error or 0.0
                fits.append(
                    {
                        "cluster": name,
                        "mass": mass,
                        "n_min": int(n_min),
                        "d": fit.d,
                        "d_err": fit.d_err,
                        "chi2": fit.chi2,
                        "dof": fit.dof,
                        "reference": ref.value,
                        "reference_err": ref_err,
                        "z": an.agreement_z(fit.d, fit.d_err**2, ref.value, ref_err),
                    }
                )
    return pd.DataFrame(fits), by_size


def _at_bound(nu: float) -> bool:
    """Whether a free fit's 1/nu ended at a bound of
    :data:`~tensegrity_rigidity.analysis.scaling.THETA` (False for NaN)."""
    return bool(np.any(np.isclose(1.0 / nu, an.THETA, rtol=1e-6)))


def pc_by_smallest_size(
    n: np.ndarray, y: np.ndarray, err: np.ndarray, scale: Scale
) -> pd.DataFrame:
    """The rods-only extrapolation refitted without the smallest sizes.

    ``p_c(n) = p_c + a n^(-1/nu)`` holds only asymptotically: corrections to scaling, largest
    at the smallest n, pull a fit towards them, the more so as their errors are the smallest
    (most samples). Dropping sizes one at a time from below shows how much the extrapolation
    rests on them; a reading that moves by more than its error is not determined by the data.

    Parameters
    ----------
    n, y, err : (K,) float
        Sizes (ascending), P = 1/2 points and their standard errors.
    scale : Scale
        The bootstrap generators of the fits.

    Returns
    -------
    DataFrame
        One row per ``n_min`` leaving at least two sizes: ``n_min``, ``sizes``; the free fit's
        ``p_c``, ``p_c_err``, ``nu``, ``nu_err``, ``chi2``, ``dof`` and ``z`` against
        :data:`PC_CHECK` (NaN with fewer than three sizes) and ``nu_at_bound``, whether its
        1/nu ended at a bound of :data:`~tensegrity_rigidity.analysis.scaling.THETA` (the
        sizes do not determine nu; False where the fit failed); the fit with nu fixed at
        :data:`NU_CHECK`'s ``p_c_fixed``, ``p_c_fixed_err``, ``chi2_fixed``, ``dof_fixed``
        and ``z_fixed``.
    """
    n, y, err = (np.asarray(a, float) for a in (n, y, err))
    rows = []
    for n_min in n[:-1]:
        keep = n >= n_min
        free = an.fit_finite_size(n[keep], y[keep], err[keep], rng=scale.rng("finite_size"))
        fixed = an.fit_finite_size(
            n[keep], y[keep], err[keep], nu=NU_CHECK.value, nu_err=NU_CHECK.error or 0.0,
            rng=scale.rng("finite_size"),
        )  # fmt: skip
        rows.append(
            {
                "n_min": int(n_min),
                "sizes": int(keep.sum()),
                "p_c": free.y_inf,
                "p_c_err": free.y_inf_err,
                "nu": free.nu,
                "nu_err": free.nu_err,
                "chi2": free.chi2,
                "dof": free.dof,
                "z": an.agreement_z(free.y_inf, free.y_inf_err**2, PC_CHECK.value, 0.0),
                "nu_at_bound": _at_bound(free.nu),
                "p_c_fixed": fixed.y_inf,
                "p_c_fixed_err": fixed.y_inf_err,
                "chi2_fixed": fixed.chi2,
                "dof_fixed": fixed.dof,
                "z_fixed": an.agreement_z(fixed.y_inf, fixed.y_inf_err**2, PC_CHECK.value, 0.0),
            }
        )
    return pd.DataFrame(rows)


def analyse(rows: Rows, scale: Scale) -> FiniteSizeResult:
    """The headline claims at each of ``scale.fss_sizes`` from the rows of :func:`sweeps`
    (:func:`~.headline.headline`), the rods-only point at its own sizes where the scale gives
    ``fss_pc``, and their n -> infinity limits (:func:`extrapolate`)."""
    frames: list[pd.DataFrame] = []
    excluded: dict[str, int] = {}
    bracketed: dict[str, int] = {}
    for n in scale.fss_sizes:
        f, ex, br = headline(
            rows, n, DEFAULT_DELTA, scale,
            samples=scale.fss_samples(n), energy=scale.fss_energy_samples(n),
        )  # fmt: skip
        frames.append(f.assign(n=n))
        excluded |= ex
        bracketed |= br
    by_size = (
        pd.concat(frames, ignore_index=True)
        if frames  # the pc scale measures only the rods-only point
        else pd.DataFrame(columns=["key", "value", "err", "n"])
    )
    widths = None
    fractal = fractal_by_size = picture = None
    if scale.fss_pc:  # the rods-only point from its own sweeps, at its own sizes
        pc_rows, per_size, pc_frames = [], [], []
        for n in scale.pc_sizes:
            (name,) = rods_pc_sweep(n, DEFAULT_DELTA, scale.pc_samples(n), scale.pc_method)
            pc, excluded[name] = rows[name]
            pc_frames.append(pc)
            per_size.append(pc.threshold_p_r.to_numpy(float))
            value, err = an.critical_point(per_size[-1], rng=scale.rng("critical_point"))
            width = (pc.threshold_p_r_high - pc.threshold_p_r_low).to_numpy(float)
            pc_rows.append(
                {
                    "key": "rods_only_pc",
                    "value": value,
                    "err": err,
                    "n": n,
                    "samples": len(pc),
                    # thresholds left as intervals by undecided probes, and their mean width
                    "intervals": int(np.sum(width > 0)),
                    "width": float(np.nanmean(width)) if width.size else np.nan,
                }
            )
        by_size = pd.concat(
            [by_size[by_size.key != "rods_only_pc"], pd.DataFrame(pc_rows)], ignore_index=True
        )
        widths = an.width_scaling(
            np.asarray(scale.pc_sizes, float), per_size, rng=scale.rng("widths")
        )
        if scale.pc_method == "pebble" and len(scale.pc_sizes) >= 2:
            fractal, fractal_by_size = fractal_dimensions(scale.pc_sizes, pc_frames, scale)
            picture = cluster_picture(scale.pc_sizes)

    return extrapolate(
        by_size, scale, excluded=excluded, bracketed=bracketed, pc_widths=widths,
        fractal=fractal, fractal_by_size=fractal_by_size, picture=picture,
    )  # fmt: skip


def extrapolate(
    by_size: pd.DataFrame,
    scale: Scale,
    *,
    pc_widths: an.WidthScaling | None = None,
    excluded: dict[str, int] | None = None,
    **extra,
) -> FiniteSizeResult:
    """Every claim of ``by_size`` extrapolated to n -> infinity, twice.

    The rods-only point with nu fitted; the other claims with nu fixed at that fit's value
    (its error widens theirs); every claim again with nu fixed at :data:`NU_CHECK`.

    Parameters
    ----------
    by_size : DataFrame
        Per (n, key): ``value`` and ``err`` (``samples`` where a row's count is not the
        scale's); a ``rods_only_pc`` row at two sizes at least.
    scale : Scale
        The study's scale (its sizes, sample counts and bootstrap generators).
    pc_widths : WidthScaling, optional
        The rods-only widths reading (:attr:`FiniteSizeResult.pc_widths`), compared here with
        the literature.
    excluded : dict, optional
        Sweep name -> undecided rows (none by default).
    **extra
        Further fields of :class:`FiniteSizeResult` (``bracketed``, ``fractal``, ...).

    Returns
    -------
    FiniteSizeResult
    """
    widths = pc_widths

    def series(key) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        s = by_size[by_size.key == key].sort_values("n")
        return s.n.to_numpy(float), s.value.to_numpy(float), s.err.to_numpy(float)

    pc_fit = an.fit_finite_size(*series("rods_only_pc"), rng=scale.rng("finite_size"))
    fits = {"rods_only_pc": pc_fit}
    for key in by_size.key.unique():
        if key != "rods_only_pc":
            fits[key] = an.fit_finite_size(
                *series(key), nu=pc_fit.nu, nu_err=pc_fit.nu_err, rng=scale.rng("finite_size")
            )
    # the second reading of every claim: nu fixed at the literature's value, not the free fit's
    nu_check, nu_check_err = NU_CHECK.value, NU_CHECK.error or 0.0
    checks = {
        key: an.fit_finite_size(
            *series(key), nu=nu_check, nu_err=nu_check_err, rng=scale.rng("finite_size")
        )
        for key in fits
    }
    extrapolated = pd.DataFrame([{"key": k, **f.__dict__} for k, f in fits.items()])
    free = [judged(r.key, r.y_inf, r.y_inf_err) for r in extrapolated.itertuples()]
    extrapolated["z_paper"] = [z for z, _ in free]
    extrapolated["verdict_paper"] = [v for _, v in free]
    extrapolated["y_inf_nu_check"] = [checks[k].y_inf for k in extrapolated.key]
    extrapolated["y_inf_nu_check_err"] = [checks[k].y_inf_err for k in extrapolated.key]
    extrapolated["chi2_nu_check"] = [checks[k].chi2 for k in extrapolated.key]
    extrapolated["dof_nu_check"] = [checks[k].dof for k in extrapolated.key]
    fixed = [judged(k, checks[k].y_inf, checks[k].y_inf_err) for k in extrapolated.key]
    extrapolated["z_paper_nu_check"] = [z for z, _ in fixed]
    extrapolated["verdict_paper_nu_check"] = [v for _, v in fixed]
    nu_z = an.agreement_z(pc_fit.nu, pc_fit.nu_err**2, nu_check, nu_check_err)
    pc_z = an.agreement_z(pc_fit.y_inf, pc_fit.y_inf_err**2, PC_CHECK.value, 0.0)
    at_check = checks["rods_only_pc"]
    at_check_z = an.agreement_z(at_check.y_inf, at_check.y_inf_err**2, PC_CHECK.value, 0.0)
    at_bound = _at_bound(pc_fit.nu)
    widths_z = widths_nu_z = float("nan")
    if widths is not None:
        widths_z = an.agreement_z(widths.p_c, widths.p_c_err**2, PC_CHECK.value, 0.0)
        widths_nu_z = an.agreement_z(
            widths.nu, widths.nu_err**2, NU_CHECK.value, NU_CHECK.error or 0.0
        )
    where = (
        f"extrapolated to n -> infinity from n = {', '.join(map(str, scale.fss_sizes))} "
        + (f"(rods-only p_c: n = {', '.join(map(str, scale.pc_sizes))}) " if scale.fss_pc else "")
        if scale.fss_sizes
        else f"extrapolated to n -> infinity from n = {', '.join(map(str, scale.pc_sizes))} "
    )
    label = where + f"(y + a n^(-1/nu), nu = {pc_fit.nu:.2f} ± {pc_fit.nu_err:.2f})"
    label_check = where + (
        f"(y + a n^(-1/nu), nu fixed at {nu_check:.2f} ± {nu_check_err:.2f}, the literature value)"
    )
    measured = tuple(
        Measurement.scalar(
            row.key,
            value,
            err,
            f"{_samples_text(scale, row.key in ENERGY_KEYS, row.key == 'rods_only_pc')} "
            "samples per point",
            factor="finite size",
            label=text + misfit(chi2, dof),
        )
        for row in extrapolated.itertuples()
        if row.key in CLAIMS
        for value, err, chi2, dof, text in (
            (row.y_inf, row.y_inf_err, row.chi2, row.dof, label),
            (
                row.y_inf_nu_check,
                row.y_inf_nu_check_err,
                row.chi2_nu_check,
                row.dof_nu_check,
                label_check,
            ),
        )
    )
    measured += replications(by_size, scale)
    return FiniteSizeResult(
        by_size=by_size,
        extrapolated=extrapolated,
        nu_z=nu_z,
        pc_z=pc_z,
        sizes=tuple(scale.fss_sizes),
        samples=tuple(scale.fss_samples(n) for n in scale.fss_sizes),
        energy_samples=tuple(scale.fss_energy_samples(n) for n in scale.fss_sizes),
        pc_sizes=scale.pc_sizes,
        pc_samples=tuple(scale.pc_samples(n) for n in scale.pc_sizes),
        measured=measured,
        pc_at_check_nu=at_check,
        pc_at_check_nu_z=at_check_z,
        nu_at_bound=at_bound,
        excluded=excluded or {},
        pc_widths=widths,
        pc_widths_z=widths_z,
        pc_widths_nu_z=widths_nu_z,
        pc_by_smallest=pc_by_smallest_size(*series("rods_only_pc"), scale),
        **extra,
    )


def replications(by_size: pd.DataFrame, scale: Scale) -> tuple[Measurement, ...]:
    """Each claim at each size of the study as a replication
    (:data:`~tensegrity_rigidity.paper.claims.REPLICATION`): the comparison sets it beside our
    own measurement of the same size.

    The study's samples (seed 61) are not those of the figure studies (seeds 12 and 21), and
    there are usually more of them (400 rods-only thresholds at n = 32 in ``--scale fss``
    against Fig. 1C's 24 samples at ``--scale paper``), so a value that agrees with the paper
    only at the figure study's precision shows it here.

    Parameters
    ----------
    by_size : DataFrame
        :attr:`FiniteSizeResult.by_size` (``key``, ``value``, ``err``, ``n``; ``samples``
        where a row's count is not the scale's).
    scale : Scale
        The study's scale (its sample counts per size).

    Returns
    -------
    tuple of Measurement
        One per row of ``by_size`` whose key is a claim: factor
        :data:`~tensegrity_rigidity.paper.claims.REPLICATION`, ``size`` its n, and its sample
        count in ``system`` (nominal, except the rods-only point's, which counts its rows).
    """
    out = []
    for row in by_size.itertuples():
        if row.key not in CLAIMS:
            continue
        n = int(row.n)
        count = getattr(row, "samples", np.nan)
        if not np.isfinite(count):
            energy = row.key in ENERGY_KEYS
            count = scale.fss_energy_samples(n) if energy else scale.fss_samples(n)
        out.append(
            Measurement.scalar(
                row.key,
                row.value,
                row.err,
                f"n = {n}, {int(count)} samples per point",
                factor=REPLICATION,
                label="the same size on the finite-size study's samples (seed 61)",
                size=n,
            )
        )
    return tuple(out)


def nu_dependent(extrapolated: pd.DataFrame) -> tuple[list[str], int]:
    """The claims whose verdict differs between the free fit's nu and nu fixed at
    :data:`NU_CHECK`.

    Parameters
    ----------
    extrapolated : DataFrame
        :attr:`FiniteSizeResult.extrapolated` (``key``, ``verdict_paper`` and
        ``verdict_paper_nu_check``).

    Returns
    -------
    changed : list of str
        Keys of the claims whose two verdicts differ ("agree", "disagree" or "inconclusive"):
        their extrapolation depends on nu.
    compared : int
        Claims with a verdict under both (neither extrapolation "n/a").
    """
    ex = extrapolated[extrapolated.key.isin(list(CLAIMS))]
    both = ex[(ex.verdict_paper != "n/a") & (ex.verdict_paper_nu_check != "n/a")]
    changed = both[both.verdict_paper != both.verdict_paper_nu_check]
    return list(changed.key), len(both)


#: a finite-size fit whose chi-square is less probable than this does not describe its sizes
MISFIT_P = 0.01


def misfit(chi2: float, dof: int) -> str:
    """A clause for an extrapolation whose form does not fit its points ("" when it does).

    With the per-size errors taken as right
    (:func:`~tensegrity_rigidity.analysis.scaling.fit_finite_size`), a chi-square above its
    99th percentile means the values do not follow
    ``y_inf + a n^(-1/nu)`` (non-monotone in n, say), and ``y_inf`` and its error say little:
    the comparison says so beside the extrapolated value.
    """
    if not (dof > 0 and np.isfinite(chi2)) or stats.chi2.sf(chi2, dof) >= MISFIT_P:
        return ""
    return f" [chi-square {chi2:.0f} with {dof} dof: the form does not fit these sizes]"


def _samples_text(scale: Scale, energy: bool = False, pc: bool = False) -> str:
    """The sample counts per size (of the energy sweeps when ``energy``, of the rods-only p_c
    sweeps when ``pc``): one number when they are equal, else one per size."""
    if pc:
        count, sizes = scale.pc_samples, scale.pc_sizes
    else:
        count = scale.fss_energy_samples if energy else scale.fss_samples
        sizes = tuple(scale.fss_sizes)
    counts = [count(n) for n in sizes]
    if len(set(counts)) == 1:
        return str(counts[0])
    return f"{', '.join(map(str, counts))} (n = {', '.join(map(str, sizes))})"


def sweeps(scale: Scale) -> dict[str, dict]:
    """Sweep name -> spec of the finite-size study (every size at the default delta)."""
    out: dict[str, dict] = {}
    for n in scale.fss_sizes:
        out |= headline_sweeps(n, DEFAULT_DELTA, scale.fss_samples(n))
        out |= energy_sweeps(n, DEFAULT_DELTA, count=scale.fss_energy_samples(n))
    for n, samples in scale.fss_pc:
        out |= rods_pc_sweep(n, DEFAULT_DELTA, samples, scale.pc_method)
    return out


def claims(result: FiniteSizeResult) -> tuple[Measurement, ...]:
    """The evidence for the factor "finite size" and the replications
    (:attr:`FiniteSizeResult.measured`)."""
    return result.measured


def study(out, scale: Scale, **kw) -> FiniteSizeResult:
    """Run (or resume) the finite-size sweeps into ``out`` and analyse them."""
    specs = sweeps(scale)
    return analyse(load_sweeps(out, specs, energy=energy_names(specs), **kw), scale)
