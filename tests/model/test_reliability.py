"""Hostile input to the model layer (issue 18): corrupt files, absurd sizes, odd dtypes, scales."""

from __future__ import annotations

import errno
import io
import warnings
import zipfile

import numpy as np
import pytest

from tensegrity_rigidity import (
    InputError,
    Instance,
    PeriodicNetwork,
    decide,
    lattice_instance,
    load_instance,
    save_instance,
    solve,
    square_lattice,
    strain_tensor,
    triangular_lattice,
)
from tensegrity_rigidity.model.mechanics import affine_extensions

GOOD = dict(
    box=np.eye(2) * 2,
    positions=[[0.0, 0.0], [1.0, 0.3]],
    bonds=[[0, 1]],
    shifts=[[0, 0]],
    kinds=[1],
)


@pytest.fixture
def arrays(tmp_path):
    save_instance(tmp_path / "a.npz", lattice_instance(4, 0.6, 0.2, seed=1))
    with np.load(tmp_path / "a.npz") as data:
        return {k: data[k] for k in data.files}


def _npz_with(path, arrays, raw_members=None):
    """An archive of ``arrays`` whose members in ``raw_members`` are replaced by raw bytes."""
    raw_members = raw_members or {}
    with zipfile.ZipFile(path, "w") as zf:
        for key, value in arrays.items():
            if key in raw_members:
                zf.writestr(f"{key}.npy", raw_members[key])
            else:
                buf = io.BytesIO()
                np.save(buf, value)
                zf.writestr(f"{key}.npy", buf.getvalue())


def test_corrupt_compressed_member_is_one_error(tmp_path, arrays):
    path = tmp_path / "c.npz"
    np.savez_compressed(path, **arrays)
    with zipfile.ZipFile(path) as zf:
        info = zf.getinfo("positions.npy")
    data = bytearray(path.read_bytes())
    data[info.header_offset + 30 + len(info.filename) + len(info.extra) + 60] ^= 0xFF
    path.write_bytes(bytes(data))
    with pytest.raises(InputError, match="not a readable"):
        load_instance(path)


def test_absurd_header_shape_is_refused_before_allocating(tmp_path, arrays):
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        header, {"descr": "<f8", "fortran_order": False, "shape": (10**11, 2)}
    )
    path = tmp_path / "huge.npz"
    _npz_with(path, arrays, {"positions": header.getvalue() + b"\0" * 32})
    with pytest.raises(InputError, match=r"declares shape \(100000000000, 2\)"):
        load_instance(path)


def test_header_and_zip_sizes_both_absurd_is_refused_by_memory(tmp_path, arrays, monkeypatch):
    """A member whose zip entry agrees with its absurd header: refused as too large."""
    import tensegrity_rigidity.model.limits as limits

    monkeypatch.setattr(limits, "physical_memory", lambda: 1000)  # a machine with 1000 bytes
    path = tmp_path / "big.npz"
    big = dict(arrays, positions=np.zeros((200, 2)))
    _npz_with(path, big)
    with pytest.raises(InputError, match="needs about .* of memory"):
        load_instance(path)


def test_plain_npy_is_named(tmp_path):
    path = tmp_path / "p.npy"
    np.save(path, np.zeros(3))
    with pytest.raises(InputError, match="plain .npy"):
        load_instance(path)


def test_object_member_is_refused(tmp_path, arrays):
    buf = io.BytesIO()
    np.save(buf, np.array([object()], dtype=object), allow_pickle=True)
    path = tmp_path / "o.npz"
    _npz_with(path, arrays, {"kinds": buf.getvalue()})
    with pytest.raises(InputError, match="not numbers"):
        load_instance(path)


def test_directory_is_not_an_instance(tmp_path):
    with pytest.raises(InputError, match="is a directory"):
        load_instance(tmp_path)


def test_save_to_a_directory_leaves_nothing(tmp_path):
    inst = lattice_instance(3, 0.5, seed=0)
    target = tmp_path / "dir.npz"
    target.mkdir()
    with pytest.raises(InputError, match="is a directory"):
        save_instance(target, inst)
    with pytest.raises(InputError, match="does not exist"):
        save_instance(tmp_path / "missing" / "a.npz", inst)
    with pytest.raises(InputError, match="empty"):
        save_instance("", inst)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dir.npz"]


