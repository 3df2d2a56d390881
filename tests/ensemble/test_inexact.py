"""The paper's procedure (L-BFGS-B + energy threshold): right where it cannot go wrong."""

from __future__ import annotations

import numpy as np
import pytest

from tensegrity_rigidity import SolverOptions, lattice_instance, solve, triangular_lattice
from tensegrity_rigidity.ensemble.inexact import PAPER_THRESHOLD, paper_verdict
from tensegrity_rigidity.model.mechanics import energy
from tensegrity_rigidity.model.network import Element, Instance
from tensegrity_rigidity.model.strain import strain_tensor


def test_perfect_rod_lattice_keeps_the_affine_energy():
    net = triangular_lattice(6, delta=0.0)
    inst = Instance(net.with_kinds(np.full(net.n_sites, Element.ROD)), strain_tensor("shear", 0.4))
    res = paper_verdict(inst)
    assert res.rigid and res.converged
    assert res.energy == pytest.approx(res.affine_energy, rel=1e-6)
    assert res.energy == pytest.approx(energy(inst), rel=1e-12)


@pytest.mark.parametrize("p_r,p_t,rigid", [(0.9, 0.05, True), (0.25, 0.2, False)])
@pytest.mark.parametrize("phi", ["dilation", "shear", "compression"])
def test_agrees_with_the_certified_verdict_far_from_the_transition(p_r, p_t, rigid, phi):
    for seed in range(3):
        inst = lattice_instance(8, p_r, p_t, 0.5, phi=phi, theta=0.3, seed=seed)
        res = paper_verdict(inst)
        assert res.rigid == rigid == solve(inst, SolverOptions(min_norm=False)).rigid


def test_never_below_the_exact_minimum_and_the_verdict_is_its_threshold():
    for seed in range(6):
        inst = lattice_instance(8, 0.55, 0.2, 1.0, phi="compression", theta=0.2 * seed, seed=seed)
        res = paper_verdict(inst)
        exact = solve(inst, SolverOptions(min_norm=False))
        assert res.energy >= exact.energy - 1e-9 * res.affine_energy
        assert res.rigid == (res.energy > PAPER_THRESHOLD * res.affine_energy)
        assert res.displacements.shape == (inst.network.n_nodes, 2)
        assert np.allclose(res.displacements.mean(axis=0), 0.0, atol=1e-12)
        rec = res.record()
        assert rec["method"] == "paper-lbfgsb" and rec["decided"] and rec["iterations"] >= 0
