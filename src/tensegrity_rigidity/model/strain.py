"""Metric strains of the supplement: eps(phi, theta) = A(theta) diag(cos phi + sin phi,
cos phi - sin phi) A(-theta), times a magnitude gamma.

``phi = 0`` is dilation, ``pi/2`` pure shear, ``pi`` compression; ``theta`` rotates the principal
axes. Run ``k`` (1-based) of ``eta`` uses ``theta = 2 pi (k - 1) / eta``.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError

#: Named strain types and their phi.
NAMED_STRAINS = {"dilation": 0.0, "shear": math.pi / 2, "compression": math.pi}


def parse_phi(phi: float | str) -> float:
    """phi as a float; accepts the names "dilation", "shear", "compression"."""
    if isinstance(phi, str):
        key = phi.strip().lower()
        if key in NAMED_STRAINS:
            return NAMED_STRAINS[key]
        try:
            phi = float(key)
        except ValueError:
            names = ", ".join(NAMED_STRAINS)
            raise InputError(f"phi must be a number or one of {names}; got {phi!r}") from None
    value = float(phi)
    if not math.isfinite(value):
        raise InputError(f"phi must be finite, got {value}")
    return value


def rotation(theta: float) -> np.ndarray:
    """A(theta), the 2x2 rotation by theta."""
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s], [s, c]])


def strain_tensor(phi: float | str, theta: float = 0.0, gamma: float = 1.0) -> np.ndarray:
    """The symmetric strain tensor gamma * eps(phi, theta), shape (2, 2)."""
    phi = parse_phi(phi)
    theta, gamma = float(theta), float(gamma)
    if not (math.isfinite(theta) and math.isfinite(gamma)):
        raise InputError("theta and gamma must be finite")
    if gamma <= 0:
        raise InputError(f"gamma must be positive, got {gamma}")
    eps0 = np.diag([math.cos(phi) + math.sin(phi), math.cos(phi) - math.sin(phi)])
    a = rotation(theta)
    eps = gamma * (a @ eps0 @ a.T)
    return 0.5 * (eps + eps.T)


def run_angle(k: int, eta: int) -> float:
    """theta of run k (1-based) out of eta runs: 2 pi (k - 1) / eta."""
    if eta < 1 or not 1 <= k <= eta:
        raise InputError(f"need 1 <= k <= eta, got k={k}, eta={eta}")
    return 2.0 * math.pi * (k - 1) / eta