def test_failed_write_leaves_no_temporary(tmp_path, monkeypatch):
    """A full disk (ENOSPC) mid-write: one InputError, no stale temporary file."""
    inst = lattice_instance(3, 0.5, seed=0)

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(np, "savez", full)
    with pytest.raises(InputError, match="No space left on device"):
        save_instance(tmp_path / "a.npz", inst)
    assert list(tmp_path.iterdir()) == []


def test_a_long_valid_file_name_is_written(tmp_path):
    """246 characters plus ".npz" is a valid name; its temporary file (the name plus a pid
    and ".tmp") passed the 255-byte limit: "File name too long", then a traceback from the
    clean-up. A name too long for the file system is one line."""
    inst = lattice_instance(3, 0.5, seed=0)
    save_instance(tmp_path / ("q" * 246 + ".npz"), inst)
    assert [p.name for p in tmp_path.iterdir()] == ["q" * 246 + ".npz"]
    with pytest.raises(InputError, match="File name too long"):
        save_instance(tmp_path / ("q" * 300 + ".npz"), inst)
    assert len(list(tmp_path.iterdir())) == 1


def test_complex_positions_and_bool_kinds_are_refused():
    with pytest.raises(InputError, match="complex"):
        PeriodicNetwork(**{**GOOD, "positions": np.array([[0, 0], [1, 0.3 + 1e-3j]])})
    with pytest.raises(InputError, match="booleans"):
        PeriodicNetwork(**{**GOOD, "kinds": np.array([True])})
    with pytest.raises(InputError, match="booleans"):
        PeriodicNetwork(**{**GOOD, "box": np.eye(2, dtype=bool)})


@pytest.mark.parametrize("scale", [1e-7, 1e-3, 1.0, 1e6])
def test_box_validity_is_relative_to_its_own_scale(scale):
    net = PeriodicNetwork(
        np.eye(2) * 2 * scale,
        np.array(GOOD["positions"]) * scale,
        GOOD["bonds"],
        GOOD["shifts"],
        GOOD["kinds"],
    )
    assert net.n_nodes == 2
    flat = np.array([[2.0, 0.0], [4.0, 1e-13]]) * scale  # parallel lattice vectors
    with pytest.raises(InputError, match="zero area"):
        PeriodicNetwork(flat, np.array(GOOD["positions"]) * scale, [[0, 1]], [[0, 0]], [1])


@pytest.mark.parametrize("scale", [1e-300, 1e-200, 1e200, 1e300])
def test_boxes_at_extreme_scales_are_valid_and_keep_their_affine_extensions(scale):
    """A box and positions scaled by 1e+-300 are a valid network (not "zero area"), and the
    affine extensions scale with them instead of under- or overflowing in d . eps . d."""
    inst = lattice_instance(5, 0.6, 0.2, phi="shear", seed=1)
    net = inst.network
    scaled = PeriodicNetwork(
        net.box * scale, net.positions * scale, net.bonds, net.shifts, net.kinds
    )
    e0 = affine_extensions(scaled, inst.strain)
    assert np.allclose(e0 / scale, affine_extensions(net, inst.strain), rtol=1e-12, atol=0)
    # the verdict at a strain that brings the affine extensions back to order one
    a = decide(inst)
    b = decide(Instance(scaled, inst.strain / scale))
    assert (a.status, a.stage) == (b.status, b.stage)


def test_a_rigid_box_at_1e_minus_300_is_refused_not_called_floppy():
    """max |e0| of 1e-300 is outside the solver's range: refused in one line (it used to
    underflow to e0 = 0, nothing strained, a floppy verdict for a rigid sample)."""
    inst = lattice_instance(5, 0.9, 0.0, phi="dilation", seed=1)
    net = inst.network
    tiny = PeriodicNetwork(
        net.box * 1e-300, net.positions * 1e-300, net.bonds, net.shifts, net.kinds
    )
    with pytest.raises(InputError, match="largest affine extension"):
        decide(Instance(tiny, inst.strain))


