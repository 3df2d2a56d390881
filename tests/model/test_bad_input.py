"""Every user mistake: a named exception from the API, one line and exit 2 from the CLI."""

from __future__ import annotations

import os

import numpy as np
import pytest

from tensegrity_rigidity import (
    InputError,
    Instance,
    PeriodicNetwork,
    lattice_instance,
    load_instance,
    save_instance,
    triangular_lattice,
)
from tensegrity_rigidity.cli.main import main

GOOD = dict(
    box=np.eye(2) * 2,
    positions=[[0.0, 0.0], [1.0, 0.3]],
    bonds=[[0, 1]],
    shifts=[[0, 0]],
    kinds=[1],
)


def _net(**over):
    return PeriodicNetwork(**{**GOOD, **over})


@pytest.mark.parametrize(
    "kw", [dict(p_r=-0.1), dict(p_r=1.2), dict(p_t=1.5), dict(f_c=-1), dict(f_c=2)]
)
def test_probability_outside_unit_interval(kw):
    args = dict(p_r=0.5, p_t=0.1, f_c=0.5) | kw
    with pytest.raises(InputError, match="must lie in"):
        lattice_instance(4, **args)


def test_p_r_plus_p_t_above_one():
    with pytest.raises(InputError, match="must not exceed 1"):
        lattice_instance(4, 0.7, 0.4)


@pytest.mark.parametrize("n", [1, 0, -3])
def test_n_below_two(n):
    with pytest.raises(InputError, match="at least 2"):
        triangular_lattice(n)


def test_negative_delta():
    with pytest.raises(InputError, match="non-negative"):
        triangular_lattice(4, -0.1, np.random.default_rng(0))


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_nan_or_inf(bad):
    with pytest.raises(InputError, match="NaN or infinite"):
        _net(positions=[[0.0, bad], [1.0, 0.3]])
    with pytest.raises(InputError, match="finite"):
        lattice_instance(4, bad, 0.1)


def test_bond_index_out_of_range():
    with pytest.raises(InputError, match="out of range"):
        _net(bonds=[[0, 2]])


def test_zero_length_bond():
    with pytest.raises(InputError, match="zero length"):
        _net(positions=[[0.0, 0.0], [0.0, 0.0]])


@pytest.mark.parametrize(
    "over",
    [
        dict(positions=[0.0, 1.0]),
        dict(bonds=[[0, 1, 1]]),
        dict(shifts=[[0, 0], [0, 0]]),
        dict(kinds=[1, 1]),
        dict(box=np.eye(3)),
    ],
)
def test_wrong_shapes(over):
    with pytest.raises(InputError, match="shape"):
        _net(**over)


def test_unknown_kind_and_bad_stiffness():
    with pytest.raises(InputError, match="kinds"):
        _net(kinds=[7])
    with pytest.raises(InputError, match="stiffness"):
        _net(stiffness=[-1.0])


def test_non_symmetric_strain():
    with pytest.raises(InputError, match="symmetric"):
        Instance(_net(), [[0.1, 0.2], [0.0, 0.1]])


def test_missing_keys(tmp_path):
    path = tmp_path / "x.npz"
    np.savez(path, box=np.eye(2), positions=np.zeros((1, 2)))
    with pytest.raises(InputError, match="missing key"):
        load_instance(path)


def test_unreadable_file(tmp_path):
    path = tmp_path / "x.npz"
    path.write_text("this is not an npz archive")
    with pytest.raises(InputError, match="not a readable"):
        load_instance(path)
    with pytest.raises(InputError, match="no such file"):
        load_instance(tmp_path / "absent.npz")


def test_a_cut_npy_header_and_a_path_that_is_no_file_are_one_line(tmp_path):
    """A header cut inside its dict raised tokenize.TokenError; a FIFO read "no such file"."""
    import io
    import zipfile

    cut = io.BytesIO()
    header = b"{'descr': '<f8', 'fortran_order': False, 'shape': (2,"
    cut.write(b"\x93NUMPY\x01\x00" + len(header).to_bytes(2, "little") + header)
    path = tmp_path / "cut.npz"
    with zipfile.ZipFile(path, "w") as zf:
        for key in ("box", "positions", "bonds", "shifts", "kinds", "strain"):
            zf.writestr(f"{key}.npy", cut.getvalue())
    with pytest.raises(InputError, match="not a readable"):
        load_instance(path)
    fifo = tmp_path / "fifo.npz"
    os.mkfifo(fifo)
    with pytest.raises(InputError, match="not a regular file"):
        load_instance(fifo)
    with pytest.raises(InputError, match="a directory"):
        load_instance(tmp_path)


