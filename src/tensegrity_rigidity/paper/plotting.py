"""Drawing one network: its elements by kind, their tensions, and the node displacements.

:func:`draw_network` draws onto a Matplotlib ``Axes`` in the style of the paper's Fig. 1A:
rods solid, cables dashed, struts hollow (a coloured outline around a white core). With a
:class:`~tensegrity_rigidity.solver.core.SolveResult` the line width grows with ``|t|`` (slack
elements stay thin) and the colour gives either the tension (``colour="tension"``, as the
paper's but colour-blind safe: vermillion pulls, grey is zero, blue pushes) or the kind
(``colour="kind"``: rods black, cables vermillion, struts blue); the displacements are drawn
as arrows. :func:`plot_solution` writes such a drawing to a file (``tensegrity-rigidity solve
FILE --plot out.png``); a 3D network is drawn as its three projections on the coordinate
planes, side by side, and a 2D rods-only network beside its rigid clusters and overconstrained
sites (:func:`draw_clusters`, from the pebble game). Colours are Okabe and Ito's
(:data:`OKABE_ITO`), safe for colour-blind readers.

Nothing here selects a Matplotlib backend: :func:`plot_solution` draws on a bare
``matplotlib.figure.Figure`` (no GUI needed), and :func:`draw_network` draws on whatever
``Axes`` it is given (an interactive figure, a report's Agg figure).
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
from matplotlib.axes import Axes
from matplotlib.cm import ScalarMappable
from matplotlib.collections import LineCollection
from matplotlib.colors import LinearSegmentedColormap, TwoSlopeNorm
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from ..combinatorics.clusters import RigidClusters, rigid_clusters
from ..errors import InputError
from ..model.io import check_output_file
from ..model.network import Element, Instance, PeriodicNetwork
from ..solver.core import SolveResult
from .template import load

WORDS = load("plotting")

#: Okabe and Ito's palette, distinguishable with every common colour-vision deficiency
#: (Wong, Nature Methods 8, 441, 2011): black, orange, sky blue, bluish green, yellow, blue,
#: vermillion, reddish purple; every drawing and figure takes its colours from it
OKABE_ITO = (
    "#000000", "#E69F00", "#56B4E9", "#009E73", "#F0E442", "#0072B2", "#D55E00", "#CC79A7"
)  # fmt: skip
BLUE, VERMILLION, GREEN, PURPLE, ORANGE, SKY = (
    "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9"
)  # fmt: skip
#: the colour cycle of every figure: the palette without black (kept for averages) and yellow
#: (too light on white)
CYCLE = (BLUE, VERMILLION, GREEN, PURPLE, ORANGE, SKY)
#: colours of ``colour="kind"``: rods black, cables vermillion, struts blue
KIND_COLOURS = {Element.ROD: "black", Element.CABLE: VERMILLION, Element.STRUT: BLUE}
#: tension colours, as the paper's Fig. 1A but colour-blind safe: blue (pushes) -> grey (zero)
#: -> vermillion (pulls)
TENSION_CMAP = LinearSegmentedColormap.from_list("tension", [BLUE, "#BBBBBB", VERMILLION])
#: rigid-cluster drawings (:func:`draw_clusters`): the spanning cluster, its stressed
#: (overconstrained) sites, the other clusters of more than one bond and the lone bonds
SPANNING_COLOUR, STRESSED_COLOUR, CLUSTER_COLOUR, LONE_COLOUR = BLUE, VERMILLION, SKY, "#C8C8C8"
_DASH = (0, (3, 2))


def bond_segments(network: PeriodicNetwork) -> np.ndarray:
    """End points of every bond site, drawn from node ``i`` to the image of node ``j``.

    Parameters
    ----------
    network : PeriodicNetwork
        The network (``N`` nodes, ``m`` sites).

    Returns
    -------
    segments : (m, 2, 2) float
        ``segments[b] = [r_i, r_i + d_b]``: a bond that wraps around the periodic box is drawn
        whole, reaching out of the box to the image of its second node.
    """
    start = network.positions[network.bonds[:, 0]]
    return np.stack([start, start + network.bond_vectors()], axis=1)


def line_widths(tensions: np.ndarray | None, m: int, widths: tuple[float, float]) -> np.ndarray:
    """Line width of each site: ``widths[0]`` at zero tension up to ``widths[1]`` at max ``|t|``.

    Parameters
    ----------
    tensions : (m,) float or None
        Tensions; None draws every site at ``widths[0]``.
    m : int
        Number of sites.
    widths : (float, float)
        Thinnest and thickest width, in points.

    Returns
    -------
    (m,) float
        Widths in points.
    """
    lo, hi = widths
    if tensions is None:
        return np.full(m, lo)
    a = np.abs(np.asarray(tensions, dtype=float))
    top = float(a.max(initial=0.0))
    return lo + (hi - lo) * (a / top if top > 0 else a)


def draw_network(
    ax: Axes,
    instance: Instance,
    result: SolveResult | None = None,
    colour: str = "tension",
    arrows: bool = True,
    widths: tuple[float, float] = (0.6, 4.0),
    legend: bool | dict = True,
    colorbar: bool = True,
    plane: tuple[int, int] = (0, 1),
) -> Axes:
    """Draw a network's elements, their tensions and the node displacements onto ``ax``.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw (its aspect is set equal).
    instance : Instance
        Network and elements; empty sites are not drawn.
    result : SolveResult, optional
        The solved state of ``instance``: its ``tensions`` (m,) set the line widths (and the
        colours with ``colour="tension"``), its ``displacements`` (N, d) the arrows.
        Without it every element is drawn thin and coloured by kind.
    colour : {"tension", "kind"}
        Colour by tension (as the paper's Fig. 1A, colour-blind safe: vermillion pulls, grey
        zero, blue pushes, on a symmetric scale) or by kind (rods black, cables vermillion,
        struts blue).
    arrows : bool
        Draw the displacements as arrows, scaled so that the longest is 0.8 mean bond
        lengths (their lengths are relative: near the transition a few nodes move far more
        than the rest, and most arrows are then dots).
    widths : (float, float)
        Line width at zero tension and at the largest ``|t|``, in points.
    legend : bool or dict
        Add a legend of the element kinds (a dict: with these keywords of ``ax.legend``).
    colorbar : bool
        Add a colour bar of the tension (``colour="tension"`` with a result only).
    plane : (int, int)
        The coordinates drawn (a projection of a 3D network: ``(0, 2)`` is the x-z plane).

    Returns
    -------
    matplotlib.axes.Axes
        ``ax``.

    Raises
    ------
    InputError
        If ``colour`` is not "tension" or "kind", or ``result`` does not belong to
        ``instance`` (other numbers of sites or nodes).
    """
    if colour not in ("tension", "kind"):
        raise InputError(f"colour must be 'tension' or 'kind', got {colour!r}")
    net = instance.network
    t = None
    if result is not None:
        t = np.asarray(result.tensions, dtype=float)
        if t.shape != (net.n_sites,) or result.displacements.shape != (net.n_nodes, net.dim):
            raise InputError("the result does not belong to this instance (sizes differ)")
    axes = list(plane)
    if len(axes) != 2 or not all(0 <= a < net.dim for a in axes) or axes[0] == axes[1]:
        raise InputError(f"plane must name two of the network's {net.dim} coordinates")
    by_tension = colour == "tension" and t is not None
    seg = bond_segments(net)[:, :, axes]
    lw = line_widths(t, net.n_sites, widths)
    scale = float(np.abs(t).max(initial=0.0)) if t is not None else 0.0
    norm = TwoSlopeNorm(vmin=-(scale or 1.0), vcenter=0.0, vmax=scale or 1.0)
    handles = []
    for kind, name in ((Element.ROD, "rod"), (Element.CABLE, "cable"), (Element.STRUT, "strut")):
        on = net.kinds == kind
        if not on.any():
            continue
        colours: Any = KIND_COLOURS[kind]
        if by_tension and t is not None:
            colours = TENSION_CMAP(norm(t[on]))
        style: dict[str, Any] = {"linestyles": _DASH} if kind == Element.CABLE else {}
        if kind == Element.STRUT:  # hollow: a coloured outline around a white core
            ax.add_collection(LineCollection(seg[on], colors=colours, linewidths=lw[on] + 2.0))
            ax.add_collection(LineCollection(seg[on], colors="white", linewidths=lw[on]))
        else:
            ax.add_collection(LineCollection(seg[on], colors=colours, linewidths=lw[on], **style))
        key = "black" if by_tension else KIND_COLOURS[kind]
        if kind == Element.STRUT:
            handles.append(Line2D([], [], color=key, lw=3.5, label=WORDS.label("strut")))
        else:
            ls = "--" if kind == Element.CABLE else "-"
            handles.append(Line2D([], [], color=key, lw=1.8, ls=ls, label=WORDS.label(name)))
    pos = net.positions[:, axes]
    ax.plot(pos[:, 0], pos[:, 1], "k.", ms=2)
    if arrows and result is not None:
        handles += _arrows(ax, net, np.asarray(result.displacements, dtype=float)[:, axes], pos)
    if by_tension and colorbar:
        sm = ScalarMappable(norm=norm, cmap=TENSION_CMAP)
        ax.figure.colorbar(sm, ax=ax, label=WORDS.label("tension"))
    if legend and handles:
        where = legend if isinstance(legend, dict) else {"loc": "upper left", "framealpha": 0.9}
        ax.legend(handles=handles, **({"fontsize": 7} | where))
    ax.set_aspect("equal")
    ax.autoscale()
    ax.set_xlabel("xyz"[axes[0]])
    ax.set_ylabel("xyz"[axes[1]])
    return ax


def _arrows(ax: Axes, net: PeriodicNetwork, u: np.ndarray, pos: np.ndarray) -> list:
    """The displacements ``u`` (N, 2) as arrows, the longest 0.8 mean bond lengths; returns
    the legend handle (none when nothing moves)."""
    longest = float(np.hypot(u[:, 0], u[:, 1]).max(initial=0.0))
    if longest <= 0:
        return []
    ell = float(net.bond_lengths().mean())
    ax.quiver(pos[:, 0], pos[:, 1], u[:, 0], u[:, 1], color="0.25", angles="xy",
              scale_units="xy", scale=longest / (0.8 * ell), width=0.003, zorder=3)  # fmt: skip
    arrow = Line2D([], [], color="0.25", marker=r"$\rightarrow$", ls="", ms=10)
    arrow.set_label(WORDS.label("displacement"))
    return [arrow]


def draw_clusters(
    ax: Axes,
    network: PeriodicNetwork,
    clusters: RigidClusters,
    spanning: np.ndarray | None = None,
    legend: bool | dict = True,
) -> Axes:
    """Draw a rods-only network's rigid clusters and its overconstrained sites onto ``ax``.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw (its aspect is set equal).
    network : PeriodicNetwork
        The network (``m`` sites); empty sites are not drawn.
    clusters : RigidClusters
        Its rigid clusters (:func:`~tensegrity_rigidity.combinatorics.clusters.rigid_clusters`).
    spanning : (k,) int, optional
        Sites of one cluster to draw as the spanning one (:data:`SPANNING_COLOUR`; its
        overconstrained sites :data:`STRESSED_COLOUR`, thicker). By default the largest
        cluster that holds an overconstrained site of a wrapping network, none otherwise.
    legend : bool or dict
        Add a legend (a dict: with these keywords of ``ax.legend``).

    Returns
    -------
    matplotlib.axes.Axes
        ``ax``. Other clusters of two bonds or more are :data:`CLUSTER_COLOUR` (their
        overconstrained sites thicker), lone bonds (a cluster of one: free to rotate)
        :data:`LONE_COLOUR`, thin.
    """
    labels = np.asarray(clusters.labels)
    over = np.asarray(clusters.overconstrained, dtype=bool)
    if labels.shape != (network.n_sites,):
        raise InputError("the clusters do not belong to this network (numbers of sites differ)")
    present = labels >= 0
    size = np.bincount(labels[present], minlength=clusters.n_clusters)
    in_span = np.zeros(network.n_sites, dtype=bool)
    if spanning is not None:
        in_span[np.asarray(spanning, dtype=np.int64)] = True
    elif clusters.wraps and over.any():
        stressed_labels = np.unique(labels[over & present])
        in_span = labels == stressed_labels[np.argmax(size[stressed_labels])]
    lone = present & (size[np.maximum(labels, 0)] == 1) & ~in_span
    other = present & ~lone & ~in_span
    seg = bond_segments(network)[:, :, :2]
    layers = (
        (lone, LONE_COLOUR, 0.5, "lone"),
        (other & ~over, CLUSTER_COLOUR, 0.9, "other"),
        (other & over, CLUSTER_COLOUR, 1.8, ""),
        (in_span & ~over, SPANNING_COLOUR, 1.1, "spanning"),
        (in_span & over, STRESSED_COLOUR, 1.8, "stressed"),
    )
    handles = []
    for on, colour, width, label in layers:
        if on.any():
            ax.add_collection(LineCollection(seg[on], colors=colour, linewidths=width))
            if label:
                lw = max(width, 1.5)
                handles.append(Line2D([], [], color=colour, lw=lw, label=WORDS.label(label)))
    if legend and handles:  # below the drawing, which fills its box
        where = legend if isinstance(legend, dict) else {}
        below = {"loc": "upper left", "bbox_to_anchor": (0.0, -0.1), "ncol": 2, "fontsize": 7}
        ax.legend(handles=handles, **(below | where))
    ax.set_aspect("equal")
    ax.autoscale()
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    return ax


def window(ax: Axes, network: PeriodicNetwork, half: float) -> None:
    """Show a square window of ``ax`` around the network's centre: at the sizes a study runs,
    the elements of the whole network cannot be told apart.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where the network is drawn.
    network : PeriodicNetwork
        The network drawn.
    half : float
        Half the window's side, in mean bond lengths.
    """
    centre = network.positions[:, :2].mean(axis=0)
    h = half * float(network.bond_lengths().mean())
    ax.set_xlim(centre[0] - h, centre[0] + h)
    ax.set_ylim(centre[1] - h, centre[1] + h)


def check_plot_path(path: str | os.PathLike) -> Path:
    """Refuse a figure path that cannot be written, before any work is done.

    Parameters
    ----------
    path : str or path-like
        Output file; its suffix names the format (``.png``, ``.svg``, ``.pdf``, ...).

    Returns
    -------
    pathlib.Path
        The path.

    Raises
    ------
    InputError
        As :func:`~tensegrity_rigidity.model.io.check_output_file` (empty, a directory, a
        link, a device, in a missing directory), or Matplotlib cannot write its format.
    """
    p = check_output_file(path, "the figure path", "network.png")
    formats = dict(Figure().canvas.get_supported_filetypes())
    if shutil.which(matplotlib.rcParams["pgf.texsystem"]) is None:
        formats.pop("pgf", None)  # Matplotlib writes PGF through a TeX installation
    fmt = p.suffix.lstrip(".").lower()
    if fmt not in formats:
        raise InputError(
            f"{p}: cannot write a figure of format {fmt or '(none)'!r}; use one of "
            f"{', '.join('.' + f for f in sorted(formats))}"
        )
    return p


def _rods_only(network: PeriodicNetwork) -> bool:
    """A 2D network with rods and no cable or strut: its rigid clusters are drawn too."""
    kinds = network.kinds
    one_sided = (kinds == Element.CABLE) | (kinds == Element.STRUT)
    return network.dim == 2 and bool((kinds == Element.ROD).any()) and not one_sided.any()


def plot_solution(
    instance: Instance,
    result: SolveResult,
    path: str | os.PathLike,
    colour: str = "tension",
    arrows: bool = True,
    title: str | None = None,
) -> Path:
    """Write a drawing of a solved instance (:func:`draw_network`) to a file.

    Parameters
    ----------
    instance : Instance
        The instance.
    result : SolveResult
        Its solution (:func:`~tensegrity_rigidity.solver.core.solve`).
    path : str or path-like
        Output file; the suffix names the format (``.png``, ``.svg``, ``.pdf``, ...).
    colour : {"tension", "kind"}
        See :func:`draw_network`.
    arrows : bool
        Draw the displacements.
    title : str, optional
        Title; by default the verdict, the energy and the element counts.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    InputError
        See :func:`check_plot_path` and :func:`draw_network`.
    """
    p = check_plot_path(path)
    net = instance.network
    if net.dim == 3:  # the three coordinate planes, one legend and one colour bar
        fig = Figure(figsize=(17, 6))
        panels = fig.subplots(1, 3)
        for i, (ax, plane) in enumerate(zip(panels, ((0, 1), (0, 2), (1, 2)), strict=True)):
            last = i == 2
            draw_network(
                ax, instance, result, colour, arrows, legend=i == 0, colorbar=last, plane=plane
            )
        ax = panels[1]
    elif _rods_only(net):  # the tensions beside the rigid clusters (pebble game)
        fig = Figure(figsize=(14, 6))
        ax, right = fig.subplots(1, 2)
        draw_network(ax, instance, result, colour=colour, arrows=arrows)
        cl = rigid_clusters(net)
        draw_clusters(right, net, cl)
        counts = {"clusters": cl.n_clusters, "over": int(cl.overconstrained.sum())}
        label = "clusters.wraps" if cl.wraps else "clusters.open"
        right.set_title(WORDS.label(label, floppy=cl.floppy_modes, **counts), fontsize=9)
    else:
        fig = Figure(figsize=(7, 6))
        ax = fig.subplots()
        draw_network(ax, instance, result, colour=colour, arrows=arrows)
    if title is None:
        title = WORDS.label(
            "title", status=result.status, energy=result.energy, affine=result.affine_energy,
            rods=net.count(Element.ROD), cables=net.count(Element.CABLE),
            struts=net.count(Element.STRUT),
        )  # fmt: skip
    ax.set_title(title, fontsize=9)
    fig.savefig(p, dpi=130, bbox_inches="tight")
    return p
