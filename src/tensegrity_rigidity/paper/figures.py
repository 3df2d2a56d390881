"""The paper's figures from study results; each saved as PNG and SVG under DIR/figures."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from cycler import cycler  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402
from matplotlib.ticker import NullFormatter, NullLocator  # noqa: E402

from ..model.network import Element  # noqa: E402
from .claims import CLAIMS  # noqa: E402
from .plotting import (  # noqa: E402
    CYCLE,
    KIND_COLOURS,
    bond_segments,
    draw_clusters,
    draw_network,
)
from .plotting import OKABE_ITO as OKABE_ITO  # noqa: E402  (the palette, re-exported)
from .studies import PT4  # noqa: E402

if TYPE_CHECKING:
    from .studies import (
        DisplacementField,
        Fig1bResult,
        Fig1cResult,
        Fig2Result,
        Fig3Result,
        Fig4Result,
    )
    from .studies.fss import FiniteSizeResult
    from .studies.three_d import ThreeDResult

#: one style for every figure: sizes a journal column takes, the palette, no top and right spines
STYLE: dict[Any, Any] = {
    "axes.prop_cycle": cycler(color=CYCLE),
    "font.size": 9,
    "axes.titlesize": 9,
    "axes.labelsize": 9,
    "legend.fontsize": 7,
    "legend.frameon": False,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "lines.linewidth": 1.3,
    "lines.markersize": 4,
    "errorbar.capsize": 2,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "image.cmap": "cividis",
    "savefig.dpi": 150,
}
STRAIN_COLOURS = {
    "dilation": "#D55E00",
    "shear": "#009E73",
    "compression": "#0072B2",
    "average": "#000000",
}
#: how the paper's values are drawn beside ours: open stars, in the colour of the curve
PAPER_MARKER: dict[str, Any] = {"marker": "*", "ms": 11, "mfc": "none", "mew": 1.2, "ls": "none"}


def _yerr(P, lo, hi):
    """Asymmetric error bars from an interval, clipped at zero against round-off."""
    P, lo, hi = (np.asarray(x, dtype=float) for x in (P, lo, hi))
    return [np.clip(P - lo, 0, None), np.clip(hi - P, 0, None)]


def _save(fig, figdir: Path, fid: str) -> list[Path]:
    figdir.mkdir(parents=True, exist_ok=True)
    paths = [figdir / f"fig{fid}.png", figdir / f"fig{fid}.svg"]
    fig.savefig(paths[0], dpi=130, bbox_inches="tight")
    fig.savefig(paths[1], bbox_inches="tight")
    plt.close(fig)
    return paths


def _placeholder(fid: str, text: str, figdir: Path) -> list[Path]:
    """A figure that says why it is empty (no sample of its sweep qualified)."""
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    ax.text(0.5, 0.5, text, ha="center", va="center", wrap=True)
    ax.set_axis_off()
    ax.set_title(fid, fontsize=9)
    return _save(fig, figdir, fid)


def fig1a(field: DisplacementField, figdir: Path):
    """A force-balanced configuration: rods solid, cables dashed, struts hollow; red/green/blue
    for positive/zero/negative tension, line width growing with |t| (:func:`.draw_network`)."""
    inst, res = field.mixed_instance, field.mixed_result
    if inst is None:
        return _placeholder("1A", "no rigid sample in the Fig. 1A sweep", figdir)
    fig, ax = plt.subplots(figsize=(6, 5.2))
    draw_network(ax, inst, res, colour="tension", arrows=False)
    ax.set_title("1A  rigid sample under shear (red pulls, blue pushes)", fontsize=9)
    return _save(fig, figdir, "1A")


def fig1b(r: Fig1bResult, figdir: Path):
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    P = np.ma.masked_invalid(r.P)
    mesh = ax.pcolormesh(r.p_r, r.p_t, P, shading="nearest", cmap="viridis", vmin=0, vmax=1)
    fig.colorbar(mesh, ax=ax, label=r"$P$ (shear, $f_c$ = 0.5)")
    ax.contour(r.p_r, r.p_t, P, levels=[0.5], colors="white", linewidths=1)
    # the mean-field line p_r + p_t / 2 = const through P = 1/2 at p_t = 0
    x0 = float(np.interp(0.5, np.nan_to_num(r.P[0]), r.p_r))
    pt = np.linspace(0, r.p_t.max(), 50)
    ax.plot(x0 - pt / 2, pt, color="orange", lw=2, label=r"$p_r + p_t/2$ = const")
    ax.set_xlim(0, 1)
    ax.set_xlabel(r"rod probability $p_r$")
    ax.set_ylabel(r"one-sided probability $p_t$")
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(f"1B  P(p_r, p_t), n = {r.n}, {r.samples} samples per p_t", fontsize=9)
    return _save(fig, figdir, "1B")


#: the paper's values drawn in Fig. 1C: (claim, f_c, strain)
FIG1C_PAPER = (
    ("st_sr_cables_compression", 1.0, "compression"),
    ("st_sr_struts_dilation", 0.0, "dilation"),
    ("st_sr_cables_dilation", 1.0, "dilation"),
    ("st_sr_half_average", 0.5, "average"),
)


def fig1c(r: Fig1cResult, figdir: Path):
    fits = r.fits
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for strain, sub in fits.groupby("strain"):
        ax.errorbar(
            sub.f_c,
            sub.lam,
            yerr=sub.lam_err,
            marker="o",
            capsize=3,
            color=STRAIN_COLOURS.get(strain, "grey"),
            label=strain,
        )
    ax.axhline(0.5, color="grey", ls=":", lw=1)
    for key, f_c, strain in FIG1C_PAPER:
        ax.plot([f_c], [CLAIMS[key].value or np.nan], color=STRAIN_COLOURS[strain], **PAPER_MARKER)
    ax.plot([], [], color="grey", **PAPER_MARKER, label="paper")
    ax.set_xlabel(r"cable fraction $f_c$")
    ax.set_ylabel(r"efficacy $S_t / S_r$")
    ax.legend()
    ax.set_title(f"1C  $n$ = {r.n}, {r.samples} samples per point; error bars: bootstrap")
    return _save(fig, figdir, "1C")


def fig2a(r: Fig2Result, figdir: Path):
    """Nonaffine displacements: unit arrows coloured by log10 |u| over a log-scaled background.

    Near the transition a few nodes move 1e3-1e4 times more than the rest; arrows of true
    length would show only those. Every arrow therefore has the same length and its colour
    (and the background) gives |u| on a logarithmic scale.
    """
    field = r.field
    inst, res = field.instance, field.result
    if inst is None or res is None:  # None together: no sample qualified
        return _placeholder("2A", "no sample of the Fig. 2A sweep has a usable threshold", figdir)
    pos = inst.network.positions
    u = res.displacements
    mag = np.hypot(u[:, 0], u[:, 1])
    floor = max(float(mag.max()) * 1e-6, 1e-300)
    mag_c = np.clip(mag, floor, None)
    norm = LogNorm(vmin=mag_c.min(), vmax=mag_c.max())
    fig, ax = plt.subplots(figsize=(6, 5.2))
    ax.tripcolor(pos[:, 0], pos[:, 1], mag_c, shading="gouraud", cmap="Greys", norm=norm, alpha=0.6)
    seg = bond_segments(inst.network)
    kinds = inst.network.kinds
    ax.add_collection(LineCollection(seg[kinds == Element.ROD], colors="k", linewidths=0.8))
    ax.add_collection(
        LineCollection(
            seg[kinds == Element.CABLE],
            colors=KIND_COLOURS[Element.CABLE],
            linewidths=0.8,
            linestyles=(0, (3, 2)),
        )
    )
    unit = u / np.where(mag > 0, mag, 1.0)[:, None]
    q = ax.quiver(
        pos[:, 0],
        pos[:, 1],
        unit[:, 0],
        unit[:, 1],
        mag_c,
        cmap="viridis",
        norm=norm,
        angles="xy",
        scale_units="xy",
        scale=2.2,
        width=0.004,
    )
    fig.colorbar(q, ax=ax, label="|u_na| (log scale; arrows show direction only)")
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_title(
        f"2A  rods + cables, compression, p_r = {field.p_r:g}, p_t = {field.p_t}; "
        f"max |u| = {mag_c.max() / np.median(mag_c):.0f} x median",
        fontsize=8,
    )
    return _save(fig, figdir, "2A")


def fig2b(r: Fig2Result, figdir: Path):
    """Gamma versus p_r: median with the interquartile band, mean as open markers."""
    c = r.curves
    sub = c[np.isclose(c.phi, math.pi)]
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    grid = np.unique(sub.p_r.to_numpy(float))
    step = float(np.diff(grid).min()) if grid.size > 1 else 0.0
    curves = list(sub.groupby("p_t"))
    bars: list[tuple[float, float, float]] = []
    for i, (p_t, s) in enumerate(curves):
        (line,) = ax.plot(s.p_r, s.gamma_median, "-", lw=1.5, label=f"p_t = {p_t:.1f} (median)")
        colour = line.get_color()
        ax.fill_between(s.p_r, s.gamma_q25, s.gamma_q75, color=colour, alpha=0.2, lw=0)
        ax.plot(s.p_r, s.gamma, "o", mfc="none", ms=4, color=colour)
        # the bars of different p_t side by side, within a fifth of a grid step
        bars += median_brackets(ax, s, colour, dx=0.2 * step * (i - (len(curves) - 1) / 2))
        pc = r.crit
        pc = pc[np.isclose(pc.phi, math.pi) & np.isclose(pc.p_t, p_t)].p_crit
        if len(pc):
            ax.axvline(float(pc.iloc[0]), color=colour, ls="--", lw=1)
    ax.plot([], [], "o", mfc="none", color="grey", label="mean")
    title = (
        f"2B  rods + cables, compression, $n$ = {r.n}, {r.samples} samples: median, quartiles "
        "(band), mean (o); "
        "dashed: p_crit"
    )
    if bars:
        ax.plot([], [], "_", color="grey", ms=8, label="median over all samples, bracketed")
        title += (
            ";\nbars: median over all samples where some are known only from below "
            "(^: unbounded above)"
        )
    ax.set_yscale("log")
    ax.set_xlabel(r"rod probability $p_r$")
    ax.set_ylabel(r"nonaffinity $\Gamma$")
    ax.legend(fontsize=7)
    ax.set_title(title, fontsize=8)
    return _save(fig, figdir, "2B")


def median_brackets(ax, s, colour, dx: float = 0.0) -> list[tuple[float, float, float]]:
    """Draw, at each p_r where samples lack a certified nonaffinity, the bracket of the median
    over all samples (``gamma_median_low`` to ``gamma_median_high``,
    :func:`~tensegrity_rigidity.paper.studies.gamma_median_brackets`) as a vertical bar.

    A bracket open above (``gamma_median_high = inf``) ends in a ``^`` just above the curves;
    one open below (``gamma_median_low = 0``: the missing samples have no bound) starts at
    the lowest quartile drawn. The median line itself uses the certified samples only, so it can
    lie outside the bracket.

    Parameters
    ----------
    ax : matplotlib Axes
        Log-scaled in y by the caller.
    s : DataFrame
        One curve's rows (``p_r``, ``gamma_q25``, ``gamma_q75``, ``gamma`` and the bracket
        columns; rows from studies without the bracket draw nothing).
    colour : colour
        The curve's colour.
    dx : float
        Horizontal offset of the bars (so that curves at the same p_r do not hide each other).

    Returns
    -------
    list of (p_r, low, high)
        The bars drawn, in data coordinates (``p_r + dx``; ``high`` where the bracket is open
        above is the drawn top, not inf).
    """
    if "gamma_median_low" not in s:
        return []
    lo, hi = s.gamma_median_low.to_numpy(float), s.gamma_median_high.to_numpy(float)
    open_ = hi > lo
    if not open_.any():
        return []
    shown = np.r_[s.gamma_q25, s.gamma_q75, s.gamma, lo, hi].astype(float)
    shown = shown[np.isfinite(shown) & (shown > 0)]
    if not shown.size:
        return []
    floor, top = shown.min(), 3.0 * shown.max()
    x = s.p_r.to_numpy(float)[open_] + dx
    low = np.where(lo[open_] > 0, lo[open_], floor)
    high = np.where(np.isfinite(hi[open_]), hi[open_], top)
    ax.vlines(x, low, high, color=colour, lw=1.5, alpha=0.7)
    ax.plot(x, low, "_", color=colour, ms=8)
    up = ~np.isfinite(hi[open_])
    ax.plot(x[up], high[up], "^", color=colour, ms=5)
    ax.plot(x[~up], high[~up], "_", color=colour, ms=8)
    return [(float(a), float(b), float(c)) for a, b, c in zip(x, low, high, strict=True)]


def fig2e(r: Fig2Result, figdir: Path):
    """CCDF of Gamma over samples at the grid p_r nearest p_crit (compression), per p_t."""
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    at = r.at_pcrit
    drawn = False
    for p_t, sub in at.groupby("p_t"):
        v = np.sort(sub.nonaffinity.to_numpy(float))
        v = v[np.isfinite(v) & (v > 0)]
        if not v.size:
            continue
        ccdf = 1.0 - np.arange(v.size) / v.size  # fraction of samples with Gamma >= v
        ax.step(v, ccdf, where="post", label=f"p_t = {p_t:.1f}, p_r = {sub.p_r.iloc[0]:g}")
        drawn = True
    if drawn:
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.legend(fontsize=7)
    else:
        ax.text(0.5, 0.5, "no nonaffinity at p_crit", ha="center", transform=ax.transAxes)
    ax.set_xlabel(r"nonaffinity $\Gamma$")
    ax.set_ylabel(r"fraction of samples with a larger $\Gamma$")
    ax.set_title(f"2E  distribution of Gamma at p_crit (compression), n = {r.n}", fontsize=9)
    return _save(fig, figdir, "2E")


def _energy_fig(r: Fig2Result, phi: float, fid: str, figdir: Path):
    c = r.curves
    fits = r.fits
    sub = c[np.isclose(c.phi, phi)]
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    inset = ax.inset_axes((0.12, 0.5, 0.35, 0.4))
    for p_t, s in sub.groupby("p_t"):
        line = ax.errorbar(
            s.p_r,
            s.energy,
            yerr=s.energy_sem,
            marker="o",
            ms=3,
            capsize=2,
            label=f"$p_t$ = {p_t:.1f}",
        )
        paper = CLAIMS.get(f"p_crit_{'compression' if phi == math.pi else 'dilation'}_{p_t}")
        if paper is not None and paper.value is not None:
            ax.plot([paper.value], [0], color=line[0].get_color(), clip_on=False, **PAPER_MARKER)
        f = fits[np.isclose(fits.phi, phi) & np.isclose(fits.p_t, p_t)].iloc[0]
        m = (s.p_r > f.p_crit) & (s.energy > 0)
        inset.loglog(s.p_r[m] - f.p_crit, s.energy[m], "o", ms=2, color=line[0].get_color())
        if np.isfinite(f.alpha):
            x = np.geomspace((s.p_r[m] - f.p_crit).min(), (s.p_r[m] - f.p_crit).max(), 20)
            inset.loglog(x, np.exp(f.beta) * x**f.alpha, "--", lw=1, color=line[0].get_color())
    inset.set_xlabel(r"$p_r - p_{crit}$", fontsize=6)
    inset.set_ylabel(r"$E$", fontsize=6)
    inset.tick_params(labelsize=6)
    inset.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel(r"rod probability $p_r$")
    ax.set_ylabel(r"mean energy $E$ ($\gamma$ = 1)")
    ax.legend(fontsize=8, loc="lower right")
    name = "compression" if phi == math.pi else "dilation"
    ax.plot([], [], color="grey", **PAPER_MARKER, label=r"paper's $p_{crit}$")
    ax.legend(fontsize=8, loc="lower right")
    ax.set_title(f"{fid}  energy, rods + cables, {name}, $n$ = {r.n}, {r.samples} samples")
    return _save(fig, figdir, fid)


def fig2c(r: Fig2Result, figdir: Path):
    return _energy_fig(r, math.pi, "2C", figdir)


def fig2d(r: Fig2Result, figdir: Path):
    return _energy_fig(r, 0.0, "2D", figdir)


def fig3b(r: Fig3Result, figdir: Path):
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    sim = r.sim
    for p_r, curve in r.analytic.items():
        line = ax.plot(r.f_c, curve, label=f"p_r = {p_r}")
        s = sim[np.isclose(sim.p_r, p_r)]
        ax.errorbar(
            s.f_c,
            s.P,
            yerr=_yerr(s.P, s.lo, s.hi),
            fmt="o",
            ms=3,
            capsize=2,
            color=line[0].get_color(),
        )
    ax.set_xlabel(r"cable fraction $f_c$")
    ax.set_ylabel(r"$P_N$")
    ax.legend(fontsize=8)
    ax.set_title(f"3B  single node: theory (lines), {r.trials} trials (95%)", fontsize=9)
    return _save(fig, figdir, "3B")


def fig4a(r: Fig4Result, figdir: Path):
    pp = r.per_phi
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    cmap = plt.get_cmap("cividis")
    for phi, s in pp.groupby("phi"):
        ax.errorbar(
            s.f_c,
            s.P,
            yerr=_yerr(s.P, s.lo, s.hi),
            marker="o",
            ms=3,
            capsize=2,
            color=cmap(phi / math.pi),
            label=f"phi = {phi / math.pi:.3g} pi",
        )
    ax.set_xlabel(r"cable fraction $f_c$")
    ax.set_ylabel(r"probability of rigidity $P$")
    ax.legend(fontsize=6, ncol=2)
    ax.set_title(f"4A  P at p_r = 0.3, p_t = 0.6, n = {r.n}, {r.samples} samples", fontsize=9)
    return _save(fig, figdir, "4A")


def fig4b(r: Fig4Result, figdir: Path):
    a = r.average
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    ax.errorbar(a.f_c, a.S_c_rel, yerr=a.S_c_rel_err, marker="o", capsize=3, label=r"$S_c / S_r$")
    ax.errorbar(a.f_c, a.S_s_rel, yerr=a.S_s_rel_err, marker="s", capsize=3, label=r"$S_s / S_r$")
    ax.axhline(0.5, color="grey", ls=":", lw=1)
    ax.set_xlabel(r"cable fraction $f_c$")
    ax.set_ylabel(r"efficacy relative to a rod, $S_c/S_r$, $S_s/S_r$")
    ax.legend(fontsize=8)
    ax.set_title("4B  cable and strut efficacies, strain average", fontsize=9)
    return _save(fig, figdir, "4B")


def fig4c(r: Fig4Result, figdir: Path):
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for name in ("average", "dilation", "compression"):
        s = getattr(r, name)
        ax.errorbar(
            s.f_c,
            s.sum_rel,
            yerr=s.sum_rel_err,
            marker="o",
            capsize=3,
            color=STRAIN_COLOURS[name],
            label=name,
        )
    ax.axhline(1.0, color="grey", ls=":", lw=1)
    ax.set_xlabel(r"cable fraction $f_c$")
    ax.set_ylabel(r"$(S_c + S_s) / S_r$")
    ax.legend(fontsize=8)
    ax.set_title("4C  combined efficacy of a cable and a strut", fontsize=9)
    return _save(fig, figdir, "4C")


#: the panels of Fig. FS that plot claims against n, each with its fitted y_inf + a n^(-1/nu):
#: (claim keys, legend labels, y label)
FSS_PANELS = (
    (("rods_only_pc",), ("rods only",), "rods-only P = 1/2 point"),
    (
        ("st_sr_cables_compression", "st_sr_cables_dilation", "st_sr_half_shear"),
        ("rods + cables, compression", "rods + cables, dilation", "f_c = 0.5, shear"),
        "S_t / S_r",
    ),
    (
        tuple(f"alpha_compression_{p_t}" for p_t in PT4),
        tuple(f"p_t = {p_t:g}" for p_t in PT4),
        "energy exponent alpha, compression",
    ),
    (
        tuple(f"alpha_dilation_{p_t}" for p_t in PT4),
        tuple(f"p_t = {p_t:g}" for p_t in PT4),
        "energy exponent alpha, dilation",
    ),
    (("taut_cables_transition",), ("rods + cables, compression",), "taut cables at p_crit"),
)


def fss_panels(r: FiniteSizeResult) -> list[tuple[tuple[str, ...], tuple[str, ...], str]]:
    """The panels of :data:`FSS_PANELS` with at least one claim extrapolated in ``r``, each
    reduced to those claims."""
    ex = set(r.extrapolated.key)
    out = []
    for keys, labels, ylabel in FSS_PANELS:
        kept = [(k, lab) for k, lab in zip(keys, labels, strict=True) if k in ex]
        if kept:
            out.append((tuple(k for k, _ in kept), tuple(lab for _, lab in kept), ylabel))
    return out


def fig_fss(r: FiniteSizeResult, figdir: Path):
    """Finite size: each claim of :data:`FSS_PANELS` that the study measured (the rods-only
    P = 1/2 point, S_t/S_r of the one-sided systems, the energy exponents under compression and
    dilation, the taut-cable fraction) against n on a log axis, with the fitted
    ``y_inf + a n^(-1/nu)`` (dashed), the extrapolations to n -> infinity (squares at the
    axis' right end, marked "inf") and the paper's values (dotted), and the widths of the
    rods-only threshold distributions against n (log-log) where they were measured. Three
    panels per row. (Against n^(-1/nu) itself, with nu about 0.6, the points of n = 32 and 64
    lie within 10 % and 3 % of the axis from the extrapolations at 0.)"""
    ex = r.extrapolated.set_index("key")
    pc = ex.loc["rods_only_pc"]
    nu = pc.nu if np.isfinite(pc.nu) else 1.0
    panels = fss_panels(r)
    w = r.pc_widths
    widths = w is not None and np.isfinite(w.nu)
    count = len(panels) + widths
    cols = min(count, 3)
    rows = -(-count // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(5 * cols, 4.2 * rows), squeeze=False)
    flat = list(axes.ravel())
    for ax in flat[count:]:
        ax.set_visible(False)
    if widths:  # after the rods-only point, beside the point it is a second reading of
        _width_panel(flat.pop(1), w)
    fig.subplots_adjust(wspace=0.3, hspace=0.35)
    sizes = np.unique(r.by_size.n.to_numpy(float))
    n_inf = 4.0 * sizes.max() if sizes.size else 1.0  # where n -> infinity is drawn
    for ax, (keys, labels, ylabel) in zip(flat, panels, strict=False):
        for key, label in zip(keys, labels, strict=True):
            ref = CLAIMS[key].value
            s = r.by_size[r.by_size.key == key].sort_values("n")
            n = s.n.to_numpy(float)
            line = ax.errorbar(n, s.value, yerr=s.err, marker="o", capsize=3, label=label)
            colour = line[0].get_color()
            f = ex.loc[key]
            if np.isfinite(f.y_inf):
                ns = np.geomspace(n.min(), n_inf, 60)
                ax.plot(ns, f.y_inf + f.a * ns ** (-1 / nu), "--", color=colour, lw=1)
                ax.errorbar([n_inf], [f.y_inf], yerr=[f.y_inf_err], fmt="s", color=colour,
                            capsize=3)  # fmt: skip
            ax.axhline(ref, color=colour, ls=":", lw=1)
        ax.set_xscale("log")
        ax.set_xticks([*sizes, n_inf], [*(f"{v:g}" for v in sizes), "inf"])
        ax.xaxis.set_minor_locator(NullLocator())
        ax.set_xlabel(f"n; dashed: y_inf + a n^(-1/nu), nu = {nu:.2f} (rods-only fit)")
        ax.set_ylabel(ylabel)
        ax.legend(fontsize=7)
    axes.ravel()[0].set_title(
        f"FS  n = {', '.join(map(str, r.sizes or r.pc_sizes))}; dotted: literature / paper",
        fontsize=9,
    )
    return _save(fig, figdir, "FS")


def _width_panel(ax, w) -> None:
    """The rods-only threshold distributions' standard deviations against n, log-log, with
    the line of slope -1/nu fitted to them."""
    ax.errorbar(w.n, w.width, yerr=w.width_err, marker="o", capsize=3, ls="none")
    # the line's height: its weighted mean offset in log-log (display only)
    weight = (w.width / w.width_err) ** 2
    offset = np.sum(weight * (np.log(w.width) + np.log(w.n) / w.nu)) / np.sum(weight)
    ns = np.geomspace(w.n.min(), w.n.max(), 20)
    ax.plot(ns, np.exp(offset) * ns ** (-1 / w.nu), "--", lw=1,
            label=f"n^(-1/nu), nu = {w.nu:.2f} ± {w.nu_err:.2f}")  # fmt: skip
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xticks(w.n, [f"{v:g}" for v in w.n])
    ax.xaxis.set_minor_locator(NullLocator())
    ax.set_xlabel("n")
    ax.set_ylabel("std of the rods-only thresholds")
    ax.set_title(f"p_c from centre vs width: {w.p_c:.4f} ± {w.p_c_err:.4f}", fontsize=9)
    ax.legend(fontsize=7)


def fig_clusters(r: FiniteSizeResult, figdir: Path):
    """Rigid clusters at the threshold (the pc scale's pebble-game sweeps): one sample drawn
    just after its threshold event, its spanning rigid cluster and that cluster's stressed
    (overconstrained) sites coloured (:func:`~tensegrity_rigidity.paper.plotting.draw_clusters`);
    beside it, log-log, the mean masses (nodes) of both at the threshold against n with their
    fitted ``n^d`` (:func:`~tensegrity_rigidity.paper.studies.fss.fractal_dimensions`)."""
    pic, fits, by = r.picture, r.fractal, r.fractal_by_size
    assert fits is not None and by is not None, "fig_clusters needs the pebble-game sweeps"
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 5.2))
    if pic is not None:
        draw_clusters(left, pic.network, pic.clusters, spanning=pic.spanning.sites)
        left.set_title(
            f"n = {pic.n}, sample {pic.sample} at its threshold p_r = {pic.p_r:.4f}: "
            f"{pic.spanning.sites.size} rods in the spanning cluster, "
            f"{int(pic.spanning.stressed.sum())} stressed",
            fontsize=8,
        )
    colours = {"rigid": CYCLE[0], "stressed": CYCLE[1]}
    names = {"rigid": "spanning rigid cluster", "stressed": "its stressed part"}
    n = by.n.to_numpy(float)
    for cluster, colour in colours.items():
        mean, err = by[f"{cluster}_nodes"], by[f"{cluster}_nodes_err"]
        f = fits[(fits.cluster == cluster) & (fits.mass == "nodes") & (fits.n_min == n.min())]
        (row,) = f.itertuples()
        right.errorbar(n, mean, yerr=err, marker="o", ls="none", color=colour, capsize=3)
        # the line through the points' weighted centre with the fitted slope (display only)
        w = (mean / err) ** 2
        c = np.sum(w * (np.log(mean) - row.d * np.log(n))) / np.sum(w)
        right.plot(n, np.exp(c) * n**row.d, "--", color=colour, lw=1,
                   label=f"{names[cluster]}: d = {row.d:.3f} ± {row.d_err:.3f}")  # fmt: skip
    right.set_xscale("log")
    right.set_yscale("log")
    right.set_xticks(n, [f"{v:g}" for v in n])
    right.xaxis.set_minor_locator(NullLocator())
    right.set_xlabel("n")
    right.set_ylabel("mean nodes at the threshold")
    right.set_title("mass against size: M ~ n^d", fontsize=9)
    right.legend(fontsize=7)
    return _save(fig, figdir, "RC")


#: the panels of Fig. 3D: (2D claim keys, legend labels, y label)
PANELS_3D = (
    (("rods_only_pc",), ("rods only",), "rods-only P = 1/2 point"),
    (
        ("st_sr_half_dilation", "st_sr_half_shear", "st_sr_half_compression"),
        ("dilation", "shear", "compression"),
        "S_t / S_r at f_c = 0.5",
    ),
    (
        ("st_sr_cables_compression", "st_sr_cables_dilation"),
        ("compression", "dilation"),
        "S_t / S_r of rods + cables",
    ),
)


def fig_3d(r: ThreeDResult, figdir: Path):
    """Beyond the paper, the FCC lattice: the rods-only P = 1/2 point, S_t/S_r at f_c = 0.5
    per strain and of rods + cables under compression and dilation against n (log axis), with
    the two extrapolations (dashed: y_inf + a n^(-1/nu), nu fitted to the rods-only points;
    dotted: 1/nu = 3, a first-order shift; squares and diamonds at "inf"), our 2D values
    extrapolated (dash-dot, grey band: one error) and the paper's 2D values (open stars at
    "inf"; for the rods-only point the literature's 3D value and Maxwell's 1/2, grey lines);
    last, where measured, the widths of the rods-only threshold distributions (log-log)."""
    from .claims import REFERENCES, TWO_D_OURS
    from .studies.three_d import KEYS_3D, NU_FIRST_ORDER, PC_3D_CHECK, PC_3D_MAXWELL

    ex = r.extrapolated.set_index("key")
    w = r.widths
    widths = w is not None and np.isfinite(getattr(w, "nu", np.nan))
    count = len(PANELS_3D) + widths
    fig, axes = plt.subplots(1, count, figsize=(4.6 * count, 4.0), squeeze=False)
    flat = list(axes.ravel())
    fig.subplots_adjust(wspace=0.32)
    sizes = np.unique(r.by_size.n.to_numpy(float))
    n_inf = 2.5 * sizes.max()
    nu = ex.loc["rods_only_pc"].nu if "rods_only_pc" in ex.index else np.nan
    for ax, (keys, labels, ylabel) in zip(flat, PANELS_3D, strict=False):
        for i, (key, label) in enumerate(zip(keys, labels, strict=True)):
            if key not in KEYS_3D or key not in ex.index:
                continue
            s = r.by_size[r.by_size.key == key].sort_values("n")
            n = s.n.to_numpy(float)
            dx = 1.0 + 0.03 * (i - (len(keys) - 1) / 2)  # side by side on the log axis
            strain = label if label in STRAIN_COLOURS else None
            colour = STRAIN_COLOURS[strain] if strain else CYCLE[i]
            ax.errorbar(n * dx, s.value, yerr=s.err, marker="o", capsize=3, color=colour,
                        label=f"{label} (3D)")  # fmt: skip
            f = ex.loc[key]
            ns = np.geomspace(n.min(), n_inf, 60)
            for y_inf, err, nu_, ls, mark in (
                (f.y_inf, f.y_inf_err, nu, "--", "s"),
                (f.y_inf_first_order, f.y_inf_first_order_err, NU_FIRST_ORDER, ":", "D"),
            ):
                if not (np.isfinite(y_inf) and np.isfinite(nu_)):
                    continue
                # the fit's amplitude from its points (display only: the study fits it)
                wts = 1 / s.err.to_numpy(float) ** 2
                x = n ** (-1 / nu_)
                a = np.sum(wts * x * (s.value.to_numpy(float) - y_inf)) / np.sum(wts * x * x)
                ax.plot(ns, y_inf + a * ns ** (-1 / nu_), ls, color=colour, lw=1)
                ax.errorbar([n_inf * dx], [y_inf], yerr=[err], fmt=mark, color=colour,
                            capsize=3, mfc="none" if mark == "D" else colour)  # fmt: skip
            two = TWO_D_OURS[key]
            if key != "rods_only_pc":  # the 2D threshold (0.66) would flatten the 3D points
                ax.axhline(two.value, color=colour, ls="-.", lw=0.9, alpha=0.8)
                ax.axhspan(two.value - (two.error or 0), two.value + (two.error or 0),
                           color="grey", alpha=0.12, lw=0)  # fmt: skip
            if key != "rods_only_pc" and CLAIMS[key].value is not None:
                ax.plot([n_inf * dx * 1.12], [CLAIMS[key].value], color=colour, **PAPER_MARKER)
        if keys[0] == "rods_only_pc":
            ax.axhline(PC_3D_CHECK.value, color="grey", ls="--", lw=0.8)
            ax.axhline(PC_3D_MAXWELL.value, color="grey", ls=":", lw=0.8)
            ax.text(0.02, 0.02, f"2D: ours {two.value:.4f}, Jacobs & Thorpe "
                    f"{REFERENCES['pc_jacobs_thorpe'].value:g} (off this axis)",
                    transform=ax.transAxes, fontsize=7)  # fmt: skip
        ax.set_xscale("log")
        ax.set_xticks([*sizes, n_inf], [*(f"{v:g}" for v in sizes), "inf"])
        ax.xaxis.set_minor_locator(NullLocator())
        ax.set_xlabel("FCC n")
        ax.set_ylabel(ylabel)
        ax.legend(fontsize=7)
    flat[0].set_title(
        "3D  dash-dot: ours in 2D (n -> inf); stars: the paper in 2D; grey: "
        f"{PC_3D_CHECK.value:g} (lit., 3D), 1/2 (Maxwell)",
        fontsize=8,
        loc="left",
    )
    if widths:
        _width_panel(flat[count - 1], w)
    return _save(fig, figdir, "3D")


def all_figures(results: dict, figdir: Path) -> dict[str, list[Path]]:
    """Draw every figure in :data:`STYLE`; returns {figure id: [png, svg]}."""
    with plt.rc_context(STYLE):
        return _all_figures(results, figdir)


def _all_figures(results: dict, figdir: Path) -> dict[str, list[Path]]:
    out = {}
    if "fig2" in results:
        out["1A"] = fig1a(results["fig2"].field, figdir)
    if "fig1b" in results:
        out["1B"] = fig1b(results["fig1b"], figdir)
    if "fig1c" in results:
        out["1C"] = fig1c(results["fig1c"], figdir)
    if "fig2" in results:
        out["2A"] = fig2a(results["fig2"], figdir)
        out["2B"] = fig2b(results["fig2"], figdir)
        out["2C"] = fig2c(results["fig2"], figdir)
        out["2D"] = fig2d(results["fig2"], figdir)
        out["2E"] = fig2e(results["fig2"], figdir)
    if "fig3" in results:
        out["3B"] = fig3b(results["fig3"], figdir)
    if "fig4" in results:
        out["4A"] = fig4a(results["fig4"], figdir)
        out["4B"] = fig4b(results["fig4"], figdir)
        out["4C"] = fig4c(results["fig4"], figdir)
    if "fss" in results:
        out["FS"] = fig_fss(results["fss"], figdir)
        if results["fss"].fractal is not None:
            out["RC"] = fig_clusters(results["fss"], figdir)
    if "three_d" in results:
        out["3D"] = fig_3d(results["three_d"], figdir)
    return out
