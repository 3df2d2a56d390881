"""Finite-size and node-disorder studies at tiny sizes: definitions, fits, evidence."""

from __future__ import annotations

import numpy as np
import pytest

from tensegrity_rigidity.ensemble.sweep import load_results
from tensegrity_rigidity.paper import finite_size as fs
from tensegrity_rigidity.paper.claims import CLAIMS
from tensegrity_rigidity.paper.studies import Scale

TINY = Scale(
    "mini", 4, 4, 3, 2, 3, 0.1, 50, 5,
    fss_sizes=(4, 5, 6, 8), samples_fss=4, deltas=(0.1, 0.2), n_delta=4, samples_delta=3,
)  # fmt: skip
KEYS = (
    {"rods_only_pc"}
    | {k for k, _, _ in fs.LAMBDA_CLAIMS}
    | {f"p_crit_{s}_{p}" for s in ("compression", "dilation") for p in fs.PT4}
)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    out = tmp_path_factory.mktemp("fss")
    kw = dict(workers="serial", scheduler=None, progress=False)
    return fs.study_fss(out, TINY, **kw), fs.study_delta(out, TINY, **kw), out


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
    assert set(delta.by_delta.delta) == {0.1, 0.2}
    assert {m.label for m in delta.measured} == {"delta = 0.1"}
    assert all(m.factor == "delta" for m in delta.measured)
    assert np.isfinite(delta.by_delta.z_paper).any()


def test_same_samples_across_the_two_sweeps_of_one_size(runs):
    """The rods-only and the mixed sweep share seed, n and delta, so sample k is the same
    lattice in both (common random numbers): adding one-sided elements (p_t = 0.1) can only
    lower a sample's threshold, sample by sample."""
    fss, _, out = runs
    rods = load_results(out / "studies" / "headline_n8_delta0.2_s4_rods")
    rods = rods[["phi", "sample", "threshold_p_r"]]
    mixed = load_results(out / "studies" / "headline_n8_delta0.2_s4_mixed")
    mixed = mixed[np.isclose(mixed.p_t, 0.1)]
    for f_c, sub in mixed.groupby("f_c"):
        joined = sub.merge(rods, on=["phi", "sample"], suffixes=("", "_rods"))
        both = joined.dropna(subset=["threshold_p_r", "threshold_p_r_rods"])
        assert len(both) and (both.threshold_p_r <= both.threshold_p_r_rods + 1e-12).all(), f_c
    assert all(v >= 0 for v in fss.excluded.values())
