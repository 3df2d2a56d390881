"""Beyond the paper: the one-sided efficacies in the thermodynamic limit, 2D against 3D.

Per size, exact per-sample thresholds along p_r of rods + cables (f_c = 1) at p_t =
:data:`P_T` under compression and under dilation, and of the rods alone, all of the same samples
(one seed, so sample k is one disorder in all three): the efficacies lambda_C, lambda_D from the
P = 1/2 points, their asymmetry A = lambda_D - lambda_C and their sum, with paired bootstrap
errors (:func:`~tensegrity_rigidity.analysis.limits.paired_efficacies`), on the triangular
lattice (2D) and on FCC (3D). Each series against the node count N is fitted by a finite limit
and, for A, by a power law to zero (:func:`~tensegrity_rigidity.analysis.limits.limit_laws`),
and :func:`~tensegrity_rigidity.analysis.limits.vanishing_verdict` says whether A vanishes, by a
rule fixed before the data. The widths of the thresholds at p_t = P_T are split into the
binomial part and the geometric part, whose decay gives the tensegrity exponent nu_t
(:func:`~tensegrity_rigidity.analysis.limits.width_exponents`). The 2D samples are the
headline sweeps' disorders (seed 61), the 3D ones the FCC study's (seed 33).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from matplotlib.ticker import NullFormatter

from ...analysis import limits
from ..claims import CLAIMS, REFERENCES
from ..comparison import fmt
from ..study import Result, Scale, Study
from ..style import COLUMN, grid, legend_below, panel_letters, save
from ..template import load
from .headline import SEED_3D, chunk_size, chunk_size_3d
from .rows import COLLAPSE_PT, Rows

NAME = "efficacy_limit"
T = load(NAME)
#: the one-sided elements' probability of the paired thresholds (that of the collapse fits)
P_T = COLLAPSE_PT
DILATION, COMPRESSION = 0.0, math.pi
#: the seeds of the 2D and 3D sweeps: those of the headline and of the FCC study's sweeps, so
#: sample k is the disorder of their sample k (common random numbers)
SEEDS = {2: 61, 3: SEED_3D}
#: bonds per node of the full lattices (triangular, FCC): M = BONDS_PER_NODE * N
BONDS_PER_NODE = {2: 3, 3: 6}
#: the laws of each series' limit (analysis.limits): A may vanish at a continuous transition,
#: so a power law to zero stands beside a finite limit, and a constant reads a series that
#: does not depend on size (where the finite law's limit is not determined); the sum has no
#: reason to vanish
LAWS = {"asym": ("finite", "zero", "constant"), "total": ("finite", "constant")}
#: the series fitted (columns of by_size): A from the P = 1/2 points, from the means of the
#: per-sample differences, and the sum
SERIES = ("asym", "asym_mean", "total")
#: the rods-only transition's nu (2D), which nu_t is set beside; 2/d, the decay of
#: uncorrelated sample-to-sample noise, N^(-1/2), is the least value a finite-size nu can take
#: (Chayes, Chayes, Fisher & Spencer 1986)
NU_RODS = REFERENCES["nu_javerzat_notarmuzi"]
#: the paper's efficacies of rods + cables (Fig. 1C), quoted beside ours, never fitted to
PAPER_C, PAPER_D = (float(CLAIMS[k].value or math.nan)
                    for k in ("st_sr_cables_compression", "st_sr_cables_dilation"))  # fmt: skip


@dataclass(frozen=True, kw_only=True)
class Params:
    """Sizes and samples per size in 2D (triangular, n x n nodes) and 3D (FCC, n^3 nodes), and
    the smallest 2D size of the width exponent's fit (corrections to scaling below)."""

    sizes_2d: tuple[int, ...] = ()
    samples_2d: tuple[int, ...] = ()
    sizes_3d: tuple[int, ...] = ()
    samples_3d: tuple[int, ...] = ()
    widths_n_min: int = 0

    def by_dim(self) -> dict[int, tuple[tuple[int, int], ...]]:
        """dim -> ((n, samples), ...)."""
        return {2: tuple(zip(self.sizes_2d, self.samples_2d, strict=True)),
                3: tuple(zip(self.sizes_3d, self.samples_3d, strict=True))}  # fmt: skip


