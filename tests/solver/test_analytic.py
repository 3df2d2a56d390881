"""Cases with a known answer."""

from __future__ import annotations

import numpy as np
import pytest

from tensegrity_rigidity import (
    Element,
    Instance,
    PeriodicNetwork,
    SolverOptions,
    solve,
    strain_tensor,
    triangular_lattice,
)
from tensegrity_rigidity.model.mechanics import energy


@pytest.mark.parametrize("n", [2, 3, 5, 8])
@pytest.mark.parametrize("phi", [0.0, 0.7, np.pi / 2, np.pi])
def test_perfect_rod_lattice_deforms_affinely(n, phi):
    net = triangular_lattice(n, delta=0.0)
    net = net.with_kinds(np.full(net.n_sites, Element.ROD))
    inst = Instance(net, strain_tensor(phi, theta=0.3, gamma=0.01))
    res = solve(inst)
    assert res.rigid
    assert res.energy == pytest.approx(res.affine_energy, rel=1e-10)
    assert np.abs(res.displacements).max() <= 1e-10


def test_single_spring_in_a_box_under_strain():
    """One node, one rod to its own image along x: length 1 changes by eps_xx."""
    box = np.eye(2)
    net = PeriodicNetwork(box, [[0.0, 0.0]], [[0, 0]], [[1, 0]], [Element.ROD], [2.0])
    res = solve(Instance(net, [[0.1, 0.0], [0.0, 0.0]]))
    assert res.rigid
    assert res.energy == pytest.approx(0.5 * 2.0 * 0.1**2)


@pytest.mark.parametrize(
    "kind,sign,rigid",
    [
        (Element.CABLE, +1, True),
        (Element.CABLE, -1, False),
        (Element.STRUT, +1, False),
        (Element.STRUT, -1, True),
    ],
)
def test_self_image_cable_and_strut(kind, sign, rigid):
    net = PeriodicNetwork(np.eye(2), [[0.0, 0.0]], [[0, 0]], [[1, 0]], [kind])
    res = solve(Instance(net, [[sign * 0.1, 0.0], [0.0, 0.0]]))
    assert res.rigid is rigid
    assert res.energy == pytest.approx(0.005 if rigid else 0.0)


def test_empty_network_is_floppy():
    net = triangular_lattice(3, 0.1, np.random.default_rng(0))
    res = solve(Instance(net, strain_tensor("shear")))
    assert not res.rigid and res.decided and res.energy == 0.0


def test_floppy_certificate_has_zero_energy():
    net = triangular_lattice(4, 0.2, np.random.default_rng(1))
    kinds = np.where(np.arange(net.n_sites) % 3 == 0, Element.ROD, Element.EMPTY)
    inst = Instance(net.with_kinds(kinds), strain_tensor("dilation"))
    res = solve(inst)
    assert not res.rigid
    assert energy(inst, res.displacements) <= SolverOptions().violation_tol ** 2 * res.affine_energy
