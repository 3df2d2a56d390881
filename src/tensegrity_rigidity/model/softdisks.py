"""Random bidisperse soft-sphere packings: the harmonic overlap energy minimised by FIRE.

O'Hern, Silbert, Liu and Nagel (Phys. Rev. E 68, 011306, 2003): ``N / 2`` small and ``N / 2`` large
particles (diameter ratio 1.4, small diameter 1) at random positions in a square (cubic) periodic
box of packing fraction ``phi``, then the energy ``U = sum_{ij} (1 - r_ij / s_ij)^2 / 2`` over
overlapping pairs (``s_ij = a_i + a_j``) minimised by FIRE on a Verlet neighbour list.
Above jamming the minimum keeps overlaps in force balance; its overlapping pairs are the contacts
(``Packing.contact_network(tolerance=0)``). :func:`jammed_packing` compresses and decompresses
one sample until its energy per particle lies in a window just above zero: a packing at its
jamming onset.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ..errors import InputError
from .packing import Packing

__all__ = [
    "DIAMETER_RATIO",
    "FIRE",
    "GRADIENT_TOL",
    "MAX_STEPS",
    "SoftPacking",
    "bidisperse_radii",
    "box_side",
    "jammed_packing",
    "minimise",
    "soft_packing",
]

#: Diameter ratio of the large to the small particles (O'Hern et al. 2003).
DIAMETER_RATIO = 1.4
#: Largest force component at which the minimisation stops (units of the energy scale over
#: the small diameter): far below the forces of any packing this package tests.
GRADIENT_TOL = 1e-14
#: Most FIRE steps of one minimisation (a packing near its jamming point at N = 1024 takes up to
#: about 10^5).
MAX_STEPS = 200_000


@dataclass(frozen=True)
class SoftPacking:
    """A minimised soft-sphere packing.

    Attributes
    ----------
    packing : Packing
        Positions, radii and the box.
    energy : float
        Energy per particle at the end of the minimisation.
    gradient : float
        Largest gradient component there.
    iterations : int
        FIRE steps.
    phi : float
        Packing fraction.
    """

    packing: Packing
    energy: float
    gradient: float
    iterations: int
    phi: float


def bidisperse_radii(n: int, ratio: float = DIAMETER_RATIO) -> np.ndarray:
    """Radii of ``n // 2`` small (diameter 1) then ``n - n // 2`` large particles.

    Parameters
    ----------
    n : int
        Particles.
    ratio : float
        Diameter ratio of large to small.

    Returns
    -------
    (n,) float
        The radii.
    """
    small = n // 2
    return np.r_[np.full(small, 0.5), np.full(n - small, 0.5 * ratio)]


def box_side(radii: np.ndarray, phi: float, dim: int) -> float:
    """Side of the cubic box in which particles of ``radii`` fill the fraction ``phi``.

    Parameters
    ----------
    radii : (N,) float
        Radii.
    phi : float
        Packing fraction.
    dim : int
        2 or 3.

    Returns
    -------
    float
        The side ``L`` with ``sum v(a_i) = phi L^d``.
    """
    volume = np.pi * radii**2 if dim == 2 else 4.0 * np.pi * radii**3 / 3.0
    return float((volume.sum() / phi) ** (1.0 / dim))


class _Energy:
    """The harmonic overlap energy of particles in a cubic box, on a Verlet neighbour list."""

    def __init__(self, radii: np.ndarray, side: float, dim: int):
        self.radii, self.side, self.dim = radii, side, dim
        self.skin = 0.2 * float(radii.min())
        self.cutoff = 2.0 * float(radii.max()) + self.skin
        if side <= 2.0 * self.cutoff:
            raise InputError(
                f"the box (side {side:.3g}) is too small for its particles: use more particles"
            )
        self.ref: np.ndarray | None = None
        self.i = self.j = np.zeros(0, dtype=np.int64)

    def _neighbours(self, x: np.ndarray) -> None:
        wrapped = np.mod(x, self.side)
        wrapped[wrapped >= self.side] = 0.0
        pairs = cKDTree(wrapped, boxsize=self.side).query_pairs(self.cutoff, output_type="ndarray")
        self.i, self.j = pairs[:, 0].astype(np.int64), pairs[:, 1].astype(np.int64)
        self.ref = x.copy()

    def pairs(self, x: np.ndarray):
        """Overlapping pairs at ``x`` (N, d): (i, j, separation vectors, distances, s_ij)."""
        if self.ref is None or np.max(np.abs(x - self.ref)) > 0.5 * self.skin / math.sqrt(self.dim):
            self._neighbours(x)
        d = x[self.j] - x[self.i]
        d -= self.side * np.round(d / self.side)
        r = np.sqrt(np.einsum("bi,bi->b", d, d))
        s = self.radii[self.i] + self.radii[self.j]
        on = r < s
        return self.i[on], self.j[on], d[on], r[on], s[on]

    def __call__(self, flat: np.ndarray):
        x = flat.reshape(-1, self.dim)
        i, j, d, r, s = self.pairs(x)
        overlap = 1.0 - r / s
        energy = 0.5 * float(np.dot(overlap, overlap))
        f = (overlap / (s * r))[:, None] * d  # -dU/dx_j
        n = len(x)
        grad = np.stack(
            [np.bincount(i, f[:, a], n) - np.bincount(j, f[:, a], n) for a in range(self.dim)],
            axis=1,
        )
        return energy, grad.ravel()


#: FIRE's constants (Bitzek et al., Phys. Rev. Lett. 97, 170201, 2006): first and largest time
#: step (unit masses and stiffness), steps before the time step grows, growth and cut factors,
#: the first mixing and its decay.
FIRE = {"dt": 0.05, "dt_max": 0.5, "n_min": 5, "grow": 1.1, "cut": 0.5, "alpha": 0.1, "decay": 0.99}


def minimise(
    positions: np.ndarray, radii: np.ndarray, side: float, max_steps: int = MAX_STEPS
) -> tuple[np.ndarray, float, float, int]:
    """Minimise the overlap energy from ``positions`` (N, d) in a cubic box of ``side`` by FIRE,
    until every force component is below :data:`GRADIENT_TOL` or after ``max_steps`` steps.

    Parameters
    ----------
    positions : (N, d) float
        Start.
    radii : (N,) float
        Radii.
    side : float
        Side of the cubic box.
    max_steps : int
        Most FIRE steps.

    Returns
    -------
    positions : (N, d) float
        The minimiser, wrapped into the box.
    energy, gradient : float
        Energy per particle and largest force component at the end.
    steps : int
        FIRE steps.
    """
    dim = positions.shape[1]
    fun = _Energy(radii, side, dim)
    x = positions.ravel().astype(float)
    v = np.zeros_like(x)
    dt, alpha, positive = FIRE["dt"], FIRE["alpha"], 0
    energy, grad = fun(x)
    force = -grad
    steps = 0
    while steps < max_steps and np.max(np.abs(force), initial=0.0) >= GRADIENT_TOL:
        steps += 1
        if float(force @ v) > 0:
            positive += 1
            if positive > FIRE["n_min"]:
                dt, alpha = min(dt * FIRE["grow"], FIRE["dt_max"]), alpha * FIRE["decay"]
        else:  # uphill: stop, step back half a step, restart slowly
            positive, dt, alpha = 0, dt * FIRE["cut"], FIRE["alpha"]
            x -= 0.5 * dt * v
            v[:] = 0.0
        v += dt * force
        norm_f = float(np.linalg.norm(force))
        if norm_f > 0:
            v = (1.0 - alpha) * v + alpha * float(np.linalg.norm(v)) / norm_f * force
        x += dt * v
        energy, grad = fun(x)
        force = -grad
    out = np.mod(x.reshape(-1, dim), side)
    out[out >= side] = 0.0
    energy, grad = fun(out.ravel())
    return out, energy / len(radii), float(np.max(np.abs(grad), initial=0.0)), steps


def _check(n: int, phi: float, dim: int) -> None:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
        raise InputError(f"n must be an integer of at least 2, got {n!r}")
    if not (isinstance(phi, (int, float)) and 0 < phi < 1):
        raise InputError(f"phi must lie in (0, 1), got {phi!r}")
    if dim not in (2, 3):
        raise InputError(f"dim must be 2 or 3, got {dim!r}")


def soft_packing(
    n: int,
    phi: float,
    rng: np.random.Generator,
    dim: int = 2,
    ratio: float = DIAMETER_RATIO,
    max_steps: int = MAX_STEPS,
) -> SoftPacking:
    """A random bidisperse soft packing at packing fraction ``phi``, energy minimised.

    Parameters
    ----------
    n : int
        Particles (half small, half large).
    phi : float
        Packing fraction of the box.
    rng : numpy.random.Generator
        Source of the initial positions (uniform in the box).
    dim : int
        2 (disks) or 3 (spheres).
    ratio : float
        Diameter ratio of large to small particles.
    max_steps : int
        Most FIRE steps.

    Returns
    -------
    SoftPacking
        The minimised packing; its contacts are its overlapping pairs
        (``.packing.contact_network(tolerance=0)``).
    """
    _check(n, phi, dim)
    radii = bidisperse_radii(n, ratio)
    side = box_side(radii, phi, dim)
    x0 = rng.uniform(0.0, side, size=(n, dim))
    x, energy, grad, it = minimise(x0, radii, side, max_steps)
    return SoftPacking(Packing(x, radii, side * np.eye(dim)), energy, grad, it, float(phi))


def jammed_packing(
    n: int,
    rng: np.random.Generator,
    dim: int = 2,
    ratio: float = DIAMETER_RATIO,
    energy_window: tuple[float, float] = (1e-16, 2e-16),
    phi_start: float | None = None,
    max_steps: int = 200,
) -> SoftPacking:
    """A bidisperse packing at its jamming onset: compressed and decompressed (affinely, each
    step minimised) until the energy per particle lies in ``energy_window``.

    The step in ``phi`` starts at ``1e-3`` and halves at every change of direction (O'Hern et al.
    2003); the result has overlaps of about ``sqrt(energy)`` and a backbone at the isostatic count.

    Parameters
    ----------
    n, rng, dim, ratio
        As :func:`soft_packing`.
    energy_window : (float, float)
        Energy per particle to end in (units of the energy scale).
    phi_start : float, optional
        Packing fraction of the random start (default 0.84 in 2D, 0.64 in 3D).
    max_steps : int
        Most minimisations.

    Returns
    -------
    SoftPacking
        The packing at the last step (``energy`` tells whether it reached the window).
    """
    lo, hi = energy_window
    phi = (0.84 if dim == 2 else 0.64) if phi_start is None else float(phi_start)
    _check(n, phi, dim)
    radii = bidisperse_radii(n, ratio)
    side = box_side(radii, phi, dim)
    x, energy, grad, it = minimise(rng.uniform(0.0, side, size=(n, dim)), radii, side)
    step, direction, total = 1e-3, 0, it
    for _ in range(max_steps):
        if lo <= energy <= hi:
            break
        new = 1 if energy < lo else -1  # compress while below the window
        if direction and new != direction:
            step *= 0.5
        direction = new
        phi_new = phi * (1 + new * step)
        scale = (phi / phi_new) ** (1.0 / dim)
        phi, side = phi_new, side * scale
        x, energy, grad, it = minimise(x * scale, radii, side)
        total += it
    return SoftPacking(Packing(x, radii, side * np.eye(dim)), energy, grad, total, float(phi))
