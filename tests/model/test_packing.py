"""Contact networks of packings, crystal packings, kagome and honeycomb builders, and the
readers from other tools (GSD, freud/HOOMD boxes, networkx)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tensegrity_rigidity import (
    InputError,
    contact_network,
    crystal_packing,
    honeycomb_lattice,
    kagome_lattice,
    read_gsd,
)
from tensegrity_rigidity.model.interop import (
    box_from_hoomd,
    hoomd_box,
    network_from_networkx,
    network_to_networkx,
    write_gsd,
)
from tensegrity_rigidity.model.network import Element
from tensegrity_rigidity.model.packing import (
    CRYSTALS,
    Packing,
    _pairs_general,
    _pairs_orthogonal,
    reduce_box,
)
from tensegrity_rigidity.model.softdisks import soft_packing


def _contacts(net):
    """Contacts as a set of (i, j, shift) with both orientations."""
    out = set()
    for (i, j), s in zip(net.bonds.tolist(), net.shifts.tolist(), strict=True):
        out.add((i, j, tuple(s)))
        out.add((j, i, tuple(-x for x in s)))
    return out


@pytest.mark.parametrize("name", sorted(CRYSTALS))
@pytest.mark.parametrize("cells", [1, 2, 3])
def test_every_crystal_particle_has_its_coordination(name, cells):
    p = crystal_packing(name, cells)
    net = p.contact_network()
    assert np.all(net.kinds == Element.STRUT)
    # counted per contact: a particle touching its own image twice (once on each side)
    assert set(np.bincount(net.bonds.ravel(), minlength=p.n_particles).tolist()) == {
        CRYSTALS[name][2]
    }
    assert np.allclose(net.bond_lengths(), 1.0)


def test_one_cell_boxes_find_every_image_of_a_pair():
    kagome = crystal_packing("kagome", 1).contact_network()
    pairs = [tuple(b) for b in kagome.bonds.tolist()]
    assert sorted(pairs) == [(0, 1), (0, 1), (0, 2), (0, 2), (1, 2), (1, 2)]
    tri = crystal_packing("triangular", 1).contact_network()
    assert tri.n_sites == 3 and np.all(tri.bonds == 0)  # a particle and its own six images


def test_orthogonal_fast_path_and_general_method_agree():
    sp = soft_packing(128, 0.86, np.random.default_rng(5))
    p = sp.packing
    cutoff = 2 * p.radii.max()
    L = np.diag(p.box)
    fast = _pairs_orthogonal(p.positions, L, cutoff)
    general = _pairs_general(p.positions, p.box, L, cutoff)

    def key(t):
        return sorted(zip(t[0].tolist(), t[1].tolist(), map(tuple, t[2].tolist()), strict=True))

    assert key(fast) == key(general) and len(fast[0]) > 100


@settings(max_examples=25, deadline=None)
@given(
    shift=st.lists(st.integers(-3, 3), min_size=2, max_size=2),
    which=st.integers(0, 15),
    perm_seed=st.integers(0, 1000),
)
def test_contacts_do_not_depend_on_images_or_labels(shift, which, perm_seed):
    p = crystal_packing("kagome", 2)
    pos = p.positions.copy()
    k = which % len(pos)
    pos[k] += np.asarray(shift) @ p.box  # another image of one particle
    base = _contacts(p.contact_network())
    moved = contact_network(pos, p.radii, p.box)
    # the same contacts, each shift changed by the image offset of its ends
    s = np.asarray(shift)
    fixed = set()
    for i, j, sh in _contacts(moved):
        corr = np.asarray(sh) + (s if j == k else 0) - (s if i == k else 0)
        fixed.add((i, j, tuple(corr.tolist())))
    assert fixed == base
    perm = np.random.default_rng(perm_seed).permutation(len(pos))
    relabelled = contact_network(p.positions[perm], p.radii[perm], p.box)
    back = {(int(perm[i]), int(perm[j]), sh) for i, j, sh in _contacts(relabelled)}
    assert back == base


def test_triclinic_and_skewed_boxes():
    hcp = crystal_packing("hcp", 2).contact_network()
    assert hcp.n_sites == 96 and np.allclose(hcp.bond_lengths(), 1.0)
    # the same triangular crystal in a sheared box (lattice vectors a1, a2 - a1)
    tri = crystal_packing("triangular", 4)
    box = np.array([tri.box[0], tri.box[1] - tri.box[0]])
    net = contact_network(tri.positions, tri.radii, box)
    assert net.n_sites == 48


def test_tolerance_and_bad_input():
    p = crystal_packing("square", 3)
    spread = Packing(p.positions * 1.001, p.radii, p.box * 1.001)
    assert spread.contact_network().n_sites == 0
    assert spread.contact_network(tolerance=2e-3).n_sites == 18
    with pytest.raises(InputError, match="tolerance"):
        contact_network(p.positions, p.radii, p.box, tolerance=-1)
    with pytest.raises(InputError, match="radii must be positive"):
        contact_network(p.positions, -p.radii, p.box)
    with pytest.raises(InputError, match="same place"):
        contact_network(np.zeros((2, 2)), [0.5, 0.5], np.eye(2) * 5)
    with pytest.raises(InputError, match="unknown crystal"):
        crystal_packing("quasicrystal", 2)
    with pytest.raises(InputError, match="positions must have shape"):
        contact_network(np.zeros((2, 3)), [0.5, 0.5], np.eye(2) * 5)


@pytest.mark.parametrize("name", ["triangular", "fcc"])
@pytest.mark.parametrize("scale", [1e-200, 1e-155, 1e-150, 1e104, 1e155, 1e200])
def test_contacts_at_any_scale(name, scale):
    """Squared lengths under- and overflowed: a triangular packing at 1e-155 had no contact
    (and was called unjammed), FCC at 1e-150 a box of "dependent rows", 1e104 an OverflowError."""
    p = crystal_packing(name, 3)
    net = contact_network(p.positions * scale, p.radii * scale, p.box * scale)
    assert _contacts(net) == _contacts(p.contact_network())
    assert Packing(p.positions * scale, p.radii * scale, p.box * scale).packing_fraction() == (
        pytest.approx(p.packing_fraction(), rel=1e-12)
    )


@pytest.mark.parametrize("tilt", [1, 7, 2000])
def test_a_tilted_box_is_searched_as_its_reduced_lattice(tilt):
    """A HOOMD tilt of 2e3 listed billions of image shifts (out of memory); the same lattice
    with short vectors has the same contacts, their shifts in the given vectors."""
    p = crystal_packing("triangular", 4)
    box = np.array([p.box[0], p.box[1] + tilt * p.box[0]])
    net = contact_network(p.positions, p.radii, box)
    vectors = p.positions[net.bonds[:, 1]] + net.shifts @ box - p.positions[net.bonds[:, 0]]
    assert net.n_sites == 48 and np.allclose(np.linalg.norm(vectors, axis=1), 1.0)
    reduced, basis = reduce_box(box)
    assert abs(round(np.linalg.det(basis))) == 1 and np.allclose(basis @ box, reduced)


def test_a_particle_wider_than_its_box_is_refused():
    """One particle of diameter 1000 in a unit box: millions of self-contacts, a hang."""
    with pytest.raises(InputError, match="wider than the box"):
        contact_network([[0.0, 0.0]], [500.0], np.eye(2))
    assert crystal_packing("triangular", 1).contact_network().n_sites == 3  # touching: kept


@pytest.mark.parametrize("tolerance", ["a", None, [0.1], 1j, "0.1", True, 1e300, float("nan")])
def test_a_tolerance_that_is_not_a_fraction_of_a_diameter_is_refused(tolerance):
    p = crystal_packing("square", 2)
    with pytest.raises(InputError, match="tolerance"):
        contact_network(p.positions, p.radii, p.box, tolerance=tolerance)


@pytest.mark.parametrize("cells", [(2, 2), [[1, 2, 3]], 2.0, 0, 10**6])
def test_crystal_cells_are_checked_before_anything_is_allocated(cells):
    """``(2, 2)`` for a 3D crystal gave NumPy's broadcast error; ``10**6`` cells exhausted the
    machine."""
    with pytest.raises(InputError, match="cells|memory"):
        crystal_packing("fcc", cells)


@pytest.mark.parametrize(
    "change, match",
    [
        (("edge", "kind", "rod"), None),
        (("edge", "kind", None), "kind"),
        (("edge", "kind", 2.7), "kind"),
        (("edge", "kind", 7), "kind"),
        (("edge", "shift", "xy"), "shift"),
        (("edge", "shift", (0.5, 0.0)), "shift"),
        (("edge", "stiffness", 2.0), "stiffness"),
        (("graph", "box", 5.0), "box"),
        (("graph", "box", "ab"), "box"),
        (("node", "position", [0.0, [1, 2]]), "position"),
    ],
)
def test_networkx_graphs_with_bad_attributes_get_one_line(change, match):
    """Each of these raised a raw ValueError, TypeError or IndexError, or (stiffness on one
    edge) was silently dropped."""
    g = network_to_networkx(crystal_packing("square", 2).contact_network())
    where, key, value = change
    if where == "edge":
        u, v, k = next(iter(g.edges(keys=True)))
        g.edges[u, v, k][key] = value
    elif where == "node":
        g.nodes[0][key] = value
    else:
        g.graph[key] = value
    if match is None:
        assert network_from_networkx(g).kinds[0] == Element.ROD
    else:
        with pytest.raises(InputError, match=match):
            network_from_networkx(g)


def test_interop_refuses_objects_of_the_wrong_type(tmp_path):
    p = crystal_packing("square", 2)
    with pytest.raises(InputError, match="networkx graph"):
        network_from_networkx({})
    with pytest.raises(InputError, match="PeriodicNetwork"):
        network_to_networkx(None)
    with pytest.raises(InputError, match="Packing"):
        write_gsd(tmp_path / "a.gsd", p.contact_network())
    write_gsd(tmp_path / "a.gsd", p)
    assert read_gsd(tmp_path / "a.gsd", frame=np.int64(0)).n_particles == 4
    for frame in ("0", None, 1.5, True):
        with pytest.raises(InputError, match="frame must be an integer"):
            read_gsd(tmp_path / "a.gsd", frame=frame)


@pytest.mark.parametrize(
    "builder, name", [(kagome_lattice, "kagome"), (honeycomb_lattice, "honeycomb")]
)
def test_kagome_and_honeycomb_builders_match_their_crystal_packings(builder, name):
    net = builder(3)
    assert np.all(net.kinds == Element.EMPTY) and np.allclose(net.bond_lengths(), 1.0)
    contacts = crystal_packing(name, 3).contact_network()
    assert np.allclose(net.positions, contacts.positions)
    assert _contacts(net) == _contacts(contacts)
    kicked = builder(3, delta=0.1, rng=np.random.default_rng(0))
    assert not np.allclose(kicked.positions, net.positions)
    with pytest.raises(InputError, match="rng"):
        builder(3, delta=0.1)


@pytest.mark.parametrize(
    "box",
    [np.diag([3.0, 4.0]), np.array([[3.0, 0.0], [1.0, 2.0]]), np.array([[2.0, 1.0], [-1.0, 3.0]]),
     np.array([[3.0, 0, 0], [0.5, 2.0, 0], [0.2, -0.3, 4.0]]),
     np.array([[1.0, 2.0, 0.5], [-2.0, 1.0, 0.3], [0.4, 0.1, 3.0]])],
)  # fmt: skip
def test_hoomd_box_convention_both_ways(box):
    params, q = hoomd_box(box)
    again = box_from_hoomd(*params, dimensions=box.shape[0])
    assert np.allclose(again, box @ q) and np.allclose(q @ q.T, np.eye(len(box)))
    assert np.allclose(np.abs(np.linalg.det(again)), np.abs(np.linalg.det(box)))
    assert np.allclose(box_from_hoomd(*hoomd_box(again)[0], dimensions=len(box)), again)


def test_gsd_frame_round_trip(tmp_path):
    p = crystal_packing("hcp", 2)
    path = tmp_path / "hcp.gsd"
    write_gsd(path, p)
    back = read_gsd(path)
    assert back.dim == 3 and np.allclose(back.radii, p.radii)
    # GSD stores positions in single precision: exact contacts come back within ~1e-7
    assert back.contact_network().n_sites < p.contact_network().n_sites
    assert _contacts(back.contact_network(tolerance=1e-5)) == _contacts(p.contact_network())
    disks = soft_packing(32, 0.9, np.random.default_rng(1)).packing
    write_gsd(tmp_path / "disks.gsd", disks)
    read = read_gsd(tmp_path / "disks.gsd", frame=0)
    assert read.dim == 2 and np.allclose(read.positions, disks.positions)
    with pytest.raises(InputError, match="no such file"):
        read_gsd(tmp_path / "missing.gsd")
    with pytest.raises(InputError, match="frame 3 out of range"):
        read_gsd(path, frame=3)
    (tmp_path / "junk.gsd").write_bytes(b"not a gsd file")
    with pytest.raises(InputError, match="not a readable GSD"):
        read_gsd(tmp_path / "junk.gsd")


def test_networkx_round_trip_keeps_every_image():
    import networkx as nx

    net = crystal_packing("kagome", 1).contact_network()
    g = network_to_networkx(net)
    assert g.number_of_edges() == 6 and g.number_of_nodes() == 3
    back = network_from_networkx(g)
    assert np.array_equal(back.bonds, net.bonds) and np.array_equal(back.shifts, net.shifts)
    assert np.array_equal(back.kinds, net.kinds)
    # an undirected graph: each periodic edge says which end its shift is measured from
    h = nx.MultiGraph(box=net.box)
    for i, p in enumerate(net.positions):
        h.add_node(f"p{i}", position=p)
    for (i, j), s in zip(net.bonds.tolist(), net.shifts.tolist(), strict=True):
        h.add_edge(f"p{j}", f"p{i}", shift=[-x for x in s], tail=f"p{j}")
    assert _contacts(network_from_networkx(h)) == _contacts(net)
    for _, _, data in h.edges(data=True):
        del data["tail"]
    with pytest.raises(InputError, match="tail"):
        network_from_networkx(h)
    with pytest.raises(InputError, match="box"):
        network_from_networkx(nx.MultiGraph())
