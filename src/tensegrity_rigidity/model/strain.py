"""Metric strains of the supplement: eps(phi, theta) = A(theta) diag(cos phi + sin phi,
cos phi - sin phi) A(-theta), times a magnitude gamma.

``phi = 0`` is dilation, ``pi/2`` pure shear, ``pi`` compression; ``theta`` rotates the principal
axes. The paper's run ``k`` (1-based) of ``eta`` uses ``theta = 2 pi (k - 1) / eta``
(:func:`run_angle`); sweeps default to a golden-angle sequence that does not depend on the
number of samples (:func:`tensegrity_rigidity.ensemble.spec.strain_angle`).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from .limits import check_gamma

#: Named strain types and their phi.
NAMED_STRAINS = {"dilation": 0.0, "shear": math.pi / 2, "compression": math.pi}


def parse_phi(phi: float | str) -> float:
    """The strain type phi as a float.

    Parameters
    ----------
    phi : float or str
        An angle (radians, or its text), or one of the names "dilation" (0), "shear" (pi/2),
        "compression" (pi), in any case.

    Returns
    -------
    float
        phi.

    Raises
    ------
    InputError
        On an unknown name or a non-finite value.
    """
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
    """The rotation A(theta).

    Parameters
    ----------
    theta : float
        Angle, radians.

    Returns
    -------
    (2, 2) float
        ``[[cos, -sin], [sin, cos]]``.
    """
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s], [s, c]])


def strain_tensor(phi: float | str, theta: float = 0.0, gamma: float = 1.0) -> np.ndarray:
    """The symmetric strain tensor ``gamma eps(phi, theta)`` of the supplement.

    Parameters
    ----------
    phi : float or str
        Strain type (:func:`parse_phi`): 0 dilation, pi/2 shear, pi compression.
    theta : float
        Angle of the principal axes, radians.
    gamma : float
        Magnitude, positive.

    Returns
    -------
    (2, 2) float
        ``gamma A(theta) diag(cos phi + sin phi, cos phi - sin phi) A(-theta)``, symmetric.

    Raises
    ------
    InputError
        On a non-finite angle, or a magnitude outside
        :data:`~tensegrity_rigidity.model.limits.GAMMA_RANGE`.

    Examples
    --------
    >>> from tensegrity_rigidity import strain_tensor
    >>> strain_tensor("dilation")
    array([[1., 0.],
           [0., 1.]])
    """
    phi = parse_phi(phi)
    theta, gamma = float(theta), float(gamma)
    if not math.isfinite(theta):
        raise InputError("theta must be finite")
    gamma = check_gamma(gamma)
    eps0 = np.diag([math.cos(phi) + math.sin(phi), math.cos(phi) - math.sin(phi)])
    a = rotation(theta)
    eps = gamma * (a @ eps0 @ a.T)
    return 0.5 * (eps + eps.T)


def run_angle(k: int, eta: int) -> float:
    """The paper's principal-axis angle of run k (1-based) out of eta: 2 pi (k - 1) / eta.

    Parameters
    ----------
    k : int
        Run, ``1 <= k <= eta``.
    eta : int
        Number of runs.

    Returns
    -------
    float
        theta, radians.

    Raises
    ------
    InputError
        When ``k`` is out of range.
    """
    if eta < 1 or not 1 <= k <= eta:
        raise InputError(f"need 1 <= k <= eta, got k={k}, eta={eta}")
    return 2.0 * math.pi * (k - 1) / eta