PARAMS = {
    "limit": Params(sizes_2d=(8, 12, 16, 24, 32, 64), samples_2d=(800, 480, 400, 240, 160, 16),
                    sizes_3d=(4, 5, 6, 8, 10, 12), samples_3d=(320, 200, 128, 48, 16, 16),
                    widths_n_min=12),
    "limit-cluster": Params(sizes_2d=(8, 12, 16, 24, 32, 48, 64, 128),
                            samples_2d=(800, 480, 400, 240, 160, 96, 64, 16),
                            sizes_3d=(4, 5, 6, 8, 10, 12, 14, 16, 20),
                            samples_3d=(320, 200, 128, 48, 32, 32, 32, 16, 8), widths_n_min=12),
    "tiny-limit": Params(sizes_2d=(4, 6, 8), samples_2d=(12, 8, 8), sizes_3d=(2, 3),
                         samples_3d=(6, 4)),
}  # fmt: skip


def _spec(dim: int, n: int, samples: int) -> dict:
    spec = {"n": n, "samples": samples, "seed": SEEDS[dim], "f_c": 1.0,
            "threshold": {"path": "p_r"}}  # fmt: skip
    if dim == 2:
        return spec | {"output": {"chunk_size": chunk_size(n)}}
    return spec | {"lattice": {"kind": "fcc"}, "output": {"chunk_size": chunk_size_3d(n)}}


def sweeps(scale: Scale) -> dict[str, dict]:
    """Per dimension and size, smaller first: ``limit_{d}d_rods_n{n}`` (p_t = 0, dilation: a
    rods-only threshold does not depend on the strain's sign) and ``limit_{d}d_cables_n{n}``
    (p_t = :data:`P_T`, f_c = 1, compression and dilation)."""
    out = {}
    for dim, sizes in scale[NAME].by_dim().items():
        for n, samples in sizes:
            base = _spec(dim, n, samples)
            out[f"limit_{dim}d_rods_n{n}"] = base | {"p_t": 0.0, "phi": [DILATION]}
            out[f"limit_{dim}d_cables_n{n}"] = base | {"p_t": P_T, "phi": [COMPRESSION, DILATION]}
    return out


@dataclass(frozen=True, eq=False)
class EfficacyLimitResult(Result):
    """``by_size``: per (dim, n) the node count ``N``, bonds ``M``, ``samples``, ``never`` and
    the columns of :class:`~tensegrity_rigidity.analysis.limits.PairedEfficacies` (``c``,
    ``d``, ``asym``, ``total``, the means, each with ``*_err``); ``limits``: per (dim, series)
    every law's fit, the limit with its statistical and fit-form errors and the verdict;
    ``widths``: (dim, strain) -> :class:`~tensegrity_rigidity.analysis.limits.WidthExponent`."""

    by_size: pd.DataFrame
    limits: pd.DataFrame
    widths: dict = field(default_factory=dict)


def _thresholds(frame: pd.DataFrame, phi: float | None = None,
                column: str = "threshold_p_r") -> pd.Series:  # fmt: skip
    """Per-sample thresholds (NaN: never rigid) of one strain, indexed by sample; ``column``
    may name an end of the interval (rows without intervals give their threshold)."""
    if phi is not None:
        frame = frame[np.isclose(frame.phi, phi)]
    if column not in frame:
        column = "threshold_p_r"
    return frame.set_index("sample")[column].astype(float).sort_index()


def _median(a: pd.Series) -> float:
    """The median with never-rigid samples (NaN) above every other."""
    return float(np.median(np.where(np.isfinite(a), a, np.inf)))


