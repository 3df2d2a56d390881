"""Drawing one network: its elements by kind, their tensions, and the node displacements.

:func:`draw_network` draws onto a Matplotlib ``Axes`` in the style of the paper's Fig. 1A:
rods solid, cables dashed, struts hollow (a coloured outline around a white core). With a
:class:`~tensegrity_rigidity.solver.core.SolveResult` the line width grows with ``|t|`` (slack
elements stay thin) and the colour gives either the tension (``colour="tension"``, the
paper's: red pulls, green is zero, blue pushes) or the kind (``colour="kind"``: rods black,
cables red, struts blue); the displacements are drawn as arrows. :func:`plot_solution` writes
such a drawing to a file (``tensegrity-rigidity solve FILE --plot out.png``); a 3D network is
drawn as its three projections on the coordinate planes, side by side.

Nothing here selects a Matplotlib backend: :func:`plot_solution` draws on a bare
``matplotlib.figure.Figure`` (no GUI needed), and :func:`draw_network` draws on whatever
``Axes`` it is given (a notebook's inline figure, a report's Agg figure).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.cm import ScalarMappable
from matplotlib.collections import LineCollection
from matplotlib.colors import LinearSegmentedColormap, TwoSlopeNorm
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from ..errors import InputError
from ..model.network import Element, Instance, PeriodicNetwork
from ..solver.core import SolveResult

#: colours of ``colour="kind"``
KIND_COLOURS = {Element.ROD: "black", Element.CABLE: "tab:red", Element.STRUT: "tab:blue"}
#: the paper's tension colours: blue (pushes) -> green (zero) -> red (pulls)
TENSION_CMAP = LinearSegmentedColormap.from_list("tension", ["blue", "limegreen", "red"])
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
    legend: bool = True,
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
        Colour by tension (the paper's Fig. 1A: red pulls, green zero, blue pushes, on a
        symmetric scale) or by kind (rods black, cables red, struts blue).
    arrows : bool
        Draw the displacements as arrows, scaled so that the longest is 0.8 mean bond
        lengths (their lengths are relative: near the transition a few nodes move far more
        than the rest, and most arrows are then dots).
    widths : (float, float)
        Line width at zero tension and at the largest ``|t|``, in points.
    legend : bool
        Add a legend of the element kinds.
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
            handles.append(Line2D([], [], color=key, lw=3.5, label="strut (hollow)"))
        else:
            ls = "--" if kind == Element.CABLE else "-"
            handles.append(Line2D([], [], color=key, lw=1.8, ls=ls, label=name))
    pos = net.positions[:, axes]
    ax.plot(pos[:, 0], pos[:, 1], "k.", ms=2)
    if arrows and result is not None:
        u = np.asarray(result.displacements, dtype=float)[:, axes]
        longest = float(np.hypot(u[:, 0], u[:, 1]).max(initial=0.0))
        if longest > 0:
            ell = float(net.bond_lengths().mean())
            ax.quiver(
                pos[:, 0],
                pos[:, 1],
                u[:, 0],
                u[:, 1],
                color="0.25",
                angles="xy",
                scale_units="xy",
                scale=longest / (0.8 * ell),
                width=0.003,
                zorder=3,
            )
            arrow = Line2D([], [], color="0.25", marker=r"$\rightarrow$", ls="", ms=10)
            arrow.set_label("displacement")
            handles.append(arrow)
    if by_tension and colorbar:
        sm = ScalarMappable(norm=norm, cmap=TENSION_CMAP)
        ax.figure.colorbar(sm, ax=ax, label="tension t (red pulls, blue pushes)")
    if legend and handles:
        ax.legend(handles=handles, loc="upper left", fontsize=7, framealpha=0.9)
    ax.set_aspect("equal")
    ax.autoscale()
    ax.set_xlabel("xyz"[axes[0]])
    ax.set_ylabel("xyz"[axes[1]])
    return ax


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
        If the path is empty or a directory, its directory does not exist, or Matplotlib
        cannot write its format.
    """
    if not os.fspath(path).strip():
        raise InputError("the figure path is empty; give a file name such as out.png")
    p = Path(path)
    if p.is_dir():
        raise InputError(f"{p}: is a directory; give a file name such as {p}/network.png")
    if not p.parent.is_dir():
        raise InputError(f"{p}: directory {p.parent} does not exist")
    formats = Figure().canvas.get_supported_filetypes()
    fmt = p.suffix.lstrip(".").lower()
    if fmt not in formats:
        raise InputError(
            f"{p}: cannot write a figure of format {fmt or '(none)'!r}; use one of "
            f"{', '.join('.' + f for f in sorted(formats))}"
        )
    return p


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
    else:
        fig = Figure(figsize=(7, 6))
        ax = fig.subplots()
        draw_network(ax, instance, result, colour=colour, arrows=arrows)
    if title is None:
        title = (
            f"{result.status}: E* = {result.energy:.3g} (affine {result.affine_energy:.3g}); "
            f"{net.count(Element.ROD)} rods, {net.count(Element.CABLE)} cables, "
            f"{net.count(Element.STRUT)} struts"
        )
    ax.set_title(title, fontsize=9)
    fig.savefig(p, dpi=130, bbox_inches="tight")
    return p
