"""Every failure of issue 18 items 7 and 8 at the command line: one line, the right status."""

from __future__ import annotations

import errno
import io
import json
import os
import subprocess
import sys
import textwrap
import zipfile

import numpy as np
import pytest

from tensegrity_rigidity import lattice_instance, save_instance
from tensegrity_rigidity.analysis.estimators import wilson
from tensegrity_rigidity.cli.main import main

from ..processes import unprivileged

SPEC = """
n = 5
p_r = [0.55, 0.7]
p_t = 0.25
phi = ["dilation", "compression"]
samples = 6
seed = 2
[output]
chunk_size = 4
"""


def _one_error(capsys, code, expected_code=2) -> str:
    err = capsys.readouterr().err.strip()
    assert code == expected_code, err
    assert len(err.splitlines()) == 1 and err.startswith("error: "), err
    return err


@pytest.fixture
def instance_file(tmp_path):
    path = tmp_path / "a.npz"
    save_instance(path, lattice_instance(4, 0.6, 0.2, seed=1))
    return path


def test_corrupt_member_absurd_header_and_plain_npy(tmp_path, capsys, instance_file):
    with np.load(instance_file) as data:
        arrays = {k: data[k] for k in data.files}
    corrupt = tmp_path / "c.npz"
    np.savez_compressed(corrupt, **arrays)
    with zipfile.ZipFile(corrupt) as zf:
        info = zf.getinfo("bonds.npy")
    raw = bytearray(corrupt.read_bytes())
    raw[info.header_offset + 30 + len(info.filename) + len(info.extra) + 50] ^= 0xFF
    corrupt.write_bytes(bytes(raw))
    assert "not a readable" in _one_error(capsys, main(["solve", str(corrupt)]))

    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        header, {"descr": "<f8", "fortran_order": False, "shape": (10**11, 2)}
    )
    huge = tmp_path / "huge.npz"
    with zipfile.ZipFile(huge, "w") as zf:
        for key, value in arrays.items():
            buf = io.BytesIO()
            np.save(buf, value)
            zf.writestr(f"{key}.npy", header.getvalue() if key == "positions" else buf.getvalue())
    assert "declares shape" in _one_error(capsys, main(["solve", str(huge)]))

    npy = tmp_path / "p.npy"
    np.save(npy, np.zeros((3, 2)))
    assert "plain .npy" in _one_error(capsys, main(["solve", str(npy)]))


def test_sample_with_negative_seed_or_huge_n(tmp_path, capsys):
    out = str(tmp_path / "s.npz")
    err = _one_error(capsys, main(["sample", out, "--p-r", "0.5", "--seed", "-1"]))
    assert "seed must be a non-negative integer" in err
    err = _one_error(capsys, main(["sample", out, "--p-r", "0.5", "--n", "1000000"]))
    assert "n = 1000000" in err and "this machine has" in err
    assert list(tmp_path.iterdir()) == []


def test_sample_into_a_directory_or_nowhere_leaves_no_temporary(tmp_path, capsys):
    target = tmp_path / "d.npz"
    target.mkdir()
    err = _one_error(capsys, main(["sample", str(target), "--n", "4", "--p-r", "0.5"]))
    assert "is a directory" in err
    err = _one_error(capsys, main(["sample", "", "--n", "4", "--p-r", "0.5"]))
    assert "empty" in err
    assert [p.name for p in tmp_path.iterdir()] == ["d.npz"]


