"""Work units of a sweep: a chunk of samples at one grid point, computed anywhere.

These functions are what executors run (a local process, a Dask worker); they take only plain,
picklable arguments and return a pandas DataFrame of rows, one per sample. They write nothing.

A row starts with its key columns (:func:`key_columns`: the grid point, ``sample``, ``theta`` and
``point_key``, the digest of the spec's settings and the grid point); ``(point_key, sample,
theta)`` identifies the row in a results directory (:mod:`~tensegrity_rigidity.ensemble.store`).
The remaining columns are the sample's record; to add a column, add it to the record.
"""

from __future__ import annotations

import time
import warnings

import numpy as np
import pandas as pd

from ..analysis.observables import sample_record
from ..model.elements import place_elements
from ..model.lattice import CrossingBondsWarning
from ..model.network import Instance
from ..model.sampling import lattice_geometry
from ..model.strain import sequence_rotation, strain_tensor
from ..solver.core import solve
from .inexact import paper_verdict
from .jamming import packing_record
from .spec import GridPoint, Spec
from .thresholds import elements_at, find_threshold, pebble_pass


def sample_rng(point: GridPoint, k: int) -> np.random.Generator:
    """The random generator of one sample.

    Parameters
    ----------
    point : GridPoint
        The grid point; only its ``seed``, ``n`` and ``delta`` are used.
    k : int
        Sample index, 1-based.

    Returns
    -------
    numpy.random.Generator
        Seeded by ``SeedSequence(seed, spawn_key=(n, bits(delta), k))``: the same for every
        ``p_r``, ``p_t``, ``f_c`` and ``phi`` (common random numbers).
    """
    delta_bits = int(np.float64(point.delta).view(np.uint64))
    ss = np.random.SeedSequence(point.seed, spawn_key=(point.n, delta_bits, k))
    return np.random.default_rng(ss)


