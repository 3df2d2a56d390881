"""A sweep can decide its samples the paper's way (spec key ``verdict``), on the same samples."""

from __future__ import annotations

import numpy as np
import pytest

from tensegrity_rigidity.ensemble.spec import parse_spec
from tensegrity_rigidity.ensemble.sweep import load_results, run_sweep
from tensegrity_rigidity.errors import SpecError

BASE = {"n": 5, "p_r": [0.5, 0.7], "p_t": 0.2, "f_c": 1.0, "phi": "compression", "samples": 4}


def test_verdict_key_is_validated_and_part_of_the_settings():
    assert parse_spec(BASE).verdict == "exact"
    exact = parse_spec(BASE).settings_digest()
    assert exact == parse_spec(BASE | {"verdict": "exact"}).settings_digest()
    paper = parse_spec(BASE | {"verdict": "paper"})
    assert paper.verdict == "paper" and paper.settings_digest() != exact
    with pytest.raises(SpecError, match="verdict"):
        parse_spec(BASE | {"verdict": "lbfgs"})
    threshold = {k: v for k, v in BASE.items() if k != "p_r"} | {"threshold": {"path": "p_r"}}
    with pytest.raises(SpecError, match="grid mode"):
        parse_spec(threshold | {"verdict": "paper"})


def test_paper_verdict_sweep_decides_the_same_samples(tmp_path):
    run_sweep(parse_spec(BASE), tmp_path / "exact", executor="serial", progress=False)
    run_sweep(
        parse_spec(BASE | {"verdict": "paper"}),
        tmp_path / "paper",
        executor="serial",
        progress=False,
    )
    exact, paper = load_results(tmp_path / "exact"), load_results(tmp_path / "paper")
    assert len(exact) == len(paper) == 8
    assert (paper.method == "paper-lbfgsb").all() and paper.decided.all()
    # same samples: the affine energy depends only on the sample's geometry and elements
    np.testing.assert_allclose(paper.affine_energy, exact.affine_energy, rtol=1e-12)
    assert (paper.energy >= exact.energy - 1e-9 * paper.affine_energy).all()


def test_a_paper_verdict_directory_reads_back_its_own_rows(tmp_path):
    """The recorded spec keeps the verdict key, so the rows of a paper-verdict sweep are the
    rows of its latest spec (they once read back as none)."""
    run_sweep(parse_spec(BASE | {"verdict": "paper"}), tmp_path, executor="serial", progress=False)
    assert len(load_results(tmp_path)) == 8
