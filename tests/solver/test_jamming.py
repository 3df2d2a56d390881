"""The certified jamming test (:mod:`tensegrity_rigidity.solver.jamming`): rattlers, both
certificates checked independently, random soft packings against an independent LP, the
isostatic count at the jamming onset."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.jamming_reference import reference_jamming, reference_rattlers
from tensegrity_rigidity import InputError
from tensegrity_rigidity.model.network import Element, PeriodicNetwork
from tensegrity_rigidity.model.packing import crystal_packing
from tensegrity_rigidity.model.softdisks import jammed_packing, soft_packing
from tensegrity_rigidity.solver.jamming import JammingOptions, jamming, rattlers


def _net(box, positions, bonds, shifts):
    kinds = np.full(len(bonds), Element.STRUT)
    return PeriodicNetwork(np.asarray(box, float), positions, bonds, shifts, kinds)


def test_rattlers_are_counted_per_contact_and_removed_iteratively():
    # particles 0 and 1 touch through two images (two contacts each) and each its own image (two
    # more): four contacts each, no rattler in 2D; particle 2 has two contacts and goes, and then
    # 3 (four contacts, two of them with 2) follows
    box = np.eye(2) * 10
    pos = np.array([[0.0, 0.0], [5.0, 0.0], [0.0, 5.0], [5.0, 5.0]])
    bonds = [[0, 1], [0, 1], [0, 0], [1, 1], [2, 3], [2, 3], [3, 3]]
    shifts = [[0, 0], [-1, 0], [0, 1], [0, 1], [0, 0], [1, 0], [1, 0]]
    net = _net(box, pos, bonds, shifts)
    assert rattlers(net).tolist() == [2, 3]
    assert reference_rattlers(net).tolist() == [2, 3]
    r = jamming(net)
    assert r.rattlers.tolist() == [2, 3] and r.rattler_contacts == 3 and r.backbone_contacts == 4


def test_a_packing_of_rattlers_only_is_unjammed():
    net = _net(np.eye(2) * 10, [[0.0, 0.0], [1.0, 0.0]], [[0, 1]], [[0, 0]])
    r = jamming(net)
    assert r.status == "unjammed" and r.n_rattlers == 2 and "rattler" in r.message


def test_bad_input_is_one_line():
    net = crystal_packing("square", 2).contact_network()
    with pytest.raises(InputError, match="kind must be one of"):
        jamming(net, kind="global")
    with pytest.raises(InputError, match="strut"):
        jamming(net.with_kinds(np.full(net.n_sites, Element.ROD)))
    with pytest.raises(InputError, match="PeriodicNetwork"):
        jamming("packing.gsd")  # type: ignore[arg-type]
    with pytest.raises(InputError, match="violation_tol"):
        JammingOptions(violation_tol=0.5)
    with pytest.raises(InputError, match="must be a JammingOptions"):  # an AttributeError
        jamming(net, "local", {"violation_tol": 1e-9})  # type: ignore[arg-type]
    assert JammingOptions(eigen_iterations=np.int64(5)).eigen_iterations == 5  # was refused


def test_a_jamming_result_prints_in_a_few_hundred_characters():
    """Its repr printed every rattler and every force: 16,595 characters at N = 128."""
    result = jamming(crystal_packing("triangular", 12).contact_network(), "strict")
    text = repr(result)
    assert len(text) < 600 and "status='jammed'" in text and "<(433,) float64 array>" in text
    assert result != jamming(crystal_packing("triangular", 12).contact_network(), "strict")


def _check_motion(net, motion, tau):
    """An unjamming motion closes no contact by more than tau (plain double precision, with a
    margin of round-off) and is not a translation."""
    R = np.zeros((net.n_sites, net.dim * net.n_nodes))
    vec = net.bond_vectors()
    u = motion.displacements.ravel()
    for s, (i, j) in enumerate(net.bonds):
        n = vec[s] / np.linalg.norm(vec[s])
        R[s, net.dim * j : net.dim * j + net.dim] += n
        R[s, net.dim * i : net.dim * i + net.dim] -= n
    w = R @ u
    if motion.strain is not None:
        w = w + np.einsum("bi,ij,bj->b", vec / np.linalg.norm(vec, axis=1)[:, None], motion.strain,
                          vec)  # fmt: skip
        assert np.trace(motion.strain) <= 1e-12
    centred = motion.displacements - motion.displacements.mean(axis=0)
    assert np.linalg.norm(centred) + (0 if motion.strain is None else 1) > 0.5
    assert w.min() >= -tau - 1e-13


def _check_forces(net, result):
    """Jammed forces are positive on every backbone contact and balance every particle."""
    f = result.contact_forces()
    alive = np.ones(net.n_nodes, bool)
    alive[result.rattlers] = False
    backbone = alive[net.bonds[:, 0]] & alive[net.bonds[:, 1]] & (net.kinds == Element.STRUT)
    assert np.all(f[backbone] > 0) and np.all(f[~backbone] == 0)
    vec = net.bond_vectors()
    n = vec / np.linalg.norm(vec, axis=1)[:, None]
    total = np.zeros((net.n_nodes, net.dim))
    np.add.at(total, net.bonds[:, 0], f[:, None] * n)
    np.add.at(total, net.bonds[:, 1], -f[:, None] * n)
    assert np.abs(total).max() <= 1e-10 * f.max()


@pytest.mark.parametrize("name, cells", [("square", 3), ("kagome", 2), ("honeycomb", 2)])
def test_unjamming_motions_of_crystals_check_out(name, cells):
    net = crystal_packing(name, cells).contact_network()
    r = jamming(net)
    assert r.status == "unjammed" and r.certificate is r.unjamming
    _check_motion(net, r.certificate, JammingOptions().violation_tol)


def test_forces_of_a_jammed_crystal_check_out():
    net = crystal_packing("triangular", 3).contact_network()
    r = jamming(net)
    assert r.status == "jammed" and r.certificate.margin > JammingOptions().violation_tol
    _check_forces(net, r)


def test_a_crystal_unjams_by_a_pure_flex_that_opening_alone_would_miss():
    # the square crystal carries a strictly positive self-stress (no motion opens a contact), and
    # still unjams: rows slide, R u = 0
    net = crystal_packing("square", 4).contact_network()
    r = jamming(net)
    assert r.status == "unjammed" and r.certificate.flex and r.certificate.opening < 1e-12
    assert r.jammed is not None and r.jammed.strictness > 0


def test_strict_unjamming_motion_shears_the_box():
    net = crystal_packing("honeycomb", 1).contact_network()
    assert jamming(net, "collective").status == "jammed"
    r = jamming(net, "strict")
    assert r.status == "unjammed" and r.certificate.strain is not None
    assert np.abs(r.certificate.strain).max() > 0.1
    _check_motion(net, r.certificate, JammingOptions().violation_tol)


def _random_packings(dim, sizes, phis, seeds):
    for n in sizes:
        for phi in phis:
            for seed in seeds:
                sp = soft_packing(n, phi, np.random.default_rng([seed, n, int(phi * 1e4)]), dim=dim)
                yield f"{dim}D n={n} phi={phi} seed={seed}", sp.packing.contact_network(tolerance=0)


def _with_contacts_removed(net, k, seed):
    """The network with ``k`` random contacts removed (a jammed packing nudged to the boundary)."""
    rng = np.random.default_rng(seed)
    kinds = net.kinds.copy()
    kinds[rng.choice(net.n_sites, size=min(k, net.n_sites), replace=False)] = Element.EMPTY
    return net.with_kinds(kinds)


def _agreement(cases, kind):
    compared = disagree = 0
    statuses = set()
    for label, net in cases:
        ours = jamming(net, kind)
        ref = reference_jamming(net, kind)
        assert ours.rattlers.tolist() == ref.rattlers.tolist(), label
        if ours.status == "jammed":
            assert ours.backbone_contacts >= ours.isostatic_contacts, label
            _check_forces(net, ours) if kind == "collective" else None
        if ref.status == "ambiguous" or ours.status == "undecided":
            continue
        compared += 1
        statuses.add(ours.status)
        disagree += ours.status != ref.status
        assert ours.status == ref.status, (label, ours.message, ref)
    return compared, disagree, statuses


@pytest.mark.parametrize("kind", ["collective", "strict"])
def test_random_disk_packings_agree_with_an_independent_lp(kind):
    base = list(_random_packings(2, (16, 32), (0.82, 0.85, 0.88, 0.92), (1, 2)))
    nudged = [(f"{lab} -{k}", _with_contacts_removed(net, k, k)) for lab, net in base
              for k in (1, 3, 8) if net.n_sites > 10]  # fmt: skip
    compared, disagree, statuses = _agreement(base + nudged, kind)
    assert disagree == 0 and statuses == {"jammed", "unjammed"}
    assert compared >= 0.9 * len(base + nudged)


def test_random_sphere_packings_agree_with_an_independent_lp():
    base = list(_random_packings(3, (32,), (0.62, 0.66, 0.72), (1, 2)))
    nudged = [(f"{lab} -{k}", _with_contacts_removed(net, k, k)) for lab, net in base
              for k in (1, 4) if net.n_sites > 10]  # fmt: skip
    for kind in ("collective", "strict"):
        compared, disagree, statuses = _agreement(base + nudged, kind)
        assert disagree == 0 and statuses == {"jammed", "unjammed"}
        assert compared >= 0.9 * len(base + nudged)


@pytest.mark.parametrize("dim, n", [(2, 32), (2, 64), (3, 32)])
def test_packings_at_their_jamming_onset_are_jammed_and_isostatic(dim, n):
    # O'Hern et al. (2003), Goodrich et al. (2012): N_c = d (N' - 1) + 1 on the backbone
    for seed in (1, 2):
        sp = jammed_packing(n, np.random.default_rng([seed, n, dim]), dim=dim)
        assert 1e-16 <= sp.energy <= 2e-16
        r = jamming(sp.packing.contact_network(tolerance=0))
        assert r.status == "jammed", r.message
        n_live = n - r.n_rattlers
        assert r.backbone_contacts == dim * (n_live - 1) + 1 == r.isostatic_contacts
        assert r.excess_contacts == 0 and r.isostatic_excess == 0.0
        # one contact fewer and the backbone is floppy: a flex or an opening motion
        nudged = _with_contacts_removed(sp.packing.contact_network(tolerance=0), 1, seed)
        assert jamming(nudged).status == "unjammed"


@pytest.mark.parametrize("name, cells", [("square", (2, 1)), ("square", (3, 1)), ("sc", (2, 1, 1))])
def test_a_contact_with_its_own_image_does_not_hold_a_particle_locally(name, cells):
    """A box one cell wide along x: each particle touches its own x-images, which move with it,
    so it slides along x alone. The local test held the image fixed and said jammed."""
    net = crystal_packing(name, cells).contact_network()
    assert np.any(net.bonds[:, 0] == net.bonds[:, 1])
    result = jamming(net, "local")
    assert result.status == "unjammed" and result.certificate.accepted


def _lowered(eps):
    """A triangular crystal of 36 with particle 14's contacts at 60, 240 and 300 degrees removed
    and 14 lowered by eps: moving it alone downwards opens its three contacts."""
    p = crystal_packing("triangular", 6)
    net = p.contact_network()
    d = p.positions[net.bonds[:, 1]] + net.shifts @ p.box - p.positions[net.bonds[:, 0]]
    angle = np.degrees(np.arctan2(d[:, 1], d[:, 0])) % 360
    out = ((net.bonds[:, 0] == 14) & np.isin(np.round(angle), [60, 240, 300])) | (
        (net.bonds[:, 1] == 14) & np.isin(np.round(angle), [240, 60, 120])  # seen from the other
    )
    q = p.positions.copy()
    q[14, 1] -= eps
    return PeriodicNetwork(p.box, q, net.bonds[~out], net.shifts[~out], net.kinds[~out])


@pytest.mark.parametrize("eps", [1e-9, 1e-10])
def test_a_particle_free_alone_unjams_the_packing_collectively_and_strictly(eps):
    """The local test certified the motion while the collective and strict searches stopped at
    "not resolved" (openings of order eps); the local motion is a motion of theirs too."""
    net = _lowered(eps)
    assert np.sum(net.bonds == 14) == 3
    for kind in ("local", "collective", "strict"):
        result = jamming(net, kind)
        assert result.status == "unjammed", (kind, result.message)
        u = result.certificate.displacements
        assert np.abs(u[14]).max() > 0.5 * np.abs(u).max()  # particle 14 carries the motion
