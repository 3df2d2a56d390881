"""Networks and packings from other tools: GSD files (HOOMD-blue), freud/HOOMD boxes, networkx.

* **Boxes.** HOOMD-blue and freud describe a triclinic box by ``(Lx, Ly, Lz, xy, xz, yz)``: lattice
  vectors ``a1 = (Lx, 0, 0)``, ``a2 = (xy Ly, Ly, 0)``, ``a3 = (xz Lz, yz Lz, Lz)``, the columns of
  an upper-triangular matrix; a 2D box has ``Lz`` and the tilts ``xz``, ``yz`` unused. Our boxes
  hold the lattice vectors as *rows*. :func:`box_from_hoomd` builds ours; :func:`hoomd_box` goes
  back, rotating a general box (and so the positions) into HOOMD's orientation.
* **GSD.** :func:`read_gsd` reads one frame's positions, diameters and box into a
  :class:`~.packing.Packing` (``gsd``, the format's own library); :func:`write_gsd` writes one.
* **networkx.** :func:`network_to_networkx` gives a ``MultiDiGraph`` (one directed edge ``i -> j``
  per bond site, several between one pair for several images); :func:`network_from_networkx`
  reads it back or any graph with positions on its nodes and image shifts on its edges.
"""

from __future__ import annotations

import os

import numpy as np

from ..errors import InputError
from .io import check_input_file
from .network import Element, PeriodicNetwork, _as_float_array, check_count, show
from .packing import Packing


def box_from_hoomd(Lx, Ly, Lz=0.0, xy=0.0, xz=0.0, yz=0.0, dimensions: int | None = None):
    """Our box (rows the lattice vectors) from HOOMD/freud box parameters.

    Parameters
    ----------
    Lx, Ly, Lz, xy, xz, yz : float
        HOOMD-blue's box: lengths and tilt factors.
    dimensions : int, optional
        2 or 3 (default 2 when ``Lz == 0``, else 3).

    Returns
    -------
    (d, d) float
        Rows ``(Lx, 0[, 0])``, ``(xy Ly, Ly[, 0])`` and in 3D ``(xz Lz, yz Lz, Lz)``.
    """
    dim = dimensions if dimensions is not None else (2 if float(Lz) == 0.0 else 3)
    if dim not in (2, 3):
        raise InputError(f"dimensions must be 2 or 3, got {dimensions!r}")
    if dim == 2:
        return np.array([[Lx, 0.0], [xy * Ly, Ly]], dtype=float)
    return np.array([[Lx, 0.0, 0.0], [xy * Ly, Ly, 0.0], [xz * Lz, yz * Lz, Lz]], dtype=float)


def hoomd_box(box) -> tuple[tuple[float, ...], np.ndarray]:
    """HOOMD/freud box parameters of our box, and the rotation into HOOMD's orientation.

    Parameters
    ----------
    box : (d, d) float
        Lattice vectors as rows.

    Returns
    -------
    params : tuple of 6 float
        ``(Lx, Ly, Lz, xy, xz, yz)`` (``Lz = 0`` and no ``xz, yz`` in 2D).
    rotation : (d, d) float
        Orthogonal ``Q`` with ``box @ Q`` lower triangular with a positive diagonal (HOOMD's
        vectors as rows); positions map as ``positions @ Q``. A left-handed box needs a
        reflection (``det Q = -1``), which no jamming or rigidity verdict notices.
    """
    box = np.asarray(box, dtype=float)
    if box.ndim != 2 or box.shape[0] != box.shape[1] or box.shape[0] not in (2, 3):
        raise InputError(f"box must have shape (2, 2) or (3, 3), got {box.shape}")
    q, r = np.linalg.qr(box.T)  # box.T = q r: box q = r.T, lower triangular
    signs = np.where(np.diag(r) < 0, -1.0, 1.0)
    q, r = q * signs, (r.T * signs).T
    lower = box @ q
    Lx, Ly = lower[0, 0], lower[1, 1]
    xy = lower[1, 0] / Ly
    if box.shape[0] == 2:
        return (float(Lx), float(Ly), 0.0, float(xy), 0.0, 0.0), q
    Lz = lower[2, 2]
    return (float(Lx), float(Ly), float(Lz), float(xy), float(lower[2, 0] / Lz),
            float(lower[2, 1] / Lz)), q  # fmt: skip


