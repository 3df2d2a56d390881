"""Self-stresses near approximate tensions (solver/selfstress.py): where purification gives up
early, that giving up loses no certificate, and the support optimum of the energy's dual."""

from __future__ import annotations

import dataclasses

import numpy as np

from tensegrity_rigidity import lattice_instance
from tensegrity_rigidity.solver.certificates import Resolution
from tensegrity_rigidity.solver.problem import Problem
from tensegrity_rigidity.solver.selfstress import purify

RES = Resolution()


def _affine(inst):
    """The problem and the tensions of its affine deformation (a poor rigid guess)."""
    p = Problem(inst, unit_stiffness=True)
    _, _, t = p.state(np.zeros(p.n2))
    return p, t


def _purify_counted(p, t, **kw):
    """``purify(p, t, **kw)`` and the factorisations it took."""
    before = p.factorizations
    tp = purify(p, t, **kw)
    return tp, p.factorizations - before


def test_purification_stops_after_two_rounds_without_positive_work():
    """Shear, n = 8, p_r = 0.55, p_t = 0.3, f_c = 0.5, seed 58: the affine tensions balance
    on their support after each round but do no positive work, and one-sided elements keep
    flipping. Without the stall rule purification goes on for 5 rounds (5 factorisations)
    and ends rejected; with it, it stops after the second such round, with the flipped signs
    left, so the result is no certificate either."""
    p, t = _affine(lattice_instance(8, 0.55, 0.3, 0.5, phi="shear", seed=58))
    full, n_full = _purify_counted(p, t, stall=0)
    stalled, n_stalled = _purify_counted(p, t)
    assert not p.exact.rigid(full, RES).accepted
    assert np.any(p.sigma * stalled < 0) and not p.exact.rigid(stalled, RES).accepted
    assert n_stalled == 2 < n_full
    assert float(stalled @ p.e0) <= 0.0


def test_rounds_doing_round_off_work_count_as_doing_none():
    """Shear (angle 0.4), n = 8, p_r = 0.4, p_t = 0.2, f_c = 0.5, seed 134: each round balances
    a self-stress of rods on which the strain does work at round-off (``3.9e-17`` of its size
    after the last, positive). Counted only when ``t . e0 <= 0``, such rounds went on for 4
    factorisations; at or below the resolution's work they stop after 2, with the flipped
    signs left. Neither result is a certificate."""
    inst = lattice_instance(8, 0.4, 0.2, 0.5, phi="shear", theta=0.4, seed=134)
    p, t = _affine(inst)
    signed, n_signed = _purify_counted(p, t, work_floor=0.0)
    floored, n_floored = _purify_counted(p, t)
    assert abs(float(signed @ p.e0)) < 1e-15 * float(np.abs(signed).sum())
    assert n_floored == 2 < n_signed == 4
    assert np.any(p.sigma * floored < 0)
    assert not p.exact.rigid(signed, RES).accepted
    assert not p.exact.rigid(floored, RES).accepted


def test_the_stall_rule_loses_no_certificate_on_small_lattices():
    """On 200 small sheared lattices around the transition, every purification of the affine
    tensions that is a certificate without the stall rule is one with it, and the rule never
    costs a factorisation, nor does counting round-off work as none (``work_floor``)."""
    accepted = 0
    for seed in range(40):
        for p_r in (0.45, 0.5, 0.55, 0.6, 0.65):
            p, t = _affine(lattice_instance(8, p_r, 0.3, 0.5, phi="shear", seed=seed))
            full, n_full = _purify_counted(p, t, stall=0)
            signed, n_signed = _purify_counted(p, t, work_floor=0.0)
            fast, n_fast = _purify_counted(p, t)
            a, b = p.exact.rigid(full, RES).accepted, p.exact.rigid(fast, RES).accepted
            assert b == a and n_fast <= n_signed <= n_full, (seed, p_r)
            accepted += a
    assert accepted > 20  # the set holds certificates to lose


