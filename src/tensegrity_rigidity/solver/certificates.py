"""The two certificates of a verdict and the resolution model that makes them exclude each other.

Units: the affine extensions and the displacements are measured in units of the largest affine
extension over all bond sites, ``s0 = max_b |e0_b|``, so nothing here depends on the strain
magnitude.

* **Floppy**: a displacement ``u`` whose extensions ``v = e0 + R u`` are admissible (rods
  unstretched, cables not stretched, struts not compressed). Its *violation* is the largest
  ``|v|`` on rods, ``max(v, 0)`` on cables, ``max(-v, 0)`` on struts; its *size* ``max |u| / s0``.
* **Rigid**: an admissible self-stress ``t`` (``t >= 0`` on cables, ``<= 0`` on struts). Its
  *work* is ``w = t . e0 / (|t|_1 s0)``, its *force residual* ``r = |R^T t|_1 / |t|_1``.

With a violation tolerance ``tau`` and a displacement bound ``U`` (:class:`Resolution`) a
floppy certificate is accepted when its violation is at most ``tau`` and its size at most
``U``, a rigid one when ``w > tau + U r``; the two can never both be accepted for one instance
(docs/model.md, "The resolution model"). Every quantity is evaluated in extended precision
with the bond vectors recomputed in it, and a bound on its round-off (:func:`violation_roundoff`,
:attr:`ExactGeometry.roundoff`, derived in docs/model.md) is added to each test. An instance
with neither certificate is reported undecided, with both best candidates, never guessed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

#: Unit round-off of the extended precision the certificates are evaluated in (``2^-64`` on
#: x86-64; ``2^-53`` where ``longdouble`` is a double).
EPS = float(np.finfo(np.longdouble).eps) / 2


def violation_roundoff(size: float) -> float:
    """Round-off bound of an extended-precision violation at displacements of ``size``
    (units of ``max |e0|``; returns a float in the same units).

    ``v_b = e0_b + dhat_b . (u_j - u_i)`` takes about ten roundings of quantities up to
    ``1 + 4 size`` (unit bond vectors and displacements), bounded by ``20 EPS (1 + 4 size)``.
    """
    return 20.0 * EPS * (1.0 + 4.0 * size)


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
    displacement: float = 1e8


@dataclass(frozen=True)
class FloppyCertificate:
    """A displacement checked against the resolution model.

    Attributes
    ----------
    u : (2N,) float or longdouble
        Displacements in units of ``max |e0|``, in extended precision when they were computed
        in it (beyond ``1e6`` times the strain, rounding ``u`` to double precision alone
        leaves violations of ``1e-10`` or more).
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
        Whether ``work > tau + U residual`` (plus the round-off bounds).
    """

    t: np.ndarray
    work: float
    residual: float
    accepted: bool


def _two_sum(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``a + b = s + e`` exactly, ``s = fl(a + b)`` (Knuth's TwoSum; round to nearest)."""
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


def bond_vectors(network, sites: np.ndarray) -> np.ndarray:
    """Bond vectors of ``sites`` in extended precision, correctly rounded up to ``~EPS^2``.

    ``d = x_j + s . box - x_i`` is summed from its terms (positions and integer multiples of the
    box vectors, each exact in a 64-bit mantissa for shifts below 2^11) by cascaded TwoSum
    (Ogita, Rump and Oishi's Sum2): the error is at most ``EPS |d| + 9 EPS^2`` times the
    largest term, however far from the origin the nodes lie (a plain sum would lose
    ``EPS |x| / |d|`` relative).

    Parameters
    ----------
    network : PeriodicNetwork
        Positions (N, d), bonds (B, 2), shifts (B, d) and box (d, d).
    sites : (m,) int
        Bond sites.

    Returns
    -------
    (m, d) longdouble
    """
    pos = network.positions.astype(np.longdouble)
    box = network.box.astype(np.longdouble)
    b, shift = network.bonds[sites], network.shifts[sites].astype(np.longdouble)
    terms = [pos[b[:, 1]], -pos[b[:, 0]]]
    terms += [shift[:, a : a + 1] * box[a] for a in range(box.shape[0])]
    total, err = terms[0], np.zeros_like(terms[0])
    for term in terms[1:]:
        total, e = _two_sum(total, term)
        err = err + e
    return total + err


