"""Observables of one relaxed sample: nonaffinity, engaged fractions, element counts.

Nonaffinity (Broedersz et al., the paper's Gamma)::

    Gamma = sum_i |u_na,i|^2 / (l^2 gamma^2 N)

with ``u_na`` the displacements relative to the affine deformation (what
:func:`~tensegrity_rigidity.solve` returns: the minimum-norm minimiser, mean translation
removed), ``l`` the mean length over all bond sites of the network, ``gamma`` the strain
magnitude (the spectral norm of eps: for ``eps(phi, theta)`` of the supplement that is
``gamma max(|cos phi + sin phi|, |cos phi - sin phi|)``, so we divide by the tensor's own norm,
``gamma_eff``) and ``N = n^2`` the number of nodes.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..model.network import Element, Instance, check_real
from ..solver.core import SolveResult


def strain_magnitude(strain: np.ndarray) -> float:
    """Spectral norm of the strain tensor (its largest absolute eigenvalue).

    Parameters
    ----------
    strain : (d, d) float
        Symmetric strain tensor.

    Returns
    -------
    float
        ``max |lambda|``: for ``strain_tensor(phi, theta, gamma)`` that is
        ``gamma max(|cos phi + sin phi|, |cos phi - sin phi|)``.
    """
    return float(np.abs(np.linalg.eigvalsh(np.asarray(strain, dtype=float))).max())


def nonaffinity(instance: Instance, result: SolveResult, gamma: float | None = None) -> float:
    """The nonaffinity ``Gamma = sum_i |u_i|^2 / (l^2 gamma^2 N)`` of a solved sample.

    Parameters
    ----------
    instance : Instance
        The sample (``N`` nodes); ``l`` is its mean bond length over all sites.
    result : SolveResult
        Its solution: ``displacements`` (N, d) are the nonaffine displacements (the
        minimum-norm minimiser, mean translation removed; check ``result.min_norm_ok``).
    gamma : float, optional
        Strain magnitude; by default the strain tensor's spectral norm
        (:func:`strain_magnitude`).

    Returns
    -------
    float
        Gamma (0 when ``gamma`` is 0).

    Notes
    -----
    On a floppy sample the minimisers are not unique; the minimum-norm one is the limit of a
    vanishing background stiffness. Near the transition Gamma is heavy-tailed over samples:
    report medians and quantiles beside means.
    """
    _check_pair(instance, result)
    u = result.displacements
    return _per_node_strain(instance, float(np.sum(u * u)), gamma)


def nonaffinity_lower(instance: Instance, result: SolveResult, gamma: float | None = None) -> float:
    """A certified lower bound on the nonaffinity of the minimum-norm minimiser.

    Parameters
    ----------
    instance : Instance
        The sample.
    result : SolveResult
        Its solution (``min_norm_lower``).
    gamma : float, optional
        Strain magnitude, as for :func:`nonaffinity`.

    Returns
    -------
    float
        Gamma itself where ``result.min_norm_ok``; where the projection ran but was not
        certified (near a sample's own threshold), the bound from its multipliers; NaN where
        no projection ran.
    """
    _check_pair(instance, result)
    return _per_node_strain(instance, float(result.min_norm_lower), gamma)


def _check_pair(instance: Instance, result: SolveResult) -> None:
    """Refuse a result that is not a solve of ``instance`` (its displacements' shape)."""
    if not isinstance(instance, Instance) or not isinstance(result, SolveResult):
        raise InputError("nonaffinity takes an Instance and the SolveResult of solve(instance)")
    net = instance.network
    if np.shape(result.displacements) != (net.n_nodes, net.dim):
        raise InputError(
            f"the result's displacements have shape {np.shape(result.displacements)}, not the "
            f"instance's ({net.n_nodes}, {net.dim}): pass the result of solve(instance)"
        )


def _per_node_strain(instance: Instance, squares: float, gamma: float | None) -> float:
    """``squares / (l^2 gamma^2 N)`` (0 when the strain magnitude is 0): :func:`nonaffinity`
    of displacements whose squares sum to ``squares``."""
    net = instance.network
    g = strain_magnitude(instance.strain) if gamma is None else check_real("gamma", gamma)
    if g == 0:
        return 0.0
    ell = float(net.bond_lengths().mean())
    return float(squares / (ell**2 * g**2 * net.n_nodes))


def engaged_fractions(instance: Instance, result: SolveResult) -> tuple[float, float]:
    """Fractions of cables under tension (t > 0) and of struts under compression (t < 0).

    Parameters
    ----------
    instance : Instance
        The sample.
    result : SolveResult
        Its solution (``tensions`` (m,)).

    Returns
    -------
    cables, struts : float
        Engaged fractions; NaN when the network has no cable (respectively no strut).
    """
    kinds, t = instance.network.kinds, result.tensions
    cab, stru = kinds == Element.CABLE, kinds == Element.STRUT
    fc = float(np.mean(t[cab] > 0)) if cab.any() else float("nan")
    fs = float(np.mean(t[stru] < 0)) if stru.any() else float("nan")
    return fc, fs


def sample_record(instance: Instance, result: SolveResult, gamma: float | None = None) -> dict:
    """The per-sample scalars stored by sweeps (one row of a grid sweep, after its keys).

    Parameters
    ----------
    instance : Instance
        The sample.
    result : SolveResult
        Its solution.
    gamma : float, optional
        Strain magnitude for the nonaffinity (:func:`nonaffinity`).

    Returns
    -------
    dict
        ``rigid``, ``decided``, ``energy``, ``energy_lower``, ``affine_energy``,
        ``nonaffinity``, ``min_norm_ok``, ``frac_cables_taut``, ``frac_struts_taut``,
        ``n_rods``, ``n_cables``, ``n_struts``, the certificate's ``work``,
        ``force_residual``, ``violation``, ``displacement_size``, and ``iterations``,
        ``factorizations``, ``method``, ``undecided_reason`` ("" when decided,
        else "within resolution" or "not resolved"), ``solve_seconds``. ``nonaffinity`` is NaN where
        ``min_norm_ok`` is False (no wrong number in its place); ``nonaffinity_lower``
        (:func:`nonaffinity_lower`) is the nonaffinity where it is certified and a certified
        lower bound on it where the projection ran but was not certified (NaN where none
        ran), so that such samples are bracketed, not dropped.
    """
    fc, fs = engaged_fractions(instance, result)
    kinds = instance.network.kinds
    gamma_value = nonaffinity(instance, result, gamma) if result.min_norm_ok else float("nan")
    return {
        "rigid": bool(result.rigid),
        "decided": bool(result.decided),
        "energy": float(result.energy),
        "energy_lower": float(result.energy_lower),
        "affine_energy": float(result.affine_energy),
        "nonaffinity": gamma_value,
        "nonaffinity_lower": nonaffinity_lower(instance, result, gamma),
        "min_norm_ok": bool(result.min_norm_ok),
        "frac_cables_taut": fc,
        "frac_struts_taut": fs,
        "n_rods": int(np.count_nonzero(kinds == Element.ROD)),
        "n_cables": int(np.count_nonzero(kinds == Element.CABLE)),
        "n_struts": int(np.count_nonzero(kinds == Element.STRUT)),
        "work": float(result.work),
        "force_residual": float(result.force_residual),
        "violation": float(result.violation),
        "displacement_size": float(result.displacement_size),
        "iterations": int(result.iterations),
        "factorizations": int(result.factorizations),
        "method": result.method,
        "undecided_reason": result.reason,
        "solve_seconds": float(result.seconds),
    }
