"""Sweeps of 3D (FCC) samples: grid and threshold modes, processes and Dask, exact agreement."""

from __future__ import annotations

import textwrap

import numpy as np
import pandas as pd
import pytest

from tensegrity_rigidity import decide, load_results, run_sweep
from tensegrity_rigidity.ensemble.runner import sample_geometry, sample_strain
from tensegrity_rigidity.ensemble.spec import load_spec
from tensegrity_rigidity.model.elements import place_elements
from tensegrity_rigidity.model.network import Instance

GRID = """
n = [2, 3]
p_r = [0.45, 0.7]
p_t = [0.0, 0.25]
phi = ["dilation", "shear", "compression"]
samples = 3
seed = 4
[lattice]
kind = "fcc"
[output]
chunk_size = 3
"""

THRESHOLD = """
n = 3
p_t = [0.0, 0.3]
phi = ["dilation", "compression"]
samples = 4
seed = 5
[lattice]
kind = "fcc"
[threshold]
path = "p_r"
"""


def _write(tmp_path, text, name="spec.toml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def _frame(out):
    return load_results(out).drop(columns=["solve_seconds"]).reset_index(drop=True)


def test_a_3d_sweep_gives_the_same_rows_serially_in_processes_and_on_dask(tmp_path):
    distributed = pytest.importorskip("distributed")
    spec = _write(tmp_path, GRID)
    run_sweep(spec, tmp_path / "serial", executor="serial", progress=False)
    run_sweep(spec, tmp_path / "proc", executor=2, progress=False)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        run_sweep(spec, tmp_path / "dask", scheduler=cluster.scheduler_address, progress=False)
    a = _frame(tmp_path / "serial")
    assert len(a) == 2 * 2 * 2 * 3 * 3 and a["decided"].all()
    pd.testing.assert_frame_equal(a, _frame(tmp_path / "proc"))
    pd.testing.assert_frame_equal(a, _frame(tmp_path / "dask"))
    # a row's instance is rebuilt from its key: the strain has the 3D kind's principal values
    sp = load_spec(spec)
    point = next(iter(sp.points()))
    net, u, v, theta = sample_geometry(sp, point, 2)
    eps = sample_strain(sp, point, 2, theta, net.dim)
    assert eps.shape == (3, 3) and net.dim == 3


def test_3d_thresholds_bracket_the_grid_verdicts(tmp_path):
    """Each sample's threshold p_r* separates its rigid from its floppy grid verdicts."""
    spec = _write(tmp_path, THRESHOLD)
    run_sweep(spec, tmp_path / "t", executor="serial", progress=False)
    rows = load_results(tmp_path / "t")
    assert len(rows) == 2 * 2 * 4 and rows["decided"].all()
    sp = load_spec(spec)
    points = {(pt.p_t, pt.phi): pt for pt in sp.points()}
    for _, row in rows.iterrows():
        point = points[(row["p_t"], row["phi"])]
        net, u, v, theta = sample_geometry(sp, point, int(row["sample"]))
        strain = sample_strain(sp, point, int(row["sample"]), theta, net.dim)
        star = row["threshold_p_r"]
        for p_r in (star - 0.02, star + 0.02):
            if not 0 <= p_r <= 1 - row["p_t"]:
                continue
            kinds = place_elements(u, v, p_r, row["p_t"], 0.5)
            status = decide(Instance(net.with_kinds(kinds), strain)).status
            assert status == ("rigid" if p_r > star else "floppy"), (row["sample"], p_r, star)
    assert np.all(rows["threshold_p_r"] > 0.1)
