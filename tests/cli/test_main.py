from __future__ import annotations

import json
import subprocess
import sys

import pytest

from tensegrity_rigidity.cli.main import main


def test_sample_then_solve_json(tmp_path, capsys):
    out = tmp_path / "s.npz"
    assert main(["sample", str(out), "--n", "6", "--p-r", "0.9", "--phi", "dilation"]) == 0
    capsys.readouterr()
    assert main(["solve", str(out), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    for key in ("energy", "rigid", "affine_energy", "force_residual", "violation", "work"):
        assert key in data
    assert data["rigid"] is True and data["energy"] > 0


@pytest.mark.parametrize(("p_r", "status"), [("0.9", "rigid"), ("0.3", "floppy")])
def test_solve_text_shows_the_deciding_certificate_and_names_the_other_candidate(
    tmp_path, capsys, p_r, status
):
    """The text form led with 'violation ... (best candidate, rejected)' for a rigid sample,
    which read like a failure: it now names the certificate that decided, and the other side's
    best candidate as what it is."""
    out = tmp_path / "s.npz"
    assert main(["sample", str(out), "--n", "6", "--p-r", p_r, "--phi", "dilation"]) == 0
    capsys.readouterr()
    assert main(["solve", str(out)]) == 0
    lines = capsys.readouterr().out.splitlines()
    first = {k: v.strip() for k, v in (line.split("  ", 1) for line in lines)}
    assert lines[0].split() == ["status", status]
    kind, other = ("self-stress", "floppy") if status == "rigid" else ("displacement", "rigid")
    assert lines[1].split()[:2] == ["certificate", kind]
    assert f"{other} candidate" in first
    candidate = first[f"{other} candidate"]
    assert candidate == "none found" or candidate.endswith(f"rejected: the sample is {status})")
    assert "rejected" not in lines[1]


def _result(status: str, **kw):
    import numpy as np

    from tensegrity_rigidity.solver.core import SolveResult

    fields = dict(
        energy=0.0,
        energy_lower=0.0,
        affine_energy=1.0,
        rigid=status == "rigid",
        decided=status != "undecided",
        tensions=np.zeros(3),
        displacements=np.zeros((1, 2)),
        extensions=np.zeros(3),
        work=0.1,
        force_residual=1e-3,
        violation=2e-9,
        displacement_size=5.0,
        iterations=3,
        factorizations=4,
        method="lp" if status != "undecided" else "undecided",
        min_norm_ok=False,
    )
    return SolveResult(**(fields | kw))


def test_solve_text_of_an_undecided_sample_shows_both_candidates_and_why():
    from tensegrity_rigidity.cli.main import solve_text

    text = solve_text(_result("undecided", reason="within resolution", message="because"))
    lines = {line.split("  ")[0]: line for line in text.splitlines()}
    assert lines["status"].split(None, 1) == ["status", "undecided (within resolution)"]
    assert "none accepted" in lines["certificate"]
    assert "work 0.1, force residual 0.001" in lines["rigid candidate"]
    assert "violation 2e-09, size 5" in lines["floppy candidate"]
    assert lines["message"].endswith("because")
    assert "not certified minimum-norm" in lines["displacements"]


@pytest.mark.parametrize("cmd", [[], ["sample"], ["solve"], ["sweep"], ["reproduce"], ["info"]])
def test_help_everywhere(cmd):
    proc = subprocess.run(
        [sys.executable, "-m", "tensegrity_rigidity", *cmd, "--help"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0 and "usage" in proc.stdout
    assert "%%" not in proc.stdout  # argparse does not %-format descriptions


def test_foreign_warnings_name_their_category_and_place():
    """A NumPy warning relayed from a worker must say where it came from to be traceable; the
    package's own warnings stay plain sentences."""
    import io
    import warnings

    import numpy as np

    from tensegrity_rigidity.cli.main import _one_line_warning
    from tensegrity_rigidity.errors import UndecidedWarning

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        np.array([1.0]) / np.array([0.0])
    (w,) = caught
    out = io.StringIO()
    _one_line_warning(w.message, w.category, w.filename, w.lineno, file=out)
    text = out.getvalue()
    assert text.startswith("warning: divide by zero encountered in divide (RuntimeWarning at ")
    assert f"test_main.py:{w.lineno})" in text and text.count("\n") == 1
    out = io.StringIO()
    _one_line_warning(UndecidedWarning("undecided sample: x"), UndecidedWarning, __file__, 1, out)
    assert out.getvalue() == "warning: undecided sample: x\n"


def test_n_help_says_n_cubed_nodes_for_fcc(capsys):
    with pytest.raises(SystemExit):
        main(["sample", "--help"])
    assert "n^3 nodes with --lattice fcc" in " ".join(capsys.readouterr().out.split())


def test_info_on_the_output_of_reproduce_summarises_its_sweeps(tmp_path, capsys):
    """info on a reproduce directory failed with 'no _spec.json'; only its sub-folders worked."""
    from tensegrity_rigidity.ensemble.spec import parse_spec
    from tensegrity_rigidity.ensemble.sweep import run_sweep

    out = tmp_path / "results"
    grid = parse_spec({"n": 4, "p_r": [0.5, 0.8], "samples": 3})
    run_sweep(grid, out / "studies" / "fig_a", executor="serial", progress=False)
    threshold = parse_spec({"n": 4, "p_t": 0.1, "samples": 2, "threshold": {"path": "p_r"}})
    run_sweep(threshold, out / "studies" / "fig_b", executor="serial", progress=False)
    (out / "studies" / "fig_c").mkdir()  # a sweep not started yet: no rows, no spec
    (out / "report.md").write_text("# report\n")
    assert main(["info", str(out)]) == 0
    text = capsys.readouterr().out
    assert text.splitlines()[0] == (
        f"{out}: the output of reproduce, 2 sweeps under studies/, report.md written"
    )
    assert "samples   8 of 8 done (0 undecided); 0 chunks missing" in text
    rows = {line.split()[0]: line.split() for line in text.splitlines()[4:]}
    assert rows["fig_a"][1:5] == ["grid", "6", "/", "6"]
    assert rows["fig_b"][1:5] == ["threshold", "2", "/", "2"]
    assert main(["info", str(out), "--rows", "1"]) == 0
    assert "... 1 more sweep (--rows to show them)" in capsys.readouterr().out
    assert main(["info", str(out / "studies" / "fig_a")]) == 0  # one sweep: as before
    assert "grid sweep, 2 grid points x 3 samples" in capsys.readouterr().out


def test_info_names_the_threshold_method(tmp_path, capsys):
    """info printed "path p_r, solver defaults" for a pebble sweep and an lp one alike (and the
    options of a solver the pebble game never calls)."""
    from tensegrity_rigidity.ensemble.spec import parse_spec
    from tensegrity_rigidity.ensemble.sweep import run_sweep

    for method in ("pebble", "lp"):
        spec = {"n": 4, "samples": 2, "threshold": {"path": "p_r", "method": method}}
        run_sweep(parse_spec(spec), tmp_path / method, executor="serial", progress=False)
        assert main(["info", str(tmp_path / method)]) == 0
        text = capsys.readouterr().out
        solver = "unused" if method == "pebble" else "defaults"
        assert f"path p_r by {method}" in text and f"solver {solver}," in text
