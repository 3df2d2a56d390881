"""Finite size: the headline claims at several n and their extrapolation to n -> infinity.

The headline claims at each size (:mod:`.headline`); the rods-only point, where the scale gives
``pc``, from one-strain sweeps of its own with more samples and sizes (by the pebble game at
the ``pc`` scale, which also measures the fractal dimensions of the spanning rigid cluster).
Each claim is extrapolated with ``y(n) = y_inf + a n^(-1/nu)``
(:func:`~tensegrity_rigidity.analysis.scaling.fit_finite_size`): the rods-only point with nu
fitted, the others with nu fixed at that value, and every claim again with nu fixed at the
literature's :data:`~.headline.NU_CHECK`; the widths of the rods-only thresholds give a reading
with no fitted exponent. The results are the comparison's evidence for the factor "finite
size", and every claim at every size is a replication.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.ticker import NullLocator

from ...analysis import estimators as an
from ...analysis import limits
from ...analysis.agreement import chi2_against
from ...model.lattice import DEFAULT_DELTA
from ..claims import CLAIMS, REFERENCES, REPLICATION, Measurement
from ..comparison import AGREE_BELOW, decimals, fit_form, fmt
from ..plotting import CYCLE, draw_clusters
from ..study import Result, Scale, Study
from ..style import PAGE, grid, save, size_axis, unresolved, width_panel
from ..style import errorbar as bars
from ..template import load
from .headline import (
    ENERGY_KEYS,
    ENERGY_SAMPLES,
    ENERGY_STEP,
    NU_CHECK,
    PC_CHECK,
    energy_names,
    energy_sweeps,
    headline,
    headline_sweeps,
    judged,
    misfit,
    paper_pcrit,
    rods_pc_sweep,
)
from .rows import PT4, Rows

NAME = "fss"
T = load(NAME)
#: (n, samples) of the rods-only thresholds of the p_c extrapolation: the median's error is
#: about 1.25 x the threshold spread / sqrt(S), 0.0007 to 0.0011 per size
FSS_PC = ((8, 4000), (16, 1200), (32, 400), (64, 100), (128, 64))
#: the same by the pebble game (the pc scale): 2,000 or more samples per size, for the masses
#: of the spanning cluster to 0.5 % per size (d_f to about 0.005) and p_c to about 1e-4
PC_PEBBLE = ((32, 4000), (64, 4000), (128, 4000), (256, 2000), (512, 2000))
#: the same with n = 1024 added (1,000 samples at about 25 CPU s each, a pebble-game pass
#: over 3 million sites: about 7 CPU hours): a Dask cluster's work
PC_PEBBLE_CLUSTER = (*PC_PEBBLE, (1024, 1000))
#: the rods-only transition's own correlation-length exponent: the calibration fixes nu here
#: (p_c is then a linear fit) instead of fitting it, and borrows no other transition's
NU_PC = REFERENCES["nu_javerzat_notarmuzi"]
#: the literature's p_c the calibration is set beside: two recent values 3.4 errors apart
PC_ANCHORS = ("pc_javerzat_notarmuzi", "pc_dynamic_pebble")
#: exponents of the one correction to scaling, p_c + a n^(-1/nu) (1 + b n^-omega): the
#: leading correction of 2D rigidity percolation is not known, so a range that spans those of
#: 2D percolation-type transitions; the spread of p_c over the fits the data allow is its
#: systematic. The reference fit takes OMEGA_REF over every size
OMEGAS = (0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0)
OMEGA_REF = 1.0
#: the laws every claim's limit is read from besides the nu-fixed extrapolations: a finite
#: limit with the claim's own correction exponent, and no size dependence (no headline claim
#: can vanish, so no power law to zero); the spread over the allowed ones is the systematic
LIMIT_LAWS = ("finite", "constant")
#: the sizes at which the paper's effective size is looked for: the paper states no n, and
#: our values move towards its as n falls below the finite-size scale's smallest, 8
PAPER_SIZES = (4, 6, 8, 10, 12)


@dataclass(frozen=True, kw_only=True)
class Params:
    """Sizes and samples per point (one count, or one per size); energy grids per size (None:
    the first :data:`~.headline.ENERGY_SAMPLES` at most); (n, samples) of the rods-only sweeps
    of the p_c extrapolation (() reads the headline sweeps) and their threshold method ("lp",
    the certified bisection, or "pebble")."""

    sizes: tuple[int, ...] = (4, 5, 6, 8)
    samples: int | tuple[int, ...] = 6
    energy: int | tuple[int, ...] | None = None
    pc: tuple[tuple[int, int], ...] = ()
    pc_method: str = "lp"

    def __post_init__(self):
        for name in ("samples", "energy"):
            value = getattr(self, name)
            if isinstance(value, tuple) and len(value) != len(self.sizes):
                raise ValueError(f"{name} has {len(value)} counts for {len(self.sizes)} sizes")

    def _at(self, value, n: int) -> int:
        return value if isinstance(value, int) else value[self.sizes.index(n)]

    def samples_at(self, n: int) -> int:
        return self._at(self.samples, n)

    def energy_at(self, n: int) -> int:
        if self.energy is None:
            return min(self.samples_at(n), ENERGY_SAMPLES)
        return self._at(self.energy, n)

    @property
    def pc_sizes(self) -> tuple[int, ...]:
        return tuple(n for n, _ in self.pc) if self.pc else tuple(self.sizes)

    def pc_at(self, n: int) -> int:
        return dict(self.pc)[n] if self.pc else self.samples_at(n)


PARAMS = {
    "tiny": Params(samples=3, pc=((4, 6), (5, 6), (6, 6), (8, 4), (10, 3))),
    "fss": Params(sizes=(8, 16, 32, 64), samples=(400, 160, 64, 8), energy=24, pc=FSS_PC[:-1]),
    "pc": Params(sizes=(), samples=(), pc=PC_PEBBLE, pc_method="pebble"),
    "pc-cluster": Params(sizes=(), samples=(), pc=PC_PEBBLE_CLUSTER, pc_method="pebble"),
    "paper-size": Params(sizes=PAPER_SIZES, samples=(400, 400, 320, 240, 160), energy=24),
    "fss-cluster": Params(sizes=(8, 16, 32, 64, 128), samples=(400, 200, 96, 32, 8), energy=24,
                          pc=FSS_PC),
}  # fmt: skip


@dataclass(frozen=True, eq=False)
class ClusterPicture:
    """One rods-only sample just after its threshold event: its ``network`` (the threshold
    bond included), ``clusters`` (rigid clusters), ``spanning`` cluster, ``n``, ``sample`` and
    threshold ``p_r``."""

    network: Any
    clusters: Any
    spanning: Any
    n: int
    sample: int
    p_r: float


@dataclass(frozen=True, eq=False)
class FiniteSizeResult(Result):
    """The headline claims at several sizes and their extrapolations.

    ``by_size``: per (n, key) value and err (``samples``, ``intervals``, ``width`` for the
    rods-only rows of their own sweeps). ``extrapolated``: per key the
    :class:`~tensegrity_rigidity.analysis.scaling.FiniteSizeFit` fields (nu fitted for the
    rods-only point, fixed at its value for the others), ``z_paper`` and ``verdict_paper``
    against the paper, and the same with nu fixed at :data:`~.headline.NU_CHECK`
    (``*_nu_check``). ``nu_z``, ``pc_z``: the free fit against the literature;
    ``pc_at_check_nu``: the rods-only fit with nu fixed there; ``pc_widths``: the widths
    reading (:class:`~tensegrity_rigidity.analysis.scaling.WidthScaling`); ``pc_by_smallest``:
    :func:`pc_by_smallest_size`; ``pc_calibration``: :func:`pc_calibration`; ``fractal``,
    ``fractal_by_size``, ``picture``: the pebble game's clusters (:func:`fractal_dimensions`,
    :func:`cluster_picture`). ``paper_pcrit``: per (n, key) the p_crit claims by the paper's
    estimator (:func:`~.headline.first_positive_pcrit`); ``paper_fit``: :func:`paper_fit` under
    both estimators; ``paper_claims``: :func:`paper_claims`.
    """

    by_size: pd.DataFrame
    extrapolated: pd.DataFrame
    nu_z: float
    pc_z: float
    sizes: tuple[int, ...]
    samples: tuple[int, ...]
    energy_samples: tuple[int, ...] = ()
    pc_at_check_nu: an.FiniteSizeFit | None = None
    pc_at_check_nu_z: float = float("nan")
    nu_at_bound: bool = False
    pc_sizes: tuple[int, ...] = ()
    pc_samples: tuple[int, ...] = ()
    pc_widths: an.WidthScaling | None = None
    pc_widths_z: float = float("nan")
    pc_widths_nu_z: float = float("nan")
    pc_by_smallest: pd.DataFrame | None = None
    pc_calibration: limits.CorrectedLimit | None = None
    fractal: pd.DataFrame | None = None
    fractal_by_size: pd.DataFrame | None = None
    picture: ClusterPicture | None = None
    paper_fit: pd.DataFrame | None = None
    paper_pcrit: pd.DataFrame | None = None
    paper_claims: pd.DataFrame | None = None


#: the size and sample drawn at its threshold in the pc report (64: small enough to read)
PICTURE_N, PICTURE_SAMPLE = 64, 1


def cluster_picture(sizes: tuple[int, ...], delta: float = DEFAULT_DELTA) -> ClusterPicture | None:
    """Sample :data:`PICTURE_SAMPLE` of the pebble sweep at the size nearest :data:`PICTURE_N`,
    rebuilt from its seed at its threshold (None if it never becomes rigid)."""
    from ...combinatorics.clusters import rigid_clusters
    from ...ensemble.runner import sample_geometry
    from ...ensemble.spec import parse_spec
    from ...ensemble.thresholds import pebble_pass
    from ...model.elements import place_elements

    n = min(sizes, key=lambda k: (abs(math.log(k / PICTURE_N)), k))
    ((_, raw),) = rods_pc_sweep(n, delta, PICTURE_SAMPLE, "pebble").items()
    spec = parse_spec(raw)
    net, u, v, _ = sample_geometry(spec, spec.points()[0], PICTURE_SAMPLE)
    th, spanning = pebble_pass(net, u, v)
    if not np.isfinite(th.s):
        return None
    # rods with u <= s: the threshold bond (u = s) included
    at = net.with_kinds(place_elements(u, v, np.nextafter(th.s, np.inf), 0.0, 0.5))
    return ClusterPicture(at, rigid_clusters(at), spanning, n, PICTURE_SAMPLE, th.s)


#: (name, mass column in nodes, in sites, literature keys) of the clusters whose fractal
#: dimension the pc scale measures at the threshold: the spanning rigid cluster, all of its
#: overconstrained rods (no literature value), and its load-carrying backbone (the stressed
#: region that holds the threshold rod), which is what Jacobs & Thorpe's "stressed backbone" is
FRACTAL_CLUSTERS = (
    ("rigid", "cluster_nodes", "cluster_sites",
     ("df_rigid_javerzat_notarmuzi", "df_dynamic_pebble", "df_rigid_jacobs_thorpe")),
    ("stressed", "stressed_nodes", "stressed_sites", ()),
    ("backbone", "backbone_nodes", "backbone_sites", ("df_stressed_jacobs_thorpe",)),
)  # fmt: skip


def fractal_dimensions(sizes, rows: list[pd.DataFrame], scale: Scale):
    """Fractal dimensions of the spanning rigid cluster and its stressed part at threshold.

    From the pebble-game rows of each size (samples never rigid left out): ``fits``, one row per
    (cluster, mass in "nodes" or "sites", smallest size fitted): ``d``, ``d_err``, ``chi2``,
    ``dof``, the first literature value's ``reference``, ``reference_err`` and ``z`` (NaN
    where there is none) (:func:`~tensegrity_rigidity.analysis.scaling.fractal_dimension`:
    M ~ n^d, each sample's mass at its own threshold); and ``by_size``, the mean masses with
    errors per size. A cluster whose mass columns the rows lack (rows written before they were
    recorded) is left out.
    """
    n = np.asarray(sizes, float)
    rigid = [r[np.isfinite(r.threshold_p_r)] for r in rows]
    by_size = pd.DataFrame({"n": np.asarray(sizes, int), "samples": [len(r) for r in rigid]})
    fits = []
    for name, nodes, sites, keys in FRACTAL_CLUSTERS:
        if not all(nodes in r and sites in r for r in rigid):
            continue
        ref = REFERENCES[keys[0]] if keys else None
        for mass, col in (("nodes", nodes), ("sites", sites)):
            masses = [r[col].to_numpy(float) for r in rigid]
            for k, n_min in enumerate(n[: max(1, n.size - 2)]):
                fit = an.fractal_dimension(n[k:], masses[k:], scale.bootstrap,
                                           rng=scale.rng("fractal", k))  # fmt: skip
                if k == 0:
                    by_size[f"{name}_{mass}"] = fit.mass
                    by_size[f"{name}_{mass}_err"] = fit.mass_err
                ref_value, ref_err = (ref.value, ref.tolerance) if ref else (np.nan, np.nan)
                fits.append(
                    {
                        "cluster": name,
                        "mass": mass,
                        "n_min": int(n_min),
                        "d": fit.d,
                        "d_err": fit.d_err,
                        "chi2": fit.chi2,
                        "dof": fit.dof,
                        "reference": ref_value,
                        "reference_err": ref_err,
                        "z": an.agreement_z(fit.d, fit.d_err**2, ref_value, ref_err),
                    }
                )
    return pd.DataFrame(fits), by_size


def _at_bound(nu: float) -> bool:
    """Whether a free fit's 1/nu ended at a bound of its range (False for NaN)."""
    return bool(np.any(np.isclose(1.0 / nu, an.THETA, rtol=1e-6)))


def pc_by_smallest_size(n, y, err, scale: Scale) -> pd.DataFrame:
    """The rods-only extrapolation refitted from the sizes ``n >= n_min``, one row per
    ``n_min`` leaving two sizes at least: corrections to scaling, largest at the smallest n,
    pull a fit towards them, and a reading that moves by more than its error is not determined
    by the data. Columns: the free fit's ``p_c``, ``p_c_err``, ``nu``, ``nu_err``, ``chi2``,
    ``dof``, ``z`` against :data:`~.headline.PC_CHECK` and ``nu_at_bound``; the fit with nu
    fixed at :data:`~.headline.NU_CHECK`'s ``p_c_fixed``, ``p_c_fixed_err``, ``chi2_fixed``,
    ``dof_fixed``, ``z_fixed``."""
    n, y, err = (np.asarray(a, float) for a in (n, y, err))
    rows = []
    for n_min in n[:-1]:
        keep = n >= n_min
        free = an.fit_finite_size(n[keep], y[keep], err[keep], rng=scale.rng("finite_size"))
        fixed = an.fit_finite_size(
            n[keep],
            y[keep],
            err[keep],
            nu=NU_CHECK.value,
            nu_err=NU_CHECK.error or 0.0,
            rng=scale.rng("finite_size"),
        )
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


def pc_calibration(n, y, err) -> limits.CorrectedLimit | None:
    """The rods-only p_c as a calibration: nu fixed at :data:`NU_PC` with its error, one
    correction to scaling for each omega of :data:`OMEGAS`, from every size and without the
    smallest (:func:`~tensegrity_rigidity.analysis.limits.corrected_limit`); None with fewer
    than four sizes (three parameters and a degree of freedom)."""
    n = np.asarray(n, float)
    if n.size < 4:
        return None
    n_mins = tuple(float(m) for m in np.sort(n)[: 1 + (n.size >= 5)])
    return limits.corrected_limit(n, y, err, NU_PC.value, NU_PC.error or 0.0, OMEGAS,
                                  OMEGA_REF, n_mins)  # fmt: skip


def calibration_table(c: limits.CorrectedLimit) -> pd.DataFrame:
    """One row per fit of a calibration: ``n_min``, ``omega``, ``p_c``, ``p_c_err``, ``chi2``,
    ``dof``, ``p_value``, ``allowed``."""
    return pd.DataFrame([{"n_min": int(f.n_min), "omega": f.omega, "p_c": f.p_c,
                          "p_c_err": f.p_c_err, "chi2": f.chi2, "dof": f.dof,
                          "p_value": f.p_value, "allowed": f.acceptable}
                         for f in c.fits])  # fmt: skip


def _own_pc(rows: Rows, scale: Scale, excluded: dict) -> tuple[pd.DataFrame, list, list]:
    """The rods-only point at each size of its own sweeps: rows of ``by_size``, the thresholds
    per size and the rows per size."""
    p = scale[NAME]
    out, per_size, frames = [], [], []
    for n in p.pc_sizes:
        (name,) = rods_pc_sweep(n, DEFAULT_DELTA, p.pc_at(n), p.pc_method)
        pc, excluded[name] = rows[name]
        frames.append(pc)
        per_size.append(pc.threshold_p_r.to_numpy(float))
        value, err = an.critical_point(per_size[-1], rng=scale.rng("critical_point"))
        width = (pc.threshold_p_r_high - pc.threshold_p_r_low).to_numpy(float)
        # thresholds left as intervals by undecided probes, and their mean width
        out.append({"key": "rods_only_pc", "value": value, "err": err, "n": n,
                    "samples": len(pc), "intervals": int(np.sum(width > 0)),
                    "width": float(np.nanmean(width)) if width.size else np.nan})  # fmt: skip
    return pd.DataFrame(out), per_size, frames


def analyse(rows: Rows, scale: Scale) -> FiniteSizeResult:
    """The headline claims at each size (:func:`~.headline.headline`), the rods-only point at
    its own sizes where the scale gives ``pc``, and their limits (:func:`extrapolate`)."""
    p = scale[NAME]
    frames = []
    excluded: dict[str, int] = {}
    bracketed: dict[str, int] = {}
    first = []
    for n in p.sizes:
        f, ex, br = headline(rows, n, DEFAULT_DELTA, scale, samples=p.samples_at(n),
                             energy=p.energy_at(n))  # fmt: skip
        frames.append(f.assign(n=n))
        first.append(paper_pcrit(rows, n, DEFAULT_DELTA, scale, energy=p.energy_at(n)).assign(n=n))
        excluded |= ex
        bracketed |= br
    by_size = (pd.concat(frames, ignore_index=True) if frames  # the pc scale: rods-only only
               else pd.DataFrame(columns=["key", "value", "err", "n"]))  # fmt: skip
    widths = fractal = fractal_by_size = picture = None
    if p.pc:  # the rods-only point from its own sweeps, at its own sizes
        own, per_size, pc_frames = _own_pc(rows, scale, excluded)
        by_size = pd.concat([by_size[by_size.key != "rods_only_pc"], own], ignore_index=True)
        widths = an.width_scaling(np.asarray(p.pc_sizes, float), per_size, rng=scale.rng("widths"))
        if p.pc_method == "pebble" and len(p.pc_sizes) >= 2:
            fractal, fractal_by_size = fractal_dimensions(p.pc_sizes, pc_frames, scale)
            picture = cluster_picture(p.pc_sizes)
    return extrapolate(
        by_size,
        scale,
        excluded=excluded,
        bracketed=bracketed,
        pc_widths=widths,
        fractal=fractal,
        fractal_by_size=fractal_by_size,
        picture=picture,
        paper_pcrit=pd.concat(first, ignore_index=True) if first else None,
    )


Series = tuple[np.ndarray, np.ndarray, np.ndarray]


def _series(by_size: pd.DataFrame) -> dict[str, Series]:
    """Per key: (n, value, err) sorted by n."""
    out = {}
    for key in by_size.key.unique():
        s = by_size[by_size.key == key].sort_values("n")
        out[key] = (s.n.to_numpy(float), s.value.to_numpy(float), s.err.to_numpy(float))
    return out


def extrapolate(by_size: pd.DataFrame, scale: Scale, *, pc_widths=None, excluded=None,
                paper_pcrit=None, **extra) -> FiniteSizeResult:  # fmt: skip
    """Every claim of ``by_size`` (per (n, key): ``value``, ``err``; a ``rods_only_pc`` row
    at two sizes at least) extrapolated to n -> infinity, twice (see the module docstring), and
    the paper's effective size with ``paper_pcrit`` (per (n, key) the p_crit claims by the
    paper's estimator) beside ours; ``**extra``: further fields of :class:`FiniteSizeResult`."""
    series, rng = _series(by_size), scale.rng
    pc_fit = an.fit_finite_size(*series["rods_only_pc"], rng=rng("finite_size"))
    fits = {"rods_only_pc": pc_fit}
    for key in series:
        if key != "rods_only_pc":
            fits[key] = an.fit_finite_size(*series[key], nu=pc_fit.nu, nu_err=pc_fit.nu_err,
                                           rng=rng("finite_size"))  # fmt: skip
    nu_check, nu_check_err = NU_CHECK.value, NU_CHECK.error or 0.0
    checks = {key: an.fit_finite_size(*series[key], nu=nu_check, nu_err=nu_check_err,
                                      rng=rng("finite_size")) for key in fits}  # fmt: skip
    ex = with_laws(_extrapolated(fits, checks), series, scale)
    w = pc_widths
    z = {
        "nu_z": an.agreement_z(pc_fit.nu, pc_fit.nu_err**2, nu_check, nu_check_err),
        "pc_z": an.agreement_z(pc_fit.y_inf, pc_fit.y_inf_err**2, PC_CHECK.value, 0.0),
        "pc_at_check_nu_z": an.agreement_z(
            checks["rods_only_pc"].y_inf, checks["rods_only_pc"].y_inf_err ** 2, PC_CHECK.value, 0.0
        ),
        "pc_widths_z": np.nan
        if w is None
        else an.agreement_z(w.p_c, w.p_c_err**2, PC_CHECK.value, 0.0),
        "pc_widths_nu_z": np.nan
        if w is None
        else an.agreement_z(w.nu, w.nu_err**2, nu_check, nu_check_err),
    }
    p = scale[NAME]
    return FiniteSizeResult(
        by_size=by_size,
        extrapolated=ex,
        sizes=tuple(p.sizes),
        samples=tuple(p.samples_at(n) for n in p.sizes),
        energy_samples=tuple(p.energy_at(n) for n in p.sizes),
        pc_sizes=p.pc_sizes,
        pc_samples=tuple(p.pc_at(n) for n in p.pc_sizes),
        measured=_measured(ex, pc_fit, scale) + replications(by_size, scale),
        pc_at_check_nu=checks["rods_only_pc"],
        nu_at_bound=_at_bound(pc_fit.nu),
        excluded=excluded or {},
        pc_widths=w,
        pc_by_smallest=pc_by_smallest_size(*series["rods_only_pc"], scale),
        pc_calibration=pc_calibration(*series["rods_only_pc"]),
        nu_z=z["nu_z"],
        pc_z=z["pc_z"],
        pc_at_check_nu_z=z["pc_at_check_nu_z"],
        pc_widths_z=z["pc_widths_z"],
        pc_widths_nu_z=z["pc_widths_nu_z"],
        paper_fit=paper_fit(by_size, paper_pcrit),
        paper_pcrit=paper_pcrit,
        paper_claims=paper_claims(by_size, paper_pcrit),
        **extra,
    )


def paper_number(key: str) -> bool:
    """Whether a claim enters the paper's effective size: a value and error the paper states
    for its own measurement (not a theory's exact value, not a literature value it cites), of
    equality, and not a repeat by symmetry of an earlier claim (our one number would count
    twice)."""
    c = CLAIMS.get(key)
    return (c is not None and c.value is not None and c.relation == "equal"
            and c.error_kind in ("stated", "rounding", "about") and not c.reference
            and not c.same_as)  # fmt: skip


#: the figure column of :func:`paper_fit` for every claim of the paper together
ALL_FIGURES = "all"
#: the estimator column of :func:`paper_fit` and :func:`paper_claims`: our p_crit (the median
#: per-sample threshold, P = 1/2) and the paper's (the first p_r of the energy grid with a
#: positive mean energy); every other claim is measured one way
OURS, PAPERS = "ours", "paper"


def with_paper_pcrit(by_size: pd.DataFrame, paper_pcrit: pd.DataFrame | None) -> pd.DataFrame:
    """``by_size`` with the value and error of each (n, key) of ``paper_pcrit`` (the p_crit
    claims by the paper's estimator) in place of ours, NaN where that is only a bound (a
    ``censored`` row: :func:`paper_fit` counts it as missing); the other rows as they are."""
    if paper_pcrit is None or not len(paper_pcrit) or not len(by_size):
        return by_size
    theirs = paper_pcrit.set_index(["n", "key"])[["value", "err"]].astype(float)
    if "censored" in paper_pcrit:
        theirs.loc[paper_pcrit.censored.astype(bool).to_numpy(), "value"] = np.nan
    out = by_size.copy()
    at = pd.MultiIndex.from_arrays([out.n, out.key])
    hit = at.isin(theirs.index)
    for col in ("value", "err"):
        out.loc[hit, col] = theirs.loc[at[hit], col].to_numpy(float)
    return out


def _fit_rows(by_size: pd.DataFrame, estimator: str) -> list[dict]:
    """The rows of :func:`paper_fit` of one estimator."""
    keys = [k for k in by_size.key.unique() if paper_number(k)] if len(by_size) else []
    rows = []
    for n in sorted(by_size.n.unique()) if keys else []:
        at = by_size[(by_size.n == n) & by_size.key.isin(keys)]
        ok = at[np.isfinite(at.value.astype(float)) & np.isfinite(at.err.astype(float))]
        figures = [ALL_FIGURES, *sorted({CLAIMS[k].figure for k in ok.key})]
        for fig in figures:
            part = ok if fig == ALL_FIGURES else ok[[CLAIMS[k].figure == fig for k in ok.key]]
            ref = [CLAIMS[k] for k in part.key]
            chi2, dof, p = chi2_against(part.value, part.err, [c.value for c in ref],
                                        [c.error for c in ref])  # fmt: skip
            rows.append({"estimator": estimator, "n": int(n), "figure": fig, "chi2": chi2,
                         "dof": dof, "p_value": p, "fits": bool(p >= limits.ACCEPT_P),
                         "missing": len(at) - len(ok) if fig == ALL_FIGURES else 0})  # fmt: skip
    return rows


def paper_fit(by_size: pd.DataFrame, paper_pcrit: pd.DataFrame | None = None) -> pd.DataFrame:
    """How well the paper's numbers fit ours at each size: the paper states no system size.

    Parameters
    ----------
    by_size : DataFrame
        Per (n, key): ``value``, ``err``.
    paper_pcrit : DataFrame, optional
        Per (n, key): ``value``, ``err`` of the p_crit claims by the paper's estimator
        (:func:`~.headline.first_positive_pcrit`); with it every row is repeated with these in
        place of ours (:func:`with_paper_pcrit`).

    Returns
    -------
    DataFrame
        One row per estimator (:data:`OURS`, then :data:`PAPERS` with ``paper_pcrit``), n and
        figure (:data:`ALL_FIGURES` first, then each figure the claims name): ``estimator``,
        ``n``, ``figure``, ``chi2`` = sum of ((ours - paper) / sqrt(err_ours^2 +
        err_paper^2))^2 over the claims of :func:`paper_number` measured at n, ``dof`` (their
        number), ``p_value`` (:func:`~tensegrity_rigidity.analysis.agreement.chi2_against`),
        ``fits`` (``p_value >= ACCEPT_P`` of :mod:`~tensegrity_rigidity.analysis.limits`, the
        rule fixed before any size was compared) and ``missing`` (claims at n without a finite
        value or error, left out of the sum and counted here).
    """
    rows = _fit_rows(by_size, OURS)
    if paper_pcrit is not None and len(paper_pcrit):
        rows += _fit_rows(with_paper_pcrit(by_size, paper_pcrit), PAPERS)
    return pd.DataFrame(rows, columns=["estimator", "n", "figure", "chi2", "dof", "p_value",
                                       "fits", "missing"])  # fmt: skip


def effective_size(fit: pd.DataFrame, figure: str = ALL_FIGURES,
                   estimator: str = OURS) -> dict | None:  # fmt: skip
    """The paper's effective size from :func:`paper_fit` under one ``estimator``: the n whose
    chi-square has the largest p-value (the smallest such n on a tie) with its ``chi2``,
    ``dof``, ``p_value``, and the sizes that fit (``fitting``); None without a size."""
    rows = fit[(fit.figure == figure) & (fit.dof > 0) & (fit.estimator == estimator)]
    rows = rows.sort_values("n")
    if not len(rows):
        return None
    best = rows.iloc[int(np.argmax(rows.p_value.to_numpy(float)))]
    return {"n": int(best.n), "chi2": float(best.chi2), "dof": int(best.dof),
            "p_value": float(best.p_value),
            "fitting": [int(n) for n in rows.n[rows.fits.astype(bool)]]}  # fmt: skip


def paper_claims(by_size: pd.DataFrame, paper_pcrit: pd.DataFrame | None = None) -> pd.DataFrame:
    """Each number of the paper (:func:`paper_number`) against ours at each size.

    Parameters
    ----------
    by_size, paper_pcrit : DataFrame
        As :func:`paper_fit`.

    Returns
    -------
    DataFrame
        One row per claim, estimator (:data:`OURS` for every claim; :data:`PAPERS` for the
        claims ``paper_pcrit`` holds) and n: ``key``, ``estimator``, ``n``, ``value``, ``err``,
        ``z`` = |ours - paper| / sqrt(err_ours^2 + err_paper^2) (the term of the chi-square;
        NaN without a finite value or where the value is a bound), ``reproduced`` (z below the
        comparison's :data:`~tensegrity_rigidity.paper.comparison.AGREE_BELOW`) and
        ``censored`` (the paper's estimator at its grid's first point: a bound).
    """
    columns = ["key", "estimator", "n", "value", "err", "z", "reproduced", "censored"]
    parts = [by_size.assign(estimator=OURS, censored=False)] if len(by_size) else []
    if paper_pcrit is not None and len(paper_pcrit):
        theirs = paper_pcrit.assign(estimator=PAPERS)
        parts.append(theirs if "censored" in theirs else theirs.assign(censored=False))
    if not parts:
        return pd.DataFrame(columns=columns)
    rows = pd.concat([p[["key", "estimator", "n", "value", "err", "censored"]] for p in parts],
                     ignore_index=True)  # fmt: skip
    rows["censored"] = rows.censored.astype(bool)
    rows = rows[[paper_number(k) for k in rows.key]].reset_index(drop=True)
    paper = np.array([CLAIMS[k].value for k in rows.key], float)
    paper_err = np.array([CLAIMS[k].error for k in rows.key], float)
    value, err = rows.value.to_numpy(float), rows.err.to_numpy(float)
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.abs(value - paper) / np.hypot(err, paper_err)
    rows["n"] = rows.n.astype(int)
    rows["z"] = np.where(np.isfinite(value) & np.isfinite(err) & ~rows.censored, z, np.nan)
    rows["reproduced"] = rows.z < AGREE_BELOW
    return rows[columns]


def _extrapolated(fits: dict, checks: dict) -> pd.DataFrame:
    """One row per key: the free fit, its z and verdict against the paper, the same with nu
    fixed at the literature's."""
    ex = pd.DataFrame([{"key": k, **f.__dict__} for k, f in fits.items()])
    free = [judged(r.key, r.y_inf, r.y_inf_err) for r in ex.itertuples()]
    ex["z_paper"], ex["verdict_paper"] = [z for z, _ in free], [v for _, v in free]
    for col, name in (("y_inf", "y_inf_nu_check"), ("y_inf_err", "y_inf_nu_check_err"),
                      ("chi2", "chi2_nu_check"), ("dof", "dof_nu_check")):  # fmt: skip
        ex[name] = [getattr(checks[k], col) for k in ex.key]
    fixed = [judged(k, checks[k].y_inf, checks[k].y_inf_err) for k in ex.key]
    ex["z_paper_nu_check"] = [z for z, _ in fixed]
    ex["verdict_paper_nu_check"] = [v for _, v in fixed]
    return ex


def with_laws(ex: pd.DataFrame, series: dict, scale: Scale) -> pd.DataFrame:
    """``ex`` with each key's limit from :data:`LIMIT_LAWS`
    (:func:`~tensegrity_rigidity.analysis.limits.limit_laws`), borrowing no exponent:
    ``limit_law`` (the first law allowed), ``limit`` (NaN where none is), ``limit_stat``,
    ``limit_syst`` (the fit-form systematic), ``limit_low``, ``limit_high``, the finite law's
    exponent ``limit_x``, ``limit_x_err``, ``limit_x_at_bound`` (an end of the profiled range:
    not determined), ``limit_chi2``, ``limit_dof``, and ``limit_laws``, the laws the data
    allow (comma-separated)."""
    out = []
    for key in ex.key:
        n, y, err = series[key]
        lim = limits.limit_laws(n, y, err, laws=LIMIT_LAWS, n_boot=scale.bootstrap,
                                rng=scale.rng("finite_size"))  # fmt: skip
        f = lim.fits[LIMIT_LAWS[0]]
        fitting = ",".join(k for k, g in lim.fits.items() if g.acceptable)
        out.append({"limit_law": lim.law, "limit": lim.value, "limit_stat": lim.stat,
                    "limit_syst": lim.syst,
                    "limit_low": lim.low, "limit_high": lim.high, "limit_x": f.x,
                    "limit_x_err": f.x_err, "limit_x_at_bound": f.x_at_bound,
                    "limit_chi2": f.chi2, "limit_dof": f.dof,
                    "limit_laws": fitting})  # fmt: skip
    return pd.concat([ex.reset_index(drop=True), pd.DataFrame(out)], axis=1)


def _sizes(p: Params, key: str) -> tuple[int, ...]:
    """The sizes one claim's extrapolation uses (rods-only p_c: its own sizes, where set)."""
    return tuple(int(n) for n in (p.pc_sizes if key == "rods_only_pc" else p.sizes))


def _samples_text(p: Params, key: str) -> str:
    """The sample counts per size of a claim: one number when equal, else one per size."""
    if key == "rods_only_pc":
        sizes, count = p.pc_sizes, p.pc_at
    else:
        sizes, count = tuple(p.sizes), p.energy_at if key in ENERGY_KEYS else p.samples_at
    counts = [count(n) for n in sizes]
    if len(set(counts)) == 1:
        return str(counts[0])
    return T.label("per_size", counts=counts, sizes=sizes)


def _measured(ex: pd.DataFrame, pc_fit, scale: Scale) -> tuple[Measurement, ...]:
    """Per claim its limit as evidence for the factor "finite size": from the laws, with the
    claim's own exponent and the fit-form systematic in its error (:func:`with_laws`); the
    rods-only p_c, whose exponent is its own transition's, by its two nu extrapolations."""
    p = scale[NAME]
    sizes = {"sizes": p.sizes or None, "pc_sizes": p.pc_sizes, "own": "" if p.pc else None}
    where = T.label("where" if p.sizes else "where_pc", **sizes)
    fits = {"free": (pc_fit.nu, pc_fit.nu_err), "fixed": (NU_CHECK.value, NU_CHECK.error or 0.0)}
    labels = {k: [T.label(f"{k}{short}", where=where, nu=nu, nu_err=e) for short in ("", ".short")]
              for k, (nu, e) in fits.items()}  # fmt: skip
    out = []
    for row in ex[ex.key.isin(list(CLAIMS))].itertuples():
        system = T.label("samples", samples=_samples_text(p, row.key))
        if row.key != "rods_only_pc":
            laws = {"where": where, "laws": row.limit_laws or T.label("no_law")}
            out.append(Measurement.scalar(
                row.key, row.limit, float(np.hypot(row.limit_stat, row.limit_syst)), system,
                factor="finite size", label=T.label("laws", **laws),
                short=T.label("laws.short", **laws), sizes=_sizes(p, row.key)))  # fmt: skip
            continue
        for v, e, chi2, dof, (label, short) in (
            (row.y_inf, row.y_inf_err, row.chi2, row.dof, labels["free"]),
            (row.y_inf_nu_check, row.y_inf_nu_check_err, row.chi2_nu_check, row.dof_nu_check,
             labels["fixed"]),
        ):  # fmt: skip
            out.append(Measurement.scalar(row.key, v, e, system, factor="finite size",
                                          label=label + misfit(chi2, dof),
                                          short=short + misfit(chi2, dof),
                                          sizes=_sizes(p, row.key)))  # fmt: skip
    return tuple(out)


def replications(by_size: pd.DataFrame, scale: Scale) -> tuple[Measurement, ...]:
    """Each claim at each size as a replication: the study's samples (seed 61) are not the
    figure studies' and usually more, so a value that agrees with the paper only at the figure
    study's precision shows it here (the comparison sets it beside ours of the same size)."""
    p, out = scale[NAME], []
    for row in by_size[by_size.key.isin(list(CLAIMS))].itertuples():
        n, count = int(row.n), getattr(row, "samples", np.nan)
        if not np.isfinite(count):
            count = p.energy_at(n) if row.key in ENERGY_KEYS else p.samples_at(n)
        out.append(Measurement.scalar(row.key, row.value, row.err,
                                      T.label("size", n=n, samples=int(count)), factor=REPLICATION,
                                      label=T.label("replication"), size=n))  # fmt: skip
    return tuple(out)


def nu_dependent(extrapolated: pd.DataFrame) -> tuple[list[str], int]:
    """The claims whose verdict differs between the free fit's nu and the literature's, and
    how many claims have a verdict under both."""
    ex = extrapolated[extrapolated.key.isin(list(CLAIMS))]
    both = ex[(ex.verdict_paper != "n/a") & (ex.verdict_paper_nu_check != "n/a")]
    return list(both[both.verdict_paper != both.verdict_paper_nu_check].key), len(both)


def sweeps(scale: Scale) -> dict[str, dict]:
    """Every size at the default delta, and the rods-only sweeps of the p_c extrapolation."""
    p, out = scale[NAME], dict[str, dict]()
    for n in p.sizes:
        out |= headline_sweeps(n, DEFAULT_DELTA, p.samples_at(n))
        out |= energy_sweeps(n, DEFAULT_DELTA, count=p.energy_at(n))
    for n, samples in p.pc:
        out |= rods_pc_sweep(n, DEFAULT_DELTA, samples, p.pc_method)
    return out


def _widths(r: FiniteSizeResult) -> dict:
    """The widths reading's numbers (empty without one)."""
    w = r.pc_widths
    if w is None or not np.isfinite(w.nu):
        return {}
    return {
        "widths": w.width,
        "width_n": w.n.astype(int),
        "w_nu": fmt(w.nu, w.nu_err),
        "w_nu_chi2": w.nu_chi2,
        "w_dof": w.n.size - 2,
        "w_nu_z": r.pc_widths_nu_z,
        "w_pc": fmt(w.p_c, w.p_c_err),
        "w_pc_chi2": w.p_c_chi2,
        "w_pc_z": r.pc_widths_z,
    }


def _smallest(r: FiniteSizeResult) -> dict:
    """The refits without the smallest sizes: the range of the free fits whose nu is inside
    its bounds with a degree of freedom, and how many were left out and why."""
    t = r.pc_by_smallest
    if t is None or len(t) < 2:
        return {}
    fitted = t[np.isfinite(t.p_c)]
    bound = fitted.nu_at_bound.astype(bool)
    loose = bound | (fitted.dof <= 0)
    free, n_bound, n_dof = fitted[~loose], int(bound.sum()), int((loose & ~bound).sum())
    left = T.label("left_out", loose=int(loose.sum()), fitted=len(fitted), n_bound=n_bound or None,
                   both="" if n_bound and n_dof else None, n_dof=n_dof or None)  # fmt: skip
    return {"smallest": "", "range_lo": free.p_c.min() if len(free) > 1 else None,
            "range_hi": free.p_c.max(), "left_out": left if loose.any() else None,
            "left_over": len(free) if len(free) <= 1 else None}  # fmt: skip


def numbers(r: FiniteSizeResult) -> dict:
    """The finite-size section's numbers, and the rigid clusters' where the pebble game ran."""
    pc = r.extrapolated.set_index("key").loc["rods_only_pc"]
    changed, compared = nu_dependent(r.extrapolated)
    by = r.by_size[r.by_size.key == "rods_only_pc"].sort_values("n")
    parts = [
        T.label(
            "interval", count=int(x.intervals), samples=int(x.samples), n=int(x.n), width=x.width
        )
        for x in by.itertuples()
        if getattr(x, "intervals", 0) > 0
    ]
    fixed = r.pc_at_check_nu
    own = bool(r.pc_sizes) and tuple(r.pc_sizes) != tuple(r.sizes)
    return {
        "sizes": r.sizes or None,
        "samples": r.samples,
        "node_disorder": DEFAULT_DELTA,
        "energy_samples": r.energy_samples,
        "pc_only": None if r.sizes else "",
        "own_pc": "" if own else None,
        "shared_pc": None if own else "",
        "pc_sizes": r.pc_sizes,
        "pc_samples": r.pc_samples,
        "pc": fmt(pc.y_inf, pc.y_inf_err),
        "nu": fmt(pc.nu, pc.nu_err),
        "chi2": pc.chi2,
        "dof": pc.dof,
        "nu_z": r.nu_z,
        "nu_check": NU_CHECK.value,
        "nu_check_err": NU_CHECK.error,
        "nu_who": NU_CHECK.who,
        "pc_check": PC_CHECK.value,
        "pc_who": PC_CHECK.who,
        "pc_z": r.pc_z,
        "at_bound": "" if r.nu_at_bound else None,
        # below 2/d (Chayes, Chayes, Fisher & Spencer) or with an error above half its value
        "nu_loose": "" if np.isfinite(pc.nu) and (pc.nu < 1.0 or pc.nu_err > pc.nu / 2) else None,
        "fixed_pc": None if fixed is None else fmt(fixed.y_inf, fixed.y_inf_err),
        "fixed_chi2": getattr(fixed, "chi2", None),
        "fixed_dof": getattr(fixed, "dof", None),
        "fixed_z": r.pc_at_check_nu_z,
        "intervals": "; ".join(parts) or None,
        "others": "" if r.sizes else None,
        "compared": compared or None,
        "changed": len(changed),
        "changed_claims": "; ".join(CLAIMS[k].text for k in changed) or None,
        **_widths(r),
        **_smallest(r),
        **_calibration(r),
        **_clusters(r),
        **_laws(r),
        **_effective(r),
    }


def _effective(r: FiniteSizeResult) -> dict:
    """The paper's effective size under both estimators of p_crit, and the sizes at which each
    of its numbers is reproduced (empty without a claim of the paper measured)."""
    fit = r.paper_fit
    best = None if fit is None else effective_size(fit)
    if fit is None or best is None:
        return {}
    out = {"effective": "", "accept_p": limits.ACCEPT_P, "eff_sizes": sorted(set(fit.n)),
           "eff_missing": int(fit.missing[fit.estimator == OURS].sum()) or None,
           **_best(fit, OURS, "eff"), **_reproduced(r)}  # fmt: skip
    if (fit.estimator == PAPERS).any():
        counts = tuple(getattr(r, "energy_samples", ())) or None
        first = getattr(r, "paper_pcrit", None)
        held = (first[first.censored.astype(bool)] if first is not None and "censored" in first
                else pd.DataFrame(columns=["key", "value"]))  # fmt: skip
        bound = [k for k in held.key if paper_number(k)]
        lo = sorted(set(held.value[held.key.map(paper_number).astype(bool)]))
        out |= {"effp_censored": len(bound) or None, "effp_censored_claims": len(set(bound)),
                "grid_lo": lo[0] if len(lo) == 1 else lo,
                "effp_missing": int(fit.missing[fit.estimator == PAPERS].sum())}  # fmt: skip
        out |= {"effective_paper": "", "grid_step": ENERGY_STEP,
                "effp_samples": counts[:1] if counts and len(set(counts)) == 1 else counts,
                **_best(fit, PAPERS, "effp")}  # fmt: skip
    return out


def _best(fit: pd.DataFrame, estimator: str, prefix: str) -> dict:
    """The effective size of one estimator: the numbers ``<prefix>_n``, ``_chi2``, ``_dof``,
    ``_p``, ``_fitting``, ``_none``, ``_chi2s`` (per size) and ``_figures`` (the best per
    figure, worded)."""
    best = effective_size(fit, estimator=estimator)
    if best is None:
        return {}
    figures = [f for f in dict.fromkeys(fit.figure) if f != ALL_FIGURES]
    per_figure = [T.label("eff_figure.one" if b["dof"] == 1 else "eff_figure", figure=f,
                          **{k: v for k, v in b.items() if k != "fitting"})
                  for f in figures
                  if (b := effective_size(fit, f, estimator)) is not None]  # fmt: skip
    every = fit[(fit.figure == ALL_FIGURES) & (fit.estimator == estimator)].sort_values("n")
    return {f"{prefix}_n": best["n"], f"{prefix}_chi2": best["chi2"],
            f"{prefix}_dof": best["dof"], f"{prefix}_p": best["p_value"],
            f"{prefix}_fitting": best["fitting"] or None,
            f"{prefix}_none": None if best["fitting"] else "",
            f"{prefix}_chi2s": [round(x, 1) for x in every.chi2],
            f"{prefix}_figures": "; ".join(per_figure) or None}  # fmt: skip


def _reproduced(r: FiniteSizeResult) -> dict:
    """How many of the paper's numbers are reproduced (z < AGREE_BELOW) at some size under our
    p_crit and, for its p_crit, under the paper's; the claims reproduced at none under
    either."""
    c = r.paper_claims
    if c is None or not len(c):
        return {}
    ever = c.groupby(["estimator", "key"]).reproduced.any()
    ours, theirs = ever[OURS], ever[PAPERS] if PAPERS in ever.index else None
    never = [k for k in ours.index if not ours[k] and not (theirs is not None and theirs.get(k))]
    per_size = c[c.estimator == OURS].groupby("n").reproduced.sum().astype(int)
    return {"repro_total": len(ours), "repro_ours": int(ours.sum()),
            "repro_sizes": len(per_size), "repro_best": int(per_size.max()),
            "repro_best_n": [int(n) for n in per_size.index[per_size == per_size.max()]],
            "repro_pcrit": None if theirs is None else len(theirs),
            "repro_paper": None if theirs is None else int(theirs.sum()),
            "repro_pcrit_ours": None if theirs is None else int(ours[theirs.index].sum()),
            "agree_below": AGREE_BELOW,
            "repro_never": "; ".join(CLAIMS[k].text for k in never) or None,
            "repro_all": None if never else ""}  # fmt: skip


def _laws(r: FiniteSizeResult) -> dict:
    """How many extrapolated claims each law of :data:`LIMIT_LAWS` fits."""
    ex = r.extrapolated
    if "limit_laws" not in ex or not len(ex):
        return {}
    allowed = [set(filter(None, v.split(","))) for v in ex.limit_laws.fillna("")]
    return {"laws_total": len(ex), "laws_finite": sum("finite" in a for a in allowed),
            "laws_constant": sum("constant" in a for a in allowed),
            "laws_none": sum(not a for a in allowed),
            "laws_syst": int(np.sum(ex.limit_syst > 0)), "laws_x_lo": limits.X_GRID[0],
            "laws_undetermined": int(np.sum(~np.isfinite(ex.limit.to_numpy(float)))),
            "laws_x_hi": limits.X_GRID[-1]}  # fmt: skip


def _calibration(r: FiniteSizeResult) -> dict:
    """The calibration's numbers (empty without one): p_c with its statistical and fit-form
    errors, the fits tried, and z against each anchor with both errors and the anchor's."""
    c = r.pc_calibration
    if c is None or not np.isfinite(c.value):
        return {}
    a, b = (REFERENCES[k] for k in PC_ANCHORS)
    out = {"cal_pc": fmt(c.value, c.stat), "cal_syst": f"{c.syst:.{decimals(c.stat)}f}",
           "cal_nu": NU_PC.value, "cal_nu_err": NU_PC.error, "cal_omega_ref": OMEGA_REF,
           "cal_omega_lo": min(OMEGAS), "cal_omega_hi": max(OMEGAS),
           "cal_n_mins": sorted({int(f.n_min) for f in c.fits}),
           "cal_allowed": c.allowed, "cal_fits": len(c.fits), "cal_lo": c.low, "cal_hi": c.high,
           "anchors_z": abs(a.value - b.value)
           / np.hypot(a.tolerance, b.tolerance),
           "cal_undetermined": "" if c.syst > c.stat else None}  # fmt: skip
    for i, ref in enumerate((a, b)):
        out |= {f"anchor{i}": ref.value, f"anchor{i}_err": ref.error,
                f"anchor{i}_who": ref.who,
                f"anchor{i}_z": abs(c.value - ref.value)
                / np.hypot(np.hypot(c.stat, c.syst), ref.tolerance)}  # fmt: skip
    return out


def _clusters(r: FiniteSizeResult) -> dict:
    """Each cluster's d_f from the most sizes the data allow (the smallest ``n_min`` whose fit
    has p >= ACCEPT_P), the move to the next ``n_min`` as its systematic: corrections to scaling
    reject the fits over every size."""
    if r.fractal is None:
        return {}
    out: dict = {"clusters": ""}
    for cluster, f in r.fractal[r.fractal.mass == "nodes"].groupby("cluster", sort=False):
        f = f.sort_values("n_min").reset_index(drop=True)
        ok = [limits.allowed(c, int(d))[1] for c, d in zip(f.chi2, f.dof, strict=True)]
        if not any(ok):
            continue
        i = ok.index(True)
        row = f.iloc[i]
        last = i + 1 == len(f)
        syst = np.nan if last else abs(f.d[i + 1] - row.d)
        out[f"d_{cluster}"] = T.label("d_f.last" if last else "d_f", d=fmt(row.d, row.d_err),
                                      n_min=int(row.n_min), syst=syst, chi2=row.chi2,
                                      dof=int(row.dof))  # fmt: skip
    return out


def _by_size_table(r: FiniteSizeResult) -> pd.DataFrame:
    ex = r.extrapolated.set_index("key")
    wide = r.by_size.pivot_table(index="key", columns="n", values="value")
    err = r.by_size.pivot_table(index="key", columns="n", values="err")
    table = pd.DataFrame({"claim": [CLAIMS[k].text for k in wide.index],
                          "paper": [CLAIMS[k].paper for k in wide.index]})  # fmt: skip
    for n in wide.columns:
        table[f"n = {n}"] = [fmt(v, e) for v, e in zip(wide[n], err[n], strict=True)]
    rows = [ex.loc[k] for k in wide.index]
    table["n -> inf"] = [fmt(x.y_inf, x.y_inf_err) for x in rows]
    table["chi2"] = [f"{x.chi2:.1f} / {x.dof}" for x in rows]
    table["z_paper"] = [f"{x.z_paper:.2f}" for x in rows]
    table[f"n -> inf, nu = {NU_CHECK.value}"] = [fmt(x.y_inf_nu_check, x.y_inf_nu_check_err)
                                                 for x in rows]  # fmt: skip
    table[f"z_paper, nu = {NU_CHECK.value}"] = [f"{x.z_paper_nu_check:.2f}" for x in rows]
    table["n -> inf, laws"] = [fmt(x.limit, x.limit_stat) for x in rows]
    table["fit form"] = [fit_form(x) for x in rows]
    table["own x"] = [f"{x.limit_x:.2f}" + (" " + T.label("at_bound")) * bool(x.limit_x_at_bound)
                      for x in rows]  # fmt: skip
    table["laws allowed"] = [x.limit_laws or "-" for x in rows]
    return table


def _smallest_table(r: FiniteSizeResult) -> pd.DataFrame | None:
    t = r.pc_by_smallest
    if t is None or len(t) < 2:
        return None
    return pd.DataFrame({
        "sizes": [f"n >= {int(x.n_min)} ({int(x.sizes)})" for x in t.itertuples()],
        "p_c": [fmt(x.p_c, x.p_c_err) for x in t.itertuples()],
        "nu": [fmt(x.nu, x.nu_err) + (" " + T.label("at_bound")) * bool(x.nu_at_bound)
               for x in t.itertuples()],
        "chi2": [f"{x.chi2:.2f} / {x.dof}" for x in t.itertuples()],
        "z": [f"{x.z:.2f}" for x in t.itertuples()],
        "p_c_fixed": [fmt(x.p_c_fixed, x.p_c_fixed_err) for x in t.itertuples()],
        "chi2_fixed": [f"{x.chi2_fixed:.2f} / {x.dof_fixed}" for x in t.itertuples()],
        "z_fixed": [f"{x.z_fixed:.2f}" for x in t.itertuples()],
    })  # fmt: skip


def _calibration_table(r: FiniteSizeResult) -> pd.DataFrame | None:
    c = r.pc_calibration
    if c is None:
        return None
    return pd.DataFrame({
        "sizes": [f"n >= {int(f.n_min)}" for f in c.fits],
        "omega": [f"{f.omega:g}" for f in c.fits],
        "p_c_cal": [fmt(f.p_c, f.p_c_err) for f in c.fits],
        "chi2": [f"{f.chi2:.2f} / {f.dof}" for f in c.fits],
        "allowed": [T.label("yes" if f.acceptable else "no") for f in c.fits],
    })  # fmt: skip


def _against(quantity: str, how: str, value: float, err: float, keys) -> list[dict]:
    """One row per literature value: ours, how it was measured, theirs, z."""
    out = []
    for key in keys:
        ref = REFERENCES[key]
        z = abs(value - ref.value) / np.hypot(err, ref.tolerance)
        theirs = (
            f"{ref.value} ± {ref.error:g}"
            if ref.error
            else T.label("no_error", value=ref.value, tolerance=ref.tolerance)
        )
        out.append({"quantity": quantity, "ours": fmt(value, err), "how": how,
                    "literature": theirs, "source": ref.who,
                    "z": f"{z:.2f}"})  # fmt: skip
    return out


def _cluster_tables(r: FiniteSizeResult) -> dict:
    if r.fractal is None or r.fractal_by_size is None:
        return {}
    pc, w, fixed = (
        r.extrapolated.set_index("key").loc["rods_only_pc"],
        r.pc_widths,
        r.pc_at_check_nu,
    )
    pcs, nus = (
        (*PC_ANCHORS, "pc_jacobs_thorpe"),
        ("nu_javerzat_notarmuzi", "nu_dynamic_pebble", "nu_moukarzel_duxbury", "nu_jacobs_thorpe"),
    )
    rows = _against("p_c", T.label("how.free"), pc.y_inf, pc.y_inf_err, pcs)
    if fixed is not None:
        rows += _against("p_c", T.label("how.fixed", nu=NU_CHECK.value), fixed.y_inf,
                         fixed.y_inf_err, pcs)  # fmt: skip
    c = r.pc_calibration
    if c is not None and np.isfinite(c.value):
        rows += _against("p_c", T.label("how.calibration", nu=NU_PC.value, lo=min(OMEGAS),
                                        hi=max(OMEGAS)), c.value, float(np.hypot(c.stat, c.syst)),
                         pcs)  # fmt: skip
    if w is not None and np.isfinite(w.p_c):
        rows += _against("p_c", T.label("how.widths"), w.p_c, w.p_c_err, pcs)
    rows += _against("nu", T.label("how.nu"), pc.nu, pc.nu_err, nus)
    if w is not None and np.isfinite(w.nu):
        rows += _against("nu", T.label("how.nu_widths"), w.nu, w.nu_err, nus)
    f = r.fractal
    refs = {name: keys for name, _, _, keys in FRACTAL_CLUSTERS}
    for x in f[f.mass == "nodes"].itertuples():  # sites: tables/pc_fractal_dimensions
        how = T.label("how.df", n_min=None if x.n_min == f.n_min.min() else x.n_min,
                      chi2=x.chi2, dof=x.dof)  # fmt: skip
        rows += _against(T.label(f"d_f.{x.cluster}"), how, x.d, x.d_err, refs[x.cluster]) or [
            {"quantity": T.label(f"d_f.{x.cluster}"), "ours": fmt(x.d, x.d_err), "how": how,
             "literature": "-", "source": "-", "z": "-"}]  # fmt: skip
    by = r.fractal_by_size
    measured = [c for c, *_ in FRACTAL_CLUSTERS if f"{c}_nodes" in by]
    masses = pd.DataFrame({"n": by.n, "samples": by.samples, **{
        f"{c}_{m}": [fmt(v, e) for v, e in zip(by[f"{c}_{m}"], by[f"{c}_{m}_err"], strict=True)]
        for c in measured for m in ("nodes", "sites")}})  # fmt: skip
    return {"clusters": pd.DataFrame(rows), "masses": masses}


def _effective_table(r: FiniteSizeResult) -> pd.DataFrame | None:
    """One row per estimator of p_crit (a column naming it where there are two) and size: the
    chi-square of every claim of the paper, its dof, p-value and whether it fits, then one
    column per figure (chi-square / dof, p)."""
    fit = r.paper_fit
    if fit is None or not len(fit):
        return None
    every = fit[fit.figure == ALL_FIGURES].sort_values(["estimator", "n"], key=lambda c: (
        c.map({OURS: 0, PAPERS: 1}) if c.name == "estimator" else c))  # fmt: skip
    table = pd.DataFrame({"n": every.n.to_numpy(int),
                          "chi2_all": [f"{x:.1f}" for x in every.chi2],
                          "dof_all": every.dof.to_numpy(int),
                          "p_all": [f"{x:.2g}" for x in every.p_value],
                          "fits": [T.label("yes" if x else "no") for x in every.fits]})  # fmt: skip
    if every.estimator.nunique() > 1:
        table.insert(0, "estimator", [T.label(f"estimator.{e}") for e in every.estimator])
    for f in dict.fromkeys(fit.figure):
        if f == ALL_FIGURES:
            continue
        part = fit[fit.figure == f].set_index(["estimator", "n"])
        table[T.label("col.figure", figure=f)] = [
            f"{part.chi2[e, n]:.1f} / {part.dof[e, n]}, p = {part.p_value[e, n]:.2g}"
            if (e, n) in part.index else "-"
            for e, n in zip(every.estimator, every.n, strict=True)]  # fmt: skip
    return table


def _reproduced_table(r: FiniteSizeResult) -> pd.DataFrame | None:
    """One row per number of the paper and estimator of p_crit (the paper's only for the p_crit
    claims): the paper's value, z at each size and the sizes where z < AGREE_BELOW."""
    c = r.paper_claims
    if c is None or not len(c):
        return None
    rows = []
    for (est, key), part in c.groupby(["estimator", "key"], sort=False):
        at_n = part.set_index("n")
        row = {"claim": CLAIMS[key].text, "paper": CLAIMS[key].paper,
               "estimator": T.label(f"estimator.{est}")}  # fmt: skip
        row |= {f"z, n = {n}": T.label("censored", value=at_n.value[n]) if at_n.censored[n]
                else f"{at_n.z[n]:.2f}" for n in sorted(at_n.index)}  # fmt: skip
        at = sorted(int(n) for n in part.n[part.reproduced.astype(bool)])
        row["reproduced"] = T.label("at_sizes", sizes=at) if at else T.label("at_no_size")
        rows.append(row)
    return pd.DataFrame(rows)


def report_tables(r: FiniteSizeResult) -> dict:
    out = {"by_size": _by_size_table(r), "effective_size": _effective_table(r),
           "reproduced": _reproduced_table(r),
           "smallest": _smallest_table(r),
           "calibration": _calibration_table(r), **_cluster_tables(r)}  # fmt: skip
    return {k: v for k, v in out.items() if v is not None}


#: the panels of Fig. FS: (claim keys, the label of each, the y label)
PANELS = (
    (("rods_only_pc",), ("rods",), "y.pc"),
    (("st_sr_cables_compression", "st_sr_cables_dilation", "st_sr_half_shear"),
     ("cables_compression", "cables_dilation", "half_shear"), "y.st_sr"),
    (tuple(f"alpha_compression_{p_t}" for p_t in PT4), ("p_t",) * 4, "y.alpha_compression"),
    (tuple(f"alpha_dilation_{p_t}" for p_t in PT4), ("p_t",) * 4, "y.alpha_dilation"),
    (("taut_cables_transition",), ("cables_compression",), "y.taut"),
)  # fmt: skip


def fss_panels(r) -> list[tuple[tuple[str, ...], tuple[str, ...], str]]:
    """The panels of :data:`PANELS` with at least one claim extrapolated, reduced to those."""
    ex, out = set(r.extrapolated.key), []
    for keys, labels, ylabel in PANELS:
        kept = [(k, lab) for k, lab in zip(keys, labels, strict=True) if k in ex]
        if kept:
            out.append((tuple(k for k, _ in kept), tuple(lab for _, lab in kept), ylabel))
    return out


def _panel(ax, r, keys, labels, nu, n_inf) -> None:
    ex = r.extrapolated.set_index("key")
    for key, label in zip(keys, labels, strict=True):
        s = r.by_size[r.by_size.key == key].sort_values("n")
        p_t = key.rsplit("_", 1)[-1]
        colour = bars(ax, s.n, s.value, s.err, ls="none", label=T.label(f"line.{label}", p_t=p_t))
        f = ex.loc[key]
        if np.isfinite(f.y_inf):
            ns = np.geomspace(s.n.min(), n_inf, 60)
            ax.plot(ns, f.y_inf + f.a * ns ** (-1 / nu), "--", color=colour, lw=1)
            bars(ax, [n_inf], [f.y_inf], [f.y_inf_err], marker="s", color=colour)
        ax.axhline(CLAIMS[key].value, color=colour, ls=":", lw=1)
    unresolved(ax)


def figure_fs(r: FiniteSizeResult, figdir):
    """Each kind of claim against n (log axis) with the fitted y_inf + a n^(-1/nu) (dashed),
    the extrapolation at the axis' end and the paper's value (dotted); the widths beside the
    rods-only point. Two panels per row."""
    nu = r.extrapolated.set_index("key").loc["rods_only_pc"].nu
    nu = nu if np.isfinite(nu) else 1.0
    panels, w = fss_panels(r), r.pc_widths
    widths = w is not None and np.isfinite(w.nu)
    fig, axes = grid(len(panels) + widths, cols=2)
    if widths:  # beside the rods-only point, whose second reading it is
        width_panel(axes.pop(1), w)
    sizes = np.unique(r.by_size.n.to_numpy(float))
    n_inf = 4.0 * sizes.max() if sizes.size else 1.0
    for ax, (keys, labels, ylabel) in zip(axes, panels, strict=False):
        _panel(ax, r, keys, labels, nu, n_inf)
        size_axis(ax, sizes, n_inf)
        ax.set(xlabel=T.label("n"), ylabel=T.label(ylabel))
        ax.legend()
    fig.suptitle(T.label("title.fs", nu=nu))
    return save(fig, figdir, "FS")


def figure_rc(r: FiniteSizeResult, figdir):
    """One pebble-game sample just after its threshold event with its spanning cluster and that
    cluster's stressed sites; beside it, log-log, the mean masses at the threshold against n
    with their fitted n^d (the line through the points' weighted centre, display only)."""
    pic, fits, by = r.picture, r.fractal, r.fractal_by_size
    assert fits is not None and by is not None, "the clusters' figure needs the pebble game's"
    fig, (left, right) = plt.subplots(1, 2, figsize=(PAGE, 3.6))
    if pic is not None:
        below = {"loc": "upper center", "bbox_to_anchor": (0.5, 0.0), "ncol": 2}
        draw_clusters(left, pic.network, pic.clusters, spanning=pic.spanning.sites, legend=below)
        left.set_axis_off()
        left.set_title(T.label("title.picture", n=pic.n, sample=pic.sample, p_r=pic.p_r,
                               rods=pic.spanning.sites.size,
                               stressed=int(pic.spanning.stressed.sum())))  # fmt: skip
    n = by.n.to_numpy(float)
    for cluster, colour in zip((c for c, *_ in FRACTAL_CLUSTERS if f"{c}_nodes" in by), CYCLE,
                               strict=False):  # fmt: skip
        mean, err = by[f"{cluster}_nodes"], by[f"{cluster}_nodes_err"]
        f = fits[(fits.cluster == cluster) & (fits.mass == "nodes") & (fits.n_min == n.min())]
        (row,) = f.itertuples()
        right.errorbar(n, mean, yerr=err, marker="o", ls="none", color=colour, capsize=2)
        w = (mean / err) ** 2
        c = np.sum(w * (np.log(mean) - row.d * np.log(n))) / np.sum(w)
        right.plot(n, np.exp(c) * n**row.d, "--", color=colour, lw=1,
                   label=T.label(f"mass.{cluster}", d=row.d, d_err=row.d_err))  # fmt: skip
    right.set(xscale="log", yscale="log", xlabel=T.label("n"), ylabel=T.label("y.mass"),
              title=T.label("title.mass"))  # fmt: skip
    right.set_xticks(n, [f"{v:g}" for v in n])
    right.xaxis.set_minor_locator(NullLocator())
    right.legend()
    return save(fig, figdir, "RC")


def figures(r: FiniteSizeResult, figdir) -> dict:
    out = {"FS": figure_fs(r, figdir)}
    if r.fractal is not None:
        out["RC"] = figure_rc(r, figdir)
    return out


def tables(r: FiniteSizeResult) -> dict:
    out = {"fss_by_size": r.by_size, "fss_extrapolated": r.extrapolated,
           "fss_pc_by_smallest_size": r.pc_by_smallest, "pc_fractal_dimensions": r.fractal,
           "pc_cluster_masses": r.fractal_by_size,
           "fss_paper_fit": None if r.paper_fit is None or not len(r.paper_fit) else r.paper_fit,
           "fss_paper_claims": None if r.paper_claims is None or not len(r.paper_claims)
           else r.paper_claims,
           "fss_pcrit_first_positive": None if r.paper_pcrit is None or not len(r.paper_pcrit)
           else r.paper_pcrit,
           "pc_calibration_fits": None if r.pc_calibration is None
           else calibration_table(r.pc_calibration),
           "pc_widths": widths_table(r.pc_widths)}  # fmt: skip
    return {k: v for k, v in out.items() if v is not None}


def widths_table(w: an.WidthScaling | None) -> pd.DataFrame | None:
    """The widths reading the report quotes: per size the standard deviation of the rods-only
    thresholds and their P = 1/2 point, with nu and p_c from them (each with its chi-square)
    repeated on every row."""
    if w is None:
        return None
    return pd.DataFrame({"n": w.n, "width": w.width, "width_err": w.width_err,
                         "centre": w.centre, "centre_err": w.centre_err, "nu": w.nu,
                         "nu_err": w.nu_err, "nu_chi2": w.nu_chi2, "p_c": w.p_c,
                         "p_c_err": w.p_c_err, "p_c_chi2": w.p_c_chi2})  # fmt: skip


def cost(scale: Scale, costs) -> float:
    """The analysis: per size, six collapse fits at Fig. 1C's rate."""
    return costs.analysis(NAME) * len(scale[NAME].sizes) * scale.bootstrap / 100


def errors(scale: Scale) -> list[tuple]:
    """Every S_t/S_r claim has the first's error, every p_crit the rods-only p_c's."""
    p = scale[NAME]
    out = [("st_sr_cables_compression", f"fss n={n}", "st_sr", n, p.samples_at(n))
           for n in p.sizes]  # fmt: skip
    return out + [("rods_only_pc", f"fss n={n}", "p_crit", n, p.pc_at(n)) for n in p.pc_sizes]


STUDY = Study(
    name=NAME, params=PARAMS, default=Params(), sweeps=sweeps, analyse=analyse,
    claims=lambda r: r.measured, cost=cost, numbers=numbers, figures=figures, tables=tables,
    report_tables=report_tables, errors=errors, energy=energy_names, evidence=True,
)  # fmt: skip
