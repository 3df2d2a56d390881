"""The cost model counts the work the studies do, prices it, and says what it cannot price."""

from __future__ import annotations

import dataclasses
import math
import re

import pytest

from tensegrity_rigidity.cli.main import main
from tensegrity_rigidity.ensemble.sweep import load_results
from tensegrity_rigidity.errors import InputError
from tensegrity_rigidity.paper import budget
from tensegrity_rigidity.paper.budget import COSTS
from tensegrity_rigidity.paper.registry import SCALES, STUDIES
from tensegrity_rigidity.paper.reproduce import EXPECTED

from .conftest import TINY


def test_counts_match_the_rows_the_tiny_sweeps_produced(tiny_out):
    """Every sweep the tiny reproduction wrote is in the estimate with the rows it holds, and
    the rows to compute, summed, are the distinct rows stored (shared sweeps counted once)."""
    est = budget.estimate(TINY)
    written = {p.name for p in (tiny_out / "studies").iterdir()}
    assert {s.name for s in est.sweeps} == written
    stored = 0
    for name in written:
        rows = load_results(tiny_out / "studies" / name)
        assert all(s.rows == len(rows) for s in est.sweeps if s.name == name), name
        stored += len(load_results(tiny_out / "studies" / name, all_rows=True))
    assert sum(s.new_rows for s in est.sweeps) == stored
    t = est.table()
    assert t.thresholds.sum() + t.grid.sum() + t.paper.sum() == stored
    assert set(t.study) == set(TINY.studies)


def test_a_finished_run_has_nothing_left_to_compute(tiny_out):
    est = budget.estimate(TINY, out=tiny_out)
    assert all(s.new_rows == 0 and s.cpu_seconds == 0 for s in est.sweeps)
    assert est.wall_seconds == pytest.approx(sum(est.serial.values()))
    full = budget.estimate(TINY)
    assert full.wall_seconds > est.wall_seconds


def test_shared_sweeps_are_priced_once():
    """fss and delta share their n_delta sweeps: the delta study computes only the other deltas."""
    scale = SCALES["fss"]
    est = budget.estimate(scale)
    shared = [s for s in est.sweeps if s.study == "delta" and "delta0.2_" in s.name]
    assert shared and all(s.new_rows == 0 for s in shared)
    assert all(s.new_rows == s.rows for s in est.sweeps if s.study == "fss")


def test_unknown_scale_study_or_mode_is_refused():
    with pytest.raises(InputError, match="unknown scale"):
        budget.estimate("huge")
    with pytest.raises(InputError, match="unknown study"):
        budget.estimate(TINY, studies=["fig9"])
    with pytest.raises(InputError, match="workers"):
        budget.estimate(TINY, workers=0)
    with pytest.raises(InputError, match="sweep mode"):
        budget.row_seconds("proximal", 32, 0.3)
    with pytest.raises(InputError, match="error model"):
        budget.sigma_1("alpha", 32)


def test_a_study_without_a_work_model_is_refused_not_skipped(monkeypatch):
    """A new study whose analysis has no measured cost yet (calibrate_budget.py --analysis
    times it) is refused by name, not priced at zero."""
    new = dataclasses.replace(
        STUDIES["fig1b"], name="newstudy", cost=lambda scale, costs: costs.analysis("newstudy")
    )
    monkeypatch.setitem(STUDIES, "newstudy", new)
    scale = dataclasses.replace(
        TINY, studies=(*TINY.studies, "newstudy"), params=dict(TINY.params, newstudy=TINY["fig1b"])
    )
    with pytest.raises(InputError, match="study 'newstudy' has no work model"):
        budget.estimate(scale)


def test_extrapolated_sizes_are_flagged():
    est = budget.estimate("fss-cluster", workers=64)
    t = est.table()
    assert t[t.n == 128].extrapolated.all() and not t[t.n == 32].extrapolated.any()
    assert any("n = 128" in note for note in est.notes)
    assert "(extrapolated)" in budget.describe(est)
    errors = budget.expected_errors("fss")
    assert errors[errors.n == 64].extrapolated.all()