def _size_row(dim: int, n: int, rods: pd.DataFrame, cables: pd.DataFrame, rng) -> dict:
    """The paired efficacies of one size from the samples with all three thresholds, the
    number of thresholds that are intervals (undecided probes; they enter at their centre, and
    half each statistic's range over their ends joins its error) and the range of A over every
    choice inside the intervals (``asym_lo``, ``asym_hi``)."""
    r, c, d = _thresholds(rods), _thresholds(cables, COMPRESSION), _thresholds(cables, DILATION)
    common = r.index.intersection(c.index).intersection(d.index)
    ends = {(phi, end): _thresholds(cables, phi, f"threshold_p_r_{end}")[common]
            for phi in (COMPRESSION, DILATION) for end in ("low", "high")}  # fmt: skip
    per = [[_thresholds(rods, None, f"threshold_p_r_{e}")[common] for e in ("low", "high")]]
    per += [[ends[phi, e] for e in ("low", "high")] for phi in (COMPRESSION, DILATION)]
    pe = limits.paired_efficacies(r[common].to_numpy(), c[common].to_numpy(),
                                  d[common].to_numpy(), P_T, rng=rng, ends=tuple(per))  # fmt: skip
    lo = (_median(ends[COMPRESSION, "low"]) - _median(ends[DILATION, "high"])) / P_T
    hi = (_median(ends[COMPRESSION, "high"]) - _median(ends[DILATION, "low"])) / P_T
    widths = [ends[phi, "high"] - ends[phi, "low"] for phi in (COMPRESSION, DILATION)]
    return {"dim": dim, "n": n, "N": n**dim, "M": BONDS_PER_NODE[dim] * n**dim,
            "lost": int(max(len(r), len(c), len(d)) - len(common)),
            "intervals": int(sum((w > 0).sum() for w in widths)), "asym_lo": lo, "asym_hi": hi,
            **pe.__dict__}  # fmt: skip


def _widths(dim: int, sizes, parts, by_size: pd.DataFrame, scale: Scale, offset: int) -> dict:
    """(dim, strain) -> the widths of the thresholds at p_t = P_T and their exponent."""
    out = {}
    p = scale[NAME]
    for k, (strain, phi, lam) in enumerate((("compression", COMPRESSION, "c"),
                                            ("dilation", DILATION, "d"))):  # fmt: skip
        thresholds, counts, binomial, ns = [], [], [], []
        for n in sizes:
            rows = parts[f"limit_{dim}d_cables_n{n}"]
            rows = rows[np.isclose(rows.phi, phi) & np.isfinite(rows.threshold_p_r)]
            size = by_size[(by_size.dim == dim) & (by_size.n == n)].iloc[0]
            if len(rows) < 3 or not np.isfinite(size[lam]):
                continue
            m = float(size.M)
            t = rows.threshold_p_r.to_numpy(float)
            thresholds.append(t)
            counts.append(
                (rows.threshold_rods + size[lam] * rows.threshold_one_sided).to_numpy(float) / m
            )
            binomial.append(limits.binomial_variance(float(np.median(t)), P_T, size[lam], int(m)))
            ns.append(n)
        if len(ns) >= 2:
            out[(dim, strain)] = limits.width_exponents(
                ns, thresholds, counts, binomial, n_min=p.widths_n_min if dim == 2 else 0,
                n_boot=scale.bootstrap, rng=scale.rng("widths", offset + k))  # fmt: skip
    return out


def _limits(by_size: pd.DataFrame, scale: Scale) -> pd.DataFrame:
    """Per (dim, series): each law's fit over the node counts, the limit and the verdict."""
    out = []
    for dim, column in ((d, c) for d in (2, 3) for c in SERIES):
        s = by_size[by_size.dim == dim].sort_values("n")
        if len(s) < 2:
            continue
        laws = LAWS["asym" if column.startswith("asym") else "total"]
        y, err = s[column].to_numpy(float), s[f"{column}_err"].to_numpy(float)
        lim = limits.limit_laws(s.N.to_numpy(float), y, err, laws=laws, n_boot=scale.bootstrap,
                                rng=scale.rng("finite_size", dim))  # fmt: skip
        row = {"dim": dim, "series": column, "law": lim.law, "value": lim.value, "stat": lim.stat,
               "syst": lim.syst, "low": lim.low, "high": lim.high,
               "verdict": limits.vanishing_verdict(lim) if "zero" in laws else ""}  # fmt: skip
        for name, f in lim.fits.items():
            row |= {f"{name}_y_inf": f.y_inf, f"{name}_y_inf_err": f.y_inf_err, f"{name}_x": f.x,
                    f"{name}_x_err": f.x_err, f"{name}_chi2": f.chi2, f"{name}_dof": f.dof,
                    f"{name}_p": f.p_value, f"{name}_ok": f.acceptable}  # fmt: skip
        out.append(row)
    return pd.DataFrame(out)


