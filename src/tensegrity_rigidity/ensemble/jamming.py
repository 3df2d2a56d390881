"""The sample loop of the jamming study: random bidisperse packings at each size and packing
fraction, each tested for collective and strict jamming, one row per sample.

A sample is a soft packing (:func:`~tensegrity_rigidity.model.softdisks.soft_packing`) drawn from
``numpy.random.default_rng([seed, n, round(phi * 1e6), sample])``, so adding sizes, fractions or
samples keeps every row already drawn; its contacts are its overlapping pairs, tested by
:func:`~tensegrity_rigidity.solver.jamming.jamming`. Undecided samples are rows like any other
(``collective`` / ``strict`` = "undecided", with the reason), never dropped.
:func:`estimate_cost` prices a run from the per-sample costs measured by
``benchmarks/bench_jamming.py`` (``ensemble/data/jamming_costs.json``).
"""

from __future__ import annotations

import json
import os
import time
from concurrent.futures import ProcessPoolExecutor
from importlib import resources

import numpy as np
import pandas as pd

from ..errors import InputError
from ..model.softdisks import DIAMETER_RATIO, soft_packing
from ..solver.jamming import JammingOptions, jamming
from .spec import fraction_key

#: Columns of a study row.
COLUMNS = (
    "n", "dim", "phi", "sample", "energy", "force", "steps", "rattlers", "contacts",
    "backbone_contacts", "isostatic_contacts", "collective", "collective_reason", "strict",
    "strict_reason", "seconds_packing", "seconds_test",
)  # fmt: skip


def sample_rng(seed: int, n: int, phi: float, sample: int) -> np.random.Generator:
    """The generator of one sample: a function of ``(seed, n, phi, sample)`` only.

    Parameters
    ----------
    seed : int
        Root seed of the study.
    n : int
        Particles.
    phi : float
        Packing fraction (rounded to 1e-6).
    sample : int
        Sample index.

    Returns
    -------
    numpy.random.Generator
        ``default_rng([seed, n, round(phi 1e6), sample])``.
    """
    return np.random.default_rng([int(seed), int(n), fraction_key(phi), int(sample)])


def jamming_row(
    n: int,
    phi: float,
    sample: int,
    seed: int = 0,
    dim: int = 2,
    ratio: float = DIAMETER_RATIO,
    options: JammingOptions | None = None,
) -> dict:
    """Draw, minimise and test one packing.

    Parameters
    ----------
    n : int
        Particles.
    phi : float
        Packing fraction.
    sample : int
        Sample index.
    seed : int
        Root seed (:func:`sample_rng`).
    dim : int
        2 or 3.
    ratio : float
        Diameter ratio.
    options : JammingOptions, optional
        The tests' resolution.

    Returns
    -------
    dict
        The :data:`COLUMNS` of one row: the packing's energy per particle, largest force and FIRE
        steps, the rattlers and contact counts, the collective and strict statuses with their
        undecided reasons, and the seconds spent on the packing and on both tests (CPU time).
    """
    t0 = time.process_time()
    sp = soft_packing(n, phi, sample_rng(seed, n, phi, sample), dim=dim, ratio=ratio)
    t1 = time.process_time()
    net = sp.packing.contact_network(tolerance=0.0)
    coll = jamming(net, "collective", options)
    strict = jamming(net, "strict", options)
    t2 = time.process_time()
    return {
        "n": n, "dim": dim, "phi": float(phi), "sample": sample, "energy": sp.energy,
        "force": sp.gradient, "steps": sp.iterations, "rattlers": coll.n_rattlers,
        "contacts": coll.n_contacts, "backbone_contacts": coll.backbone_contacts,
        "isostatic_contacts": coll.isostatic_contacts, "collective": coll.status,
        "collective_reason": coll.reason, "strict": strict.status, "strict_reason": strict.reason,
        "seconds_packing": t1 - t0, "seconds_test": t2 - t1,
    }  # fmt: skip


#: Columns of a packing sweep's row after its key columns (:func:`packing_record`).
RECORD = (*(c for c in COLUMNS if c not in ("n", "phi", "sample")), "decided", "undecided_reason")


def packing_record(
    n: int, fraction: float, sample: int, seed: int, dim: int = 2, ratio: float = DIAMETER_RATIO
) -> dict:
    """One sample of a packing sweep (``[packing]`` mode of the sweep engine): its record after
    the key columns.

    Parameters
    ----------
    n, fraction, sample, seed, dim, ratio
        As :func:`jamming_row` (``fraction``: its ``phi``).

    Returns
    -------
    dict
        The :data:`RECORD` columns: :func:`jamming_row`'s record, with ``decided`` (the
        collective test decided: an undecided sample is kept, counted and reported by the
        studies, never dropped silently) and ``undecided_reason`` (its reason, "" if decided).
    """
    row = jamming_row(n, fraction, sample, seed, dim, ratio)
    return {key: row[key] for key in RECORD[:-2]} | {
        "decided": row["collective"] != "undecided",
        "undecided_reason": row["collective_reason"],
    }


