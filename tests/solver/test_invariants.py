"""Property tests (Hypothesis) of the exact invariants of MODEL.md."""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tensegrity_rigidity import Element, Instance, PeriodicNetwork, lattice_instance, solve
from tensegrity_rigidity.model.elements import place_elements
from tensegrity_rigidity.model.mechanics import affine_extensions, net_forces
from tensegrity_rigidity.model.sampling import lattice_geometry
from tensegrity_rigidity.model.strain import rotation, strain_tensor

SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@st.composite
def instances(draw):
    n = draw(st.integers(2, 6))
    p_r = draw(st.floats(0.0, 1.0))
    p_t = draw(st.floats(0.0, 1.0 - p_r))
    f_c = draw(st.sampled_from([0.0, 0.5, 1.0]) | st.floats(0.0, 1.0))
    phi = draw(st.floats(0.0, np.pi))
    theta = draw(st.floats(0.0, 2 * np.pi))
    gamma = 10 ** draw(st.floats(-4, 2))
    seed = draw(st.integers(0, 2**32 - 1))
    return lattice_instance(n, p_r, p_t, f_c, phi=phi, theta=theta, gamma=gamma, seed=seed)


def _rel(a, b):
    return abs(a - b) / max(abs(a), abs(b), 1e-300)


@SETTINGS
@given(instances())
def test_energy_nonnegative_and_below_affine(inst):
    res = solve(inst)
    assert res.decided
    assert 0.0 <= res.energy <= res.affine_energy * (1 + 1e-12) + 1e-300


@SETTINGS
@given(instances(), st.floats(-3, 3))
def test_energy_scales_as_gamma_squared(inst, log_scale):
    c = 10.0**log_scale
    a, b = solve(inst), solve(inst.with_strain(c * inst.strain))
    assert a.rigid == b.rigid
    if a.rigid:
        assert _rel(b.energy, c**2 * a.energy) < 1e-8


@SETTINGS
@given(instances(), st.floats(0, 2 * np.pi))
def test_rotating_everything_changes_nothing(inst, angle):
    q = rotation(angle)
    net = inst.network
    rotated = Instance(
        PeriodicNetwork(net.box @ q.T, net.positions @ q.T, net.bonds, net.shifts, net.kinds),
        q @ inst.strain @ q.T,
    )
    a, b = solve(inst), solve(rotated)
    assert a.rigid == b.rigid
    if a.rigid:
        assert _rel(a.energy, b.energy) < 1e-8
        # t* is unique, but near-degenerate networks (n = 2 has parallel bonds) determine it
        # only to the conditioning of the problem; its norm (|t*|^2 = 2 E* k) is well-conditioned.
        assert _rel(float(a.tensions @ a.tensions), float(b.tensions @ b.tensions)) < 1e-8


@SETTINGS
@given(instances())
def test_rod_equals_cable_plus_strut(inst):
    net = inst.network
    rods = np.flatnonzero(net.kinds == Element.ROD)
    if rods.size == 0:
        return
    kinds = net.kinds.copy()
    kinds[rods] = Element.CABLE
    split = Instance(
        PeriodicNetwork(
            net.box,
            net.positions,
            np.r_[net.bonds, net.bonds[rods]],
            np.r_[net.shifts, net.shifts[rods]],
            np.r_[kinds, np.full(rods.size, Element.STRUT)],
        ),
        inst.strain,
    )
    a, b = solve(inst), solve(split)
    assert a.rigid == b.rigid
    assert abs(a.energy - b.energy) <= 1e-8 * max(a.energy, 1e-12 * a.affine_energy)


@SETTINGS
@given(
    st.integers(2, 6),
    st.integers(0, 2**32 - 1),
    st.floats(0, 1),
    st.floats(0, 1),
    st.floats(0, 1),
    st.floats(0, 1),
    st.floats(0, np.pi),
)
def test_adding_elements_never_lowers_energy(n, seed, a, b, c, f_c, phi):
    """Raise p_r and p_t with the same site uniforms: E and rigidity can only grow."""
    rng = np.random.default_rng(seed)
    net, u, v = lattice_geometry(n, 0.2, rng)
    p_r1, p_t1 = a * b, (1 - a * b) * c * b  # a point below (p_r2, p_t2)
    p_r2 = p_r1 + (1 - p_r1) * a * (1 - b)
    p_t2 = max(p_t1 + p_r1 - p_r2, 0.0) + (1 - p_r2 - max(p_t1 + p_r1 - p_r2, 0.0)) * c
    eps = strain_tensor(phi)
    lo = solve(Instance(net.with_kinds(place_elements(u, v, p_r1, p_t1, f_c)), eps))
    hi = solve(Instance(net.with_kinds(place_elements(u, v, p_r2, p_t2, f_c)), eps))
    assert hi.energy >= lo.energy * (1 - 1e-9) - 1e-12 * lo.affine_energy
    assert hi.rigid or not lo.rigid


@SETTINGS
@given(instances())
def test_tension_signs_and_force_balance(inst):
    res = solve(inst)
    kinds = inst.network.kinds
    t = res.tensions
    assert np.all(t[kinds == Element.CABLE] >= 0)
    assert np.all(t[kinds == Element.STRUT] <= 0)
    assert np.all(t[kinds == Element.EMPTY] == 0)
    if res.rigid:
        forces = net_forces(inst.network, t)
        assert np.abs(forces).max() <= 1e-9 * np.abs(t).max()
        # at the optimum the work of t* on the strain is twice the energy
        assert _rel(float(t @ affine_extensions(inst.network, inst.strain)), 2 * res.energy) < 1e-8
    else:
        assert np.all(t == 0)


@SETTINGS
@given(instances())
def test_displacements_are_minimisers(inst):
    from tensegrity_rigidity.model.mechanics import energy

    res = solve(inst)
    e_u = energy(inst, res.displacements)
    # The displacements satisfy the minimisers' constraints to the min-norm tolerance (1e-8 of
    # max |e0|, above the floppy certificate's 1e-9): each engaged element can then hold an
    # energy of 1/2 k (1e-8 max |e0|)^2 that the exact minimum does not have.
    s0 = float(np.abs(affine_extensions(inst.network, inst.strain)).max())
    slack = 0.5 * float(inst.network.stiffness_or_ones().sum()) * (1e-8 * s0) ** 2
    assert abs(e_u - res.energy) <= 1e-8 * res.energy + slack
    np.testing.assert_allclose(
        res.displacements.mean(axis=0), 0, atol=1e-12 + 1e-9 * np.abs(res.displacements).max()
    )
