"""Networks in three dimensions: the FCC builder, mixed dimensions refused, 3D strains, files."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from tensegrity_rigidity import (
    InputError,
    Instance,
    PeriodicNetwork,
    decide,
    lattice_instance,
    load_instance,
    random_periodic_network,
    save_instance,
    strain_tensor,
)
from tensegrity_rigidity.model.lattice import (
    CROSSING_DELTA,
    FCC_VECTORS,
    CrossingBondsWarning,
    fcc_lattice,
    inverted_tetrahedra,
)
from tensegrity_rigidity.model.mechanics import affine_extensions, rigidity_matrix
from tensegrity_rigidity.model.network import norms_from_squares, vector_norms
from tensegrity_rigidity.model.strain import check_rotation, sequence_rotation


@pytest.mark.parametrize("n", [2, 3, 4])
def test_fcc_lattice_has_n3_nodes_6n3_sites_and_12_unit_neighbours(n):
    net = fcc_lattice(n, delta=0.0)
    assert (net.dim, net.n_nodes, net.n_sites) == (3, n**3, 6 * n**3)
    np.testing.assert_allclose(net.bond_lengths(), 1.0, rtol=1e-14)
    np.testing.assert_allclose(net.box, n * FCC_VECTORS)
    assert set(np.bincount(net.bonds.ravel(), minlength=net.n_nodes)) == {12}
    if n >= 3:  # every node's 12 neighbours are distinct nodes
        for i in range(0, net.n_nodes, 7):
            mine = (net.bonds[:, 0] == i) | (net.bonds[:, 1] == i)
            others = np.where(net.bonds[mine, 0] == i, net.bonds[mine, 1], net.bonds[mine, 0])
            assert len(set(others.tolist())) == 12


def test_the_perfect_fcc_lattice_has_only_the_three_translations_as_mechanisms():
    net = fcc_lattice(3, delta=0.0)
    R = rigidity_matrix(net).toarray()
    assert R.shape == (6 * 27, 3 * 27)
    assert np.linalg.matrix_rank(R) == 3 * 27 - 3


def test_fcc_disorder_warns_when_tetrahedra_invert_and_refuses_half_a_bond():
    assert CROSSING_DELTA["fcc"] == pytest.approx(1 / (3 * np.sqrt(2)))
    with warnings.catch_warnings():
        warnings.simplefilter("error", CrossingBondsWarning)
        net = fcc_lattice(5, 0.2, np.random.default_rng(1))
    assert inverted_tetrahedra(net) == 0
    with pytest.warns(CrossingBondsWarning, match="tetrahedra"):
        fcc_lattice(6, 0.45, np.random.default_rng(2))
    with pytest.raises(InputError, match="below 0.5"):
        fcc_lattice(3, 0.5, np.random.default_rng(1))


def test_a_corner_kick_at_the_crossing_delta_flattens_a_tetrahedron():
    """The corner argument behind CROSSING_DELTA["fcc"]: just below it no kick inverts the
    tetrahedron (0, a1, a2, a3); at it the worst corner makes its volume zero."""
    import itertools

    corners = np.array(list(itertools.product([-1.0, 1.0], repeat=12))).reshape(-1, 4, 3)
    tet = np.vstack([np.zeros(3), FCC_VECTORS])

    def least_volume(delta):
        p = tet[None] + delta * corners
        return np.linalg.det(np.stack([p[:, 1] - p[:, 0], p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]], 1))

    assert least_volume(0.999 * CROSSING_DELTA["fcc"]).min() > 0
    assert least_volume(CROSSING_DELTA["fcc"]).min() == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize(
    ("over", "needle"),
    [
        (dict(positions=np.zeros((2, 2))), "positions must have shape"),
        (dict(shifts=np.zeros((1, 2), dtype=int)), "shifts must have shape"),
        (dict(box=np.eye(4)), "box must have shape"),
        (dict(box=np.ones((3, 2))), "box must have shape"),
        (dict(box=np.diag([1.0, 1.0, 0.0])), "zero volume"),
    ],
)
def test_wrong_or_mixed_dimensions_are_one_line_errors(over, needle):
    good = dict(
        box=np.eye(3) * 2,
        positions=[[0.0, 0.0, 0.0], [1.0, 0.3, 0.2]],
        bonds=[[0, 1]],
        shifts=[[0, 0, 0]],
        kinds=[1],
    )
    PeriodicNetwork(**good)
    with pytest.raises(InputError, match=needle) as info:
        PeriodicNetwork(**{**good, **over})
    assert "\n" not in str(info.value)


def test_a_2d_strain_on_a_3d_network_is_refused():
    net = fcc_lattice(2, delta=0.0)
    with pytest.raises(InputError, match="3-dimensional"):
        Instance(net, np.eye(2))
    with pytest.raises(InputError, match="2-dimensional"):
        Instance(lattice_instance(3, 0.5).network, np.eye(3))


@pytest.mark.parametrize(
    ("phi", "eigenvalues"),
    [("dilation", [1, 1, 1]), ("shear", [-1, 0, 1]), ("compression", [-1, -1, -1])],
)
def test_3d_strains_have_the_principal_values_of_their_kind_about_any_axes(phi, eigenvalues):
    for k in (1, 2, 17):
        q = sequence_rotation(k)
        eps = strain_tensor(phi, gamma=2.0, rotation_matrix=q)
        np.testing.assert_allclose(eps, eps.T)
        np.testing.assert_allclose(np.linalg.eigvalsh(eps), 2.0 * np.array(eigenvalues), atol=1e-12)
    np.testing.assert_allclose(strain_tensor("shear", dim=3), np.diag([1.0, -1.0, 0.0]), atol=1e-15)
    # in 2D the rotation form is the supplement's A(theta) diag(...) A(-theta)
    theta = 0.4
    a = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
    np.testing.assert_allclose(
        strain_tensor(1.0, rotation_matrix=a), strain_tensor(1.0, theta), atol=1e-15
    )


def test_a_rotation_must_be_proper_and_orthogonal():
    with pytest.raises(InputError, match="rotation"):
        check_rotation(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(InputError, match="rotation"):
        check_rotation(np.eye(3) * 1.01)
    with pytest.raises(InputError, match="shape"):
        check_rotation(np.eye(4))


def test_the_rotation_sequence_covers_so3_evenly_for_every_count():
    """The first K rotations of the sequence send a unit vector to points whose mean is near
    0 and whose second moments are near 1/3, as uniform rotations do, for small and large K;
    the sequence does not depend on K."""
    for count in (50, 500):
        z = np.array(
            [sequence_rotation(k) @ np.array([0.0, 0.0, 1.0]) for k in range(1, count + 1)]
        )
        assert np.abs(z.mean(axis=0)).max() < 4.0 / count**0.5 * 0.5
        np.testing.assert_allclose((z**2).mean(axis=0), 1 / 3, atol=0.04)
    np.testing.assert_array_equal(sequence_rotation(7), sequence_rotation(7))
    for k in (1, 100, 10_000):
        q = sequence_rotation(k)
        np.testing.assert_allclose(q @ q.T, np.eye(3), atol=1e-14)
        assert np.linalg.det(q) == pytest.approx(1.0)


def test_rotating_positions_box_and_strain_together_leaves_the_affine_extensions():
    inst = lattice_instance(3, 0.6, 0.2, phi="shear", lattice="fcc", seed=4)
    net = inst.network
    q = sequence_rotation(3)
    turned = PeriodicNetwork(net.box @ q.T, net.positions @ q.T, net.bonds, net.shifts, net.kinds)
    np.testing.assert_allclose(
        affine_extensions(turned, q @ inst.strain @ q.T),
        affine_extensions(net, inst.strain),
        rtol=1e-12,
        atol=1e-13,
    )


def test_3d_instances_round_trip_through_files(tmp_path):
    rng = np.random.default_rng(3)
    inst = lattice_instance(
        3, 0.6, 0.3, phi="compression", lattice="fcc", seed=2, rotation_matrix=sequence_rotation(5)
    )
    save_instance(tmp_path / "fcc.npz", inst)
    back = load_instance(tmp_path / "fcc.npz")
    assert back.network.dim == 3
    np.testing.assert_array_equal(back.network.positions, inst.network.positions)
    np.testing.assert_array_equal(back.strain, inst.strain)
    net = random_periodic_network(12, 40, rng, dim=3)
    assert net.dim == 3 and net.shifts.shape == (40, 3)
    assert np.all(net.bond_lengths() > 0)


@pytest.mark.parametrize("scale", [1e-300, 1e-170, 1.3e154, 1e200, 1e300])
def test_fcc_boxes_at_extreme_scales_keep_their_lengths_and_verdicts(scale):
    """3D bond lengths must not square into under- or overflow: a box of 1e-170 was refused
    as "bond 0 has zero length" and boxes around 1.3e154 or beyond left rigid samples
    undecided, where 2D (hypot) kept them."""
    inst = lattice_instance(3, 0.7, 0.2, f_c=0.5, phi="dilation", lattice="fcc", seed=1)
    net = inst.network
    scaled = PeriodicNetwork(
        net.box * scale, net.positions * scale, net.bonds, net.shifts, net.kinds
    )
    assert np.allclose(scaled.bond_lengths() / scale, net.bond_lengths(), rtol=1e-14, atol=0)
    assert inverted_tetrahedra(scaled) == inverted_tetrahedra(net) == 0
    e0 = affine_extensions(scaled, inst.strain)
    assert np.allclose(e0 / scale, affine_extensions(net, inst.strain), rtol=1e-12, atol=0)
    a = decide(inst)
    b = decide(Instance(scaled, inst.strain / scale))
    assert a.status == "rigid"
    assert (a.status, a.stage) == (b.status, b.stage)


def test_3d_norms_at_ordinary_scales_are_the_plain_formula_bit_for_bit():
    """The scaled norm rescales only rows out of range: everywhere else it is the plain
    square root of the sum of squares, so no ordinary verdict moves by a bit."""
    rng = np.random.default_rng(3)
    v = rng.normal(size=(2000, 3)) * 10.0 ** rng.uniform(-100, 100, size=(2000, 1))
    assert np.array_equal(vector_norms(v), np.sqrt(np.einsum("bi,bi->b", v, v)))
    ld = v.astype(np.longdouble)
    squares = (ld * ld).sum(axis=1)
    assert np.array_equal(norms_from_squares(ld, squares), np.sqrt(squares))


@pytest.mark.parametrize("exponent", [-1040, -1000, -520, -300, 300, 511, 600, 1020])
def test_3d_norms_keep_their_digits_at_any_scale(exponent):
    rng = np.random.default_rng(4)
    v = rng.normal(size=(50, 3))
    want = np.sqrt(np.einsum("bi,bi->b", v, v))
    got = vector_norms(np.ldexp(v, exponent))
    # exact below the subnormal range; there the components themselves lost digits
    rtol = 1e-15 if exponent > -1000 else 1e-9
    assert np.allclose(np.ldexp(got, -exponent), want, rtol=rtol, atol=0)
    for scale in (1e-170, 1e200):
        d = v * scale
        with np.errstate(over="ignore"):  # the squares overflow: that is the case tested
            squares = (d * d).sum(axis=1)
        assert np.allclose(norms_from_squares(d, squares) / scale, want, rtol=1e-15)
