"""The bootstrap over samples, and the estimate type of every estimator.

One helper draws every replica (:func:`replicas`): rows, or groups of rows that are one
independent unit (a sample under several strains), redrawn with replacement from a generator
the caller passes in (a scale's :meth:`~tensegrity_rigidity.paper.study.Scale.rng`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np


def resampler(n_rows: int, groups=None, rng: np.random.Generator | None = None):
    """A function returning the row indices of one bootstrap replica.

    Parameters
    ----------
    n_rows : int
        Rows of the data.
    groups : (n_rows,) array, optional
        Label of each row's independent unit. Rows of one unit are drawn together (a cluster
        bootstrap): the same sample measured under several strains is one unit, not several.
        Without it every row is a unit.
    rng : numpy.random.Generator, optional
        Source of the draws.

    Returns
    -------
    callable
        ``draw()`` -> (R,) int row indices of a replica (``R = n_rows`` without groups, and
        with groups of equal size). Without groups a draw is ``rng.integers(0, n_rows,
        n_rows)``, exactly the rows the estimators drew before groups existed.
    """
    rng = rng or np.random.default_rng(0)
    if groups is None:
        return lambda: rng.integers(0, n_rows, n_rows)
    labels = np.asarray(groups)
    if labels.shape != (n_rows,):
        raise ValueError(f"groups has shape {labels.shape}, expected ({n_rows},)")
    _, unit = np.unique(labels, return_inverse=True)
    order = np.argsort(unit, kind="stable")
    members = np.split(order, np.cumsum(np.bincount(unit))[:-1])
    k = len(members)
    return lambda: np.concatenate([members[i] for i in rng.integers(0, k, k)])


def n_units(n_rows: int, groups=None) -> int:
    """Independent units behind ``n_rows`` rows.

    Parameters
    ----------
    n_rows : int
        Rows of the data.
    groups : (n_rows,) array, optional
        Label of each row's independent unit, as in :func:`resampler`.

    Returns
    -------
    int
        Distinct labels in ``groups``; ``n_rows`` without groups.
    """
    return n_rows if groups is None else int(np.unique(np.asarray(groups)).size)


@dataclass(frozen=True)
class Estimate:
    """A value with its standard error: a derivative of P, a slope, a crossing, a location.

    Attributes
    ----------
    value : float
        The estimate.
    err : float
        Its standard error (NaN where the bootstrap had too few finite replicas).
    """

    value: float
    err: float


def replicas(
    statistic: Callable[[np.ndarray], object],
    n_rows: int,
    n_boot: int,
    rng: np.random.Generator,
    groups=None,
) -> list:
    """A statistic on ``n_boot`` bootstrap replicas of the rows (or of groups of rows).

    Parameters
    ----------
    statistic : callable
        ``statistic(idx)`` -> the estimate on the rows ``idx`` (R,) int of one replica.
    n_rows : int
        Rows of the data.
    n_boot : int
        Replicas.
    rng : numpy.random.Generator
        Source of the draws (the caller's: every estimate is reproducible from its seed).
    groups : (n_rows,) array, optional
        Independent unit of each row (:func:`resampler`).

    Returns
    -------
    list
        The statistic of each replica, in the order drawn.
    """
    draw = resampler(n_rows, groups, rng)
    return [statistic(draw()) for _ in range(n_boot)]
