"""The two certificates of a verdict and the resolution model that makes them exclude each other.

In units of ``s0 = max_b |e0_b|``: a **floppy** certificate is a displacement ``u`` whose extensions
``v = e0 + R u`` are admissible to ``tau`` with ``max |u| <= U``; a **rigid** one an admissible
self-stress ``t`` with work ``t . e0 / |t|_1 > tau + U |R^T t|_1 / |t|_1``. Both cannot pass for one
instance (docs/model.md, "The resolution model"). Everything is evaluated in extended precision,
with a bound on its round-off added to each test.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..model.network import norms_from_squares, short_repr

#: Unit round-off of the extended precision the certificates are evaluated in (``2^-64`` on
#: x86-64; ``2^-53`` where ``longdouble`` is a double).
EPS = float(np.finfo(np.longdouble).eps) / 2


def violation_roundoff(size: float) -> float:
    """Round-off bound ``20 EPS (1 + 4 size)`` of an extended-precision violation at displacements
    of ``size`` (units of ``max |e0|``): about ten roundings of quantities up to ``1 + 4 size``."""
    return 20.0 * EPS * (1.0 + 4.0 * size)


@dataclass(frozen=True)
class Resolution:
    """Tolerances of the resolution model (dimensionless, units of ``max |e0|``).

    Attributes
    ----------
    violation : float
        ``tau``: largest violation of a floppy certificate.
    displacement : float
        ``U``: largest displacement of a floppy certificate.
    """

    violation: float = 1e-9
    displacement: float = 1e8


@dataclass(frozen=True, eq=False)
class FloppyCertificate:
    """A displacement checked against the resolution model.

    Attributes
    ----------
    u : (2N,) float or longdouble
        Displacements in units of ``max |e0|`` (in extended precision when computed in it).
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

    def __repr__(self) -> str:
        return short_repr(
            self, [(k, getattr(self, k)) for k in ("accepted", "violation", "size", "u")]
        )


@dataclass(frozen=True, eq=False)
class RigidCertificate:
    """An admissible self-stress checked against the resolution model.

    Attributes
    ----------
    t : (m,) float or longdouble
        Tensions on the non-empty sites (signs admissible).
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

    def __repr__(self) -> str:
        return short_repr(
            self, [(k, getattr(self, k)) for k in ("accepted", "work", "residual", "t")]
        )


def _two_sum(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``a + b = s + e`` exactly, ``s = fl(a + b)`` (Knuth's TwoSum; round to nearest)."""
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


def bond_vectors(network, sites: np.ndarray) -> np.ndarray:
    """Bond vectors ((m, d) longdouble) of ``sites`` (m,) of ``network``, correctly rounded up to
    ``~EPS^2`` by cascaded TwoSum however far from the origin the nodes lie (docs/solver.md)."""
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

    Built from the node pairs ``bonds`` (m, 2), the bond vectors ``d`` (m, dim) of
    :func:`bond_vectors`, the affine extensions ``e0`` (m,) in units of ``max |e0|``, the signs
    ``sigma`` (m,) and the number of nodes ``n_nodes``.
    """

    def __init__(self, bonds, d, e0, sigma, n_nodes: int):
        self.bonds = bonds
        self.dhat = d / norms_from_squares(d, (d * d).sum(axis=1))[:, None]
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
        """The rigidity matrix ``R`` (m, dN) in extended precision (built on first use)."""
        if self._R is None:
            m, dim = len(self.bonds), self.dim
            i, j = self.bonds[:, 0], self.bonds[:, 1]
            axes = range(dim)
            cols = np.concatenate([dim * j + a for a in axes] + [dim * i + a for a in axes])
            vals = np.concatenate([self.dhat.T, -self.dhat.T]).ravel()  # d columns of j, then of i
            rows = np.tile(np.arange(m), 2 * dim)
            shape = (m, dim * self.n_nodes)
            self._R = sp.csr_matrix((vals, (rows, cols)), shape=shape, dtype=np.longdouble)
        return self._R

    def extensions(self, u_n: np.ndarray) -> np.ndarray:
        """``e0 + R u`` ((m,) longdouble) at displacements ``u_n`` (dN,), units of ``max |e0|``."""
        u = np.asarray(u_n, dtype=np.longdouble).reshape(-1, self.dim)
        i, j = self.bonds[:, 0], self.bonds[:, 1]
        return self.e0n + (self.dhat * (u[j] - u[i])).sum(axis=1)

    def forces(self, t: np.ndarray) -> np.ndarray:
        """Net forces ``R^T t`` ((dN,) longdouble) of tensions ``t`` (m,)."""
        return self.matrix.T @ np.asarray(t, dtype=np.longdouble)

    def violations(self, v: np.ndarray) -> np.ndarray:
        """Per-site violation ((m,)) of extensions ``v`` (m,): ``|v|`` on rods, ``max(sigma v, 0)``
        on one-sided elements."""
        return np.where(self.rod, np.abs(v), np.maximum(self.sigma * v, 0))

    def floppy(self, u: np.ndarray, res: Resolution) -> FloppyCertificate:
        """Check displacements ``u`` ((2N,), extended precision kept) as a floppy certificate at
        resolution ``res``."""
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
        """Check tensions ``t`` ((m,); wrong signs are rejected, never clipped) as a rigid
        certificate at resolution ``res``."""
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
    """Why neither best candidate was accepted: within resolution of the boundary, or not resolved.

    Any self-stress and displacement satisfy ``violation >= work - size * residual`` (docs/model.md,
    "Undecided verdicts"): a displacement whose violation is at most the least work a rigid
    certificate can show, or a self-stress whose margin proves every displacement within ``U``
    violates, puts the sample within resolution; otherwise the strategies ran out.

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