def test_a_hopeless_purification_skips_the_extended_precision_steps():
    """Shear, n = 8, p_r = 0.45, p_t = 0.3, f_c = 0.5, seed 53: the affine tensions stay 0.8
    of their size away from balance after the first projection. The extended-precision
    steps cannot bring such a residual near a certificate's margin, so the double-precision
    projection is returned as it is (they would have returned a longdouble array)."""
    p, t = _affine(lattice_instance(8, 0.45, 0.3, 0.5, phi="shear", seed=53))
    tp = purify(p, t)
    assert tp.dtype == np.float64
    assert not np.any(p.sigma * tp < 0)
    assert float(np.abs(p.RT @ tp).sum()) > 1e-3 * float(np.abs(tp).sum())
    assert not p.exact.rigid(tp, RES).accepted


def _dual_bound(p, t):
    """The energy's dual at the best multiple of the self-stress ``t``: ``(t . e0)^2 / (2 t .
    K^-1 t)``."""
    t = np.asarray(t, dtype=float)
    return float(t @ p.e0) ** 2 / (2.0 * float(t @ (t / p.k)))


def test_the_support_optimum_does_not_depend_on_the_point_the_tensions_come_from():
    """Rigid n = 8 lattices with random stiffnesses (0.5 to 2): from the tensions ``K (e0 + R
    u)`` of the minimiser's engaged set at a point ``u`` 1e-3 away from the minimiser, the
    stiffness-weighted projection returns the minimiser's own tensions (``t*``, to 1e-9
    relative), whose dual bound is ``E*``; purification (weighed by ``t^2``) from the same
    tensions lands on another self-stress, whose bound is lower by more than 1e-6 relative on
    at least three quarters of them (all 12 here)."""
    from tensegrity_rigidity.solver.core import SolverOptions
    from tensegrity_rigidity.solver.relaxation import _relax
    from tensegrity_rigidity.solver.selfstress import optimal_on_support

    rng = np.random.default_rng(5)
    checked = looser = 0
    for seed in range(12):
        base = lattice_instance(8, 0.75, 0.15, 0.5, phi="compression", theta=0.3, seed=seed)
        k = rng.uniform(0.5, 2.0, base.network.n_sites)
        inst = dataclasses.replace(base, network=dataclasses.replace(base.network, stiffness=k))
        p = Problem(inst)
        u, E, _ = _relax(p, np.zeros(p.n2), SolverOptions())
        e, engaged, t_star = p.state(u)
        if E <= 0 or float(np.abs(p.RT @ t_star).sum()) > 1e-12 * float(np.abs(t_star).sum()):
            continue  # floppy, or the minimiser is not resolved
        u_off = u + 1e-3 * rng.standard_normal(p.n2)
        t_off = np.where(engaged, p.k * (p.e0 + p.R @ u_off), 0.0)
        x = optimal_on_support(p, t_off)
        assert x is not None
        x = np.asarray(x, dtype=float)
        assert np.abs(x - t_star).max() <= 1e-9 * np.abs(t_star).max(), seed
        assert abs(_dual_bound(p, x) - E) <= 1e-10 * E
        purified = np.asarray(purify(p, t_off), dtype=float)
        looser += _dual_bound(p, purified) < (1 - 1e-6) * E
        checked += 1
    assert checked >= 8 and 4 * looser >= 3 * checked, (checked, looser)


def test_purification_reads_its_defaults_from_the_problems_tolerances():
    """The instance of the test above: a problem whose ``Tolerances.purify_work_floor`` is 0
    purifies as an explicit ``work_floor=0`` does (4 factorisations, not 2), so the default
    is the options' field, part of the settings digest."""
    from tensegrity_rigidity.solver.tolerances import Tolerances

    inst = lattice_instance(8, 0.4, 0.2, 0.5, phi="shear", theta=0.4, seed=134)
    p = Problem(inst, unit_stiffness=True, tolerances=Tolerances(purify_work_floor=0.0))
    _, _, t = p.state(np.zeros(p.n2))
    tp, n = _purify_counted(p, t)
    explicit, n_explicit = _purify_counted(Problem(inst, unit_stiffness=True), t, work_floor=0.0)
    assert n == n_explicit == 4
    assert np.array_equal(tp, explicit)
