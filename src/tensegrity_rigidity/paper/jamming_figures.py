"""Figures of the jamming study: one packing with its contact forces and rattlers, and
P(jammed) against packing fraction per size (with the fraction strictly jammed).

Plain functions of their data (a packing and its :class:`~tensegrity_rigidity.JammingResult`, a
:func:`~tensegrity_rigidity.analysis.jamming.jamming_table`), which the report's study of the
jamming onset draws into its figures.
"""

from __future__ import annotations

import os

import numpy as np
import pandas as pd

from ..model.network import PeriodicNetwork
from ..model.packing import Packing
from ..solver.jamming import JammingResult
from .template import load

WORDS = load("jamming_figures")


def plot_packing(
    packing: Packing,
    network: PeriodicNetwork,
    result: JammingResult,
    path: str | os.PathLike | None = None,
    ax=None,
):
    """Draw a 2D packing: disks (rattlers hollow), contacts as lines whose width is the
    certificate's contact force, across the periodic boundary as well. The forces are the
    certificate's (the self-stress that maximises the smallest force); on an isostatic backbone
    they are the packing's contact forces, on a hyperstatic one one admissible set of them.

    Parameters
    ----------
    packing : Packing
        Positions (N, 2), radii (N,), box (2, 2).
    network : PeriodicNetwork
        Its contact network (m sites), as tested.
    result : JammingResult
        The test of ``network`` (forces from ``result.contact_forces()``, rattlers from
        ``result.rattlers``).
    path : str or path-like, optional
        Where to save the figure (format from the suffix).
    ax : matplotlib Axes, optional
        Where to draw (a new figure when omitted).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib

    if ax is None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection, PatchCollection
    from matplotlib.patches import Circle, Polygon

    if packing.dim != 2:
        raise ValueError("plot_packing draws 2D packings")
    fig = ax.figure if ax is not None else plt.figure(figsize=(6, 6))
    ax = ax if ax is not None else fig.add_subplot(1, 1, 1)
    box = packing.box
    frac = packing.positions @ np.linalg.inv(box)
    pos = (frac - np.floor(frac)) @ box
    rattler = np.zeros(packing.n_particles, dtype=bool)
    rattler[result.rattlers] = True
    cell = Polygon(np.array([[0, 0], box[0], box[0] + box[1], box[1]]), fill=False, lw=1.0,
                   ec="black")  # fmt: skip
    ax.add_patch(cell)
    images = [np.array([a, b]) @ box for a in (-1, 0, 1) for b in (-1, 0, 1)]
    disks, colors = [], []
    for shift in images:
        for p, r, rat in zip(pos + shift, packing.radii, rattler, strict=True):
            disks.append(Circle(p, r))
            colors.append("white" if rat else "#c9d6e8")
    ax.add_collection(PatchCollection(disks, facecolors=colors, edgecolors="#555555", lw=0.4))
    net = network
    forces = result.contact_forces()
    if net.n_sites != forces.size:
        raise ValueError("the result is not the test of this network (site counts differ)")
    if forces.max(initial=0) > 0:
        i = net.bonds[:, 0]
        d = net.bond_vectors()
        start = pos[i]
        segs = [np.stack([start + s, start + d + s], axis=1) for s in images]
        width = 4.0 * forces / forces.max()
        lc = LineCollection(list(np.concatenate(segs)), linewidths=np.tile(width, len(images)),
                            colors="#b2182b")  # fmt: skip
        ax.add_collection(lc)
    corners = np.array([[0, 0], box[0], box[1], box[0] + box[1]])
    ax.set_xlim(corners[:, 0].min() - 0.5, corners[:, 0].max() + 0.5)
    ax.set_ylim(corners[:, 1].min() - 0.5, corners[:, 1].max() + 0.5)
    ax.set_aspect("equal")
    title = WORDS.label("title", kind=result.kind, status=result.status,
                        rattlers=result.n_rattlers, contacts=result.backbone_contacts)  # fmt: skip
    ax.set_title(title, fontsize=9)
    ax.set_xticks([])
    ax.set_yticks([])
    if path is not None:
        fig.savefig(path, dpi=150, bbox_inches="tight")
    return fig


def plot_jamming_probability(table: pd.DataFrame, path: str | os.PathLike | None = None, axes=None):
    """P(collectively jammed) against ``phi`` per size with Wilson intervals (left), and the
    fraction strictly jammed among the collectively jammed (right).

    Parameters
    ----------
    table : pandas.DataFrame
        :func:`~tensegrity_rigidity.analysis.jamming.jamming_table`.
    path : str or path-like, optional
        Where to save the figure.
    axes : pair of matplotlib Axes, optional
        Where to draw the two panels (a new figure when omitted).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib

    if axes is None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    if axes is None:
        fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4), sharex=True)
    else:
        (left, right), fig = axes, axes[0].figure
    for n, g in table.groupby("n"):
        g = g.sort_values("phi")
        lo, hi = g["p"] - g["p_lo"], g["p_hi"] - g["p"]
        label = WORDS.label("size", n=n)
        left.errorbar(g["phi"], g["p"], yerr=[lo, hi], marker="o", ms=3, capsize=2, label=label)
        s = g[g["strict_tested"] > 0]
        right.errorbar(s["phi"], s["p_strict"], yerr=[s["p_strict"] - s["p_strict_lo"],
                       s["p_strict_hi"] - s["p_strict"]], marker="o", ms=3, capsize=2)  # fmt: skip
    left.set_xlabel(WORDS.label("phi"))
    left.set_ylabel(WORDS.label("p"))
    right.set_xlabel(WORDS.label("phi"))
    right.set_ylabel(WORDS.label("p_strict"))
    left.legend(fontsize=8)
    for a in (left, right):
        a.set_ylim(-0.05, 1.05)
    if path is not None:
        fig.savefig(path, dpi=150, bbox_inches="tight")
    return fig
