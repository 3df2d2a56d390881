"""Beyond the paper: the headline questions asked of the disordered FCC lattice in 3D.

Per size n (:attr:`~.scales.Scale.sizes_3d`), exact per-sample thresholds along p_r of the
periodic FCC lattice (node disorder delta = 0.2, principal strain axes from the SO(3) sequence by
sample index): rods only (p_t = 0) under dilation and shear; rods + cables and struts at p_t =
:data:`~.fig1c.FIG1C_PT` with f_c = 0.5 under dilation, shear and compression; rods + cables (f_c
= 1) under compression and dilation. Rods only under compression is rods only under dilation
(compression is minus dilation and a rod resists both signs, sample by sample: one system), so it
is read from the dilation sweep. From these, as in 2D:

* the rods-only threshold (median of the per-sample thresholds; its own sweep with more samples
  and one size more, :attr:`~.scales.Scale.pc_3d`);
* S_t/S_r from the collapse P = F(p_r + lam p_t) over p_t = 0 and 0.3
  (:func:`~tensegrity_rigidity.analysis.fits.fit_collapse`) for f_c = 0.5 per strain and for
  rods + cables under compression and dilation (the paper's 37 % and 67 % questions);

each extrapolated to n -> infinity with ``y(n) = y_inf + a n^(-1/nu)``
(:func:`~tensegrity_rigidity.analysis.scaling.fit_finite_size`) in two readings: nu fitted to
the rods-only thresholds (used for every quantity, as in 2D), and ``1/nu = d = 3``, the
finite-size shift of a first-order transition, which is what the literature finds for bond-diluted
central-force FCC (:data:`PC_3D_CHECK`). The widths of the rods-only threshold distributions
give a third reading of p_c with no exponent
(:func:`~tensegrity_rigidity.analysis.scaling.width_scaling`).

The quantities are not claims of the paper (which is 2D): their measurements carry keys of
their own (``fcc_<2D key>``), and the report's 3D section sets each beside its 2D counterpart:
the paper's value (:data:`~tensegrity_rigidity.paper.claims.CLAIMS`) and ours extrapolated
from the finite-size study (:data:`~tensegrity_rigidity.paper.claims.TWO_D_OURS`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ...analysis import estimators as an
from ..claims import CLAIMS, REFERENCES, TWO_D_OURS, Measurement
from .fig1c import FIG1C_PT
from .rows import Rows, interval_straddles, load_sweeps, threshold_matrix
from .scales import Scale

#: seed of the 3D sweeps (sample k's disorder derives from (seed, n, delta, k))
SEED_3D = 33
#: the strains of the 3D study
DILATION, SHEAR, COMPRESSION = 0.0, math.pi / 2, math.pi
#: (f_c, strains) of the one-sided sweeps at p_t = FIG1C_PT: name suffix -> (f_c, phi list)
MIXED_3D = {"half": (0.5, [DILATION, SHEAR, COMPRESSION]), "cables": (1.0, [COMPRESSION, DILATION])}


def chunk_size_3d(n: int) -> int:
    """Samples per chunk of a 3D threshold sweep at size ``n`` (the unit of resumption).

    A threshold search at p_t = 0.3 takes about 0.35 s at n = 4, 2 s at 6, 9 s at 8 and about
    30 s at 10 on one core: chunks of a minute or less keep what an interruption loses small
    and let two workers share a sweep's last chunks. Rows do not depend on it.
    """
    return {4: 32, 5: 16, 6: 8, 8: 4}.get(n, 2 if n >= 10 else 32)


def _base(n: int, samples: int) -> dict:
    return {
        "n": n,
        "samples": samples,
        "seed": SEED_3D,
        "lattice": {"kind": "fcc"},
        "threshold": {"path": "p_r"},
        "output": {"chunk_size": chunk_size_3d(n)},
    }


def sweeps(scale: Scale) -> dict[str, dict]:
    """Sweep name -> spec of the 3D study, smaller sizes first.

    Per size of :attr:`~.scales.Scale.sizes_3d`: ``fcc_rods_n{n}`` (p_t = 0, dilation; the
    scale's :attr:`~.scales.Scale.pc_3d` count, at least the size's count, for the rods-only
    threshold), ``fcc_rods_shear_n{n}`` (p_t = 0, shear), ``fcc_half_n{n}`` (p_t = 0.3, f_c =
    0.5, three strains) and ``fcc_cables_n{n}`` (p_t = 0.3, f_c = 1, compression and
    dilation). Sizes of ``pc_3d`` beyond ``sizes_3d`` get the rods-only sweep only. One seed
    (:data:`SEED_3D`), so sample k is the same disorder and rotation in every sweep of its size
    (common random numbers).
    """
    out: dict[str, dict] = {}
    pc = dict(scale.pc_3d)
    sizes = sorted(set(scale.sizes_3d) | set(pc))
    for n in sizes:
        samples = scale.samples_3d_at(n)
        rods = max(samples, pc.get(n, 0))
        out[f"fcc_rods_n{n}"] = _base(n, rods) | {"p_t": 0.0, "f_c": 0.5, "phi": [DILATION]}
        if n not in scale.sizes_3d:
            continue
        out[f"fcc_rods_shear_n{n}"] = _base(n, samples) | {"p_t": 0.0, "f_c": 0.5, "phi": [SHEAR]}
        for suffix, (f_c, phis) in MIXED_3D.items():
            out[f"fcc_{suffix}_n{n}"] = _base(n, samples) | {
                "p_t": FIG1C_PT, "f_c": f_c, "phi": phis,
            }  # fmt: skip
    return out


#: p_r grid of the outcomes the collapse fits read from the thresholds: the 3D thresholds at
#: p_t = 0.3 lie near 0.3 (0.27 to 0.37 at n = 4 to 8), below the 2D grid's start
FIT_P_R_3D = np.arange(0.1, 0.9001, 0.01)
#: 2D key -> (f_c, strain) of the S_t/S_r quantities measured in 3D
LAMBDA_3D = {
    "st_sr_half_dilation": (0.5, "dilation"),
    "st_sr_half_shear": (0.5, "shear"),
    "st_sr_half_compression": (0.5, "compression"),
    "st_sr_cables_compression": (1.0, "compression"),
    "st_sr_cables_dilation": (1.0, "dilation"),
}
#: the 2D keys of every 3D quantity, in the report's order
KEYS_3D = ("rods_only_pc", *LAMBDA_3D)
#: the literature's rods-only threshold of bond-diluted FCC, and Maxwell's count
PC_3D_CHECK = REFERENCES["pc_fcc_chubynsky_thorpe"]
PC_3D_MAXWELL = REFERENCES["pc_fcc_maxwell"]
#: the second extrapolation's exponent: the shift of a first-order transition's finite-size
#: threshold falls as the inverse volume, n^(-d) (1/nu = d = 3)
NU_FIRST_ORDER = 1.0 / 3.0


def key_3d(key: str) -> str:
    """The measurement key of a 3D quantity (``fcc_`` and the 2D claim's key)."""
    return f"fcc_{key}"


@dataclass(frozen=True, eq=False)
class ThreeDResult:
    """The headline quantities on the FCC lattice at several n and their n -> infinity limits.

    Attributes
    ----------
    by_size : DataFrame
        Per (n, key): ``value``, ``err``, ``samples`` (key: the 2D claim's key, :data:`KEYS_3D`);
        the S_t/S_r rows also ``contour``, ``contour_err`` (the slope of the P = 1/2 contour,
        :func:`~tensegrity_rigidity.analysis.fits.contour_slope`, the model-free estimator);
        the rods-only rows also ``width`` (standard deviation of the thresholds) and
        ``intervals`` (thresholds left as intervals by undecided probes).
    extrapolated : DataFrame
        Per key: ``y_inf``, ``y_inf_err``, ``nu``, ``nu_err``, ``chi2``, ``dof`` with nu fitted
        to the rods-only thresholds (every key uses that nu), and ``y_inf_first_order``,
        ``y_inf_first_order_err``, ``chi2_first_order``, ``dof_first_order`` with 1/nu = 3.
    widths : WidthScaling or None
        The rods-only threshold distributions against n (p_c with no fitted exponent).
    strain_free : float
        Fraction of the samples whose rods-only threshold is the same under shear as under
        dilation (a rods-only threshold should not depend on the strain).
    half_strain_free : float
        Fraction of the samples whose threshold at f_c = 0.5, p_t = 0.3 is the same under
        dilation, shear and compression.
    """

    by_size: pd.DataFrame
    extrapolated: pd.DataFrame
    sizes: tuple[int, ...]
    samples: tuple[int, ...]
    pc_sizes: tuple[int, ...]
    pc_samples: tuple[int, ...]
    excluded: dict[str, int]
    widths: object = None
    strain_free: float = float("nan")
    half_strain_free: float = float("nan")
    straddling: int | None = None
    measured: tuple[Measurement, ...] = ()

    def at(self, key: str, n: int) -> tuple[float, float]:
        """(value, error) of one quantity at size n."""
        row = self.by_size[(self.by_size.key == key) & (self.by_size.n == n)].iloc[0]
        return float(row.value), float(row.err)


def _rods_rows(parts: dict[str, pd.DataFrame], n: int, phi: float) -> pd.DataFrame:
    """Rods-only thresholds of size n under one strain (compression reads dilation's rows)."""
    if math.isclose(phi, SHEAR):
        return parts[f"fcc_rods_shear_n{n}"]
    return parts[f"fcc_rods_n{n}"].assign(phi=phi)


def analyse(rows: Rows, scale: Scale) -> ThreeDResult:
    """The 3D quantities per size (collapse fits, medians) and their extrapolations."""
    parts = {name: frame for name, (frame, _) in rows.items()}
    excluded = {name: count for name, (_, count) in rows.items()}
    rng = scale.rng
    by_size, straddle = [], []
    for n in scale.sizes_3d:
        mixed = pd.concat([parts[f"fcc_{s}_n{n}"] for s in MIXED_3D], ignore_index=True)
        for key, (f_c, strain) in LAMBDA_3D.items():
            phi = {"dilation": DILATION, "shear": SHEAR, "compression": COMPRESSION}[strain]
            # the rods-only rows of the same samples (the one-sided sweeps' count)
            rods = _rods_rows(parts, n, phi)
            one = mixed[np.isclose(mixed.phi, phi) & np.isclose(mixed.f_c, f_c)]
            rods = rods[rods["sample"].isin(one["sample"])]
            sub = pd.concat([rods.assign(f_c=f_c), one], ignore_index=True)
            straddle.append(sub)
            y, pr, pt = an.outcomes_from_thresholds(sub, FIT_P_R_3D)
            fit = an.fit_collapse(y, pr, pt, n_boot=scale.bootstrap, rng=rng("collapse"))
            units = len(an.common_samples(sub))
            # the model-free alternative: the slope of the P = 1/2 contour
            c = an.contour_slope(
                threshold_matrix(sub, [0.0, FIG1C_PT]), np.array([0.0, FIG1C_PT]),
                n_boot=scale.bootstrap, rng=rng("contour"),
            )  # fmt: skip
            by_size.append(
                {"n": n, "key": key, "value": fit.lam, "err": fit.lam_err, "samples": units,
                 "contour": c.value, "contour_err": c.err}
            )  # fmt: skip
    pc_sizes = sorted(set(scale.sizes_3d) | {m for m, _ in scale.pc_3d})
    per_size = []
    for n in pc_sizes:
        rods = parts[f"fcc_rods_n{n}"]
        t = rods.threshold_p_r.to_numpy(float)
        per_size.append(t)
        value, err = an.critical_point(t, rng=rng("critical_point"))
        width = (rods.threshold_p_r_high - rods.threshold_p_r_low).to_numpy(float)
        by_size.append(
            {
                "n": n,
                "key": "rods_only_pc",
                "value": value,
                "err": err,
                "samples": len(rods),
                "width": float(np.std(t, ddof=1)) if t.size > 1 else np.nan,
                "intervals": int(np.sum(width > 0)),
            }
        )
    by = pd.DataFrame(by_size)
    widths = (
        an.width_scaling(np.asarray(pc_sizes, float), per_size, rng=rng("widths"))
        if len(pc_sizes) >= 3
        else None
    )
    same, total = 0, 0
    for n in scale.sizes_3d:
        a = parts[f"fcc_rods_n{n}"].set_index("sample").threshold_p_r
        b = parts[f"fcc_rods_shear_n{n}"].set_index("sample").threshold_p_r
        common = a.index.intersection(b.index)
        same += int(np.sum(np.isclose(a[common], b[common], rtol=0, atol=1e-12)))
        total += len(common)
    # f_c = 0.5: the fraction of samples whose threshold is the same under the three strains
    alike, count = 0, 0
    for n in scale.sizes_3d:
        half = (
            parts[f"fcc_half_n{n}"]
            .pivot_table(index="sample", columns="phi", values="threshold_p_r")
            .dropna()
        )
        if half.shape[1] == len(MIXED_3D["half"][1]):
            alike += int(np.sum(np.ptp(half.to_numpy(float), axis=1) <= 1e-12))
            count += len(half)
    extrapolated = extrapolate(by, rng)
    result = ThreeDResult(
        by_size=by,
        extrapolated=extrapolated,
        sizes=tuple(scale.sizes_3d),
        samples=tuple(scale.samples_3d),
        pc_sizes=tuple(pc_sizes),
        pc_samples=tuple(len(t) for t in per_size),
        excluded=excluded,
        widths=widths,
        strain_free=same / total if total else float("nan"),
        half_strain_free=alike / count if count else float("nan"),
        straddling=interval_straddles(pd.concat(straddle, ignore_index=True), FIT_P_R_3D)
        if straddle
        else None,
    )
    return dataclasses.replace(result, measured=claims(result))


def extrapolate(by_size: pd.DataFrame, rng) -> pd.DataFrame:
    """Each quantity of ``by_size`` extrapolated to n -> infinity in the two readings.

    Parameters
    ----------
    by_size : DataFrame
        :attr:`ThreeDResult.by_size` (``n``, ``key``, ``value``, ``err``).
    rng : callable
        ``Scale.rng``: the bootstrap stream of the finite-size fits.

    Returns
    -------
    DataFrame
        :attr:`ThreeDResult.extrapolated`, one row per key of ``by_size``.
    """

    def series(key) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        s = by_size[by_size.key == key].sort_values("n")
        return s.n.to_numpy(float), s.value.to_numpy(float), s.err.to_numpy(float)

    pc = an.fit_finite_size(*series("rods_only_pc"), rng=rng("finite_size"))
    rows = []
    for key in [k for k in KEYS_3D if k in set(by_size.key)]:
        n, y, err = series(key)
        free = (
            pc
            if key == "rods_only_pc"
            else an.fit_finite_size(n, y, err, nu=pc.nu, nu_err=pc.nu_err, rng=rng("finite_size"))
        )
        first = an.fit_finite_size(n, y, err, nu=NU_FIRST_ORDER, rng=rng("finite_size"))
        rows.append(
            {
                "key": key,
                "y_inf": free.y_inf,
                "y_inf_err": free.y_inf_err,
                "nu": free.nu,
                "nu_err": free.nu_err,
                "chi2": free.chi2,
                "dof": free.dof,
                "y_inf_first_order": first.y_inf,
                "y_inf_first_order_err": first.y_inf_err,
                "chi2_first_order": first.chi2,
                "dof_first_order": first.dof,
            }
        )
    return pd.DataFrame(rows)


def beside_2d(result: ThreeDResult) -> pd.DataFrame:
    """Each 3D quantity beside its 2D counterparts, with the differences in units of both errors.

    Returns
    -------
    DataFrame
        Per key of :data:`KEYS_3D`: ``quantity`` (the 2D claim's text), ``n_max`` and the value
        there (``largest``, ``largest_err``), the two extrapolations (``y_inf``...,
        ``y_inf_first_order``...), ``paper_2d`` (the paper's value as printed, or the
        literature's for the rods-only threshold), ``ours_2d`` and ``ours_2d_err``
        (:data:`~tensegrity_rigidity.paper.claims.TWO_D_OURS`) and ``z_2d``, the largest size's
        value against ours in 2D, and ``z_2d_inf``, the free extrapolation against it (NaN where
        an error is missing).
    """
    ex = result.extrapolated.set_index("key")
    out = []
    for key in KEYS_3D:
        if key not in ex.index:
            continue
        s = result.by_size[result.by_size.key == key].sort_values("n").iloc[-1]
        two = TWO_D_OURS[key]
        out.append(
            {
                "key": key,
                "quantity": CLAIMS[key].text,
                "n_max": int(s.n),
                "largest": float(s.value),
                "largest_err": float(s.err),
                "y_inf": float(ex.loc[key].y_inf),
                "y_inf_err": float(ex.loc[key].y_inf_err),
                "y_inf_first_order": float(ex.loc[key].y_inf_first_order),
                "y_inf_first_order_err": float(ex.loc[key].y_inf_first_order_err),
                "paper_2d": CLAIMS[key].paper,
                "ours_2d": two.value,
                "ours_2d_err": two.error or np.nan,
                "z_2d": an.agreement_z(float(s.value), float(s.err) ** 2, two.value,
                                       two.error or np.nan),
                "z_2d_inf": an.agreement_z(float(ex.loc[key].y_inf),
                                           float(ex.loc[key].y_inf_err) ** 2, two.value,
                                           two.error or np.nan),
            }
        )  # fmt: skip
    return pd.DataFrame(out)


def claims(result: ThreeDResult) -> tuple[Measurement, ...]:
    """The 3D quantities as measurements (keys :func:`key_3d`): each extrapolation and each size.

    They are not claims of the paper, so the comparison table does not list them; the report's
    3D section does, beside the 2D values.
    """
    out = []
    sizes = ", ".join(map(str, result.sizes))
    for row in result.extrapolated.itertuples():
        ns = ", ".join(map(str, result.pc_sizes)) if row.key == "rods_only_pc" else sizes
        system = f"FCC, extrapolated to n -> infinity from n = {ns}"
        out.append(
            Measurement.scalar(
                key_3d(row.key), row.y_inf, row.y_inf_err, system,
                label=f"y + a n^(-1/nu), nu = {row.nu:.2f} fitted to the rods-only thresholds",
            )
        )  # fmt: skip
        out.append(
            Measurement.scalar(
                key_3d(row.key), row.y_inf_first_order, row.y_inf_first_order_err, system,
                factor="finite size", label="y + a n^(-3): the shift of a first-order transition",
            )
        )  # fmt: skip
    for row in result.by_size.itertuples():
        out.append(
            Measurement.scalar(
                key_3d(row.key), row.value, row.err, f"FCC n = {row.n}, {row.samples} samples",
                factor="finite size", label=f"n = {row.n}", size=int(row.n),
            )
        )  # fmt: skip
    return tuple(out)


def study(out, scale: Scale, **kw) -> ThreeDResult:
    """Run (or resume) the sweeps of the 3D study into ``out`` and analyse them."""
    return analyse(load_sweeps(out, sweeps(scale), **kw), scale)
