"""The paper's way of deciding a sample: a generic local minimiser read by an energy threshold.

The paper minimises the energy with Mathematica's ``FindMinimum`` and calls a sample rigid "if
the energy is greater than 0" (supplement, section A). This reproduces it with SciPy's L-BFGS-B
at its default tolerances, the exact gradient ``R^T t``, from ``u = 0``: rigid when the energy
it stops at exceeds :data:`PAPER_THRESHOLD` times the affine energy. A minimiser stopped at
default tolerances resolves the energy to about half the machine digits of its scale
(Mathematica's ``PrecisionGoal``, L-BFGS-B's ``ftol`` = 2.2e-9), so "E > 0" is read as
``E > 1e-8 E(0)``; energies are stored, so other thresholds can be applied afterwards. Nothing
here is certified: this is the method under test, set beside
:func:`~tensegrity_rigidity.solver.core.solve` (and so it lives outside ``solver/``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize

from ..model.mechanics import affine_extensions, rigidity_matrix
from ..model.network import Element, Instance
from ..solver.linalg import one_blas_thread

#: rigid when the minimiser's energy exceeds this fraction of the affine energy (see above)
PAPER_THRESHOLD = 1e-8


@dataclass(frozen=True, eq=False)
class InexactResult:
    """The outcome of the paper's procedure on one instance.

    Attributes
    ----------
    rigid : bool
        ``energy > threshold * affine_energy``.
    energy : float
        Energy at the point where L-BFGS-B stopped.
    affine_energy : float
        E(u = 0).
    iterations, evaluations : int
        L-BFGS-B iterations and energy evaluations.
    converged : bool
        Whether L-BFGS-B reported success (its tolerances met, not its iteration limit).
    message : str
        L-BFGS-B's message.
    displacements : (N, d) float
        Where it stopped (mean translation removed).
    threshold : float
        The relative energy threshold of the verdict.
    seconds : float
        Wall time.
    """

    rigid: bool
    energy: float
    affine_energy: float
    iterations: int
    evaluations: int
    converged: bool
    message: str
    displacements: np.ndarray
    threshold: float
    seconds: float

    def record(self) -> dict:
        """The per-sample scalars stored by sweeps with ``verdict = "paper"``.

        Returns
        -------
        dict
            ``rigid``, ``decided`` (always True: the method always answers, which is the point of
            comparing it), ``energy``, ``affine_energy``, ``iterations``, ``evaluations``,
            ``converged``, ``method`` ("paper-lbfgsb"), ``solve_seconds``.
        """
        return {
            "rigid": bool(self.rigid),
            "decided": True,
            "energy": float(self.energy),
            "affine_energy": float(self.affine_energy),
            "iterations": int(self.iterations),
            "evaluations": int(self.evaluations),
            "converged": bool(self.converged),
            "method": "paper-lbfgsb",
            "solve_seconds": float(self.seconds),
        }


def paper_verdict(instance: Instance, threshold: float = PAPER_THRESHOLD) -> InexactResult:
    """Decide one instance the way the paper did (see the module docstring).

    Parameters
    ----------
    instance : Instance
        Network, elements and strain.
    threshold : float
        Relative energy threshold of the verdict (times the affine energy).

    Returns
    -------
    InexactResult
        Verdict, the energy reached, the iteration count and the point reached.
    """
    start = time.perf_counter()
    net = instance.network
    on = net.kinds != Element.EMPTY
    R = rigidity_matrix(net)[on]
    e0 = affine_extensions(net, instance.strain)[on]
    kinds = net.kinds[on]
    k = net.stiffness_or_ones()[on]
    rod = kinds == Element.ROD
    cable = kinds == Element.CABLE
    strut = kinds == Element.STRUT

    def energy_and_gradient(u):
        e = e0 + R @ u
        engaged = rod | (cable & (e > 0)) | (strut & (e < 0))
        t = np.where(engaged, k * e, 0.0)
        return 0.5 * float(t @ e), R.T @ t

    affine = energy_and_gradient(np.zeros(R.shape[1]))[0]
    with one_blas_thread():  # the same iterates whatever the thread settings
        res = minimize(energy_and_gradient, np.zeros(R.shape[1]), jac=True, method="L-BFGS-B")
    u = res.x.reshape(-1, instance.network.dim)
    u = u - u.mean(axis=0)
    energy = float(res.fun)
    return InexactResult(
        rigid=bool(energy > threshold * affine),
        energy=energy,
        affine_energy=float(affine),
        iterations=int(res.nit),
        evaluations=int(res.nfev),
        converged=bool(res.success),
        message=str(res.message),
        displacements=u,
        threshold=float(threshold),
        seconds=time.perf_counter() - start,
    )
