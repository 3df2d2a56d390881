"""Finite-size and node-disorder studies at tiny sizes: definitions, fits, evidence."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from tensegrity_rigidity.ensemble.sweep import load_results
from tensegrity_rigidity.paper import finite_size as fs
from tensegrity_rigidity.paper.claims import CLAIMS
from tensegrity_rigidity.paper.reproduce import reproduce

from .conftest import SERIAL, TINY

KEYS = (
    {"rods_only_pc"}
    | {k for k, _, _ in fs.LAMBDA_CLAIMS}
    | {f"p_crit_{s}_{p}" for s in ("compression", "dilation") for p in fs.PT4}
)


@pytest.fixture(scope="module")
def runs(tiny_out):
    """Both studies on the session's tiny reproduction (their sweeps resume)."""
    return (
        fs.study_fss(tiny_out, TINY, **SERIAL),
        fs.study_delta(tiny_out, TINY, **SERIAL),
        tiny_out,
    )


def test_every_headline_claim_at_every_size(runs):
    fss, _, _ = runs
    assert KEYS <= set(CLAIMS)
    assert set(fss.by_size.key) == KEYS
    assert sorted(set(fss.by_size.n)) == list(TINY.fss_sizes)
    assert len(fss.by_size) == len(KEYS) * len(TINY.fss_sizes)


def test_extrapolations_fit_nu_for_the_threshold_and_reuse_it(runs):
    fss, _, _ = runs
    ex = fss.extrapolated.set_index("key")
    pc = ex.loc["rods_only_pc"]
    assert not pc.nu_fixed and pc.dof == len(TINY.fss_sizes) - 3
    others = ex.drop(index="rods_only_pc")
    assert others.nu_fixed.all()
    assert np.allclose(others.nu, pc.nu, equal_nan=True)
    assert np.isfinite(fss.nu_z) or np.isnan(pc.nu)
    assert all(m.factor == "finite size" for m in fss.measured)


def test_delta_study_gives_evidence_for_the_other_deltas_only(runs):
    _, delta, _ = runs
    assert set(delta.by_delta.delta) == set(TINY.deltas) == {0.1, 0.2, 0.3}
    assert {m.label for m in delta.measured} == {"delta = 0.1", "delta = 0.3"}
    assert all(m.factor == "delta" for m in delta.measured)
    assert np.isfinite(delta.by_delta.z_paper).any()


def test_same_samples_across_the_two_sweeps_of_one_size(runs):
    """The rods-only and the mixed sweep share seed, n and delta, so sample k is the same
    lattice in both (common random numbers): adding one-sided elements (p_t = 0.1) can only
    lower a sample's threshold, sample by sample."""
    fss, _, out = runs
    rods = load_results(out / "studies" / "headline_n8_delta0.2_s3_rods")
    rods = rods[["phi", "sample", "threshold_p_r"]]
    mixed = load_results(out / "studies" / "headline_n8_delta0.2_s3_mixed")
    mixed = mixed[np.isclose(mixed.p_t, 0.1)]
    for f_c, sub in mixed.groupby("f_c"):
        joined = sub.merge(rods, on=["phi", "sample"], suffixes=("", "_rods"))
        both = joined.dropna(subset=["threshold_p_r", "threshold_p_r_rods"])
        assert len(both) and (both.threshold_p_r <= both.threshold_p_r_rods + 1e-12).all(), f_c
    assert all(v >= 0 for v in fss.excluded.values())


def test_a_report_of_the_finite_size_studies_alone(tiny_out, tmp_path):
    shutil.copytree(tiny_out / "studies", tmp_path / "studies")  # resume: no new samples
    res = reproduce(tmp_path, "tiny", workers="serial", progress=False, studies=["fss", "delta"])
    md = res["report"]["md"].read_text()
    assert "## Finite size" in md and "## Node disorder delta" in md and "## Figure FS" in md
    assert (tmp_path / "tables" / "fss_extrapolated.csv").exists()
