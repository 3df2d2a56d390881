"""Observables of one relaxed sample: nonaffinity, engaged fractions, element counts.

Nonaffinity (Broedersz et al., the paper's Gamma)::

    Gamma = sum_i |u_na,i|^2 / (l^2 gamma^2 N)

with ``u_na`` the displacements relative to the affine deformation (what :func:`solve` returns:
the minimum-norm minimiser, mean translation removed), ``l`` the mean length over all bond sites
of the network, ``gamma`` the strain magnitude (the spectral norm of eps: for
``eps(phi, theta)`` of the supplement that is gamma * max(|cos phi + sin phi|, |cos phi - sin phi|),
so we divide by the tensor's own norm, ``gamma_eff``) and ``N = n^2`` the number of nodes.
"""

from __future__ import annotations

import numpy as np

from ..model.network import Element, Instance
from ..solver.core import SolveResult


def strain_magnitude(strain: np.ndarray) -> float:
    """Spectral norm of the strain tensor (largest |eigenvalue|)."""
    return float(np.abs(np.linalg.eigvalsh(np.asarray(strain, dtype=float))).max())


def nonaffinity(instance: Instance, result: SolveResult, gamma: float | None = None) -> float:
    """Gamma = sum_i |u_i|^2 / (l^2 gamma^2 N); gamma defaults to the strain's spectral norm."""
    net = instance.network
    g = strain_magnitude(instance.strain) if gamma is None else float(gamma)
    if g == 0:
        return 0.0
    ell = float(net.bond_lengths().mean())
    u = result.displacements
    return float(np.sum(u * u) / (ell**2 * g**2 * net.n_nodes))


def engaged_fractions(instance: Instance, result: SolveResult) -> tuple[float, float]:
    """Fractions of cables under tension (t > 0) and of struts under compression (t < 0).

    NaN when the network has no cable (respectively no strut).
    """
    kinds, t = instance.network.kinds, result.tensions
    cab, stru = kinds == Element.CABLE, kinds == Element.STRUT
    fc = float(np.mean(t[cab] > 0)) if cab.any() else float("nan")
    fs = float(np.mean(t[stru] < 0)) if stru.any() else float("nan")
    return fc, fs


def sample_record(instance: Instance, result: SolveResult, gamma: float | None = None) -> dict:
    """The per-sample scalars stored by sweeps.

    ``nonaffinity`` is computed from the minimum-norm displacements and is NaN where
    ``min_norm_ok`` is False (no wrong number in its place).
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
        "solve_seconds": float(result.seconds),
    }
