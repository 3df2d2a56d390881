"""One style for every figure of the report, and the drawing helpers the studies share.

Sizes a journal column takes, Okabe and Ito's palette, mathtext for every symbol (labels come
from the studies' templates), no top or right spines. Error bars follow one rule: a value whose
error exceeds its magnitude is not resolved at this precision (the comparison's rule) and is
drawn as an open marker without a bar (clipped to the panel), so that it cannot flatten it.
The paper's values are open stars with the paper's error bars.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from cycler import cycler  # noqa: E402
from matplotlib.ticker import NullLocator  # noqa: E402

from ..model.io import atomic_output  # noqa: E402
from .claims import CLAIMS  # noqa: E402
from .plotting import BLUE, CYCLE, GREEN, OKABE_ITO, VERMILLION  # noqa: E402
from .template import load  # noqa: E402

__all__ = ["OKABE_ITO", "CYCLE"]

STYLE: dict[Any, Any] = {
    "axes.prop_cycle": cycler(color=CYCLE),
    "font.size": 9, "axes.titlesize": 9, "axes.labelsize": 9, "legend.fontsize": 7,
    "legend.frameon": False, "xtick.labelsize": 8, "ytick.labelsize": 8,
    "lines.linewidth": 1.3, "lines.markersize": 4, "errorbar.capsize": 2,
    "axes.spines.top": False, "axes.spines.right": False, "image.cmap": "cividis",
    "mathtext.fontset": "dejavusans", "savefig.dpi": 150, "figure.constrained_layout.use": True,
}  # fmt: skip
#: one column and two columns of a journal page (inches)
COLUMN, PAGE = 3.4, 7.0
STRAIN_COLOURS = {"dilation": VERMILLION, "shear": GREEN, "compression": BLUE, "average": "#000000"}
#: the paper's values: open stars in the colour of the curve
PAPER_MARKER: dict[str, Any] = {"marker": "*", "ms": 9, "mfc": "none", "mew": 1.1, "ls": "none"}
WORDS = load("style")


#: the seed of the SVG element ids (matplotlib draws them at random otherwise)
SVG_SALT = "tensegrity-rigidity"


def save(fig, figdir: Path, fid: str) -> list[Path]:
    """Write ``fig`` as ``fig<fid>.png`` and ``.svg`` under ``figdir``; close it. The same
    figure gives the same bytes on every run (no date, fixed SVG ids), so a re-rendered report
    changes only where its numbers do."""
    figdir.mkdir(parents=True, exist_ok=True)
    paths = [figdir / f"fig{fid}.png", figdir / f"fig{fid}.svg"]
    with atomic_output(paths[0], "the figure", "fig.png") as tmp:
        fig.savefig(tmp, dpi=150, bbox_inches="tight")
    with (
        atomic_output(paths[1], "the figure", "fig.svg") as tmp,
        plt.rc_context({"svg.hashsalt": SVG_SALT}),
    ):
        fig.savefig(tmp, bbox_inches="tight", metadata={"Date": None})
    plt.close(fig)
    return paths


def placeholder(fid: str, text: str, figdir: Path) -> list[Path]:
    """A figure that says why it is empty."""
    fig, ax = plt.subplots(figsize=(COLUMN, 2.0))
    ax.text(0.5, 0.5, text, ha="center", va="center", wrap=True)
    ax.set_axis_off()
    return save(fig, figdir, fid)


def resolved(y, err) -> np.ndarray:
    """(k,) bool: finite values whose error is at most their magnitude."""
    y, err = np.asarray(y, float), np.asarray(err, float)
    return np.isfinite(y) & np.isfinite(err) & (err <= np.abs(y))


def errorbar(ax, x, y, err, **kw):
    """Error bars for the resolved points, open markers (drawn by :func:`unresolved`) for the
    others; returns the colour used."""
    x, y, err = (np.asarray(a, float) for a in (x, y, err))
    ok = resolved(y, err)
    line = ax.errorbar(x[ok], y[ok], yerr=err[ok], **({"marker": "o", "capsize": 2} | kw))
    colour = line[0].get_color()
    pending = ax.__dict__.setdefault("_unresolved", [])
    pending += [(a, b, colour) for a, b in zip(x[~ok], y[~ok], strict=True) if np.isfinite(a)]
    return colour


def unresolved(ax) -> None:
    """Draw the points :func:`errorbar` left out, at their value clipped to the panel."""
    pending = ax.__dict__.pop("_unresolved", [])
    if not pending:
        return
    lo, hi = ax.get_ylim()
    for x, y, colour in pending:
        at = float(np.clip(y if np.isfinite(y) else hi, lo, hi))
        ax.plot([x], [at], "o", mfc="white", color=colour, zorder=4, clip_on=False)
    ax.plot([], [], "o", mfc="white", color="grey", label=WORDS.label("unresolved"))
    ax.set_ylim(lo, hi)


def legend_below(ax, ncol: int = 3) -> None:
    """The legend under the panel, where it hides no data."""
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.22), ncol=ncol)


def paper_point(ax, x: float, key: str, colour, dx: float = 0.0) -> None:
    """The paper's value of a claim at ``x``, with its error bar where it states one."""
    claim = CLAIMS[key]
    if claim.value is None:
        return
    err = claim.error if claim.error_kind == "stated" else 0.0
    ax.errorbar([x + dx], [claim.value], yerr=[err], color=colour, capsize=2, **PAPER_MARKER)