def analyse(rows: Rows, scale: Scale) -> EfficacyLimitResult:
    """Paired efficacies per size, their limits in 2D and 3D, the widths' exponents."""
    parts = {name: frame for name, (frame, _) in rows.items()}
    sizes = {dim: [n for n, _ in s] for dim, s in scale[NAME].by_dim().items()}
    by_size = pd.DataFrame([
        _size_row(dim, n, parts[f"limit_{dim}d_rods_n{n}"], parts[f"limit_{dim}d_cables_n{n}"],
                  scale.rng("paired", 100 * dim + k))
        for dim, ns in sizes.items() for k, n in enumerate(ns)])  # fmt: skip
    widths: dict[tuple[int, str], limits.WidthExponent] = {}
    for dim, ns in sizes.items():
        if ns:
            widths |= _widths(dim, ns, parts, by_size, scale, 10 * dim)
    return EfficacyLimitResult(
        by_size=by_size, limits=_limits(by_size, scale) if len(by_size) else pd.DataFrame(),
        widths=widths, excluded={name: count for name, (_, count) in rows.items()},
    )  # fmt: skip


def widths_frame(r: EfficacyLimitResult) -> pd.DataFrame:
    """Per (dim, strain, n): the total, binomial, geometric and count widths, and the fitted
    exponents of the counts (``nu``) and of the subtraction (``nu_sub``)."""
    out = []
    for (dim, strain), w in r.widths.items():
        for i, n in enumerate(w.n):
            out.append({"dim": dim, "strain": strain, "n": int(n), "total": w.total[i],
                        "total_err": w.total_err[i], "binomial": w.binomial[i],
                        "geometric": w.geometric[i], "geometric_err": w.geometric_err[i],
                        "counts": w.counts[i], "counts_err": w.counts_err[i], "nu": w.nu,
                        "nu_err": w.nu_err, "chi2": w.chi2, "dof": w.dof, "nu_sub": w.nu_sub,
                        "nu_sub_err": w.nu_sub_err})  # fmt: skip
    return pd.DataFrame(out)


def _limit(r: EfficacyLimitResult, dim: int, series: str) -> pd.Series | None:
    if not len(r.limits):
        return None
    hit = r.limits[(r.limits.dim == dim) & (r.limits.series == series)]
    return hit.iloc[0] if len(hit) else None


def _limit_text(row: pd.Series | None) -> str | None:
    if row is None or not row.law:
        return None
    return T.label("limit", value=fmt(row.value, row.stat), syst=row.syst, law=row.law,
                   span=_span(row.low, row.high))  # fmt: skip


def _span(lo: float, hi: float) -> str:
    """The range lo to hi in the template's words: one value when both ends print alike."""
    one = T.label("span.one", lo=lo)
    return one if one == T.label("span.one", lo=hi) else T.label("span", lo=lo, hi=hi)


def _bracket(q) -> str:
    """A size's range of A over the choices inside its intervals, and how many intervals."""
    k = int(q.intervals)
    count = T.label("intervals.one" if k == 1 else "intervals.many", k=k)
    return T.label("bracket", n=int(q.n), dim=int(q.dim), count=count,
                   span=_span(q.asym_lo, q.asym_hi))  # fmt: skip


def _verdict_text(row: pd.Series) -> str:
    """The verdict in words; a vanishing one with the limit's upper bound at two errors (the
    rule asks only that zero be allowed, so the bound says how far the data are from it)."""
    err = np.hypot(row.stat, row.syst)
    return T.label(f"verdict.{row.verdict.replace(' ', '_')}", upper=row.value + 2 * err,
                   limit=fmt(row.value, err))  # fmt: skip


def _laws_text(row: pd.Series | None, laws) -> list[str] | None:
    if row is None:
        return None
    return [T.label("law", law=law, chi2=row[f"{law}_chi2"], dof=int(row[f"{law}_dof"]),
                    p=row[f"{law}_p"], ok=T.label("allowed" if row[f"{law}_ok"] else "rejected"))
            for law in laws if np.isfinite(row[f"{law}_chi2"])] or None  # fmt: skip


#: a 2D and a 3D size are set side by side when their node counts differ by less than this factor
EQUAL_NODES = 1.3