def test_round_trip(tmp_path):
    inst = lattice_instance(4, 0.6, 0.2, 0.3, phi="compression", seed=5)
    save_instance(tmp_path / "a.npz", inst)
    back = load_instance(tmp_path / "a.npz")
    for name in ("box", "positions", "bonds", "shifts", "kinds"):
        np.testing.assert_array_equal(getattr(back.network, name), getattr(inst.network, name))
    np.testing.assert_array_equal(back.strain, inst.strain)
    with np.load(tmp_path / "a.npz") as data:
        assert set(data.files) == {"box", "positions", "bonds", "shifts", "kinds", "strain"}


@pytest.mark.parametrize(
    "argv,needle",
    [
        (["sample", "OUT", "--p-r", "1.5"], "p_r must lie in"),
        (["sample", "OUT", "--p-r", "0.8", "--p-t", "0.5"], "p_r + p_t"),
        (["sample", "OUT", "--p-r", "0.5", "--n", "1"], "at least 2"),
        (["sample", "OUT", "--p-r", "0.5", "--delta", "-1"], "non-negative"),
        (["sample", "OUT", "--p-r", "nan"], "finite"),
        (["sample", "OUT", "--p-r", "0.5", "--phi", "twist"], "phi must be"),
        (["solve", "ABSENT"], "no such file"),
        (["solve", "GARBAGE"], "not a readable"),
        (["solve", "BADSTRAIN"], "symmetric"),
    ],
)
def test_cli_errors_are_one_line_and_exit_2(tmp_path, capsys, argv, needle):
    (tmp_path / "garbage.npz").write_text("nope")
    np.savez(
        tmp_path / "badstrain.npz",
        box=np.eye(2),
        positions=[[0.0, 0.0]],
        bonds=[[0, 0]],
        shifts=[[1, 0]],
        kinds=[1],
        strain=[[0.0, 1.0], [0.0, 0.0]],
    )
    subst = {
        "OUT": str(tmp_path / "o.npz"),
        "ABSENT": str(tmp_path / "absent.npz"),
        "GARBAGE": str(tmp_path / "garbage.npz"),
        "BADSTRAIN": str(tmp_path / "badstrain.npz"),
    }
    code = main([subst.get(a, a) for a in argv])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1 and err.startswith("error:") and needle in err


@pytest.mark.parametrize("offset", [1e7, 1e12, 1e15])
def test_positions_far_outside_the_box_are_refused(offset):
    """Translated far away, positions cannot resolve bond vectors in double precision: one
    clear error instead of silently different energies and verdicts."""
    net = triangular_lattice(4, 0.1, np.random.default_rng(0))
    with pytest.raises(InputError, match="box lengths from the origin"):
        PeriodicNetwork(net.box, net.positions + offset, net.bonds, net.shifts, net.kinds)


def test_positions_a_few_cells_away_are_fine():
    net = triangular_lattice(4, 0.1, np.random.default_rng(0))
    PeriodicNetwork(net.box, net.positions + 1e3, net.bonds, net.shifts, net.kinds)


def test_solve_and_decide_say_what_they_take(tmp_path):
    from tensegrity_rigidity import solve
    from tensegrity_rigidity.solver import decide

    path = tmp_path / "s.npz"
    save_instance(path, lattice_instance(4, 0.6, seed=1))
    for fn in (solve, decide):
        with pytest.raises(InputError, match=r"got str \(load a file with load_instance"):
            fn(str(path))
        with pytest.raises(InputError, match=r"expected an Instance, got PosixPath \("):
            fn(path)
        with pytest.raises(InputError, match=r"expected an Instance, got PeriodicNetwork$"):
            fn(load_instance(path).network)