def paper_legend(ax) -> None:
    """The legend entry of the paper's values."""
    ax.plot([], [], color="grey", label=WORDS.label("paper"), **PAPER_MARKER)


def counts(ax, x, n) -> None:
    """The sample count of each point, written under it at the bottom of the panel."""
    trans = ax.get_xaxis_transform()
    for a, k in zip(np.asarray(x, float), np.asarray(n, float), strict=True):
        if np.isfinite(k):
            ax.text(a, 0.02, f"{k:.0f}", transform=trans, ha="center", fontsize=6, color="0.4")


def size_axis(ax, sizes, n_inf: float) -> None:
    """A log axis of the sizes with n -> infinity drawn at ``n_inf``."""
    ax.set_xscale("log")
    ax.set_xticks([*sizes, n_inf], [*(f"{v:g}" for v in sizes), r"$\infty$"])
    ax.xaxis.set_minor_locator(NullLocator())


def grid(count: int, cols: int = 2, size: tuple[float, float] = (3.3, 2.7)):
    """A figure of ``count`` panels in rows of ``cols`` (the spare ones hidden); its axes flat."""
    rows = -(-count // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(size[0] * cols, size[1] * rows), squeeze=False)
    flat = list(axes.ravel())
    for ax in flat[count:]:
        ax.set_visible(False)
    return fig, flat[:count]


def panel_letters(axes) -> None:
    """A, B, C, ... at the top left of each panel."""
    for ax, letter in zip(axes, "ABCDEFGH", strict=False):
        ax.text(-0.02, 1.02, letter, transform=ax.transAxes, fontweight="bold", va="bottom",
                ha="right")  # fmt: skip


def width_panel(ax, w) -> None:
    """The rods-only threshold distributions' standard deviations against n, log-log, with the
    line of slope -1/nu fitted to them (its height: the weighted mean offset, display only)."""
    ax.errorbar(w.n, w.width, yerr=w.width_err, marker="o", capsize=2, ls="none")
    weight = (w.width / w.width_err) ** 2
    offset = np.sum(weight * (np.log(w.width) + np.log(w.n) / w.nu)) / np.sum(weight)
    ns = np.geomspace(w.n.min(), w.n.max(), 20)
    ax.plot(ns, np.exp(offset) * ns ** (-1 / w.nu), "--", lw=1,
            label=WORDS.label("width_fit", nu=w.nu, nu_err=w.nu_err))  # fmt: skip
    ax.set(xscale="log", yscale="log", ylabel=WORDS.label("width"), xlabel=WORDS.label("n"))
    ax.set_xticks(w.n, [f"{v:g}" for v in w.n])
    ax.set_title(WORDS.label("title.width", p_c=w.p_c, p_c_err=w.p_c_err))
    ax.legend()