def equal_nodes(by_size: pd.DataFrame) -> list[tuple[pd.Series, pd.Series]]:
    """(2D row, 3D row) pairs of sizes whose node counts differ by less than
    :data:`EQUAL_NODES` (the nearest 2D size to each 3D one)."""
    two, three = by_size[by_size.dim == 2], by_size[by_size.dim == 3]
    out = []
    for _, row in three.iterrows():
        if not len(two):
            break
        near = two.iloc[int(np.argmin(np.abs(np.log(two.N.to_numpy(float) / row.N))))]
        if max(near.N, row.N) / min(near.N, row.N) < EQUAL_NODES:
            out.append((near, row))
    return out


def _answer(verdicts: dict[int, str], rows: dict | None = None, apart: bool = True) -> str | None:
    """The label that answers the study's question from the two verdicts of A (``rows``: each
    dimension's limit row, whose words the answer quotes). A 2D limit consistent with 0 beside
    a finite 3D one answers "yes" only when the two limits are more than two errors ``apart``:
    otherwise a vanishing 2D limit is allowed, not shown."""
    pair = (verdicts.get(2), verdicts.get(3))
    if None in pair:
        return None
    known = {("vanishes", "finite"), ("finite", "finite"), ("vanishes", "vanishes"),
             ("finite", "vanishes")}  # fmt: skip
    key = ".".join(pair) if pair in known else "open"
    if key == "vanishes.finite" and not apart:
        key += ".close"
    words = {d: _verdict_text(row) for d, row in (rows or {}).items()}
    return T.label(f"answer.{key}", two=words.get(2, pair[0]), three=words.get(3, pair[1]))


def numbers(r: EfficacyLimitResult) -> dict:
    by = r.by_size
    out: dict = {"p_t": P_T, "lost": int(by.lost.sum()) or None if len(by) else None,
                 "intervals": int(by.intervals.sum()) or None if len(by) else None,
                 "brackets": [_bracket(q) for q in by.itertuples() if q.intervals > 0] or None,
                 "never": int(by.never.sum()) or None if len(by) else None,
                 "paper_c": PAPER_C, "paper_d": PAPER_D,
                 "paper_asym": PAPER_D - PAPER_C}  # fmt: skip
    out["equal_nodes"] = [
        T.label("pair", n2=int(a.n), n3=int(b.n), N2=int(a.N), N3=int(b.N),
                a2=fmt(a.asym, a.asym_err), a3=fmt(b.asym, b.asym_err))
        for a, b in equal_nodes(by)] or None if len(by) else None  # fmt: skip
    verdicts: dict[int, str] = {}
    rows: dict[int, pd.Series] = {}
    for dim in (2, 3):
        s = by[by.dim == dim].sort_values("n") if len(by) else by
        if not len(s):
            continue
        out[f"sizes_{dim}"] = [T.label("size", n=int(q.n), N=int(q.N), samples=int(q.samples))
                               for q in s.itertuples()]  # fmt: skip
        out[f"asym_{dim}"] = [T.label("value", n=int(q.n), value=fmt(q.asym, q.asym_err))
                              for q in s.itertuples()]  # fmt: skip
        out[f"total_{dim}"] = [T.label("value", n=int(q.n), value=fmt(q.total, q.total_err))
                               for q in s.itertuples()]  # fmt: skip
        for series in SERIES:
            row = _limit(r, dim, series)
            out[f"{series}_limit_{dim}"] = _limit_text(row)
            kind = "asym" if series.startswith("asym") else "total"
            out[f"{series}_laws_{dim}"] = _laws_text(row, LAWS[kind])
            if row is not None and row.verdict:
                out[f"{series}_verdict_{dim}"] = _verdict_text(row)
                if series == "asym":
                    verdicts[dim], rows[dim] = row.verdict, row
        for strain in ("compression", "dilation"):
            w = r.widths.get((dim, strain))
            if w is None:
                continue
            tag = f"{strain}_{dim}"
            out[f"nu_{tag}"] = fmt(w.nu, w.nu_err) if np.isfinite(w.nu) else None
            out[f"nu_chi2_{tag}"] = w.chi2 if np.isfinite(w.nu) else None
            out[f"nu_dof_{tag}"] = w.dof
            out[f"nu_sub_{tag}"] = fmt(w.nu_sub, w.nu_sub_err) if np.isfinite(w.nu_sub) else None
            if np.isfinite(w.nu):
                out[f"nu_z_{tag}"] = [
                    T.label("nu_z", what=T.label(f"against.{what}", dim=dim), value=ref,
                            z=abs(w.nu - ref) / np.hypot(w.nu_err, err))
                    for what, ref, err in (("rods", NU_RODS.value, NU_RODS.error or 0.0),
                                           ("noise", 2 / dim, 0.0))
                    if what == "noise" or dim == 2]  # fmt: skip
            share = (w.binomial / w.total) ** 2
            err = 2 * share * w.total_err / w.total
            out[f"binomial_share_{tag}"] = [
                T.label("share", n=int(n), share=100 * v, err=100 * e)
                for n, v, e in zip(w.n, share, err, strict=True)]  # fmt: skip
    caveats = _caveats(rows)
    out["answer"] = _answer(verdicts, rows, apart="not_apart" not in caveats)
    out.update(caveats)
    return out