@pytest.mark.parametrize(
    "bonds", [np.array([[0, 2**64 - 1]], dtype=np.uint64), np.array([[0.0, 1e30]])]
)
def test_bond_indices_beyond_int64_are_named_not_wrapped(bonds):
    with pytest.raises(InputError, match="beyond int64"):
        PeriodicNetwork(**{**GOOD, "bonds": bonds})


@pytest.mark.parametrize("shift", [2**11, 2**62, -(2**40)])
def test_image_shifts_beyond_the_range_are_refused(shift):
    with pytest.raises(InputError, match="shifts must lie within"):
        PeriodicNetwork(**{**GOOD, "shifts": [[shift, 0]]})
    PeriodicNetwork(**{**GOOD, "shifts": [[2**11 - 1, 0]]})  # the largest allowed


@pytest.mark.parametrize("gamma", [1e200, 1e-200, 1e141, 0.0, -1.0])
def test_strain_magnitudes_outside_the_documented_range_are_refused(gamma, tmp_path):
    with pytest.raises(InputError, match="gamma"):
        strain_tensor("shear", 0.0, gamma)
    with pytest.raises(InputError, match="gamma"):
        lattice_instance(4, 0.6, gamma=gamma, seed=1)


@pytest.mark.parametrize("gamma", ["1e200", "1e-200"])
def test_sample_never_writes_an_instance_that_solve_refuses(tmp_path, capsys, gamma):
    from tensegrity_rigidity.cli.main import main

    out = tmp_path / "x.npz"
    assert main(["sample", str(out), "--p-r", "0.6", "--gamma", gamma]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "gamma" in err[0] and not out.exists()


def test_zero_strain_is_floppy_with_zero_energy():
    """The documented exception to the strain range: nothing strained, u = 0 is exact."""
    inst = lattice_instance(5, 0.9, 0.0, seed=1)
    r = solve(Instance(inst.network, np.zeros((2, 2))))
    assert r.status == "floppy" and r.energy == 0.0 and r.affine_energy == 0.0


def test_negative_seed_is_refused():
    with pytest.raises(InputError, match="non-negative integer"):
        lattice_instance(4, 0.5, seed=-1)
    with pytest.raises(InputError, match="non-negative integer"):
        lattice_instance(4, 0.5, seed=1.5)


def test_huge_lattice_is_refused_before_allocating():
    with pytest.raises(InputError, match=r"n = 100000 .* needs about .* TiB of memory"):
        triangular_lattice(100_000, 0.2, np.random.default_rng(0))
    with pytest.raises(InputError, match="needs about"):
        square_lattice(1_000_000, 0.2, np.random.default_rng(0))


def test_crossing_delta_is_the_first_inverted_triangle():
    """Below CROSSING_DELTA no corner of the kick box inverts a triangle; just above one does."""
    import itertools

    from tensegrity_rigidity.model.lattice import CROSSING_DELTA

    b1, b2 = np.array([1.0, 0.0]), np.array([-0.5, np.sqrt(3) / 2])
    tri = np.array([0 * b1, b1, b1 + b2])

    def min_area(d):
        areas = []
        for signs in itertools.product([-1, 1], repeat=6):
            p = tri + d * np.reshape(signs, (3, 2))
            a, b = p[1] - p[0], p[2] - p[0]
            areas.append(a[0] * b[1] - a[1] * b[0])
        return min(areas)

    dc = CROSSING_DELTA["triangular"]
    assert min_area(dc * (1 - 1e-9)) > 0 > min_area(dc * (1 + 1e-6))


def test_large_delta_warns_that_bonds_cross():
    from tensegrity_rigidity.model.lattice import CrossingBondsWarning

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        triangular_lattice(16, 0.3, np.random.default_rng(0))
        square_lattice(16, 0.45, np.random.default_rng(0))
    assert not caught
    with pytest.warns(CrossingBondsWarning, match="inside out"):
        triangular_lattice(16, 0.49, np.random.default_rng(0))
    with pytest.warns(CrossingBondsWarning, match="inside out"):
        square_lattice(16, 0.45, np.random.default_rng(0), diagonals=True)
