"""Memory guards per lattice and dimension, from the costs benchmarks/measure_memory.py wrote."""

from __future__ import annotations

import importlib.resources
import tomllib

import numpy as np
import pytest

import tensegrity_rigidity.ensemble.sweep as sweep_mod
import tensegrity_rigidity.model.limits as limits
from tensegrity_rigidity import InputError, SpecError, decide, lattice_instance, parse_spec
from tensegrity_rigidity.combinatorics.clusters import rigid_clusters
from tensegrity_rigidity.ensemble.sweep import check_size, estimate
from tensegrity_rigidity.model.lattice import fcc_lattice, triangular_lattice
from tensegrity_rigidity.model.sampling import LATTICE_DIMENSIONS, LATTICES

GiB = 1 << 30


def _machine(monkeypatch, memory: int) -> None:
    """Pretend this machine has ``memory`` bytes."""
    monkeypatch.setattr(limits, "physical_memory", lambda: memory)
    monkeypatch.setattr(sweep_mod, "physical_memory", lambda: memory)


def test_the_costs_are_package_data_written_by_the_measurement():
    text = importlib.resources.files("tensegrity_rigidity.model").joinpath("memory_costs.toml")
    costs = tomllib.loads(text.read_text())
    assert "benchmarks/measure_memory.py" in text.read_text().splitlines()[0]
    assert set(costs) == set(LATTICES)
    for lattice, entry in costs.items():
        assert entry["dim"] == LATTICE_DIMENSIONS[lattice]
        stages = {"build", "solve", "threshold"} | ({"clusters"} if entry["dim"] == 2 else set())
        for stage in stages:
            assert entry[stage] > 0 and entry[f"{stage}_exponent"] >= 1
            assert entry[f"{stage}_nodes"] >= 64


def test_an_fcc_sweep_counts_n_cubed_nodes_at_3d_costs(monkeypatch):
    """FCC sweeps were estimated at n^2 nodes with 2D costs: n = 100 at 0.12 GiB, against tens
    of GiB measured. Now n^3 nodes at the FCC lattice's own costs per node."""
    fcc = parse_spec({"n": 100, "p_r": 0.5, "samples": 1, "lattice": {"kind": "fcc"}})
    flat = parse_spec({"n": 100, "p_r": 0.5, "samples": 1})
    nodes = 100**3
    costs = limits.MEMORY_COSTS["fcc"]
    assert estimate(fcc)["sample_bytes"] >= (costs["build"] + costs["solve"]) * nodes
    assert estimate(fcc)["sample_bytes"] > 10 * GiB > estimate(flat)["sample_bytes"]
    _machine(monkeypatch, 16 * GiB)
    with pytest.raises(SpecError, match=r"n = 100 needs about .* \(100\^3 nodes of the fcc"):
        check_size(fcc, "never")
    check_size(flat, "never")


@pytest.mark.parametrize(
    "threshold, stage",
    [({"path": "p_r"}, "threshold"), ({"path": "p_r", "method": "pebble"}, "clusters")],
)
def test_a_threshold_sweep_is_priced_at_its_own_work(threshold, stage):
    spec = parse_spec({"n": 64, "p_t": 0.0, "samples": 1, "threshold": threshold})
    nodes = 64**2
    want = limits.stage_bytes("build", nodes, "triangular") + limits.stage_bytes(
        stage, nodes, "triangular"
    )
    assert estimate(spec)["sample_bytes"] == pytest.approx(want)


def test_costs_grow_beyond_the_largest_size_measured_as_fitted():
    costs = limits.MEMORY_COSTS["fcc"]
    ref, e = costs["solve_nodes"], costs["solve_exponent"]
    small = limits.stage_bytes("solve", ref, "fcc")
    large = limits.stage_bytes("solve", 8 * ref, "fcc")
    assert small == pytest.approx(costs["solve"] * ref)
    assert large == pytest.approx(8 * small * 8 ** (e - 1))


def test_rigid_clusters_is_guarded(monkeypatch):
    """The pebble game had no guard (about 300 bytes per node)."""
    inst = lattice_instance(16, 0.7, seed=1)
    need = limits.stage_bytes("clusters", 16**2, dim=2)
    _machine(monkeypatch, int(need / 2))
    with pytest.raises(InputError, match=r"the pebble game on 256 nodes needs about"):
        rigid_clusters(inst)
    _machine(monkeypatch, int(need * 2))
    assert rigid_clusters(inst).rank > 0


def test_solves_and_builders_are_guarded_by_dimension(monkeypatch):
    inst = lattice_instance(3, 0.7, lattice="fcc", seed=1)
    need = limits.stage_bytes("solve", 27, dim=3)
    assert need == limits.stage_bytes("solve", 27, "fcc")
    _machine(monkeypatch, int(need / 2))
    with pytest.raises(InputError, match=r"solving a 3D network of 27 nodes needs about"):
        decide(inst)
    _machine(monkeypatch, 4 * GiB)
    build = limits.MEMORY_COSTS["fcc"]["build"]
    n = int((4 * GiB / build) ** (1 / 3)) + 1  # just beyond this machine at the FCC cost
    with pytest.raises(InputError, match=rf"a lattice of n = {n} \({n}\^3 nodes\) needs about"):
        fcc_lattice(n, 0.0)
    triangular_lattice(n, 0.0, np.random.default_rng(0))  # n^2 nodes fit