def _caveats(rows: dict[int, pd.Series]) -> dict:
    """What the answer does not exclude: 2D and 3D limits less than two errors apart (the
    sizes cannot tell the dimensions apart), and, per dimension, a power law to zero rejected
    with its exponent at the slowest decay the fit tries (only decays at least that fast are
    rejected)."""
    out: dict = {}
    if 2 in rows and 3 in rows:
        two, three = rows[2], rows[3]
        diff = abs(two.value - three.value)
        err = float(np.hypot(np.hypot(two.stat, two.syst), np.hypot(three.stat, three.syst)))
        if diff < 2 * err:
            out["not_apart"] = T.label("not_apart", diff=diff, err=err)
    slowest = [
        T.label("slowest", dim=dim, x=row.zero_x)
        for dim, row in rows.items()
        if not bool(row.get("zero_ok", True))
        and np.isclose(row.zero_x, limits.X_GRID[0], atol=1e-4)
    ]
    out["slowest"] = slowest or None
    return out


def _series_panel(ax, r: EfficacyLimitResult, column: str, ylabel: str) -> None:
    """One series against N per dimension, with the curves of the laws the data allow."""
    for dim, marker in ((2, "o"), (3, "s")):
        s = r.by_size[r.by_size.dim == dim].sort_values("n")
        if not len(s):
            continue
        line = ax.errorbar(s.N, s[column], yerr=s[f"{column}_err"], marker=marker, capsize=2,
                           ls="none", label=T.label(f"dim{dim}"))  # fmt: skip
        row = _limit(r, dim, column)
        if row is None:
            continue
        ns = np.geomspace(s.N.min(), s.N.max() * 4, 60)
        for law, style in (("finite", "--"), ("zero", ":"), ("constant", "-.")):
            ok = row.get(f"{law}_ok")
            if not (isinstance(ok, bool | np.bool_) and ok):
                continue
            fit = _curve(s, column, law, row)
            if fit is not None:
                ax.plot(ns, fit(ns), style, lw=1, color=line[0].get_color(),
                        label=T.label(f"law.{law}", dim=dim))  # fmt: skip
    ax.set_xscale("log")
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set(xlabel=T.label("N"), ylabel=ylabel)


def _curve(s: pd.DataFrame, column: str, law: str, row: pd.Series):
    """The curve of ``law`` through one series with the limit and exponent of its fit in
    ``row`` (the limits table); the amplitude, linear given those, by weighted least squares."""
    y_inf = float(row[f"{law}_y_inf"])
    if law == "constant":
        return lambda ns: np.full_like(ns, y_inf)
    x = float(row[f"{law}_x"])
    n, y, e = s.N.to_numpy(float), s[column].to_numpy(float), s[f"{column}_err"].to_numpy(float)
    ok = np.isfinite(y) & np.isfinite(e) & (e > 0)
    if not (np.isfinite(x) and ok.any()):
        return None
    w, f = 1 / e[ok] ** 2, n[ok] ** -x
    b = np.sum(w * f * (y[ok] - y_inf)) / np.sum(w * f * f)
    return lambda ns: y_inf + b * ns**-x


