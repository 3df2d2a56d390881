"""Beyond the paper: the headline questions asked of the disordered FCC lattice in 3D.

Per size n, exact per-sample thresholds along p_r of the periodic FCC lattice (principal strain
axes from the SO(3) sequence by sample index): rods only under dilation and shear (rods only
under compression is the dilation system, sample by sample); rods + cables and struts at p_t =
:data:`~.rows.COLLAPSE_PT` with f_c = 0.5 under three strains; rods + cables under compression
and dilation. From them, as in 2D, the rods-only threshold (its own sweep with more samples and
a size more) and S_t/S_r from the collapse, each extrapolated with ``y_inf + a n^(-1/nu)`` in
two readings: nu fitted to the rods-only points, and ``1/nu = d = 3``, the inverse-volume shift
of a first-order transition without quenched disorder (an assumed exponent: the literature finds
the transition first-order, not this shift), beside the rods-only p_c over every exponent of a
declared range. The
quantities are not the paper's claims: their measurements carry keys of their own
(``fcc_<2D key>``), and the section sets each beside its 2D counterparts.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from ...analysis import estimators as an
from ...analysis import limits
from ...model.lattice import DEFAULT_DELTA
from ..claims import CLAIMS, REFERENCES, TWO_D_OURS, Measurement
from ..comparison import fit_form, fmt
from ..study import Result, Scale, Study
from ..style import (
    CYCLE,
    PAPER_MARKER,
    STRAIN_COLOURS,
    grid,
    save,
    size_axis,
    unresolved,
    width_panel,
)
from ..style import errorbar as bars
from ..template import load
from .headline import SEED_3D, chunk_size_3d, misfit
from .rows import COLLAPSE_PT, Rows, threshold_bounds

NAME = "three_d"
T = load(NAME)
DILATION, SHEAR, COMPRESSION = 0.0, math.pi / 2, math.pi
#: (f_c, strains) of the one-sided sweeps at p_t = COLLAPSE_PT: name suffix -> (f_c, phi list)
MIXED_3D = {"half": (0.5, [DILATION, SHEAR, COMPRESSION]), "cables": (1.0, [COMPRESSION, DILATION])}
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
PC_3D_CHECK = REFERENCES["pc_fcc_chubynsky_thorpe"]
PC_3D_MAXWELL = REFERENCES["pc_fcc_maxwell"]
#: the second extrapolation's exponent: a first-order transition's shift, 1/nu = d = 3
NU_FIRST_ORDER = 1.0 / 3.0
#: the exponents x of ``y_inf + a n^-x`` the rods-only p_c is extrapolated over when no
#: exponent is assumed: 1/nu for nu from 1/3 (1/nu = d, the shift of a first-order
#: transition) to 2 (well above 3D percolation's 0.88)
X_3D = np.round(np.arange(0.5, 3.0001, 0.05), 2)
#: the laws of each quantity's limit with no exponent borrowed (analysis.limits): a finite
#: limit with its own exponent, and no size dependence
LIMIT_LAWS = ("finite", "constant")
#: a size with fewer samples per point than this has error bars that are themselves uncertain
#: by 1 / sqrt(2 (S - 1)) or more (the scales' floor wherever an error bar is compared)
ERROR_FLOOR_SAMPLES = 24


@dataclass(frozen=True, kw_only=True)
class Params:
    """FCC sizes and samples per point at each; (n, samples) of the rods-only thresholds
    (sizes may go beyond)."""

    sizes: tuple[int, ...] = ()
    samples: tuple[int, ...] = ()
    pc: tuple[tuple[int, int], ...] = ()

    def samples_at(self, n: int) -> int:
        return dict(zip(self.sizes, self.samples, strict=True)).get(n, 0)


PARAMS = {
    "3d": Params(sizes=(4, 6, 8, 10), samples=(160, 64, 24, 6),
                 pc=((4, 640), (6, 320), (8, 160), (10, 48), (12, 16))),
    "tiny-3d": Params(sizes=(2, 3, 4), samples=(4, 3, 2), pc=((2, 8), (3, 6), (4, 3))),
}  # fmt: skip


def key_3d(key: str) -> str:
    """The measurement key of a 3D quantity."""
    return f"fcc_{key}"


def _base(n: int, samples: int) -> dict:
    return {"n": n, "samples": samples, "seed": SEED_3D, "lattice": {"kind": "fcc"},
            "threshold": {"path": "p_r"}, "output": {"chunk_size": chunk_size_3d(n)}}  # fmt: skip


def sweeps(scale: Scale) -> dict[str, dict]:
    """Per size, smaller first: ``fcc_rods_n{n}`` (dilation, the size's rods-only count),
    ``fcc_rods_shear_n{n}``, ``fcc_half_n{n}`` and ``fcc_cables_n{n}``; sizes of ``pc`` only
    get the first. One seed: sample k is the same disorder in every sweep of its size."""
    p, out = scale[NAME], {}
    pc = dict(p.pc)
    for n in sorted(set(p.sizes) | set(pc)):
        samples = p.samples_at(n)
        rods = max(samples, pc.get(n, 0))
        out[f"fcc_rods_n{n}"] = _base(n, rods) | {"p_t": 0.0, "f_c": 0.5, "phi": [DILATION]}
        if n not in p.sizes:
            continue
        out[f"fcc_rods_shear_n{n}"] = _base(n, samples) | {"p_t": 0.0, "f_c": 0.5, "phi": [SHEAR]}
        for suffix, (f_c, phis) in MIXED_3D.items():
            out[f"fcc_{suffix}_n{n}"] = _base(n, samples) | {"p_t": COLLAPSE_PT, "f_c": f_c,
                                                              "phi": phis}  # fmt: skip
    return out


@dataclass(frozen=True, eq=False)
class ThreeDResult(Result):
    """``by_size``: per (n, key) ``value``, ``err``, ``samples`` (the S_t/S_r rows also the
    contour slope ``contour``, ``contour_err``; the rods-only rows ``width`` and ``intervals``);
    ``extrapolated``: per key the fit with nu fitted to the rods-only points (``y_inf``, ``a``,
    ``nu``, ``chi2``, ...) and with 1/nu = 3 (``*_first_order``); ``widths``: the rods-only
    threshold distributions against n; ``strain_free``, ``half_strain_free``: the fractions of
    samples whose threshold is the same under the strains (rods only; f_c = 0.5);
    ``pc_envelope``: the rods-only p_c over every exponent of :data:`X_3D` the data allow
    (:func:`~tensegrity_rigidity.analysis.limits.exponent_envelope`); ``binomial_widths``: the
    widths of the rods-only thresholds against the binomial bond-count noise alone
    (:func:`~tensegrity_rigidity.analysis.limits.widths_against_binomial`), ``sites`` the
    lattice's bonds M at each rods-only size."""

    by_size: pd.DataFrame
    extrapolated: pd.DataFrame
    sizes: tuple[int, ...]
    samples: tuple[int, ...]
    pc_sizes: tuple[int, ...]
    pc_samples: tuple[int, ...]
    widths: Any = None
    strain_free: float = float("nan")
    half_strain_free: float = float("nan")
    pc_envelope: Any = None
    binomial_widths: Any = None
    sites: tuple[int, ...] = ()

    def at(self, key: str, n: int) -> tuple[float, float]:
        """(value, error) of one quantity at size n."""
        row = self.by_size[(self.by_size.key == key) & (self.by_size.n == n)].iloc[0]
        return float(row.value), float(row.err)


def _rods_rows(parts: dict[str, pd.DataFrame], n: int, phi: float) -> pd.DataFrame:
    """Rods-only thresholds of size n under one strain (compression reads dilation's rows)."""
    if math.isclose(phi, SHEAR):
        return parts[f"fcc_rods_shear_n{n}"]
    return parts[f"fcc_rods_n{n}"].assign(phi=phi)


def _lambdas(parts, sizes, scale: Scale) -> list[dict]:
    """S_t/S_r per size and quantity (collapse fit; contour slope beside it)."""
    out = []
    for n in sizes:
        mixed = pd.concat([parts[f"fcc_{s}_n{n}"] for s in MIXED_3D], ignore_index=True)
        for key, (f_c, strain) in LAMBDA_3D.items():
            phi = {"dilation": DILATION, "shear": SHEAR, "compression": COMPRESSION}[strain]
            one = mixed[np.isclose(mixed.phi, phi) & np.isclose(mixed.f_c, f_c)]
            rods = _rods_rows(parts, n, phi)  # of the same samples (the one-sided count)
            rods = rods[rods["sample"].isin(one["sample"])]
            sub = pd.concat([rods.assign(f_c=f_c), one], ignore_index=True)
            t, lo, hi = threshold_bounds(sub, [0.0, COLLAPSE_PT])
            fit = an.fit_collapse_thresholds(t, np.array([0.0, COLLAPSE_PT]), lo, hi,
                                             n_boot=scale.bootstrap,
                                             rng=scale.rng("collapse"))  # fmt: skip
            c = an.contour_slope(t, np.array([0.0, COLLAPSE_PT]), n_boot=scale.bootstrap,
                                 rng=scale.rng("contour"))  # fmt: skip
            out.append({"n": n, "key": key, "value": fit.lam, "err": fit.lam_err,
                        "samples": len(an.common_samples(sub)), "contour": c.value,
                        "contour_err": c.err})  # fmt: skip
    return out


def _same_thresholds(parts, sizes) -> tuple[float, float]:
    """The fractions of samples whose rods-only threshold is the same under shear as under
    dilation, and whose threshold at f_c = 0.5 is the same under the three strains."""
    same = total = alike = count = 0
    for n in sizes:
        a = parts[f"fcc_rods_n{n}"].set_index("sample").threshold_p_r
        b = parts[f"fcc_rods_shear_n{n}"].set_index("sample").threshold_p_r
        common = a.index.intersection(b.index)
        same += int(np.sum(np.isclose(a[common], b[common], rtol=0, atol=1e-12)))
        total += len(common)
        half = parts[f"fcc_half_n{n}"].pivot_table(index="sample", columns="phi",
                                                   values="threshold_p_r").dropna()  # fmt: skip
        if half.shape[1] == len(MIXED_3D["half"][1]):
            alike += int(np.sum(np.ptp(half.to_numpy(float), axis=1) <= 1e-12))
            count += len(half)
    return same / total if total else np.nan, alike / count if count else np.nan


def analyse(rows: Rows, scale: Scale) -> ThreeDResult:
    """The 3D quantities per size (collapse fits, medians) and their extrapolations."""
    p = scale[NAME]
    parts = {name: frame for name, (frame, _) in rows.items()}
    by_size = _lambdas(parts, p.sizes, scale)
    pc_sizes, per_size, sites = sorted(set(p.sizes) | {m for m, _ in p.pc}), [], []
    for n in pc_sizes:
        rods = parts[f"fcc_rods_n{n}"]
        per_size.append(rods.threshold_p_r.to_numpy(float))
        sites.append(int(rods.sites.iloc[0]))
        value, err = an.critical_point(per_size[-1], rng=scale.rng("critical_point"))
        width = (rods.threshold_p_r_high - rods.threshold_p_r_low).to_numpy(float)
        spread = float(np.std(per_size[-1], ddof=1)) if per_size[-1].size > 1 else np.nan
        by_size.append({"n": n, "key": "rods_only_pc", "value": value, "err": err,
                        "samples": len(rods), "width": spread,
                        "intervals": int(np.sum(width > 0))})  # fmt: skip
    by = pd.DataFrame(by_size)
    widths = (an.width_scaling(np.asarray(pc_sizes, float), per_size, rng=scale.rng("widths"))
              if len(pc_sizes) >= 3 else None)  # fmt: skip
    strain_free, half_free = _same_thresholds(parts, p.sizes)
    binomial = (limits.widths_against_binomial(per_size, sites, n_boot=scale.bootstrap,
                                               rng=scale.rng("binomial_widths"))
                if per_size else None)  # fmt: skip
    return ThreeDResult(
        by_size=by, extrapolated=extrapolate(by, scale.rng), sizes=tuple(p.sizes),
        samples=tuple(p.samples), pc_sizes=tuple(pc_sizes),
        pc_samples=tuple(len(t) for t in per_size),
        excluded={name: count for name, (_, count) in rows.items()}, widths=widths,
        strain_free=strain_free, half_strain_free=half_free, pc_envelope=pc_envelope(by),
        binomial_widths=binomial, sites=tuple(sites),
    )  # fmt: skip


def pc_envelope(by_size: pd.DataFrame) -> limits.Envelope | None:
    """The rods-only p_c with no exponent assumed: ``y_inf + a n^-x`` at every x of
    :data:`X_3D`, from every size and without the smallest (with four sizes or more), the
    union of the allowed fits' intervals; None with fewer than three sizes."""
    s = by_size[by_size.key == "rods_only_pc"].sort_values("n")
    n = s.n.to_numpy(float)
    if n.size < 3:
        return None
    n_mins = tuple(float(m) for m in n[: 1 + (n.size >= 4)])
    return limits.exponent_envelope(n, s.value.to_numpy(float), s.err.to_numpy(float), X_3D,
                                    n_mins)  # fmt: skip


def extrapolate(by_size: pd.DataFrame, rng) -> pd.DataFrame:
    """Each quantity of ``by_size`` extrapolated to n -> infinity in the two readings, and by
    :data:`LIMIT_LAWS` with the quantity's own exponent (``limit_law``, the first allowed,
    ``limit``, ``limit_stat``, the fit-form systematic ``limit_syst``, the allowed
    ``limit_laws``; NaN where none is); ``rng``: a scale's ``rng``."""

    def series(key) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        s = by_size[by_size.key == key].sort_values("n")
        return s.n.to_numpy(float), s.value.to_numpy(float), s.err.to_numpy(float)

    pc = an.fit_finite_size(*series("rods_only_pc"), rng=rng("finite_size"))
    rows = []
    for key in [k for k in KEYS_3D if k in set(by_size.key)]:
        n, y, err = series(key)
        free = pc if key == "rods_only_pc" else an.fit_finite_size(
            n, y, err, nu=pc.nu, nu_err=pc.nu_err, rng=rng("finite_size"))  # fmt: skip
        first = an.fit_finite_size(n, y, err, nu=NU_FIRST_ORDER, rng=rng("finite_size"))
        lim = limits.limit_laws(n, y, err, laws=LIMIT_LAWS, rng=rng("finite_size"))
        fitting = ",".join(k for k, f in lim.fits.items() if f.acceptable)
        rows.append({"key": key, "y_inf": free.y_inf, "y_inf_err": free.y_inf_err, "a": free.a,
                     "nu": free.nu, "nu_err": free.nu_err, "chi2": free.chi2, "dof": free.dof,
                     "y_inf_first_order": first.y_inf, "y_inf_first_order_err": first.y_inf_err,
                     "a_first_order": first.a, "chi2_first_order": first.chi2,
                     "dof_first_order": first.dof, "limit": lim.value, "limit_stat": lim.stat,
                     "limit_law": lim.law,
                     "limit_syst": lim.syst,
                     "limit_laws": fitting})  # fmt: skip
    return pd.DataFrame(rows)


def _z(v: float, e: float, two) -> float:
    return an.agreement_z(v, e**2, two.value, two.error or np.nan)


def _own(f) -> tuple[float, float]:
    """A quantity's own limit (its laws, no exponent borrowed) and its error, statistical and
    fit-form combined (NaN where the sizes fix none)."""
    return float(f.limit), float(np.hypot(f.limit_stat, f.limit_syst))


def beside_2d(r: ThreeDResult) -> pd.DataFrame:
    """Per quantity: the largest size's value, the two extrapolations, the paper's 2D value as
    printed, ours in 2D (:data:`~tensegrity_rigidity.paper.claims.TWO_D_OURS`) and the z of the
    largest size (``z_2d``) and of the quantity's own limit (``z_2d_inf``: its own laws, no
    exponent borrowed; NaN where the sizes fix none) against ours in 2D."""
    ex, out = r.extrapolated.set_index("key"), []
    for key in [k for k in KEYS_3D if k in ex.index]:
        s, f, two = (
            r.by_size[r.by_size.key == key].sort_values("n").iloc[-1],
            ex.loc[key],
            TWO_D_OURS[key],
        )
        out.append({"key": key, "quantity": CLAIMS[key].text, "n_max": int(s.n),
                    "largest": float(s.value), "largest_err": float(s.err),
                    "y_inf": float(f.y_inf), "y_inf_err": float(f.y_inf_err),
                    "y_inf_first_order": float(f.y_inf_first_order),
                    "y_inf_first_order_err": float(f.y_inf_first_order_err),
                    "paper_2d": CLAIMS[key].paper, "ours_2d": two.value,
                    "ours_2d_err": two.error or np.nan, "z_2d": _z(s.value, s.err, two),
                    "z_2d_inf": _z(*_own(f), two)})  # fmt: skip
    return pd.DataFrame(out)


def claims(r: ThreeDResult) -> tuple[Measurement, ...]:
    """Each extrapolation and each size as measurements of the 3D keys (not the paper's claims,
    so the comparison table does not list them)."""
    out = []
    for row in r.extrapolated.itertuples():
        system = T.label("system", sizes=r.pc_sizes if row.key == "rods_only_pc" else r.sizes)
        out += [Measurement.scalar(key_3d(row.key), row.y_inf, row.y_inf_err, system,
                                   label=T.label("free", nu=row.nu)),
                Measurement.scalar(key_3d(row.key), row.y_inf_first_order,
                                   row.y_inf_first_order_err, system, factor="finite size",
                                   label=T.label("first_order"))]  # fmt: skip
    return (*out, *(Measurement.scalar(
        key_3d(row.key), row.value, row.err, T.label("size", n=row.n, samples=row.samples),
        factor="finite size", label=T.label("n", n=row.n), size=int(row.n))
        for row in r.by_size.itertuples()))  # fmt: skip


def _group(r: ThreeDResult, keys: tuple[str, ...], few: list[int]) -> dict:
    """One paragraph's numbers: each quantity's own limit, and the largest z against ours in
    2D of those limits and of the largest size."""
    ex, n_top = r.extrapolated.set_index("key"), max(r.sizes)
    parts, z_top, z_inf, misfits = [], [], [], ""
    for key in keys:
        f, (v, e), two = ex.loc[key], r.at(key, n_top), TWO_D_OURS[key]
        own = _own(f)
        value = fmt(*own) if np.isfinite(own[0]) else T.label("no_limit")
        parts.append(T.label("part", name=T.label(f"short.{key}"), value=value))
        z_top.append(_z(v, e, two))
        z_inf.append(_z(*own, two))
        misfits += misfit(f.chi2, f.dof)
    return {"parts": "; ".join(parts) + misfits, "z_inf": np.nanmax(z_inf),
            "z_top": np.nanmax(z_top), "few": "" if n_top in few else None}  # fmt: skip


def numbers(r: ThreeDResult) -> dict:
    ex = r.extrapolated.set_index("key")
    pc, n_max = ex.loc["rods_only_pc"], max(r.pc_sizes)
    few = [n for n, s in zip(r.sizes, r.samples, strict=True) if s < ERROR_FLOOR_SAMPLES]
    lam = r.by_size[r.by_size.key != "rods_only_pc"]
    dz = np.abs(lam.value - lam.contour) / np.hypot(lam.err, lam.contour_err)
    half, cables = (_group(r, keys, few) for keys in (tuple(LAMBDA_3D)[:3], tuple(LAMBDA_3D)[3:]))
    z_check = an.agreement_z(
        pc.y_inf_first_order,
        pc.y_inf_first_order_err**2,
        PC_3D_CHECK.value,
        PC_3D_CHECK.tolerance,
    )
    return {
        **_envelope(r),
        **_binomial(r),
        "node_disorder": DEFAULT_DELTA,
        "p_t": COLLAPSE_PT,
        "counts": [
            T.label("count", samples=s, n=n) for n, s in zip(r.sizes, r.samples, strict=True)
        ],
        "pc_counts": [
            T.label("count", samples=s, n=n) for n, s in zip(r.pc_sizes, r.pc_samples, strict=True)
        ],
        "n_top": max(r.sizes),
        "nodes": max(r.sizes) ** 3,
        "n_2d": round(max(r.sizes) ** 1.5),
        "n_max": n_max,
        "pc_top": fmt(*r.at("rods_only_pc", n_max)),
        "pc": fmt(pc.y_inf, pc.y_inf_err),
        "nu": pc.nu,
        "nu_err": pc.nu_err,
        "at_bound": ""
        if np.isfinite(pc.nu) and np.any(np.isclose(1 / pc.nu, an.THETA, rtol=1e-6))
        else None,
        "pc_first": fmt(pc.y_inf_first_order, pc.y_inf_first_order_err),
        "misfit": misfit(pc.chi2_first_order, pc.dof_first_order),
        "check": PC_3D_CHECK.value,
        "check_tolerance": PC_3D_CHECK.tolerance,
        # ours minus the literature's: negative where our threshold lies below 0.495
        "from_check": pc.y_inf_first_order - PC_3D_CHECK.value,
        "consistent": z_check if z_check < 2 else None,
        "different": z_check if z_check >= 2 else None,
        "maxwell": PC_3D_MAXWELL.value,
        "pc_2d": fmt(TWO_D_OURS["rods_only_pc"].value, TWO_D_OURS["rods_only_pc"].error),
        "jacobs_thorpe": REFERENCES["pc_jacobs_thorpe"].value,
        "strain_free": 100 * r.strain_free,
        "few": few or None,
        **_few_counts(r, few),
        "floor": ERROR_FLOOR_SAMPLES,
        **{f"half_{k}": v for k, v in half.items()},
        **{f"cables_{k}": v for k, v in cables.items()},
        "half_free": 100 * r.half_strain_free,
        "contour_z": np.nanmax(dz) if len(lam) and np.isfinite(dz).any() else None,
        "contour_diff": np.nanmax(np.abs(lam.value - lam.contour)) if len(lam) else None,
    }


def _few_counts(r: ThreeDResult, few: list[int]) -> dict:
    """``few_sizes``: the sizes with fewer than :data:`ERROR_FLOOR_SAMPLES` samples with their
    counts, per point and of the rods-only thresholds (with the bootstrap error of the median
    beside the spread's ``sd / sqrt(S)``); None where there is none."""
    counts = []
    for n in few:  # the samples each quantity counted at n (one number where all agree)
        s = r.by_size[(r.by_size.key != "rods_only_pc") & (r.by_size.n == n)].samples
        s = s if len(s) else pd.Series([r.samples[r.sizes.index(n)]])
        lo, hi = int(s.min()), int(s.max())
        counts.append(T.label("few", n=n, samples=lo if lo == hi else f"{lo} to {hi}"))
    rods = r.by_size[(r.by_size.key == "rods_only_pc")
                     & (r.by_size.samples < ERROR_FLOOR_SAMPLES)].sort_values("n")  # fmt: skip
    pc = [T.label("few_pc", n=int(s.n), samples=int(s.samples), err=s.err,
                  sd_err=s.width / math.sqrt(s.samples)) for s in rods.itertuples()]  # fmt: skip
    return {"few_sizes": "; ".join(counts + pc) or None}


def _envelope(r: ThreeDResult) -> dict:
    """The exponent-agnostic p_c's numbers (empty without one)."""
    e = r.pc_envelope
    if e is None or not np.isfinite(e.value):
        return {}
    return {"env_pc": fmt(e.value, e.err), "env_lo": e.low, "env_hi": e.high,
            "env_x_lo": float(X_3D[0]), "env_x_hi": float(X_3D[-1]), "env_allowed": e.allowed,
            "env_fits": len(e.fits), "env_n_mins": sorted({int(f.n_min) for f in e.fits}),
            "env_x_low": e.x_low, "env_x_high": e.x_high,
            "env_at_ends": "" if (e.x_low, e.x_high) == (X_3D[0], X_3D[-1]) else None,
            "env_z": an.agreement_z(e.value, e.err**2, PC_3D_CHECK.value,
                                    PC_3D_CHECK.tolerance)}  # fmt: skip


def envelope_table(r: ThreeDResult) -> pd.DataFrame | None:
    """Every fit of the exponent-agnostic p_c: smallest size, exponent, limit, chi-square and
    whether the data allow it (the report quotes their range)."""
    e = r.pc_envelope
    if e is None:
        return None
    return pd.DataFrame([vars(f) for f in e.fits])


def _binomial(r: ThreeDResult) -> dict:
    """The widths against the binomial bond-count noise (empty without them)."""
    b = r.binomial_widths
    if b is None or b.dof == 0:
        return {}
    counting = b.p_value >= limits.ACCEPT_P
    return {"bw_n": list(r.pc_sizes), "bw_sites": list(r.sites),
            "bw_total": [f"{t:.4f}" for t in b.total],
            "bw_binomial": [f"{t:.4f}" for t in b.binomial],
            "bw_ratio": [fmt(v, e, 2) for v, e in zip(b.ratio, b.ratio_err, strict=True)],
            "bw_chi2": b.chi2, "bw_dof": b.dof, "bw_p": b.p_value,
            "bw_counting": "" if counting else None,
            "bw_geometric": None if counting else ""}  # fmt: skip


def report_tables(r: ThreeDResult) -> dict:
    """Each quantity per size (samples in brackets), and each beside its 2D values."""
    wide = pd.DataFrame({"quantity": [T.label(f"quantity.{k}") for k in KEYS_3D]})
    for n in sorted(set(r.by_size.n)):
        s = r.by_size[r.by_size.n == n].set_index("key")
        wide[f"n = {n}"] = [f"{fmt(s.value[k], s.err[k])} ({int(s.samples[k])})" if k in s.index
                            else "" for k in KEYS_3D]  # fmt: skip
    b = beside_2d(r)
    ex_rows = [r.extrapolated.set_index("key").loc[k] for k in b.key]
    side = pd.DataFrame({
        "quantity": [T.label(f"quantity.{k}") for k in b.key],
        "largest": [f"{fmt(v, e)} (n = {n})" for v, e, n in zip(b.largest, b.largest_err, b.n_max,
                                                                 strict=True)],
        "free": [fmt(v, e) for v, e in zip(b.y_inf, b.y_inf_err, strict=True)],
        "first_order": [fmt(v, e) for v, e in zip(b.y_inf_first_order, b.y_inf_first_order_err,
                                                  strict=True)],
        "ours_2d": [fmt(TWO_D_OURS[k].value, TWO_D_OURS[k].error) for k in b.key],
        "paper_2d": list(b.paper_2d), "z_2d": [f"{z:.2f}" for z in b.z_2d],
        "z_2d_inf": [f"{z:.2f}" for z in b.z_2d_inf],
        "own": [fmt(x.limit, x.limit_stat) for x in ex_rows],
        "fit_form": [fit_form(x) for x in ex_rows],
        "laws": [x.limit_laws or "-" for x in ex_rows],
    })  # fmt: skip
    return {"by_size": wide, "beside_2d": side}


def _curves(ax, r: ThreeDResult, keys, labels, n_inf: float) -> None:
    """One panel: each quantity against n with both extrapolations, ours in 2D (dash-dot, grey
    band) and the paper's 2D value (open star at infinity)."""
    ex = r.extrapolated.set_index("key")
    for i, (key, label) in enumerate(zip(keys, labels, strict=True)):
        if key not in ex.index:
            continue
        s = r.by_size[r.by_size.key == key].sort_values("n")
        dx = 1.0 + 0.03 * (i - (len(keys) - 1) / 2)  # side by side on the log axis
        colour = STRAIN_COLOURS.get(label, CYCLE[i])
        bars(ax, s.n * dx, s.value, s.err, color=colour, label=T.label("line", label=label))
        f, ns = ex.loc[key], np.geomspace(s.n.min(), n_inf, 60)
        first = (f.y_inf_first_order, f.y_inf_first_order_err, f.a_first_order, NU_FIRST_ORDER)
        for y_inf, err, a, nu, ls, mark in ((f.y_inf, f.y_inf_err, f.a, f.nu, "--", "s"),
                                            (*first, ":", "D")):  # fmt: skip
            if np.isfinite(y_inf) and np.isfinite(nu):
                ax.plot(ns, y_inf + a * ns ** (-1 / nu), ls, color=colour, lw=1)
                bars(
                    ax,
                    [n_inf * dx],
                    [y_inf],
                    [err],
                    marker=mark,
                    ls="none",
                    color=colour,
                    mfc="none" if mark == "D" else colour,
                )
        two = TWO_D_OURS[key]
        if key != "rods_only_pc":  # the 2D threshold (0.66) would flatten the 3D points
            ax.axhline(two.value, color=colour, ls="-.", lw=0.9, alpha=0.8)
            ax.axhspan(two.value - (two.error or 0), two.value + (two.error or 0), color="grey",
                       alpha=0.12, lw=0)  # fmt: skip
            ax.plot([n_inf * dx * 1.12], [CLAIMS[key].value], color=colour, **PAPER_MARKER)
    unresolved(ax)


#: the panels of Fig. 3D: (2D keys, legend labels, y label)
PANELS_3D = (
    (("rods_only_pc",), ("rods only",), "y.pc"),
    (tuple(LAMBDA_3D)[:3], ("dilation", "shear", "compression"), "y.half"),
    (tuple(LAMBDA_3D)[3:], ("compression", "dilation"), "y.cables"),
)


def figures(r: ThreeDResult, figdir) -> dict:
    """A 2x2 grid: the rods-only P = 1/2 point (with the literature's 3D value, dashed, and
    Maxwell's 1/2, dotted), S_t/S_r at f_c = 0.5 per strain, of rods + cables, and the widths
    of the rods-only threshold distributions where measured."""
    w = r.widths
    widths = w is not None and np.isfinite(getattr(w, "nu", np.nan))
    fig, axes = grid(len(PANELS_3D) + widths, cols=2)
    sizes = np.unique(r.by_size.n.to_numpy(float))
    n_inf = 2.5 * sizes.max()
    for ax, (keys, labels, ylabel) in zip(axes, PANELS_3D, strict=False):
        _curves(ax, r, keys, labels, n_inf)
        size_axis(ax, sizes, n_inf)
        ax.set(xlabel=T.label("xlabel"), ylabel=T.label(ylabel))
        ax.legend()
    axes[0].axhline(PC_3D_CHECK.value, color="grey", ls="--", lw=0.8)
    axes[0].axhline(PC_3D_MAXWELL.value, color="grey", ls=":", lw=0.8)
    fig.suptitle(T.label("title", check=PC_3D_CHECK.value))
    if widths:
        width_panel(axes[-1], w)
    return {"3D": save(fig, figdir, "3D")}


def cost(scale: Scale, costs) -> float:
    """The analysis: per size, five collapse fits and a critical point."""
    return costs.analysis(NAME) * len(scale[NAME].sizes) * scale.bootstrap / 100


STUDY = Study(
    name=NAME, params=PARAMS, default=Params(), sweeps=sweeps, analyse=analyse, claims=claims,
    cost=cost, numbers=numbers, figures=figures, report_tables=report_tables,
    tables=lambda r: {"three_d_by_size": r.by_size, "three_d_extrapolated": r.extrapolated,
                      "three_d_beside_2d": beside_2d(r), "three_d_pc_envelope": envelope_table(r)},
)  # fmt: skip