def test_sample_into_a_read_only_directory_leaves_no_temporary(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    cmd = [sys.executable, "-m", "tensegrity_rigidity", "sample", str(ro / "s.npz")]
    try:
        proc = subprocess.run(
            unprivileged(cmd + ["--n", "4", "--p-r", "0.5"]), capture_output=True, text=True
        )
        err = proc.stderr.strip()
        assert proc.returncode == 2 and len(err.splitlines()) == 1, err
        assert err.startswith("error: ") and "Permission denied" in err
        assert list(ro.iterdir()) == []
    finally:
        ro.chmod(0o755)


def test_sample_onto_a_full_disk(tmp_path, capsys, monkeypatch):
    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(np, "savez", full)
    out = tmp_path / "s.npz"
    err = _one_error(capsys, main(["sample", str(out), "--n", "4", "--p-r", "0.5"]))
    assert "No space left on device" in err and list(tmp_path.iterdir()) == []


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
def test_solve_output_to_a_full_device(instance_file):
    with open("/dev/full", "w") as full:
        proc = subprocess.run(
            [sys.executable, "-m", "tensegrity_rigidity", "solve", str(instance_file)],
            stdout=full,
            stderr=subprocess.PIPE,
            text=True,
        )
    err = proc.stderr.strip()
    assert proc.returncode == 2 and len(err.splitlines()) == 1, err
    assert err.startswith("error: ") and "No space left on device" in err


def test_a_command_with_its_output_closed_exits_quietly(instance_file):
    """``solve FILE >&-``: Python has no sys.stdout; the work was done, then the final flush
    ended in "AttributeError: 'NoneType' object has no attribute 'flush'" with status 1."""
    proc = subprocess.run(
        [sys.executable, "-m", "tensegrity_rigidity", "solve", str(instance_file)],
        stdin=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: os.close(1),
    )
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr


def test_solve_into_a_closed_pipe(instance_file):
    """``solve FILE | head``: the reader is gone before the output is written. It printed
    "error: the output pipe was closed" with status 2, noise after ``info DIR | head -1``."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "tensegrity_rigidity", "solve", str(instance_file), "--json"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    proc.stdout.close()
    err = proc.stderr.read().strip()
    proc.wait(timeout=60)
    assert proc.returncode == 141 and err == "", err  # silent, as the shell's own tools


def test_solve_json_has_no_nan_or_infinity(capsys, instance_file, monkeypatch):
    from tensegrity_rigidity.solver.core import SolveResult

    real = SolveResult.summary

    def with_nonfinite(self):
        return real(self) | {"work": float("nan"), "force_residual": float("inf")}

    monkeypatch.setattr(SolveResult, "summary", with_nonfinite)
    assert main(["solve", str(instance_file), "--json"]) == 0
    text = capsys.readouterr().out

    def refuse(name):
        raise AssertionError(f"{name} in JSON output")

    data = json.loads(text, parse_constant=refuse)
    assert data["work"] is None and data["force_residual"] is None


def test_non_utf8_spec(tmp_path, capsys):
    spec = tmp_path / "latin1.toml"
    spec.write_bytes("# réseau\nn = 5\np_r = 0.5\n".encode("latin-1"))
    err = _one_error(capsys, main(["sweep", str(spec), "--out", str(tmp_path / "o")]))
    assert "not UTF-8" in err and not (tmp_path / "o").exists()


def test_empty_out_is_refused_everywhere(tmp_path, capsys, monkeypatch):
    spec = tmp_path / "s.toml"
    spec.write_text(textwrap.dedent(SPEC))
    monkeypatch.chdir(tmp_path)
    assert "--out is empty" in _one_error(capsys, main(["sweep", str(spec), "--out", ""]))
    err = _one_error(capsys, main(["reproduce", "--scale", "tiny", "--out", ""]))
    assert "--out is empty" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


def test_workers_below_one_and_missing_evidence_are_refused_everywhere(tmp_path, capsys):
    """0 workers is an error everywhere (it once meant every core in reproduce --estimate),
    and --evidence must exist even when only estimating."""
    spec = tmp_path / "s.toml"
    spec.write_text(textwrap.dedent(SPEC))
    out = str(tmp_path / "o")
    for workers in ("0", "-2"):
        expected = f"error: --workers must be at least 1, got {workers}"
        for cmd in (
            ["sweep", str(spec), "--out", out],
            ["reproduce", "--scale", "tiny", "--out", out],
            ["reproduce", "--scale", "tiny", "--estimate"],
        ):
            assert _one_error(capsys, main([*cmd, "--workers", workers])) == expected
    absent = str(tmp_path / "absent")
    err = _one_error(
        capsys, main(["reproduce", "--scale", "quick", "--estimate", "--evidence", absent])
    )
    assert err == f"error: --evidence {absent}: no such directory"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]
    from tensegrity_rigidity.ensemble.executors import local_workers, open_pool, usable_cores
    from tensegrity_rigidity.errors import SpecError

    with pytest.raises(SpecError, match="executor must be at least 1, got 0"):
        with open_pool(0):
            pass
    assert local_workers(None) == usable_cores() and local_workers(1) == 1


def test_an_estimate_prices_the_workers_asked_for_even_above_the_local_cores(capsys):
    """``--estimate --workers 100`` priced 2 workers and warned "running at most 2", although
    the help promises the wall time on N workers for the cluster scales."""
    assert main(["reproduce", "--scale", "tiny", "--estimate", "--workers", "100"]) in (0, 1)
    out, err = capsys.readouterr()
    assert "on 100 worker(s)" in out and "running at most" not in err


def test_an_estimate_against_a_file_is_refused(tmp_path, capsys):
    (tmp_path / "f").write_text("")
    code = main(["reproduce", "--scale", "tiny", "--estimate", "--out", str(tmp_path / "f")])
    assert "not a directory" in _one_error(capsys, code)


def test_large_delta_warns_in_one_line(tmp_path, capsys):
    spec = tmp_path / "s.toml"
    spec.write_text(textwrap.dedent(SPEC).replace("n = 5", "n = 5\ndelta = 0.49"))
    assert main(["sweep", str(spec), "--out", str(tmp_path / "o"), "--workers", "1"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("warning: delta = 0.49 lets bonds"), err


def test_sweep_prints_p_with_wilson_intervals(tmp_path, capsys):
    from tensegrity_rigidity.ensemble.sweep import load_results

    spec = tmp_path / "s.toml"
    spec.write_text(textwrap.dedent(SPEC))
    out = tmp_path / "o"
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[0].startswith(f"{out}: ran 24 samples")
    assert lines[1].split() == ["p_r", "phi", "N", "undecided", "rigid", "P", "[95%", "Wilson]"]
    rows = load_results(out)
    for line in lines[2:]:
        p_r, phi, n, und, k, *_ = line.split()
        sub = rows[
            (rows.p_r == float(p_r)) & np.isclose(rows.phi, 0 if phi == "dilation" else np.pi)
        ]
        assert int(n) == sub.decided.sum() == 6 and int(und) == 0 and int(k) == sub.rigid.sum()
        p, lo, hi = wilson(int(k), int(n))
        assert line.endswith(f"{p:.3f} [{lo:.3f}, {hi:.3f}]")
    assert len(lines) == 2 + 4


def test_info_says_what_a_directory_holds(tmp_path, capsys):
    spec = tmp_path / "s.toml"
    spec.write_text(textwrap.dedent(SPEC))
    out = tmp_path / "o"
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1"]) == 0
    capsys.readouterr()
    assert main(["info", str(out)]) == 0
    text = capsys.readouterr().out
    assert f"{out}: grid sweep, 4 grid points x 6 samples" in text
    assert "done      24 of 24 samples (0 undecided); 0 chunks missing" in text
    assert "golden angles" in text and "P [95% Wilson]" in text
    # a grown spec that was interrupted before any work: 4 points x 2 new chunks missing
    from tensegrity_rigidity.ensemble.spec import load_spec
    from tensegrity_rigidity.ensemble.store import ResultStore

    spec.write_text(textwrap.dedent(SPEC).replace("samples = 6", "samples = 14"))
    with ResultStore(out).writing() as store:
        store.prepare(load_spec(spec))
    assert main(["info", str(out)]) == 0
    text = capsys.readouterr().out
    assert "done      24 of 56 samples (0 undecided); 8 chunks missing" in text
    assert "left      about" in text and "damaged" not in text
    part = sorted(out.glob("part-*.parquet"))[0]
    part.write_bytes(part.read_bytes()[:-8] + b"12345678")
    assert main(["info", str(out)]) == 0
    text = capsys.readouterr().out
    assert "done      20 of 56 samples" in text and "damaged   1 parts" in text
    assert "not a results directory" in _one_error(capsys, main(["info", str(tmp_path)]))
    err = _one_error(capsys, main(["info", str(tmp_path / "absent")]))
    assert "no such results directory" in err
    for rows in ("0", "-3"):
        err = _one_error(capsys, main(["info", str(out), "--rows", rows]))
        assert err == f"error: --rows must be at least 1, got {rows}"
    assert main(["info", str(out), "--rows", "1"]) == 0
    assert "... 3 more grid points" in capsys.readouterr().out


# --------------------------------------------------------------------------- output paths


def _special_nodes(tmp_path):
    """(name, path, check it is unchanged) of nodes that are not regular files."""
    import stat

    fifo = tmp_path / "fifo.npz"
    os.mkfifo(fifo)
    target = tmp_path / "target.npz"
    target.write_bytes(b"the link's target")
    link = tmp_path / "link.npz"
    link.symlink_to(target)
    nodes = [
        ("FIFO", fifo, lambda: stat.S_ISFIFO(os.lstat(fifo).st_mode)),
        (
            "symbolic link",
            link,
            lambda: link.is_symlink() and target.read_bytes() == b"the link's target",
        ),
    ]
    device = tmp_path / "null.npz"
    try:  # a character device like /dev/null (root only): never touch the real /dev
        os.mknod(device, 0o666 | stat.S_IFCHR, os.makedev(1, 3))
        nodes.append(("device", device, lambda: stat.S_ISCHR(os.lstat(device).st_mode)))
    except (PermissionError, AttributeError, OSError):
        pass
    return nodes


def test_outputs_are_regular_files_only(tmp_path, capsys, instance_file):
    """`sample /dev/full` as root replaced the device node by a regular file (and a FIFO or a
    symbolic link too): the output is written beside the path and renamed over it. Such paths
    are refused before any work, in one line, and left as they were."""
    nodes = _special_nodes(tmp_path)
    for name, path, unchanged in nodes:
        code = main(["sample", str(path), "--n", "4", "--p-r", "0.5"])
        err = _one_error(capsys, code)
        assert "regular files only" in err, (name, err)
        plot = path.with_suffix(".png")
        os.rename(path, plot)
        code = main(["solve", str(instance_file), "--plot", str(plot)])
        err = _one_error(capsys, code)
        assert "regular files only" in err and "rigid" not in capsys.readouterr().out, err
        os.rename(plot, path)
        assert unchanged(), name
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_a_figure_on_a_full_disk_leaves_no_file(tmp_path, capsys, instance_file, monkeypatch):
    """`--plot` on a full disk left a 0-byte figure: now nothing, and one line."""
    from matplotlib.figure import Figure

    def full(self, fname, *args, **kwargs):
        with open(fname, "wb") as fh:
            fh.write(b"\x89PNG partial")  # what the disk took before it was full
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(Figure, "savefig", full)
    figure = tmp_path / "f.png"
    err = _one_error(capsys, main(["solve", str(instance_file), "--plot", str(figure)]))
    assert "No space left on device" in err and str(figure) in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.npz"]


def test_sample_refuses_a_theta_the_fcc_lattice_would_ignore(tmp_path, capsys):
    out = tmp_path / "s.npz"
    args = ["sample", str(out), "--n", "3", "--p-r", "0.6", "--lattice", "fcc"]
    err = _one_error(capsys, main(args + ["--theta", "0.5"]))
    assert "theta" in err and "ignored in 3D" in err and not out.exists()
    assert main(args) == 0 and out.exists()