def _widths_panel(ax, r: EfficacyLimitResult) -> None:
    """The count widths at p_t = P_T against N, with the binomial parts (grey, open)."""
    labelled: set[int] = set()
    for (dim, strain), w in r.widths.items():
        nodes = w.n**dim
        ax.errorbar(nodes, w.counts, yerr=w.counts_err, marker="o" if dim == 2 else "s",
                           capsize=2, ls="none",
                           label=T.label("width", dim=dim, strain=strain))  # fmt: skip
        ax.plot(
            nodes,
            w.binomial,
            marker="o" if dim == 2 else "s",
            mfc="none",
            ls=":",
            color="0.45",
            label=None if dim in labelled else T.label("binomial", dim=dim),
        )
        labelled.add(dim)
    ax.set(xscale="log", yscale="log", xlabel=T.label("N"), ylabel=T.label("width_axis"))
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_minor_formatter(NullFormatter())


def figures(r: EfficacyLimitResult, figdir) -> dict:
    """``limit``: A against N in 2D and 3D with the allowed laws, the sum, the widths."""
    if not len(r.by_size):
        return {}
    fig, axes = grid(3, cols=3, size=(COLUMN * 1.05, COLUMN * 0.9))
    _series_panel(axes[0], r, "asym", T.label("asym"))
    axes[0].axhline(0, color="grey", lw=0.6)
    _series_panel(axes[1], r, "total", T.label("total"))
    _widths_panel(axes[2], r)
    for ax in axes:
        legend_below(ax, ncol=1)
    panel_letters(axes)
    return {"limit": save(fig, figdir, "limit")}


def _by_size_table(r: EfficacyLimitResult) -> pd.DataFrame:
    by = r.by_size
    return pd.DataFrame({
        "dim": by.dim.astype(int), "n": by.n.astype(int), "N": by.N.astype(int),
        "samples": by.samples.astype(int),
        "c": [fmt(a, b) for a, b in zip(by.c, by.c_err, strict=True)],
        "d": [fmt(a, b) for a, b in zip(by.d, by.d_err, strict=True)],
        "asym": [fmt(a, b) for a, b in zip(by.asym, by.asym_err, strict=True)],
        "asym_mean": [fmt(a, b) for a, b in zip(by.asym_mean, by.asym_mean_err, strict=True)],
        "total": [fmt(a, b) for a, b in zip(by.total, by.total_err, strict=True)],
    })  # fmt: skip


def _limits_table(r: EfficacyLimitResult) -> pd.DataFrame:
    if not len(r.limits):
        return pd.DataFrame()
    li = r.limits
    return pd.DataFrame({
        "dim": li.dim.astype(int), "series": [T.label(f"series.{s}") for s in li.series],
        "limit": [fmt(v, e) if law else "-" for v, e, law in zip(li.value, li.stat, li.law,
                                                                  strict=True)],
        "syst": [f"{v:.3f}" if law else "-" for v, law in zip(li.syst, li.law, strict=True)],
        "finite": [f"{a:.1f} / {int(b)}" for a, b in zip(li.finite_chi2, li.finite_dof,
                                                          strict=True)],
        "other": [f"{a:.1f} / {int(b)}" for a, b in zip(
            li.zero_chi2.fillna(li.constant_chi2), li.zero_dof.fillna(li.constant_dof),
            strict=True)],
        "verdict": [_verdict_text(row) if row.verdict else "-" for _, row in li.iterrows()],
    })  # fmt: skip


def cost(scale: Scale, costs) -> float:
    """The analysis: bootstraps of the paired efficacies, the laws and the widths."""
    p = scale[NAME]
    return costs.analysis(NAME) * (len(p.sizes_2d) + len(p.sizes_3d)) * scale.bootstrap / 100


STUDY = Study(
    name=NAME, params=PARAMS, default=Params(), sweeps=sweeps, analyse=analyse,
    claims=lambda r: (), cost=cost, numbers=numbers, figures=figures,
    report_tables=lambda r: {"by_size": _by_size_table(r), "limits": _limits_table(r)},
    tables=lambda r: {"efficacy_limit_by_size": r.by_size, "efficacy_limit_laws": r.limits,
                      "efficacy_limit_widths": widths_frame(r)},
)  # fmt: skip
