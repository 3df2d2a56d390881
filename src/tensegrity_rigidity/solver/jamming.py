"""The certified jamming test of a packing's contact network (local, collective, strict).

A contact is a strut: to first order its gap changes by ``(A x)_c`` under a motion ``x`` and may
open, never close. Rattlers (fewer than ``d + 1`` contacts, counted per contact, removed
iteratively) are set aside. The rest is **jammed** when every motion with ``A x >= 0`` is trivial
(a translation; nothing for ``local``), **unjammed** when some motion is not. Each side has a
certificate checked in extended precision (docs/model.md, "The jamming test"):

* **jammed**: contact forces ``y >= y_min > 0`` on every row with force residual ``rho = A_0^T y``,
  and a certified lower bound ``sigma`` on the smallest singular value of ``A_0`` (``A`` without
  the columns of one pinned particle) from a shifted ``L D L^T`` factorisation and its
  extended-precision residual. Then every motion of size ``|x|`` closes some contact by at least
  ``margin |x|``, ``margin = (sigma - |rho|_2 / y_min) / (|y|_1 / y_min + sqrt(rows))``;
  accepted when ``margin > tau``;
* **unjammed**: a motion of size ``|x|`` (translations removed) closing no contact by more than
  ``tau |x|``: it opens contacts, or it is a flex (``A x = 0`` to that resolution).

Both can never be accepted together; an instance where neither is accepted is undecided, within
resolution of the boundary or not resolved, and the message says which.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import InputError
from ..model.network import Element, PeriodicNetwork, check_count, fields_repr
from .certificates import EPS, WITHIN_RESOLUTION, bond_vectors
from .highs import run_lp
from .linalg import one_blas_thread

#: The jamming categories of Torquato and Stillinger, weakest first.
KINDS = ("local", "collective", "strict")
NOT_RESOLVED = "not resolved"


@dataclass(frozen=True)
class JammingOptions:
    """The resolution of the jamming test.

    Attributes
    ----------
    violation_tol : float
        ``tau``: an unjamming motion of size ``|x|`` may close contacts by at most ``tau |x|``; a
        jammed certificate must prove that every motion closes some contact by more.
    eigen_iterations : int
        Most shift-invert Lanczos iterations of the smallest-eigenvalue estimate.
    polish_rounds : int
        Projections of an opening motion onto the contacts it keeps closed.
    """

    violation_tol: float = 1e-12
    eigen_iterations: int = 300
    polish_rounds: int = 3

    def __post_init__(self):
        tau = self.violation_tol
        if isinstance(tau, bool) or not isinstance(tau, (int, float)) or not 0 < tau < 1e-3:
            raise InputError(f"JammingOptions.violation_tol must lie in (0, 1e-3), got {tau!r}")
        for name in ("eigen_iterations", "polish_rounds"):
            value = getattr(self, name)
            check_count(f"JammingOptions.{name}", value, least=1)


@dataclass(frozen=True, eq=False)
class JammedCertificate:
    """Contact forces and a rank bound, checked against the resolution model.

    Attributes
    ----------
    forces : (rows,) float
        Non-negative forces on the rows of the test (contacts; for ``strict`` the last row is the
        volume constraint; for ``local`` each contact once per end), ``sum = rows``.
    sites : (rows,) int
        The network site of each row (-1: the volume row).
    strictness : float
        ``min forces / sum forces``.
    residual : float
        ``|A_0^T y|_2 / sum y`` with its round-off bound added.
    sigma : float
        Certified lower bound on the smallest singular value of ``A_0`` (``inf``: no motion).
    margin : float
        Every non-trivial motion closes some contact by at least ``margin`` times its size.
    accepted : bool
        ``margin > tau``.
    """

    forces: np.ndarray
    sites: np.ndarray
    strictness: float
    residual: float
    sigma: float
    margin: float
    accepted: bool

    __repr__ = fields_repr


@dataclass(frozen=True, eq=False)
class UnjammingMotion:
    """A motion checked against the resolution model.

    Attributes
    ----------
    displacements : (N, d) float
        Particle displacements of unit size (translations removed; zero on rattlers).
    strain : (d, d) float or None
        The box's symmetric strain (``strict`` only, its trace <= 0 to resolution).
    violation : float
        Largest closing of a contact per unit size, round-off bound included.
    opening : float
        Largest opening of a contact per unit size.
    opened : int
        Contacts opened by more than ``tau`` (0: a flex).
    accepted : bool
        ``violation <= tau``.
    """

    displacements: np.ndarray
    strain: np.ndarray | None
    violation: float
    opening: float
    opened: int
    accepted: bool

    __repr__ = fields_repr

    @property
    def flex(self) -> bool:
        """Whether the motion opens no contact (``A x = 0`` to resolution)."""
        return self.opened == 0


@dataclass(frozen=True, eq=False)
class JammingResult:
    """The verdict of :func:`jamming`.

    Attributes
    ----------
    status : str
        "jammed", "unjammed" or "undecided".
    kind : str
        "local", "collective" or "strict".
    rattlers : (r,) int
        Particles removed iteratively for having fewer than ``d + 1`` contacts.
    n_particles, n_contacts : int
        Particles ``N`` and contacts (struts) of the network.
    backbone_contacts : int
        Contacts between non-rattlers.
    certificate : JammedCertificate or UnjammingMotion or None
        The accepted certificate (None when undecided or when every particle is a rattler).
    jammed, unjamming : JammedCertificate or UnjammingMotion or None
        The best candidate of each side.
    reason : str
        "" when decided, else "within resolution" or "not resolved".
    message : str
        Why (undecided, or every particle a rattler).
    dim : int
        Dimension d.
    n_sites : int
        Sites ``m`` of the tested network.
    """

    status: str
    kind: str
    rattlers: np.ndarray
    n_particles: int
    n_contacts: int
    backbone_contacts: int
    certificate: JammedCertificate | UnjammingMotion | None
    jammed: JammedCertificate | None = field(repr=False)  # the certificate or a candidate
    unjamming: UnjammingMotion | None = field(repr=False)
    reason: str = ""
    message: str = ""
    dim: int = 2

    __repr__ = fields_repr

    @property
    def n_rattlers(self) -> int:
        """Number of rattlers."""
        return int(self.rattlers.size)

    @property
    def rattler_contacts(self) -> int:
        """Contacts with at least one rattler."""
        return self.n_contacts - self.backbone_contacts

    @property
    def isostatic_contacts(self) -> int:
        """The fewest contacts a jammed backbone of ``N'`` particles can have: ``d (N' - 1) + 1``
        with the box fixed (Goodrich et al. 2012), ``d (N' - 1) + d (d + 1) / 2`` for ``strict``."""
        n = self.n_particles - self.n_rattlers
        if n == 0:
            return 0
        extra = self.dim * (self.dim + 1) // 2 if self.kind == "strict" else 1
        return self.dim * (n - 1) + extra

    @property
    def excess_contacts(self) -> int:
        """``backbone_contacts - isostatic_contacts``."""
        return self.backbone_contacts - self.isostatic_contacts

    @property
    def isostatic_excess(self) -> float:
        """``z - z_iso``: mean contacts per non-rattler minus the isostatic value, ``2 (N_c -
        N_iso) / N'`` (NaN without non-rattlers)."""
        n = self.n_particles - self.n_rattlers
        return 2.0 * self.excess_contacts / n if n else math.nan

    def contact_forces(self) -> np.ndarray:
        """Forces of the accepted or best jammed candidate on every site of the network.

        Returns
        -------
        (m,) float
            Non-negative forces (zero on rattlers' contacts and empty sites; ``local``: the
            larger of the two ends); all zero without a jammed candidate.
        """
        out = np.zeros(self.n_sites)
        c = self.jammed
        if c is not None:
            rows = c.sites >= 0
            np.maximum.at(out, c.sites[rows], c.forces[rows])
        return out

    #: number of sites of the network (set by :func:`jamming`)
    n_sites: int = field(default=0)


def strain_components(dim: int) -> list[tuple[int, int]]:
    """The independent components of a symmetric strain.

    Parameters
    ----------
    dim : int
        Dimension d.

    Returns
    -------
    list of (int, int)
        ``(a, a)`` for the diagonal, then ``(a, b)`` with ``a < b``: ``d (d + 1) / 2`` pairs.
    """
    return [(a, a) for a in range(dim)] + [(a, b) for a in range(dim) for b in range(a + 1, dim)]


def rattlers(network: PeriodicNetwork, dim: int | None = None) -> np.ndarray:
    """Particles with fewer than ``d + 1`` contacts, removed iteratively.

    Parameters
    ----------
    network : PeriodicNetwork
        A contact network (non-empty sites are contacts).
    dim : int, optional
        The ``d`` of the rule (default the network's).

    Returns
    -------
    (r,) int
        Rattlers in increasing order. Contacts are counted per contact: a particle touching two
        images of one neighbour has two, touching its own image two (one on each side).
    """
    d = network.dim if dim is None else dim
    bonds = network.bonds[network.kinds != Element.EMPTY]
    n = network.n_nodes
    count = np.bincount(bonds.ravel(), minlength=n)
    alive = np.ones(n, dtype=bool)
    live_bond = np.ones(len(bonds), dtype=bool)
    while True:
        out = alive & (count < d + 1)
        if not out.any():
            break
        alive &= ~out
        dying = live_bond & (out[bonds[:, 0]] | out[bonds[:, 1]])
        live_bond &= ~dying
        count = np.bincount(bonds[live_bond].ravel(), minlength=n)
    return np.flatnonzero(~alive)


class _System:
    """The linear inequality system ``A x >= 0`` of one test, in double and extended precision."""

    def __init__(self, network: PeriodicNetwork, kind: str, sites: np.ndarray, nodes: np.ndarray):
        dim = network.dim
        self.kind, self.dim, self.nodes = kind, dim, nodes
        index = np.full(network.n_nodes, -1)
        index[nodes] = np.arange(nodes.size)
        bonds = network.bonds[sites]
        d = bond_vectors(network, sites)  # (m, dim) longdouble, correctly rounded
        length = np.sqrt((d * d).sum(axis=1))
        nhat = d / length[:, None]
        i, j = index[bonds[:, 0]], index[bonds[:, 1]]
        m = len(sites)
        axes = np.arange(dim)
        if kind == "local":  # each contact once per end, its neighbour held fixed
            # a particle's own image moves with it: that contact blocks nothing (a square box of
            # one cell along x let its particle slide along x, and read locally jammed)
            two = np.flatnonzero(i != j)
            rows = np.arange(2 * two.size)
            ends = np.r_[i[two], j[two]]
            values = np.r_[-nhat[two], nhat[two]]
            self.sites = np.r_[sites[two], sites[two]]
            coo_r = np.repeat(rows, dim)
            coo_c = (dim * ends[:, None] + axes).ravel()
            coo_v = values.ravel()
            self.n_rows, self.n_cols, self.q = 2 * two.size, dim * nodes.size, 0
        else:
            moving = i != j  # a contact with its own image: the particle's displacement cancels
            r = np.flatnonzero(moving)
            coo_r = np.repeat(np.r_[r, r], dim)
            coo_c = np.r_[
                (dim * i[r][:, None] + axes).ravel(), (dim * j[r][:, None] + axes).ravel()
            ]
            coo_v = np.r_[(-nhat[r]).ravel(), nhat[r].ravel()]
            self.sites = sites.copy()
            self.n_rows, self.n_cols, self.q = m, dim * nodes.size, 0
            if kind == "strict":  # strain columns in units of 1/ell, then the volume row
                self.ell = float(np.mean(np.asarray(length, dtype=float)))
                pairs = strain_components(dim)
                self.q = len(pairs)
                cols = []
                for k, (a, b) in enumerate(pairs):
                    col = nhat[:, a] * d[:, b] + (nhat[:, b] * d[:, a] if a != b else 0)
                    cols.append(col / np.longdouble(self.ell))
                    coo_r = np.r_[coo_r, np.arange(m)]
                    coo_c = np.r_[coo_c, np.full(m, self.n_cols + k)]
                    coo_v = np.r_[coo_v, cols[-1]]
                vol = np.longdouble(-1.0) / np.sqrt(np.longdouble(dim))
                coo_r = np.r_[coo_r, np.full(dim, m)]
                coo_c = np.r_[coo_c, self.n_cols + np.arange(dim)]
                coo_v = np.r_[coo_v, np.full(dim, vol)]
                self.sites = np.r_[sites, -1]
                self.n_rows, self.n_cols = m + 1, self.n_cols + self.q
        shape = (self.n_rows, self.n_cols)
        self.A_ld = sp.csr_matrix(
            (np.asarray(coo_v, dtype=np.longdouble), (coo_r, coo_c)), shape=shape
        )
        self.A_ld.sum_duplicates()
        self.A = self.A_ld.astype(float)
        self.abs_A = abs(self.A)
        # the pinned particle: the one with the most contacts (translations leave the test)
        self.keep = np.arange(self.n_cols)
        if kind != "local" and nodes.size:
            degree = np.bincount(np.r_[i, j], minlength=nodes.size)
            p = int(np.argmax(degree))
            self.keep = np.setdiff1d(self.keep, dim * p + axes)
        self.A0 = self.A[:, self.keep].tocsc()
        self.A0_ld = self.A_ld[:, self.keep].tocsc()
        col_count = np.diff(self.A0.tocsc().indptr)
        row_count = np.diff(self.A.indptr)
        #: relative error of an entry of A (a unit vector in extended precision; strain columns
        #: take two more roundings) and of a sum along a row or a column, in units of EPS
        self.entry_err = 8 + 4 * (kind == "strict")
        self.row_terms = int(row_count.max(initial=1))
        self.col_terms = int(col_count.max(initial=1))

    def size(self, x: np.ndarray) -> np.longdouble:
        """Size of a motion ``x`` (n_cols,): its 2-norm, translations removed (not for local)."""
        x = np.asarray(x, dtype=np.longdouble)
        if self.kind == "local":
            return np.sqrt((x * x).sum())
        n_u = self.n_cols - self.q
        u = x[:n_u].reshape(-1, self.dim)
        u = u - u.mean(axis=0)
        return np.sqrt((u * u).sum() + (x[n_u:] ** 2).sum())

    def check_motion(self, x: np.ndarray, tau: float) -> tuple[float, float, int, bool]:
        """(violation, opening, opened, accepted) of a motion ``x`` (n_cols,) per unit size."""
        x_ld = np.asarray(x, dtype=np.longdouble)
        size = self.size(x_ld)
        if not (np.isfinite(float(size)) and size > 0):
            return math.inf, 0.0, 0, False
        w = (self.A_ld @ x_ld) / size
        # round-off: the entries' relative error and a sum of row_terms products, per row
        bound = (self.abs_A @ np.abs(np.asarray(x_ld / size, dtype=float))) * (
            (self.entry_err + self.row_terms + 4) * EPS
        )
        viol = float(np.max(np.asarray(-w, dtype=float) + bound, initial=0.0))
        viol = max(viol, 0.0)
        opening = float(np.max(np.asarray(w, dtype=float), initial=0.0))
        opened = int(np.count_nonzero(np.asarray(w, dtype=float) - bound > tau))
        return viol, opening, opened, viol <= tau


def _highs_stress_lp(A: sp.csr_matrix):
    """``max t`` s.t. ``A^T y = 0``, ``y_c >= t``, ``sum y <= rows`` (HiGHS, one thread): the
    forces ``y`` (rows,), ``t`` and the motion ``x = -duals`` (cols,) with ``A x >= 0``, ``sum A x
    = 1`` when ``t = 0``; None when HiGHS fails."""
    import highspy

    m, n = A.shape
    inf = highspy.kHighsInf
    M = sp.vstack(
        [
            sp.hstack([A.T, sp.csr_matrix((n, 1))]),
            sp.hstack([sp.eye(m), -np.ones((m, 1))]),
            sp.hstack([sp.csr_matrix(np.ones((1, m))), sp.csr_matrix((1, 1))]),
        ]
    ).tocsc()
    h = run_lp(
        M,
        np.r_[np.zeros(m), -1.0],
        np.full(m + 1, -inf),
        np.full(m + 1, inf),
        np.r_[np.zeros(n), np.zeros(m), -inf],
        np.r_[np.zeros(n), np.full(m, inf), float(m)],
        solver="simplex",
        random_seed=0,
    )
    if h.getModelStatus() != highspy.HighsModelStatus.kOptimal:
        return None
    sol = h.getSolution()
    z = np.asarray(sol.col_value, dtype=float)
    x = -np.asarray(sol.row_dual, dtype=float)[:n]
    return z[:m], float(z[m]), x


def _factor(matrix: sp.spmatrix):
    """SuperLU of a symmetric matrix in symmetric mode (no row pivoting): ``P M P^T = L U``."""
    return spla.splu(
        sp.csc_matrix(matrix),
        permc_spec="MMD_AT_PLUS_A",
        diag_pivot_thresh=0.0,
        options={"SymmetricMode": True},
    )


def _gram_bound(s: _System) -> tuple[sp.csc_matrix, sp.csc_matrix, float]:
    """``G = A_0^T A_0`` in double, in extended precision, and a bound on the 2-norm distance of
    the extended one from the exact Gram matrix of the exact ``A_0`` (round-off of the product
    and of the entries)."""
    G_ld = (s.A0_ld.T @ s.A0_ld).tocsc()
    G = G_ld.astype(float)
    absA = abs(s.A0)
    B = (absA.T @ absA).tocsr()
    factor = (s.col_terms + 2 * s.entry_err + 4) * EPS
    return G, G_ld, float(np.max(np.asarray(B.sum(axis=1)).ravel(), initial=0.0)) * factor


def _certified_lambda(G: sp.csc_matrix, G_ld: sp.csc_matrix, shift: float, gram_err: float):
    """A certified lower bound on the smallest eigenvalue of the exact Gram matrix: ``shift`` less
    the residual of an ``L D L^T`` factorisation of ``G - shift I`` (D > 0), both bounded in
    extended precision. None when the factorisation fails or has a non-positive pivot."""
    n = G.shape[0]
    try:
        lu = _factor(G - shift * sp.eye(n, format="csc"))
    except RuntimeError:
        return None
    if not np.array_equal(lu.perm_r, lu.perm_c):
        return None
    D = lu.U.diagonal()
    if not np.all(D > 0):
        return None
    # SuperLU's convention: Pr M Pc = L U with Pr[perm_r[k], k] = 1 and Pc[k, perm_c[k]] = 1
    Pr = sp.csc_matrix((np.ones(n), (lu.perm_r, np.arange(n))), shape=(n, n))
    Pc = sp.csc_matrix((np.ones(n), (np.arange(n), lu.perm_c)), shape=(n, n))
    L = sp.csc_matrix(lu.L)
    M = L.astype(np.longdouble) @ sp.diags(D.astype(np.longdouble)) @ L.T.astype(np.longdouble)
    shifted = G_ld - np.longdouble(shift) * sp.eye(n, dtype=np.longdouble)
    target = Pr.astype(np.longdouble) @ shifted @ Pc.astype(np.longdouble)
    E = (target - M).tocsr()
    absL = abs(L)
    terms = int(np.diff(L.tocsr().indptr).max(initial=1))
    rounding = (absL @ sp.diags(D) @ absL.T + abs(target.astype(float))).tocsr()
    row_e = np.asarray(abs(E).sum(axis=1), dtype=float).ravel()
    row_r = np.asarray(rounding.sum(axis=1)).ravel() * ((terms + 4) * EPS)
    residual = float(np.max(row_e + row_r, initial=0.0)) * (1 + 1e-6)
    return shift - residual - gram_err


def _smallest_eigen(G: sp.csc_matrix, iterations: int):
    """An estimate ``(lambda, v)`` of the smallest eigenvalue of ``G`` and its unit eigenvector
    (shift-invert Lanczos from a fixed start; deterministic)."""
    n = G.shape[0]
    scale = float(np.max(G.diagonal(), initial=1.0))
    mu = 1e-13 * scale
    lu = _factor(G + mu * sp.eye(n, format="csc"))
    op = spla.LinearOperator((n, n), matvec=lu.solve, dtype=float)
    v0 = np.random.default_rng(0).standard_normal(n)
    if n <= 8:
        w, V = np.linalg.eigh(G.toarray())
        return float(w[0]), V[:, 0], lu, mu
    try:
        w, V = spla.eigsh(G, k=1, sigma=0.0, OPinv=op, v0=v0, maxiter=iterations, which="LM")
        v = V[:, 0]
    except spla.ArpackNoConvergence as exc:
        if exc.eigenvectors.shape[1] == 0:
            return math.inf, v0 / np.linalg.norm(v0), lu, mu
        v = exc.eigenvectors[:, 0]
    for _ in range(3):  # inverse iteration: the eigenvector to the shift's resolution
        v = v / np.linalg.norm(v)
        v = lu.solve(v)
    v = v / np.linalg.norm(v)
    return float(v @ (G @ v)), v, lu, mu


def _project_stress(s: _System, y: np.ndarray, lu, rounds: int = 3) -> np.ndarray:
    """Move forces ``y`` (rows,) onto ``A_0^T y = 0`` by ``y - A_0 G^{-1} A_0^T y``, residuals in
    extended precision; returns a longdouble array."""
    y_ld = np.asarray(y, dtype=np.longdouble)
    for _ in range(rounds):
        r = s.A0_ld.T @ y_ld
        if not np.any(r):
            break
        z = lu.solve(np.asarray(r, dtype=float))
        y_ld = y_ld - s.A0_ld @ np.asarray(z, dtype=np.longdouble)
    return y_ld


def _jammed_certificate(s: _System, y_ld: np.ndarray, sigma: float, tau: float):
    """Check forces ``y`` and a singular value bound ``sigma`` as a jammed certificate."""
    y_pos = np.asarray(y_ld, dtype=float)
    total = float(np.abs(y_ld).sum()) * (1 + 4 * EPS * max(len(y_pos), 1))
    y_min = float(np.min(y_ld, initial=np.inf))
    scale = y_pos.sum() if y_pos.sum() > 0 else 1.0
    forces = y_pos * (s.n_rows / scale)
    if not (y_min > 0 and total > 0):
        return JammedCertificate(forces, s.sites, y_min / total if total else 0.0, math.inf,
                                 sigma, -math.inf, False)  # fmt: skip
    rho = np.asarray(s.A0_ld.T @ y_ld, dtype=float)
    err = (abs(s.A0).T @ np.abs(y_pos)) * ((s.entry_err + s.col_terms + 4) * EPS)
    rho_norm = float(np.linalg.norm(np.abs(rho) + err))
    if s.A0.shape[1] == 0:
        margin = math.inf
    else:
        margin = (sigma - rho_norm / y_min) / (total / y_min + math.sqrt(s.n_rows))
    return JammedCertificate(
        forces, s.sites, y_min / total, rho_norm / total, sigma, margin, bool(margin > tau)
    )


def _polish(s: _System, x: np.ndarray, rounds: int) -> np.ndarray:
    """Project an approximate opening motion ``x`` onto the contacts it keeps (nearly) closed,
    by proximal steps on a direct factorisation with residuals in extended precision."""
    w = s.A @ x
    top = float(np.max(w, initial=0.0))
    if not top > 0:
        return np.asarray(x, dtype=np.longdouble)
    tight = np.flatnonzero(w <= 1e-6 * top)
    x_ld = np.asarray(x, dtype=np.longdouble)
    if tight.size == 0:
        return x_ld
    At = s.A0[tight]
    At_ld = s.A_ld[tight]
    H = (At.T @ At).tocsc()
    n = H.shape[0]
    if n == 0:
        return x_ld
    mu = 1e-12 * float(np.max(H.diagonal(), initial=1.0))
    try:
        lu = _factor(H + mu * sp.eye(n, format="csc"))
    except RuntimeError:
        return x_ld
    for _ in range(rounds * 4):
        r = At_ld @ x_ld
        if float(np.max(np.abs(np.asarray(r, dtype=float)), initial=0.0)) == 0.0:
            break
        delta = lu.solve(np.asarray(At.T @ np.asarray(r, dtype=float), dtype=float))
        x_ld[s.keep] -= np.asarray(delta, dtype=np.longdouble)
    return x_ld


def _motion(s: _System, x: np.ndarray, n_nodes: int, tau: float) -> UnjammingMotion:
    """An :class:`UnjammingMotion` from a motion ``x`` (n_cols,) of the test."""
    viol, opening, opened, ok = s.check_motion(x, tau)
    size = float(s.size(x))
    xs = np.asarray(x, dtype=float) / size if size > 0 else np.asarray(x, dtype=float)
    dim = s.dim
    n_u = s.n_cols - s.q
    u = xs[:n_u].reshape(-1, dim)
    if s.kind != "local" and len(u):
        u = u - u.mean(axis=0)
    disp = np.zeros((n_nodes, dim))
    disp[s.nodes] = u
    strain = None
    if s.kind == "strict":
        strain = np.zeros((dim, dim))
        for k, (a, b) in enumerate(strain_components(dim)):
            strain[a, b] = strain[b, a] = xs[n_u + k] / s.ell
    return UnjammingMotion(disp, strain, viol, opening, opened, ok)


def jamming(
    network: PeriodicNetwork, kind: str = "collective", options: JammingOptions | None = None
) -> JammingResult:
    """Certified jamming test of a contact network (every non-empty site a strut).

    Parameters
    ----------
    network : PeriodicNetwork
        A packing's contacts (:func:`~tensegrity_rigidity.model.packing.contact_network`), ``N``
        particles, ``m`` sites; its empty sites are ignored.
    kind : {"collective", "strict", "local"}
        "local": no particle can move with the others held; "collective": no motion but
        translations with the box fixed; "strict": none even with the box deformed at
        non-increasing volume (symmetric strain added to the motions, Donev et al. 2004).
    options : JammingOptions, optional
        The resolution ``tau`` and the work limits.

    Returns
    -------
    JammingResult
        Status, rattlers, counts and the certificates: the accepted one in ``certificate``, the best
        candidate of each side in ``jammed`` and ``unjamming``. A packing whose every particle is
        a rattler is "unjammed" (with no motion computed).

    Raises
    ------
    InputError
        If ``network`` is not a network, a non-empty site is not a strut, or ``kind`` is unknown.

    Examples
    --------
    >>> from tensegrity_rigidity import crystal_packing, jamming
    >>> net = crystal_packing("square", 3).contact_network()
    >>> r = jamming(net)
    >>> r.status, r.certificate.flex  # rows of disks slide: a flex, no contact opens
    ('unjammed', True)
    """
    if not isinstance(network, PeriodicNetwork):
        raise InputError(f"expected a PeriodicNetwork, got {type(network).__name__}")
    if kind not in KINDS:
        raise InputError(f"kind must be one of {', '.join(KINDS)}, got {kind!r}")
    opts = JammingOptions() if options is None else options
    if not isinstance(opts, JammingOptions):
        raise InputError(f"options must be a JammingOptions, got {type(opts).__name__}")
    occupied = network.kinds != Element.EMPTY
    if np.any(network.kinds[occupied] != Element.STRUT):
        raise InputError("every contact must be a strut (Element.STRUT); rods or cables are not "
                         "contacts of a packing")  # fmt: skip
    contacts = np.flatnonzero(occupied)
    out = rattlers(network)
    alive = np.ones(network.n_nodes, dtype=bool)
    alive[out] = False
    b = network.bonds[contacts]
    backbone = contacts[alive[b[:, 0]] & alive[b[:, 1]]]
    base = JammingResult(
        status="undecided",
        kind=kind,
        rattlers=out,
        n_particles=network.n_nodes,
        n_contacts=int(contacts.size),
        backbone_contacts=int(backbone.size),
        certificate=None,
        jammed=None,
        unjamming=None,
        dim=network.dim,
        n_sites=network.n_sites,
    )
    nodes = np.flatnonzero(alive)
    if nodes.size == 0:
        why = "every particle is a rattler (fewer than d + 1 contacts, removed iteratively)"
        return replace(base, status="unjammed", message=why)
    s = _System(network, kind, backbone, nodes)
    with one_blas_thread():  # the same last bits whatever the thread settings
        jammed, motion, reason, message = _search(s, network.n_nodes, opts)
        if kind != "local" and not (motion is not None and motion.accepted):
            motion = _local_motion(network, s, backbone, opts) or motion
    base = replace(base, jammed=jammed, unjamming=motion)
    if motion is not None and motion.accepted:
        return replace(base, status="unjammed", certificate=motion)
    if jammed is not None and jammed.accepted:
        return replace(base, status="jammed", certificate=jammed)
    return replace(base, reason=reason, message=message)


def _local_motion(network: PeriodicNetwork, s: _System, backbone: np.ndarray,
                  opts: JammingOptions) -> UnjammingMotion | None:  # fmt: skip
    """The local test's unjamming motion (one particle moves, the others held) checked as a
    motion of the collective or strict test ``s``, or None: a particle free alone unjams the
    packing collectively too, where the collective search may stop short of a motion whose
    openings are tiny (a particle 1e-9 off its neighbours' plane)."""
    local = _System(network, "local", backbone, s.nodes)
    _, motion, _, _ = _search(local, network.n_nodes, opts)
    if motion is None or not motion.accepted:
        return None
    x = np.r_[motion.displacements[s.nodes].ravel(), np.zeros(s.q)].astype(np.longdouble)
    lifted = _motion(s, x, network.n_nodes, opts.violation_tol)
    return lifted if lifted.accepted else None


def _search(s: _System, n_nodes: int, opts: JammingOptions):
    """Candidates of both sides, in order: the stress LP (forces, or an opening motion), the
    smallest singular direction of ``A_0`` (a flex), the certified rank bound."""
    tau = opts.violation_tol
    best: UnjammingMotion | None = None

    def offer(x) -> bool:
        nonlocal best
        if x is None or not np.all(np.isfinite(np.asarray(x, dtype=float))):
            return False
        for sign in (1.0, -1.0):
            cand = _motion(s, sign * np.asarray(x, dtype=np.longdouble), n_nodes, tau)
            if best is None or (cand.accepted, -cand.violation) > (best.accepted, -best.violation):
                best = cand
            if cand.accepted:
                return True
        return False

    n0 = s.A0.shape[1]
    if s.n_rows == 0:  # no contact constrains anything: every motion is free
        x = np.zeros(s.n_cols)
        x[s.keep[0] if s.keep.size else 0] = 1.0
        offer(x)
        return None, best, "", ""
    lp = _highs_stress_lp(s.A)
    y = None
    if lp is not None:
        y, t, x = lp
        full = np.zeros(s.n_cols)
        full[:] = x
        if t <= 1e-6 and offer(_polish(s, full, opts.polish_rounds)):
            return None, best, "", ""
    if n0 == 0:  # nothing moves once translations are pinned
        yy = np.ones(s.n_rows) if y is None else y
        cert = _jammed_certificate(s, np.asarray(yy, dtype=np.longdouble), math.inf, tau)
        return cert, best, *_why(cert, None, s, tau, math.inf)
    G, G_ld, gram_err = _gram_bound(s)
    lam, v, lu, mu = _smallest_eigen(G, opts.eigen_iterations)
    x = np.zeros(s.n_cols)
    x[s.keep] = v
    y_ld = None if y is None else _project_stress(s, y, lu)
    if offer(x):  # a flex; the forces still say whether some motion opens a contact
        forces = None if y_ld is None else _jammed_certificate(s, y_ld, -math.inf, tau)
        return forces, best, "", ""
    cert = None
    if y_ld is not None and np.isfinite(lam) and lam > 0:
        sigma = -math.inf
        for fraction in (0.5, 0.125):
            bound = _certified_lambda(G, G_ld, fraction * lam, gram_err)
            if bound is not None and bound > 0:
                sigma = math.sqrt(bound)
                break
        cert = _jammed_certificate(s, y_ld, sigma, tau)
    elif y is not None:
        cert = _jammed_certificate(s, np.asarray(y, dtype=np.longdouble), -math.inf, tau)
    if cert is not None and cert.accepted:
        return cert, best, "", ""
    return cert, best, *_why(cert, best, s, tau, lam)


def _why(cert, motion, s: _System, tau: float, lam: float) -> tuple[str, str]:
    """Why neither side was accepted: within resolution or not resolved, in one clause each."""
    if cert is not None and cert.accepted:
        return "", ""
    parts = []
    if cert is not None:
        parts.append(
            f"best forces: strictness {cert.strictness:.2e}, residual {cert.residual:.2e}, "
            f"sigma {cert.sigma:.2e}, margin {cert.margin:.2e}"
        )
    if motion is not None:
        parts.append(f"best motion: violation {motion.violation:.2e}, opening {motion.opening:.2e}")
    evidence = ""
    if cert is not None and 0 < cert.margin <= tau:
        evidence = (f"every motion closes some contact by at least {cert.margin:.2e} of its size, "
                    "below tau")  # fmt: skip
    elif np.isfinite(lam) and lam >= 0:
        needed = tau * (s.n_rows + math.sqrt(s.n_rows))
        if math.sqrt(lam) <= needed:
            evidence = (f"a near-mechanism with |A x| = {math.sqrt(lam):.2e} |x| lies below the "
                        f"{needed:.2e} a jammed certificate needs")  # fmt: skip
    if evidence:
        return WITHIN_RESOLUTION, "; ".join([f"{WITHIN_RESOLUTION}: {evidence}", *parts])
    return NOT_RESOLVED, "; ".join([f"{NOT_RESOLVED}: no candidate reaches either side", *parts])