def read_gsd(path: str | os.PathLike, frame: int = -1) -> Packing:
    """One frame of a GSD file (HOOMD-blue's format) as a packing.

    Parameters
    ----------
    path : str or path-like
        The ``.gsd`` file.
    frame : int
        Frame index (negative counts from the end; default the last).

    Returns
    -------
    Packing
        Positions (the ``z`` column dropped in 2D), radii ``particles.diameter / 2`` (1/2 where
        the file stores none: GSD's default diameter is 1) and the box from
        ``configuration.box`` (:func:`box_from_hoomd`). GSD stores positions in single
        precision (a relative error of about 6e-8): exact contacts come back as gaps of that
        size, so give ``contact_network`` a tolerance above it (``1e-5``, say).
    """
    import gsd.hoomd

    if isinstance(frame, (bool, np.bool_)) or not isinstance(frame, (int, np.integer)):
        raise InputError(f"frame must be an integer, got {show(frame)}")
    frame = int(frame)
    path = check_input_file(path, "a GSD file")
    try:
        with gsd.hoomd.open(str(path), mode="r") as trajectory:
            count = len(trajectory)
            if not -count <= frame < count:
                raise InputError(f"{path}: frame {frame} out of range for {count} frame(s)")
            snap = trajectory[frame]
    except InputError:
        raise
    except (OSError, RuntimeError, ValueError, KeyError) as exc:
        raise InputError(f"{path}: not a readable GSD file ({exc})") from None
    dim = int(snap.configuration.dimensions)
    Lx, Ly, Lz, xy, xz, yz = (float(v) for v in snap.configuration.box)
    box = box_from_hoomd(Lx, Ly, Lz, xy, xz, yz, dimensions=dim)
    positions = np.asarray(snap.particles.position, dtype=float)[:, :dim]
    diameter = snap.particles.diameter
    n = positions.shape[0]
    radii = 0.5 * (np.ones(n) if diameter is None else np.asarray(diameter, dtype=float))
    return Packing(positions, radii, box)


def write_gsd(path: str | os.PathLike, packing: Packing) -> None:
    """Write a packing as one GSD frame (positions rotated into HOOMD's box orientation).

    Parameters
    ----------
    path : str or path-like
        The ``.gsd`` file to create (overwritten).
    packing : Packing
        Positions ``(N, d)``, radii ``(N,)``, box ``(d, d)``.
    """
    import gsd.hoomd

    if not isinstance(packing, Packing):
        raise InputError(f"write_gsd needs a Packing (positions, radii, box), got {show(packing)}")
    params, q = hoomd_box(packing.box)
    dim = packing.dim
    frame = gsd.hoomd.Frame()
    frame.configuration.dimensions = dim
    frame.configuration.box = list(params)
    pos = packing.positions @ q
    frame.particles.N = packing.n_particles
    frame.particles.position = np.c_[pos, np.zeros(len(pos))] if dim == 2 else pos
    frame.particles.diameter = 2.0 * packing.radii
    try:
        with gsd.hoomd.open(str(path), mode="w") as f:
            f.append(frame)
    except OSError as exc:
        raise InputError(f"{path}: cannot write ({exc.strerror or exc})") from None


def network_to_networkx(network: PeriodicNetwork):
    """The network as a ``networkx.MultiDiGraph``.

    Parameters
    ----------
    network : PeriodicNetwork
        ``N`` nodes, ``m`` bond sites.

    Returns
    -------
    networkx.MultiDiGraph
        Nodes ``0..N-1`` with ``position`` ((d,) array); one edge ``i -> j`` per bond site ``b``
        with ``shift`` (tuple of d ints: ``d_b = r_j + shift @ box - r_i``), ``kind`` (an
        :class:`~.network.Element`), ``site`` (b) and ``stiffness`` when set; the box as the
        graph attribute ``box``.
    """
    import networkx as nx

    if not isinstance(network, PeriodicNetwork):
        raise InputError(f"network_to_networkx needs a PeriodicNetwork, got {show(network)}")
    g = nx.MultiDiGraph(box=np.array(network.box))
    for i, p in enumerate(network.positions):
        g.add_node(i, position=np.array(p))
    k = network.stiffness
    for b, ((i, j), s, kind) in enumerate(
        zip(network.bonds.tolist(), network.shifts.tolist(), network.kinds.tolist(), strict=True)
    ):
        attrs = {"shift": tuple(s), "kind": Element(kind), "site": b}
        if k is not None:
            attrs["stiffness"] = float(k[b])
        g.add_edge(i, j, **attrs)
    return g