class ExactGeometry:
    """The rigidity matrix of a problem in extended precision, for certificate checks.

    Parameters
    ----------
    bonds : (m, 2) int
        Node pairs of the non-empty sites.
    d : (m, dim) longdouble
        Bond vectors of those sites in extended precision (:func:`bond_vectors`), ``dim = 2``
        or ``3``.
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
        self.dim = int(d.shape[1])
        degree = int(np.bincount(np.asarray(bonds).ravel(), minlength=n_nodes).max(initial=0))
        sums = int(np.ceil(np.log2(max(len(bonds), self.dim * n_nodes, 2))))
        # 2 sqrt(dim) rounded up, and the roundings of a unit vector (one more sum in 3D)
        factor, unit = (3, 6) if self.dim == 2 else (4, 7)
        #: Bound on the round-off of the normalised work and force residual (module docstring).
        self.roundoff = (factor * (degree + unit) + 2 * sums + 3) * EPS
        self._R: sp.csr_matrix | None = None

    @property
    def matrix(self) -> sp.csr_matrix:
        """The rigidity matrix ``R`` (m, dN) in extended precision (built on first use); a row
        holds ``-dhat`` at its first node and ``+dhat`` at its second, so a node's force in
        ``R^T t`` sums at most ``D`` products in turn, as the bound assumes."""
        if self._R is None:
            m, dim = len(self.bonds), self.dim
            i, j = self.bonds[:, 0], self.bonds[:, 1]
            axes = range(dim)
            cols = np.concatenate([dim * j + a for a in axes] + [dim * i + a for a in axes])
            vals = np.concatenate(
                [self.dhat[:, a] for a in axes] + [-self.dhat[:, a] for a in axes]
            )
            rows = np.tile(np.arange(m), 2 * dim)
            shape = (m, dim * self.n_nodes)
            self._R = sp.csr_matrix((vals, (rows, cols)), shape=shape, dtype=np.longdouble)
        return self._R

    def extensions(self, u_n: np.ndarray) -> np.ndarray:
        """``e0 + R u`` in extended precision.

        Parameters
        ----------
        u_n : (dN,) float
            Displacements in units of ``max |e0|``.

        Returns
        -------
        (m,) longdouble
        """
        u = np.asarray(u_n, dtype=np.longdouble).reshape(-1, self.dim)
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
        return self.matrix.T @ np.asarray(t, dtype=np.longdouble)

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
        u : (2N,) float or longdouble
            Displacements in units of ``max |e0|`` (extended precision is kept).
        res : Resolution
            The tolerances.

        Returns
        -------
        FloppyCertificate
        """
        u_n = np.asarray(u).ravel()
        if u_n.dtype != np.longdouble:
            u_n = u_n.astype(float)
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
        work, resid = self.work(t), self.residual(t)
        ro = self.roundoff
        ok = bool(work - ro > res.violation + res.displacement * (resid + ro))
        return RigidCertificate(t, float(work), float(resid), ok)

    def work(self, t: np.ndarray) -> np.longdouble:
        """``t . e0 / |t|_1`` in extended precision (pairwise sums), for nonzero ``t`` (m,)."""
        t = np.asarray(t, dtype=np.longdouble)
        return (t * self.e0n).sum() / np.abs(t).sum()

    def residual(self, t: np.ndarray) -> np.longdouble:
        """``|R^T t|_1 / |t|_1`` in extended precision, for nonzero ``t`` (m,)."""
        t = np.asarray(t, dtype=np.longdouble)
        return np.abs(self.forces(t)).sum() / np.abs(t).sum()


#: The two kinds of undecided verdict (:func:`undecided_reason`).
WITHIN_RESOLUTION = "within resolution"
NOT_RESOLVED = "not resolved"


def undecided_reason(
    rigid: RigidCertificate | None,
    floppy: FloppyCertificate | None,
    res: Resolution,
    roundoff: float,
) -> tuple[str, str]:
    """Why neither best candidate was accepted: the boundary is within resolution, or the
    search did not resolve it.

    Any self-stress and displacement satisfy ``violation >= work - size * residual``
    (docs/model.md, "Undecided verdicts"), so the candidates bound the verdict LP both ways:

    * a displacement of violation ``v`` bounds the work of every exact self-stress by ``v``;
      at or below the smallest work a rigid certificate can show, ``tau + (U + 1) roundoff``,
      no self-stress can ever pass;
    * a self-stress with ``work - U (residual + roundoff) - roundoff > 0`` proves that every
      displacement within ``U`` violates by more than that: no zero-energy displacement
      exists within the bound, yet the margin is below ``tau``.

    Either proves the sample lies within resolution of the boundary. Otherwise the strategies
    ran out before reaching either side: the probe is not resolved.

    Parameters
    ----------
    rigid, floppy : certificate or None
        The best candidates of the search.
    res : Resolution
        The tolerances.
    roundoff : float
        :attr:`ExactGeometry.roundoff` of the problem.

    Returns
    -------
    kind : str
        :data:`WITHIN_RESOLUTION` or :data:`NOT_RESOLVED`.
    evidence : str
        The bound behind the kind, in one clause.
    """
    if floppy is not None and np.isfinite(floppy.violation):
        bound = floppy.violation + violation_roundoff(floppy.size)
        smallest = res.violation + (res.displacement + 1.0) * roundoff
        if bound <= smallest:
            return WITHIN_RESOLUTION, (
                f"every exact self-stress does work at most {bound:.2e}, below the "
                f"{smallest:.2e} a rigid certificate needs"
            )
    if rigid is not None and np.isfinite(rigid.residual):
        margin = rigid.work - roundoff - res.displacement * (rigid.residual + roundoff)
        if margin > 0:
            return WITHIN_RESOLUTION, (
                f"every displacement within U violates by at least {margin:.2e}, below tau"
            )
    return NOT_RESOLVED, "no candidate reaches either side of the resolution model"