def sample_geometry(spec: Spec, point: GridPoint, k: int):
    """The geometry, site uniforms and strain angle of one sample.

    Parameters
    ----------
    spec : Spec
        The sweep (lattice and angle sequence).
    point : GridPoint
        The grid point.
    k : int
        Sample index, 1-based.

    Returns
    -------
    network : PeriodicNetwork
        The empty lattice (``m`` sites).
    u, v : (m,) float
        Site uniforms: the elements at any (p_r, p_t, f_c) follow from
        :func:`~tensegrity_rigidity.model.elements.place_elements`.
    theta : float
        The strain's principal-axis angle (in 3D the row's key; the axes follow from ``k``).

    Notes
    -----
    Together with :func:`sample_strain` this rebuilds any row's instance.
    Crossing bonds at a large ``delta`` were announced once when the spec was parsed; the
    builder's per-sample warning is silenced here.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CrossingBondsWarning)
        net, u, v = lattice_geometry(point.n, point.delta, sample_rng(point, k), spec.lattice)
    return net, u, v, spec.angle(k)


def sample_strain(spec: Spec, point: GridPoint, k: int, theta: float, dim: int) -> np.ndarray:
    """The strain tensor of sample ``k``: principal axes at ``theta`` in 2D, the rotation
    :func:`~tensegrity_rigidity.model.strain.sequence_rotation` ``(k)`` in 3D.

    Parameters
    ----------
    spec : Spec
        The sweep (its ``gamma``).
    point : GridPoint
        The grid point (its ``phi``).
    k : int
        Sample index, 1-based.
    theta : float
        The sample's angle (:meth:`Spec.angle`; in 3D only the row's key).
    dim : int
        The network's dimension.

    Returns
    -------
    (dim, dim) float
        The strain tensor, magnitude included.
    """
    if dim == 3:
        return strain_tensor(point.phi, gamma=spec.gamma, rotation_matrix=sequence_rotation(k))
    return strain_tensor(point.phi, theta, spec.gamma)


def key_columns(spec: Spec, point: GridPoint, k: int, theta: float) -> dict:
    """The columns that identify a row: grid point, sample index, angle and point key.

    Parameters
    ----------
    spec : Spec
        The sweep.
    point : GridPoint
        The grid point.
    k : int
        Sample index, 1-based.
    theta : float
        The sample's strain angle.

    Returns
    -------
    dict
        ``n``, ``delta``, ``p_r``, ``p_t``, ``f_c``, ``phi``, ``seed``, ``theta``,
        ``sample``, ``point_key``.
    """
    return {
        "n": point.n,
        "delta": point.delta,
        "p_r": point.p_r,
        "p_t": point.p_t,
        "f_c": point.f_c,
        "phi": point.phi,
        "seed": point.seed,
        "theta": theta,
        "sample": k,
        "point_key": spec.point_key(point),
    }


def grid_chunk(spec: Spec, point: GridPoint, samples: list[int]) -> pd.DataFrame:
    """Solve samples at one grid point (grid mode).

    Parameters
    ----------
    spec : Spec
        The sweep.
    point : GridPoint
        The grid point.
    samples : list of int
        Sample indices, 1-based.

    Returns
    -------
    pandas.DataFrame
        One row per sample: :func:`key_columns`, then
        :func:`~tensegrity_rigidity.analysis.observables.sample_record` (or the paper's
        verdict's record with ``verdict = "paper"``).
    """
    opts = spec.solver_options()
    rows = []
    for k in samples:
        net, u, v, theta = sample_geometry(spec, point, k)
        kinds = place_elements(u, v, point.p_r, point.p_t, point.f_c)
        inst = Instance(net.with_kinds(kinds), sample_strain(spec, point, k, theta, net.dim))
        if spec.verdict == "paper":
            rows.append(key_columns(spec, point, k, theta) | paper_verdict(inst).record())
            continue
        res = solve(inst, opts)
        rows.append(key_columns(spec, point, k, theta) | sample_record(inst, res, spec.gamma))
    return pd.DataFrame(rows)


def threshold_chunk(spec: Spec, point: GridPoint, samples: list[int]) -> pd.DataFrame:
    """Per-sample exact thresholds along the spec's path (threshold mode).

    Parameters
    ----------
    spec : Spec
        The sweep (its ``threshold`` path).
    point : GridPoint
        The grid point (its ``p_r`` is unused).
    samples : list of int
        Sample indices, 1-based.

    Returns
    -------
    pandas.DataFrame
        One row per sample: :func:`key_columns`, ``path``, ``threshold_p_r`` (the estimate,
        NaN if never rigid), ``threshold_p_t``, the interval ``threshold_p_r_low``,
        ``threshold_p_r_high`` (equal unless ``threshold_undecided`` probes on the
        bisection path were undecided; ``threshold_not_resolved`` of them not resolved by the
        search, the others within resolution), ``solves``, ``decided`` (the
        interval is a single event) and ``solve_seconds``. With the ``"pebble"`` method also
        the spanning rigid cluster at the threshold
        (:class:`~tensegrity_rigidity.combinatorics.clusters.SpanningCluster`): its bond sites
        ``cluster_sites`` and nodes ``cluster_nodes``, and those of its stressed
        (overconstrained) part, ``stressed_sites`` and ``stressed_nodes``, and its
        load-carrying backbone (the threshold bond's component in the rigidity matroid),
        ``backbone_sites`` and ``backbone_nodes`` (0 when never rigid). Every row also counts
        the ``sites`` of its lattice and the elements just after its threshold,
        ``threshold_rods`` and ``threshold_one_sided`` (NaN when never rigid:
        :func:`~tensegrity_rigidity.ensemble.thresholds.elements_at`).
    """
    assert spec.threshold is not None, "threshold_chunk needs a threshold spec"
    opts = spec.solver_options()
    path = spec.threshold["path"]
    method = spec.threshold.get("method", "lp")
    rows = []
    for k in samples:
        net, u, v, theta = sample_geometry(spec, point, k)
        start = time.perf_counter()
        strain = sample_strain(spec, point, k, theta, net.dim)
        extra = {}
        if method == "pebble":
            th, cl = pebble_pass(net, u, v, point.p_t, point.f_c, path)
            extra = {
                "cluster_sites": int(cl.sites.size),
                "cluster_nodes": cl.nodes,
                "stressed_sites": int(cl.stressed.sum()),
                "stressed_nodes": cl.stressed_nodes,
                "backbone_sites": int(cl.backbone.sum()),
                "backbone_nodes": cl.backbone_nodes,
            }
        else:
            th = find_threshold(net, u, v, strain, point.p_t, point.f_c, path, opts, method)
        rods, one_sided = elements_at(u, th.s, point.p_t, path)
        rows.append(
            key_columns(spec, point, k, theta)
            | {
                "path": path,
                "threshold_p_r": th.s,
                "threshold_p_t": th.p_t,
                "threshold_p_r_low": th.s_low,
                "threshold_p_r_high": th.s_high,
                "threshold_undecided": th.undecided,
                "threshold_not_resolved": th.not_resolved,
                "solves": th.solves,
                "decided": th.decided,
                "solve_seconds": time.perf_counter() - start,
                "sites": net.n_sites,
                "threshold_rods": rods,
                "threshold_one_sided": one_sided,
            }
            | extra
        )
    return pd.DataFrame(rows)


def packing_chunk(spec: Spec, point: GridPoint, samples: list[int]) -> pd.DataFrame:
    """Random soft packings at one grid point, each tested for jamming (packing mode).

    Parameters
    ----------
    spec : Spec
        The sweep (its ``packing`` section: dimension and diameter ratio).
    point : GridPoint
        The grid point (its ``n``, ``fraction`` and ``seed``).
    samples : list of int
        Sample indices, 1-based.

    Returns
    -------
    pandas.DataFrame
        One row per sample: ``n``, ``fraction``, ``seed``, ``theta`` (0), ``sample``,
        ``point_key``, then :func:`~tensegrity_rigidity.ensemble.jamming.packing_record`.
    """
    assert spec.packing is not None, "packing_chunk needs a packing spec"
    rows = []
    for k in samples:
        key = {"n": point.n, "fraction": point.fraction, "seed": point.seed, "theta": 0.0,
               "sample": k, "point_key": spec.point_key(point)}  # fmt: skip
        rows.append(key | packing_record(point.n, point.fraction, k, point.seed,
                                         spec.packing["dim"], spec.packing["ratio"]))  # fmt: skip
    return pd.DataFrame(rows)


def run_chunk(spec: Spec, point: GridPoint, samples: list[int]) -> pd.DataFrame:
    """Compute one chunk: what executors run.

    Parameters
    ----------
    spec : Spec
        The sweep.
    point : GridPoint
        The grid point.
    samples : list of int
        Sample indices, 1-based.

    Returns
    -------
    pandas.DataFrame
        :func:`threshold_chunk`, :func:`packing_chunk` or :func:`grid_chunk`, by the spec's
        mode.
    """
    fn = {"threshold": threshold_chunk, "packing": packing_chunk}.get(spec.mode, grid_chunk)
    return fn(spec, point, samples)
