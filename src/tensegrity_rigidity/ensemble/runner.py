"""Work units of a sweep: a chunk of samples at one grid point, computed anywhere.

These functions are what executors run (a local process, a Dask worker); they take only plain,
picklable arguments and return a pandas DataFrame of rows, one per sample. They write nothing.
"""

from __future__ import annotations

import time

import numpy as np
import pandas as pd

from ..analysis.observables import sample_record
from ..model.elements import place_elements
from ..model.network import Instance
from ..model.sampling import lattice_geometry
from ..model.strain import run_angle, strain_tensor
from ..solver.core import SolverOptions, solve
from ..solver.inexact import paper_verdict
from .spec import GridPoint, Spec
from .thresholds import find_threshold


def sample_rng(point: GridPoint, k: int) -> np.random.Generator:
    """The generator of sample k (1-based) at this point: depends on (seed, n, delta, k) only."""
    delta_bits = int(np.float64(point.delta).view(np.uint64))
    ss = np.random.SeedSequence(point.seed, spawn_key=(point.n, delta_bits, k))
    return np.random.default_rng(ss)


def sample_geometry(spec: Spec, point: GridPoint, k: int):
    """(network, U, V, theta) of sample k at a grid point."""
    net, u, v = lattice_geometry(point.n, point.delta, sample_rng(point, k), spec.lattice)
    return net, u, v, run_angle(k, spec.samples)


def _base(point: GridPoint, k: int, theta: float) -> dict:
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
    }


def grid_chunk(spec: Spec, point: GridPoint, samples: list[int]) -> pd.DataFrame:
    """Solve samples (1-based indices) at one grid point; one row each."""
    opts = spec.solver_options()
    rows = []
    for k in samples:
        net, u, v, theta = sample_geometry(spec, point, k)
        kinds = place_elements(u, v, point.p_r, point.p_t, point.f_c)
        inst = Instance(net.with_kinds(kinds), strain_tensor(point.phi, theta, spec.gamma))
        if spec.verdict == "paper":
            rows.append(_base(point, k, theta) | paper_verdict(inst).record())
            continue
        res = solve(inst, opts)
        rows.append(_base(point, k, theta) | sample_record(inst, res, spec.gamma))
    return pd.DataFrame(rows)


def threshold_chunk(spec: Spec, point: GridPoint, samples: list[int]) -> pd.DataFrame:
    """Per-sample exact thresholds along the spec's path; one row each."""
    opts = SolverOptions(**({"min_norm": False} | spec.solver))
    path = spec.threshold["path"]
    rows = []
    for k in samples:
        net, u, v, theta = sample_geometry(spec, point, k)
        start = time.perf_counter()
        th = find_threshold(
            net, u, v, strain_tensor(point.phi, theta, spec.gamma), point.p_t, point.f_c, path, opts
        )
        rows.append(
            _base(point, k, theta)
            | {
                "path": path,
                "threshold_p_r": th.s,
                "threshold_p_t": th.p_t,
                "solves": th.solves,
                "decided": th.decided,
                "solve_seconds": time.perf_counter() - start,
            }
        )
    return pd.DataFrame(rows)


def run_chunk(spec: Spec, point: GridPoint, samples: list[int]) -> pd.DataFrame:
    """Dispatch on the spec's mode."""
    fn = threshold_chunk if spec.mode == "threshold" else grid_chunk
    return fn(spec, point, samples)
