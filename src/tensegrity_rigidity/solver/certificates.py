"""The two certificates of a verdict and the resolution model that makes them exclude each other.

Units. The affine extensions are measured in units of their largest magnitude over all bond
sites of the instance, ``s0 = max_b |e0_b|`` (a property of the geometry and the strain, the
same for every element configuration of a sample), and displacements in the same units
(``u_n = u / s0``). The verdict does not depend on the strain magnitude, and nothing here can
underflow or overflow with it.

Certificates (MODEL.md, Farkas' lemma):

* **Floppy**: a displacement ``u`` whose extensions ``v = e0 + R u`` lie in the admissible set
  ``Z`` (rods unstretched, cables not stretched, struts not compressed). Its *violation* is
  ``max_b viol_b(v)`` with ``viol = |v|`` on rods, ``max(v, 0)`` on cables, ``max(-v, 0)`` on
  struts, and its *size* is ``max |u_n|``.
* **Rigid**: an admissible self-stress ``t`` (``t >= 0`` on cables, ``<= 0`` on struts, any sign
  on rods, zero on empty sites). Its *work* is ``w = t . e0 / (|t|_1 s0)`` and its *force
  residual* ``r = |R^T t|_1 / |t|_1``.

Resolution model. With a violation tolerance ``tau`` and a displacement bound ``U``
(:class:`Resolution`):

* a floppy certificate is accepted when its violation is at most ``tau`` and its size at most
  ``U``;
* a rigid certificate is accepted when ``w > tau + U r``.

Both can never be accepted for one instance. For any admissible ``t`` and any ``u``,
``t . e0 = t . v - (R^T t) . u_n s0``. An accepted floppy ``u`` has ``t_b v_b <= |t_b| tau s0``
for every ``b`` (the sign of ``t_b`` matches the side on which ``v_b`` may be violated), so
``t . v <= |t|_1 tau s0``, and ``|(R^T t) . u_n| <= |R^T t|_1 U``. Hence ``w <= tau + U r``,
and ``t`` is not accepted. A rigid certificate therefore rules out every zero-energy
displacement smaller than ``(w - tau) / r`` (in units of ``s0``), and a floppy one every
self-stress whose work exceeds what its residual could explain.

Every quantity is evaluated in extended precision (``numpy.longdouble``, a 64-bit mantissa on
x86-64), with the unit bond vectors recomputed from the positions in that precision, so that
the round-off of an evaluation stays far below the tolerances: at most ``1e-18 (1 + 4 U)``
(4e-11 at the default ``U = 1e7``) for a violation, about ``1e-18`` for the normalised work and
residual; these bounds are added to each test (:func:`violation_roundoff`, ``ROUNDOFF``).

An instance with neither certificate is *within resolution of the boundary* (or was not
resolved by the stages tried): it is reported undecided, with both best candidates, never
guessed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Safety margin for the round-off of the extended-precision evaluations of the normalised
#: work and force residual (see the module docstring).
ROUNDOFF = 1e-15


def violation_roundoff(size: float) -> float:
    """Round-off bound of an extended-precision violation at displacements of ``size``
    (units of ``max |e0|``; returns a float in the same units).

    ``v_b = e0_b + dhat_b . (u_j - u_i)`` takes about ten roundings of quantities up to
    ``1 + 4 size`` (unit bond vectors and displacements); ``1e-18`` is ten units in the last
    place of a 64-bit mantissa.
    """
    return 1e-18 * (1.0 + 4.0 * size)


@dataclass(frozen=True)
class Resolution:
    """Tolerances of the resolution model (dimensionless; see the module docstring).

    Attributes
    ----------
    violation : float
        ``tau``: largest violation of a floppy certificate, in units of ``max |e0|``.
    displacement : float
        ``U``: largest displacement of a floppy certificate, in units of ``max |e0|``.
    """

    violation: float = 1e-9
    displacement: float = 1e7


@dataclass(frozen=True)
class FloppyCertificate:
    """A displacement checked against the resolution model.

    Attributes
    ----------
    u : (2N,) float
        Displacements in units of ``max |e0|``.
    violation : float
        Largest violation of ``e0 + R u``, in units of ``max |e0|``.
    size : float
        ``max |u| / max |e0|``.
    accepted : bool
        Whether the certificate passes the resolution model.
    """

    u: np.ndarray
    violation: float
    size: float
    accepted: bool


@dataclass(frozen=True)
class RigidCertificate:
    """An admissible self-stress checked against the resolution model.

    Attributes
    ----------
    t : (m,) float or longdouble
        Tensions on the non-empty sites (signs admissible), in extended precision when
        purification refined them beyond double-precision round-off.
    work : float
        ``t . e0 / (|t|_1 max |e0|)``.
    residual : float
        ``|R^T t|_1 / |t|_1``.
    accepted : bool
        Whether ``work > tau + U residual`` (plus the round-off margin).
    """

    t: np.ndarray
    work: float
    residual: float
    accepted: bool


class ExactGeometry:
    """The rigidity matrix of a problem in extended precision, for certificate checks.

    Parameters
    ----------
    bonds : (m, 2) int
        Node pairs of the non-empty sites.
    d : (m, 2) longdouble
        Bond vectors of those sites, computed in extended precision.
    e0 : (m,) float
        Affine extensions in units of the instance's ``max |e0|`` (so ``|e0| <= 1``).
    sigma : (m,) float
        +1 on cables, -1 on struts, 0 on rods.
    n_nodes : int
        Number of nodes.
    """

    def __init__(self, bonds, d, e0, sigma, n_nodes: int):
        self.bonds = bonds
        self.dhat = d / np.sqrt((d * d).sum(axis=1))[:, None]
        self.sigma = sigma
        self.rod = sigma == 0
        self.e0n = np.asarray(e0, dtype=np.longdouble)
        self.strained = bool(np.any(e0))
        self.n_nodes = n_nodes

    def extensions(self, u_n: np.ndarray) -> np.ndarray:
        """``e0 + R u`` in extended precision.

        Parameters
        ----------
        u_n : (2N,) float
            Displacements in units of ``max |e0|``.

        Returns
        -------
        (m,) longdouble
        """
        u = np.asarray(u_n, dtype=np.longdouble).reshape(-1, 2)
        i, j = self.bonds[:, 0], self.bonds[:, 1]
        return self.e0n + (self.dhat * (u[j] - u[i])).sum(axis=1)

    def forces(self, t: np.ndarray) -> np.ndarray:
        """Net forces ``R^T t`` in extended precision.

        Parameters
        ----------
        t : (m,) float or longdouble
            Tensions.

        Returns
        -------
        (2N,) longdouble
        """
        t = np.asarray(t, dtype=np.longdouble)
        f = np.zeros((self.n_nodes, 2), dtype=np.longdouble)
        contrib = self.dhat * t[:, None]
        np.add.at(f, self.bonds[:, 1], contrib)
        np.add.at(f, self.bonds[:, 0], -contrib)
        return f.ravel()

    def violations(self, v: np.ndarray) -> np.ndarray:
        """Per-site violation of extensions.

        Parameters
        ----------
        v : (m,) float or longdouble
            Extensions.

        Returns
        -------
        (m,) array
            ``|v|`` on rods, ``max(sigma v, 0)`` on one-sided elements.
        """
        return np.where(self.rod, np.abs(v), np.maximum(self.sigma * v, 0))

    def floppy(self, u: np.ndarray, res: Resolution) -> FloppyCertificate:
        """Check displacements as a floppy certificate.

        Parameters
        ----------
        u : (2N,) float
            Displacements in units of ``max |e0|``.
        res : Resolution
            The tolerances.

        Returns
        -------
        FloppyCertificate
        """
        u_n = np.asarray(u, dtype=float).ravel()
        if not self.strained:  # nothing is strained: u = 0 is exact
            return FloppyCertificate(np.zeros_like(u_n), 0.0, 0.0, True)
        size = float(np.abs(u_n).max(initial=0.0))
        if not np.isfinite(size):
            return FloppyCertificate(u_n, np.inf, np.inf, False)
        viol = float(self.violations(self.extensions(u_n)).max(initial=0.0))
        ok = viol + violation_roundoff(size) <= res.violation and size <= res.displacement
        return FloppyCertificate(u_n, viol, size, ok)

    def rigid(self, t: np.ndarray, res: Resolution) -> RigidCertificate:
        """Check tensions as a rigid certificate.

        Parameters
        ----------
        t : (m,) float or longdouble
            Tensions on the non-empty sites (wrong signs are rejected, never clipped).
        res : Resolution
            The tolerances.

        Returns
        -------
        RigidCertificate
        """
        t = np.asarray(t)
        if t.dtype != np.longdouble:
            t = t.astype(float)
        t1 = np.abs(t.astype(np.longdouble)).sum()
        signs_ok = not np.any(self.sigma * t < 0)
        if t1 == 0.0 or not np.isfinite(t1) or not signs_ok or not self.strained:
            return RigidCertificate(t, 0.0, np.inf, False)
        work = float(np.dot(t.astype(np.longdouble), self.e0n) / t1)
        resid = float(np.abs(self.forces(t)).sum() / t1)
        ok = work - ROUNDOFF > res.violation + res.displacement * (resid + ROUNDOFF)
        return RigidCertificate(t, work, resid, ok)
