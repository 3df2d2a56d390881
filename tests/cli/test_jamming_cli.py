"""The ``jamming`` command on a GSD file and an instance file."""

from __future__ import annotations

import json

import numpy as np
import pytest

from tensegrity_rigidity import Instance, crystal_packing, save_instance
from tensegrity_rigidity.cli.main import main
from tensegrity_rigidity.model.interop import write_gsd


@pytest.mark.parametrize("name", ["tri.gsd", "TRI.GSD"])  # an upper-case suffix was refused
def test_jamming_command_on_a_gsd_frame(tmp_path, capsys, name):
    path = tmp_path / name
    write_gsd(path, crystal_packing("triangular", 3))
    assert main(["jamming", str(path)]) == 0
    out = capsys.readouterr().out
    assert "9 particles, 27 contacts, 0 rattlers" in out
    assert out.count("jammed") == 3 and "unjammed" not in out


def test_jamming_command_json_on_an_instance_file(tmp_path, capsys):
    net = crystal_packing("square", 3).contact_network()
    save_instance(tmp_path / "sq.npz", Instance(net, np.zeros((2, 2))))
    assert main(["jamming", str(tmp_path / "sq.npz"), "--kind", "collective", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["status"] == "unjammed" and result["motion"] == "flex"


def test_jamming_command_refuses_other_files(tmp_path, capsys):
    (tmp_path / "p.txt").write_text("1 2 3")
    assert main(["jamming", str(tmp_path / "p.txt")]) == 2
    assert capsys.readouterr().err.startswith("error: ")


def test_a_packing_with_nothing_left_to_move_prints_an_infinite_margin(tmp_path, capsys):
    """One particle in its box: after pinning nothing moves, the margin is infinite (null in
    JSON), and the text form printed a traceback formatting it."""
    net = crystal_packing("triangular", 1).contact_network()
    save_instance(tmp_path / "one.npz", Instance(net, np.zeros((2, 2))))
    assert main(["jamming", str(tmp_path / "one.npz"), "--kind", "collective"]) == 0
    assert "jammed     margin inf" in capsys.readouterr().out


def test_gsd_options_on_an_instance_file_are_refused_not_ignored(tmp_path, capsys):
    net = crystal_packing("square", 2).contact_network()
    save_instance(tmp_path / "sq.npz", Instance(net, np.zeros((2, 2))))
    for flag in (["--tolerance", "0.1"], ["--frame", "3"]):
        assert main(["jamming", str(tmp_path / "sq.npz"), *flag]) == 2
        assert "--tolerance and --frame read a GSD file" in capsys.readouterr().err
