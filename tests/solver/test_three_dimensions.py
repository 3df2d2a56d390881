"""Certified verdicts in three dimensions: the independent LP agrees, rotations change nothing,
the perfect FCC lattice relaxes affinely."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from benchmarks.reference import lp_verdict
from tensegrity_rigidity import (
    Element,
    Instance,
    PeriodicNetwork,
    UndecidedWarning,
    decide,
    lattice_instance,
    random_periodic_network,
    solve,
    strain_tensor,
)
from tensegrity_rigidity.model.elements import place_elements, site_uniforms
from tensegrity_rigidity.model.lattice import fcc_lattice
from tensegrity_rigidity.model.mechanics import energy
from tensegrity_rigidity.model.strain import sequence_rotation

STRAINS = ("dilation", "shear", "compression", 0.9, 2.3)


def _fcc_case(i: int) -> Instance:
    rng = np.random.default_rng(1000 + i)
    p_r = rng.uniform(0.2, 0.9)
    p_t = rng.uniform(0.0, 1.0 - p_r)
    return lattice_instance(
        int(rng.integers(2, 5)),
        p_r,
        p_t,
        rng.uniform(),
        phi=STRAINS[i % len(STRAINS)],
        lattice="fcc",
        seed=i,
        rotation_matrix=sequence_rotation(i + 1),
    )


def _random_case(i: int) -> Instance:
    rng = np.random.default_rng(2000 + i)
    n_nodes = int(rng.integers(3, 12))
    net = random_periodic_network(n_nodes, int(rng.integers(2, 5 * n_nodes)), rng, dim=3)
    u, v = site_uniforms(net.n_sites, rng)
    p_r = rng.uniform(0.1, 0.9)
    kinds = place_elements(u, v, p_r, rng.uniform(0, 1 - p_r), rng.uniform())
    strain = strain_tensor(STRAINS[i % len(STRAINS)], rotation_matrix=sequence_rotation(7 * i + 3))
    return Instance(net.with_kinds(kinds), strain)


def _agreement(cases) -> tuple[int, int]:
    decided = 0
    for i, inst in enumerate(cases):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UndecidedWarning)
            v = decide(inst)
        if not v.decided:
            continue
        decided += 1
        ref = lp_verdict(inst)
        assert (v.status == "rigid") == ref.rigid, (i, v.status, ref)
    return decided, len(cases)


def test_fcc_verdicts_agree_with_the_independent_lp():
    """120 disordered FCC samples (n = 2 to 4), every strain kind, mixed elements."""
    decided, total = _agreement([_fcc_case(i) for i in range(120)])
    assert decided >= 0.95 * total


def test_random_3d_network_verdicts_agree_with_the_independent_lp():
    """100 random periodic 3D networks in skewed boxes, with images and self-images."""
    decided, total = _agreement([_random_case(i) for i in range(100)])
    assert decided >= 0.95 * total


@pytest.mark.parametrize("i", range(6))
def test_rotating_positions_box_and_strain_together_changes_neither_verdict_nor_energy(i):
    inst = _fcc_case(i)
    net = inst.network
    q = sequence_rotation(40 + i)
    turned = Instance(
        PeriodicNetwork(net.box @ q.T, net.positions @ q.T, net.bonds, net.shifts, net.kinds),
        q @ inst.strain @ q.T,
    )
    a, b = solve(inst), solve(turned)
    assert a.status == b.status
    assert b.energy == pytest.approx(a.energy, rel=1e-8, abs=1e-12 * a.affine_energy)
    np.testing.assert_allclose(
        b.displacements, a.displacements @ q.T, atol=1e-7 * max(1.0, np.abs(a.displacements).max())
    )


@pytest.mark.parametrize("phi", ["dilation", "shear", "compression"])
def test_the_perfect_fcc_lattice_of_rods_relaxes_affinely(phi):
    """Every node of the perfect FCC lattice is a centre of inversion: the affine forces cancel
    at each node, so u = 0 is a minimiser and E* = E(u = 0) (the 3D counterpart of the
    perfect triangular lattice's exact case)."""
    net = fcc_lattice(3, delta=0.0)
    inst = Instance(
        net.with_kinds(np.full(net.n_sites, Element.ROD)),
        strain_tensor(phi, gamma=0.5, rotation_matrix=sequence_rotation(2)),
    )
    r = solve(inst)
    assert r.status == "rigid"
    assert r.energy == pytest.approx(energy(inst), rel=1e-10)
    assert np.abs(r.displacements).max() < 1e-9
