"""The resolution model: the two certificates exclude each other, by construction."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tensegrity_rigidity import Instance, SolverOptions, lattice_instance, solve, strain_tensor
from tensegrity_rigidity.solver import decide
from tensegrity_rigidity.solver.certificates import Resolution
from tensegrity_rigidity.solver.problem import Problem
from tensegrity_rigidity.solver.reference import lp_verdict
from tensegrity_rigidity.solver.selfstress import purify
from tests.instances import random_instance

RES = Resolution()


def _lp_candidates(inst, p):
    """The reference LP's tensions and displacements, in the problem's units."""
    lp = lp_verdict(inst)
    t = lp.tensions[p.sites]
    u = lp.displacements.ravel() / p.scale
    return lp, t, u


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_no_instance_is_certified_both_ways(seed):
    """For the accepted certificate of an instance, every candidate of the other kind that an
    independent LP offers (its tensions raw and purified, its dual displacements, and those
    displacements shifted by a huge translation) is rejected."""
    rng = np.random.default_rng(seed)
    inst = random_instance(rng)
    verdict = decide(inst)
    if not verdict.decided:
        return
    p = Problem(inst, unit_stiffness=True)
    lp, t, u = _lp_candidates(inst, p)
    if verdict.status == "rigid":
        for cand in (u, u + 1e3, np.zeros_like(u)):
            assert not p.exact.floppy(cand, RES).accepted
    else:
        t_adm = np.where(p.sigma * t < 0, 0.0, t)
        for cand in (t_adm, purify(p, t_adm) if np.any(t_adm) else t_adm):
            assert not p.exact.rigid(cand, RES).accepted


def test_a_floppy_displacement_beyond_the_bound_is_rejected():
    """A zero-energy displacement moved by a rigid translation of 1e9 strain units still has
    zero violation in exact arithmetic, but it is no certificate: at that size the rounding of
    e0 + R u alone exceeds the tolerance (the issue's n = 64 failure)."""
    rng = np.random.default_rng(5)
    checked = 0
    for _ in range(20):
        inst = random_instance(rng, "lattice")
        v = decide(inst)
        if v.status != "floppy":
            continue
        p = Problem(inst, unit_stiffness=True)
        u = v.floppy.u
        assert p.exact.floppy(u, RES).accepted
        far = u + 1e9
        cert = p.exact.floppy(far, RES)
        assert cert.size > RES.displacement and not cert.accepted
        checked += 1
    assert checked >= 3


def test_a_self_stress_whose_residual_could_explain_its_work_is_rejected():
    """Perturb an accepted self-stress so that its force residual times the displacement bound
    exceeds its work: rejected, although its work is still positive."""
    rng = np.random.default_rng(6)
    checked = 0
    for _ in range(30):
        inst = random_instance(rng, "lattice")
        v = decide(inst)
        if v.status != "rigid":
            continue
        p = Problem(inst, unit_stiffness=True)
        t = v.rigid.t
        assert p.exact.rigid(t, RES).accepted
        bumped = t.copy()
        i = int(np.argmax(np.abs(t)))
        bumped[i] *= 1 + 1e-3  # breaks force balance at two nodes by 1e-3 |t_i|
        cert = p.exact.rigid(bumped, RES)
        assert cert.work > 0 and not cert.accepted
        checked += 1
    assert checked >= 3


def test_wrong_signs_are_never_a_rigid_certificate():
    inst = lattice_instance(6, 0.3, 0.6, 1.0, phi="dilation", seed=2)
    p = Problem(inst, unit_stiffness=True)
    t = np.where(p.sigma > 0, -1.0, 0.0)  # compressed cables
    assert not p.exact.rigid(t, RES).accepted


@pytest.mark.parametrize("gamma", [1e-140, 1e-20, 1e20, 1e140])
def test_verdicts_do_not_depend_on_the_strain_magnitude(gamma):
    """The certificates work in units of max |e0|: no energy underflows to 0 or overflows."""
    rng = np.random.default_rng(7)
    for i in range(15):
        inst = random_instance(rng, "lattice")
        scaled = Instance(inst.network, inst.strain / np.abs(inst.strain).max() * gamma)
        unit = Instance(inst.network, inst.strain / np.abs(inst.strain).max())
        a, b = decide(unit), decide(scaled)
        assert (a.status, a.stage) == (b.status, b.stage), i


def test_energies_beyond_double_precision_are_refused():
    inst = lattice_instance(4, 0.8, 0.0, phi="shear", gamma=1e200, seed=1)
    with pytest.raises(Exception, match="not representable"):
        solve(inst)


def test_verdicts_do_not_depend_on_the_stiffnesses():
    """A stiffness contrast of 1e20 changes the energy, never the verdict (the LP's verdict
    does not involve stiffnesses; the search runs on unit stiffness)."""
    rng = np.random.default_rng(8)
    for i in range(20):
        inst = random_instance(rng, "lattice")
        k = 10.0 ** rng.uniform(-10, 10, inst.network.n_sites)
        stiff = Instance(
            type(inst.network)(
                inst.network.box,
                inst.network.positions,
                inst.network.bonds,
                inst.network.shifts,
                inst.network.kinds,
                k,
            ),
            inst.strain,
        )
        opts = SolverOptions(min_norm=False)
        a, b = solve(inst, opts), solve(stiff, opts)
        assert a.status == b.status == ("rigid" if lp_verdict(inst).rigid else "floppy"), i


def test_purify_returns_an_admissible_self_stress_at_round_off():
    """Purifying the tensions of a rigid sample's affine deformation (a poor guess) gives an
    exact self-stress: signs admissible, residual at round-off."""
    inst = lattice_instance(8, 0.8, 0.1, 0.5, phi="shear", seed=3)
    p = Problem(inst, unit_stiffness=True)
    _, _, t = p.state(np.zeros(p.n2))
    tp = purify(p, t)
    assert not np.any(p.sigma * tp < 0)
    cert = p.exact.rigid(tp, RES)
    assert cert.residual <= 1e-14 and cert.accepted


def test_an_unstrained_sample_is_floppy_with_u_zero():
    inst = lattice_instance(4, 0.9, 0.0, phi="shear", seed=1)
    zero = Instance(inst.network, strain_tensor("shear") * 0 + np.diag([1e-300, 0]) * 0)
    v = decide(zero)
    assert v.status == "floppy" and not np.any(v.floppy.u)