def test_over_budget_is_said(monkeypatch, capsys):
    small = dataclasses.replace(SCALES["quick"], budget_minutes=0.5)
    est = budget.estimate(small)
    assert est.over_budget and "OVER BUDGET" in budget.describe(est)
    monkeypatch.setitem(SCALES, "quick", small)
    assert main(["reproduce", "--scale", "quick", "--estimate", "--workers", "2"]) == 1
    assert "OVER BUDGET" in capsys.readouterr().out


@pytest.mark.parametrize("name", [n for n, s in SCALES.items() if s.budget_minutes])
def test_every_scale_fits_its_budget_on_two_workers(name):
    est = budget.estimate(name, workers=2)
    assert est.wall_seconds <= 60 * SCALES[name].budget_minutes, budget.describe(est)


def test_paper_and_fss_budgets_leave_a_margin():
    """The issue's limits are 60 and 120 min; the scales aim at 50 and 120. On fss the model
    errs long on the threshold sweeps (109 min estimated, 97 measured from a clean clone,
    2026-11-26) and short on the energy grids (10 estimated, about 15 measured): the measured
    pieces add to about 113 min."""
    assert SCALES["paper"].budget_minutes <= 50 and SCALES["fss"].budget_minutes <= 120
    assert SCALES["quick"].budget_minutes <= 10


def test_headline_targets_are_met_where_the_scales_say():
    """paper: every claim within its target (Fig. 4C too, since it is measured on each
    system's transition: 0.072 at n = 32 with 8 samples); fss: every size within the targets."""
    paper = budget.expected_errors("paper")
    assert paper.meets.all(), list(paper[~paper.meets].claim)
    stated = paper[paper.estimator == "st_sr"]
    assert (stated.expected <= 0.013).all()  # the paper's +-0.013
    fss = budget.expected_errors("fss")
    assert fss.meets.all()
    floor = paper[paper.estimator.isin(["st_sr", "p_crit", "taut"])]
    assert (floor.samples >= 24).all()


def test_samples_for_inverts_the_error_model():
    for est, n in (("st_sr", 32), ("p_crit", 16), ("st_sr", 64)):
        s = budget.samples_for(est, n, 0.01)
        assert budget.expected_error(est, n, s) <= 0.01 < budget.expected_error(est, n, s - 1)
    assert budget.samples_for("st_sr", 32, 0.013) == math.ceil((0.0401 / 0.013) ** 2)


def test_power_laws_hit_the_measured_sizes_and_interpolate_between():
    th = COSTS.table("threshold")
    assert budget.row_seconds("threshold", 32, 0.3) == (th[32], False)
    t16, _ = budget.row_seconds("threshold", 16, 0.3)
    t24, ext = budget.row_seconds("threshold", 24, 0.3)
    assert t16 < t24 < th[32] and not ext
    assert t24 == pytest.approx(th[16] * (1.5 ** (math.log(th[32] / th[16]) / math.log(2))))
    t128, ext = budget.row_seconds("threshold", 128, 0.3)
    assert ext and t128 == pytest.approx(th[64] * th[64] / th[32])
    # rods-only searches (p_t = 0) have a table of their own, measured up to n = 128
    rods = COSTS.table("rods_threshold")
    assert budget.row_seconds("threshold", 32, 0.0) == (rods[32], False)
    assert budget.row_seconds("threshold", 128, 0.0) == (rods[128], False)
    p01, _ = budget.row_seconds("threshold", 32, 0.1)
    assert p01 == pytest.approx(th[32] * COSTS.factor("threshold_pt_factor", 0.1))
    grid = COSTS.table("grid")
    g32, _ = budget.row_seconds("grid", 32, 0.15)
    assert g32 == pytest.approx(grid[32], rel=0.01)
    g64, ext = budget.row_seconds("grid", 64, 0.15)
    assert ext and g64 == pytest.approx(grid[32] * 2 ** COSTS.data["grid"]["exponent"], rel=0.01)


