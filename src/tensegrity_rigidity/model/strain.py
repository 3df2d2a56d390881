"""Metric strains of the supplement: eps(phi, theta) = A(theta) diag(cos phi + sin phi,
cos phi - sin phi) A(-theta), times a magnitude gamma; in 3D eps(phi) = Q (cos phi I + sin phi
diag(1, -1, 0)) Q^T with a rotation Q.

``phi = 0`` is dilation, ``pi/2`` pure shear (in 3D volume-preserving, one axis neutral),
``pi`` compression; ``theta`` (or ``Q``) rotates the principal axes. Sweeps in 3D draw Q from a
low-discrepancy sequence on SO(3) that does not depend on the number of samples
(:func:`sequence_rotation`). The paper's run ``k`` (1-based) of ``eta`` uses
``theta = 2 pi (k - 1) / eta`` (:func:`run_angle`); sweeps default to a golden-angle
sequence that does not depend on the number of samples
(:func:`tensegrity_rigidity.ensemble.spec.strain_angle`).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from .limits import check_gamma
from .network import check_real, show

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
            raise InputError(f"phi must be a number or one of {names}; got {show(phi)}") from None
    return check_real("phi", phi)


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


def strain_tensor(
    phi: float | str,
    theta: float = 0.0,
    gamma: float = 1.0,
    rotation_matrix: np.ndarray | None = None,
    dim: int | None = None,
) -> np.ndarray:
    """The symmetric strain tensor ``gamma eps(phi, theta)`` of the supplement, in 2D or 3D.

    Parameters
    ----------
    phi : float or str
        Strain type (:func:`parse_phi`): 0 dilation, pi/2 shear, pi compression.
    theta : float
        Angle of the principal axes in 2D, radians. A nonzero ``theta`` is refused in 3D and
        beside ``rotation_matrix``, which set the axes there (it would be ignored).
    gamma : float
        Magnitude, positive.
    rotation_matrix : (d, d) float, optional
        The principal axes as a rotation Q (orthogonal, determinant +1); its shape sets the
        dimension.
    dim : int, optional
        2 or 3 (default: that of ``rotation_matrix``, else 2); in 3D without a rotation the
        principal axes are the coordinate axes.

    Returns
    -------
    (d, d) float
        ``gamma Q (cos phi I + sin phi diag(1, -1[, 0])) Q^T``, symmetric; in 2D with
        ``Q = A(theta)`` this is ``gamma A(theta) diag(cos phi + sin phi, cos phi - sin phi)
        A(-theta)``.

    Raises
    ------
    InputError
        On a non-finite angle, a magnitude outside
        :data:`~tensegrity_rigidity.model.limits.GAMMA_RANGE`, a dimension other than 2 or 3,
        or a nonzero ``theta`` where the rotation sets the axes.

    Examples
    --------
    >>> from tensegrity_rigidity import strain_tensor
    >>> strain_tensor("dilation")
    array([[1., 0.],
           [0., 1.]])
    """
    phi = parse_phi(phi)
    theta = check_real("theta", theta)
    gamma = check_gamma(gamma)
    if dim is not None and not (
        isinstance(dim, (int, np.integer)) and not isinstance(dim, bool) and dim in (2, 3)
    ):
        raise InputError(f"dim must be 2 or 3, got {show(dim)}")
    if theta != 0 and dim == 3:
        raise InputError(
            f"theta = {theta:g} is an angle of 2D axes and would be ignored in 3D: give the "
            "axes as rotation_matrix (e.g. sequence_rotation(k)) and leave theta at 0"
        )
    if theta != 0 and rotation_matrix is not None:
        raise InputError(
            f"theta = {theta:g} and rotation_matrix both set the principal axes (theta would be "
            "ignored): give one of them"
        )
    if rotation_matrix is not None:
        a = check_rotation(rotation_matrix)
        if dim is not None and a.shape[0] != dim:
            raise InputError(f"rotation_matrix has shape {a.shape}, not ({dim}, {dim})")
    elif dim in (None, 2):
        a = rotation(theta)
    else:
        a = np.eye(3)
    if a.shape[0] == 2:
        eps0 = np.diag([math.cos(phi) + math.sin(phi), math.cos(phi) - math.sin(phi)])
    else:
        eps0 = math.cos(phi) * np.eye(3) + math.sin(phi) * np.diag([1.0, -1.0, 0.0])
    eps = gamma * (a @ eps0 @ a.T)
    return 0.5 * (eps + eps.T)


def check_rotation(q) -> np.ndarray:
    """Validate a rotation matrix: finite, (2, 2) or (3, 3), orthogonal to ``1e-10``, proper.

    Parameters
    ----------
    q : (d, d) array_like
        The matrix.

    Returns
    -------
    (d, d) float
        A float copy.

    Raises
    ------
    InputError
        When ``q`` is not a proper rotation.
    """
    try:
        a = np.array(q, dtype=float)
    except (TypeError, ValueError, OverflowError) as exc:
        raise InputError(f"rotation_matrix must be a numeric array ({exc})") from None
    if a.ndim != 2 or a.shape[0] != a.shape[1] or a.shape[0] not in (2, 3):
        raise InputError(f"rotation_matrix must have shape (2, 2) or (3, 3), got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InputError("rotation_matrix contains NaN or infinite values")
    if np.abs(a @ a.T - np.eye(a.shape[0])).max() > 1e-10 or np.linalg.det(a) < 0:
        raise InputError("rotation_matrix must be a rotation (orthogonal, determinant +1)")
    return a


#: The additive steps of the 3D Kronecker sequence behind :func:`sequence_rotation`: the powers
#: ``1 / g, 1 / g^2, 1 / g^3`` of the real root ``g = 1.2207...`` of ``x^4 = x + 1`` (Roberts'
#: generalised golden ratio in three dimensions), whose multiples modulo 1 fill the unit cube
#: with low discrepancy for every sample count.
_R3_ROOT = 1.2207440846057596
R3_STEPS = tuple(_R3_ROOT ** -(i + 1) for i in range(3))


def sequence_rotation(k: int) -> np.ndarray:
    """Rotation ``k`` (1-based) of a low-discrepancy sequence on SO(3).

    The point ``frac(k R3_STEPS)`` of the unit cube is mapped to a unit quaternion by
    Shoemake's volume-preserving map (uniform points give rotations uniform on SO(3), "Uniform
    random rotations", Graphics Gems III, 1992), so the first ``K`` rotations cover SO(3)
    evenly for every ``K``: the 3D counterpart of the golden angles, independent of the
    sample count.

    Parameters
    ----------
    k : int
        Index, at least 1.

    Returns
    -------
    (3, 3) float
        A proper rotation.
    """
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not 1 <= k <= 2**53:
        raise InputError(
            f"the rotation index must be a positive integer up to 2^53 (beyond, k times "
            f"the sequence's steps loses its digits), got {show(k)}"
        )
    u1, u2, u3 = (math.fmod(k * step, 1.0) for step in R3_STEPS)
    a, b = math.sqrt(1.0 - u1), math.sqrt(u1)
    w, x = a * math.sin(2 * math.pi * u2), a * math.cos(2 * math.pi * u2)
    y, z = b * math.sin(2 * math.pi * u3), b * math.cos(2 * math.pi * u3)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


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