def _row(args) -> dict:
    return jamming_row(*args)


def jamming_samples(
    sizes,
    phis,
    samples: int,
    seed: int = 0,
    dim: int = 2,
    workers: int = 1,
    progress: bool = True,
) -> pd.DataFrame:
    """Every sample of a jamming study.

    Parameters
    ----------
    sizes : sequence of int
        Particle numbers N.
    phis : sequence of float
        Packing fractions.
    samples : int
        Samples per (N, phi).
    seed : int
        Root seed of :func:`sample_rng`.
    dim : int
        2 or 3.
    workers : int
        Processes (1: in this process).
    progress : bool
        Show a progress bar with the time left (tqdm, on stderr).

    Returns
    -------
    pandas.DataFrame
        One row per sample (:data:`COLUMNS`), sorted by ``(n, phi, sample)``.
    """
    sizes = [int(n) for n in sizes]
    phis = [float(p) for p in phis]
    if not sizes or not phis or samples < 1:
        raise InputError("a jamming study needs sizes, packing fractions and samples >= 1")
    if workers < 1:
        raise InputError(f"workers must be at least 1, got {workers}")
    # the largest systems first, so that the pool ends on small ones
    tasks = [(n, phi, k, seed, dim) for n in sorted(sizes, reverse=True) for phi in phis
             for k in range(samples)]  # fmt: skip
    from tqdm import tqdm

    bar = tqdm(total=len(tasks), disable=not progress, desc="jamming samples", unit="sample")
    rows = []
    if workers == 1:
        for t in tasks:
            rows.append(_row(t))
            bar.update()
    else:
        with ProcessPoolExecutor(workers) as pool:
            for row in pool.map(_row, tasks, chunksize=1):
                rows.append(row)
                bar.update()
    bar.close()
    frame = pd.DataFrame(rows, columns=list(COLUMNS))
    return frame.sort_values(["n", "phi", "sample"], ignore_index=True)


def load_costs() -> dict:
    """The per-sample cost model measured by ``benchmarks/bench_jamming.py``.

    Returns
    -------
    dict
        Per dimension, for the packing and for the two tests, ``seconds = a N^b`` (``{"2":
        {"packing": [a, b], "tests": [a, b]}, ...}``), and ``measured``: where and when.
    """
    text = resources.files("tensegrity_rigidity.ensemble").joinpath("data/jamming_costs.json")
    return json.loads(text.read_text())


def sample_seconds(n: int, dim: int = 2) -> float:
    """CPU seconds of one sample at ``n`` particles: its packing and both tests, from the
    measured costs (:func:`load_costs`).

    Parameters
    ----------
    n : int
        Particles.
    dim : int
        2 or 3.

    Returns
    -------
    float
        ``a_p n^b_p + a_t n^b_t``: the minimisation's and the tests' power laws.
    """
    model = load_costs().get(str(dim))
    if model is None:
        raise InputError(f"no measured costs for dim = {dim}")
    return float(sum(a * float(n) ** b for a, b in (model["packing"], model["tests"])))


def estimate_cost(sizes, phis, samples: int, dim: int = 2, workers: int = 1) -> dict:
    """What a jamming study costs, from the measured per-sample costs (:func:`load_costs`).

    Parameters
    ----------
    sizes, phis, samples, dim
        As :func:`jamming_samples`.
    workers : int
        Processes sharing the work.

    Returns
    -------
    dict
        ``cpu_seconds`` (total), ``wall_seconds`` (the CPU time over ``workers``, the largest
        sample as a floor), ``per_size`` (N -> CPU seconds), ``samples`` (count) and ``model``
        (the constants used and where they come from).
    """
    costs = load_costs()
    model = costs.get(str(dim))
    if model is None:
        raise InputError(f"no measured costs for dim = {dim}")
    per_size = {}
    largest = 0.0
    for n in sizes:
        one = sample_seconds(n, dim)
        per_size[int(n)] = one * len(phis) * samples
        largest = max(largest, one)
    cpu = float(sum(per_size.values()))
    return {
        "cpu_seconds": cpu,
        "wall_seconds": max(cpu / max(workers, 1), largest),
        "per_size": per_size,
        "samples": len(list(sizes)) * len(list(phis)) * samples,
        "model": {"dim": dim, **model, "measured": costs.get("measured", "")},
    }


def default_workers() -> int:
    """Processes to use.

    Returns
    -------
    int
        The CPUs this process may run on.
    """
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else 1