def test_makespan_is_that_of_the_engine_order():
    assert budget._makespan([4, 1, 1, 1, 1], 2) == 4
    assert budget._makespan([1, 1, 1, 1, 4], 2) == 6
    assert budget._makespan([3, 3, 3], 1) == 9


def test_stated_run_times_are_the_estimates():
    """EXPECTED states the budget's estimate of each priced scale (beside the measurement where
    a run has been timed), so that a change of the scales cannot leave a stale number."""
    assert set(EXPECTED) == set(SCALES)
    for name in ("paper", "fss", "paper-size", "limit"):
        minutes = round(budget.estimate(name, workers=2).wall_seconds / 60)
        assert re.search(rf"estimated {minutes} minutes", EXPECTED[name]), name
    for name in ("fss-cluster", "pc-cluster", "limit-cluster"):
        cpu_hours = round(budget.estimate(name).cpu_seconds / 3600)
        assert f"estimated {cpu_hours} CPU hours" in EXPECTED[name], name


def test_cli_estimate_prints_every_study_and_runs_nothing(tmp_path, capsys):
    out = tmp_path / "never"
    assert main(["reproduce", "--scale", "paper", "--estimate", "--workers", "2"]) == 0
    text = capsys.readouterr().out
    for study in SCALES["paper"].studies:
        assert re.search(rf"^{study}\s+", text, re.M), study
    assert "budget: 50 min on 2 workers (within)" in text
    assert "st_sr_cables_compression" in text and "expected" in text
    assert main(["reproduce", "--scale", "fss", "--estimate", "--out", str(out)]) == 0
    assert not out.exists()


def test_reproduce_needs_an_output_directory_unless_estimating(capsys):
    assert main(["reproduce", "--scale", "tiny"]) == 2
    assert "--out" in capsys.readouterr().err


def test_pebble_game_sweeps_are_priced_as_such():
    est = budget.estimate("pc", workers=2)
    assert {s.mode for s in est.sweeps} == {"pebble"}
    by_n = {s.n: s for s in est.sweeps}
    assert set(by_n) == {32, 64, 128, 256, 512}
    for n, s in by_n.items():
        assert s.cpu_seconds == pytest.approx(COSTS.table("pebble")[n] * s.new_rows)
    table = est.table()
    assert list(table.thresholds) == [s.new_rows for _, s in sorted(by_n.items())]
    assert budget.row_seconds("pebble", 64, 0.0) == (COSTS.table("pebble")[64], False)
    # a bisection costs orders of magnitude more at the same size
    assert budget.row_seconds("threshold", 128, 0.0)[0] > 100 * COSTS.table("pebble")[128]


def test_the_costs_file_names_the_source_of_every_measured_constant():
    """Every entry of data/costs.toml says what it is and where it was measured, and the
    script that measures them writes it back unchanged."""
    import importlib.util
    import sys
    import tomllib
    from pathlib import Path

    for name, entry in COSTS.data.items():
        if name == "sigma_1":
            assert all(e["source"] for k, e in entry.items() if k != "what")
        elif name != "shift_targets":
            assert entry["what"] and entry["source"], name
    bench = Path(__file__).parents[2] / "benchmarks"
    sys.path.insert(0, str(bench))
    try:
        spec = importlib.util.spec_from_file_location(
            "calibrate_budget", bench / "calibrate_budget.py"
        )
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    finally:
        sys.path.remove(str(bench))
    # a pebble-game sweep is priced, and measured, as "pebble", not as a threshold search
    spec_file = Path(__file__).parent / "_pebble_spec.json"
    try:
        spec_file.write_text('{"settings": {"mode": "threshold", "threshold_method": "pebble"}}')
        assert module.sweep_mode(spec_file) == "pebble"
    finally:
        spec_file.unlink(missing_ok=True)
    out = Path(__file__).parent / "_costs_roundtrip.toml"
    try:
        module.write_costs(COSTS.data, out)
        assert tomllib.loads(out.read_text()) == COSTS.data
        assert out.read_text() == budget.DATA.read_text()
    finally:
        out.unlink(missing_ok=True)