def network_from_networkx(graph, box=None, kind: Element = Element.STRUT) -> PeriodicNetwork:
    """A periodic network from a networkx graph with positions and image shifts.

    Parameters
    ----------
    graph : networkx graph
        Nodes (in iteration order, any labels) with a ``position`` attribute (d,); edges with an
        optional ``shift`` (d ints, default zeros), ``kind`` (Element or its code) and
        ``stiffness``. Directed edges ``u -> v`` measure the shift from ``u``: ``d = r_v + shift @
        box - r_u``. An undirected edge with a non-zero shift needs a ``tail`` attribute naming
        the node it is measured from (networkx reports undirected edges in either order).
    box : (d, d) float, optional
        Lattice vectors as rows (default the graph attribute ``box``).
    kind : Element
        Kind of edges without a ``kind`` attribute (default struts: contacts).

    Returns
    -------
    PeriodicNetwork
        Edges in the graph's edge order (``site`` attributes, if all present, order them).
    """
    if not all(hasattr(graph, a) for a in ("graph", "nodes", "edges", "is_directed")):
        raise InputError(f"graph must be a networkx graph, got {show(graph)}")
    box = graph.graph.get("box") if box is None else box
    if box is None:
        raise InputError("the graph has no 'box' attribute: pass box=(d, d) lattice vectors")
    box = _as_float_array("box", box, (None, None))
    dim = box.shape[0]
    if box.shape != (dim, dim) or dim not in (2, 3):
        raise InputError(f"box must have shape (2, 2) or (3, 3), got {box.shape}")
    nodes = list(graph.nodes)
    index = {v: k for k, v in enumerate(nodes)}
    positions = np.array([_node_position(graph, v, dim) for v in nodes]).reshape(-1, dim)
    rows = [_edge_row(graph, u, v, data, dim, index, kind) for u, v, data in graph.edges(data=True)]
    if rows and all(r[0] is not None for r in rows):
        rows.sort(key=lambda r: r[0])
    bonds = np.array([[r[1], r[2]] for r in rows], dtype=np.int64).reshape(-1, 2)
    shifts = np.array([r[3] for r in rows]).reshape(-1, dim)
    kinds = np.array([r[4] for r in rows], dtype=np.int64)
    stiff = [r[5] for r in rows]
    given = sum(x is not None for x in stiff)
    if 0 < given < len(rows):
        raise InputError(
            f"{given} of {len(rows)} edges carry a 'stiffness': give it on every edge or on none"
        )
    stiffness = np.array(stiff, dtype=float) if rows and given else None
    return PeriodicNetwork(box, positions, bonds, shifts, kinds, stiffness)


def _node_position(graph, v, dim: int) -> np.ndarray:
    """The ``position`` attribute of node ``v``: ``dim`` numbers."""
    if "position" not in graph.nodes[v]:
        raise InputError(f"node {v!r} has no 'position' attribute (every node needs one)")
    return _as_float_array(f"node {v!r}'s position", graph.nodes[v]["position"], (dim,))


def _edge_kind(value) -> int:
    """An edge's kind: an :class:`~.network.Element`, its integer code or its name ("strut")."""
    if isinstance(value, str) and value.upper() in Element.__members__:
        return int(Element[value.upper()])
    if isinstance(value, (Element, int, np.integer)) and not isinstance(value, (bool, np.bool_)):
        if int(value) in set(Element):
            return int(value)
    names = ", ".join(e.name.lower() for e in Element)
    raise InputError(f"kind must be an Element, its code or one of {names}; got {show(value)}")


def _edge_row(graph, u, v, data, dim: int, index: dict, kind) -> tuple:
    """One edge as ``(site, i, j, shift, kind code, stiffness)``, measured from its tail."""
    where = f"edge ({u!r}, {v!r})"
    shift = np.asarray(data.get("shift", np.zeros(dim, dtype=np.int64)))
    whole = shift.dtype.kind in "iuf" and bool(np.all(shift == np.round(shift)))
    if shift.shape != (dim,) or not whole:
        raise InputError(f"{where}: shift must be {dim} integers, got {show(data.get('shift'))}")
    tail = data.get("tail")
    if not graph.is_directed() and np.any(shift) and tail is None:
        raise InputError(
            f"undirected {where} has a non-zero shift but no 'tail' attribute saying which end it "
            "is measured from"
        )
    if tail is not None and tail not in (u, v):
        raise InputError(f"{where}: tail {tail!r} is not one of its ends")
    if tail is not None and tail != u:
        u, v = v, u
    stiffness = data.get("stiffness")
    if stiffness is not None:
        stiffness = float(_as_float_array(f"{where}'s stiffness", stiffness, ()))
    site = data.get("site")
    if site is not None:
        site = check_count(f"{where}'s site", site)
    code = _edge_kind(data.get("kind", kind))
    return site, index[u], index[v], shift.astype(np.int64), code, stiffness
