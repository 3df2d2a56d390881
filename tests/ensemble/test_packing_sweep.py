"""Packing sweeps: random soft packings tested for jamming as a sweep of the ensemble layer
(spec, rows, resume, summary, estimate)."""

from __future__ import annotations

import tomllib

import numpy as np
import pandas as pd
import pytest

from tensegrity_rigidity.cli.main import main
from tensegrity_rigidity.ensemble.jamming import RECORD, jamming_row, sample_seconds
from tensegrity_rigidity.ensemble.spec import PACKING_KEYS, parse_spec
from tensegrity_rigidity.ensemble.store import ResultStore, spec_from_canonical
from tensegrity_rigidity.ensemble.summary import format_table, probability_table
from tensegrity_rigidity.ensemble.sweep import estimate, load_results, run_sweep
from tensegrity_rigidity.errors import SpecError

SPEC = """
n = [16, 24]
fraction = [0.80, 0.87]
samples = 3
seed = 5
[packing]
dim = 2
[output]
chunk_size = 2
"""
#: the columns that are CPU times, not functions of the sample
TIMES = ["seconds_packing", "seconds_test"]


def _spec(text: str = SPEC):
    return parse_spec(tomllib.loads(text))


def _rows(out):
    return load_results(out).drop(columns=TIMES)


def test_a_packing_spec_has_its_own_grid_settings_and_keys():
    spec = _spec()
    assert spec.mode == "packing" and spec.packing == {"dim": 2, "ratio": 1.4}
    points = spec.points()
    assert [(p.n, p.fraction) for p in points] == [(16, 0.8), (16, 0.87), (24, 0.8), (24, 0.87)]
    assert spec.n_points() == 4 and spec.n_samples() == 12 and spec.angle(2) == 0.0
    settings = spec.settings()
    assert settings["mode"] == "packing" and settings["packing"] == {"dim": 2, "ratio": 1.4}
    assert {"minimiser", "jamming"} <= set(settings)
    keys = {spec.point_key(p) for p in points}
    assert len(keys) == 4
    # the ratio changes every row, so it changes every key
    other = _spec(SPEC.replace("dim = 2", "dim = 2\nratio = 1.2"))
    assert not keys & {other.point_key(p) for p in other.points()}
    # the recorded spec reads back as the same sweep
    again = spec_from_canonical(spec.canonical())
    assert again.settings() == settings and again.points() == points
    assert PACKING_KEYS == ("n", "fraction", "seed")


@pytest.mark.parametrize(
    "text,needle",
    [
        ("p_t = 0.2\n" + SPEC, "has no lattice"),
        (SPEC.replace("samples = 3", "samples = 3\ndelta = 0.1"), "remove 'delta'"),
        (SPEC + "[lattice]\nkind = 'square'\n", "remove 'lattice'"),
        (SPEC.replace("fraction = [0.80, 0.87]\n", ""), "'fraction'"),
        (SPEC.replace("0.87", "1.2"), "must lie in (0, 1)"),
        (SPEC.replace("dim = 2", "dim = 4"), "dim 2 or 3"),
        (SPEC.replace("n = [16, 24]", "n = 2"), "at least 4"),
        (SPEC.replace("dim = 2", "dim = 2\nshape = 1"), "unknown key"),
        ("n = 6\nfraction = 0.8\np_r = 0.5\n", "needs a [packing] section"),
        (SPEC.replace("[0.80, 0.87]", "[0.8, 0.8]"), "twice"),
    ],
)
def test_bad_packing_specs_are_refused_before_any_work(tmp_path, capsys, text, needle):
    with pytest.raises(SpecError, match=None) as err:
        _spec(text)
    assert needle in str(err.value), str(err.value)
    path = tmp_path / "spec.toml"
    path.write_text(text)
    assert main(["sweep", str(path), "--out", str(tmp_path / "never")]) == 2
    assert needle in capsys.readouterr().err
    assert not (tmp_path / "never").exists()


def test_rows_are_the_samples_of_the_jamming_loop_on_any_executor(tmp_path):
    """Every row is jamming_row at its (n, fraction, sample, seed), the same serially and on two
    workers; a decided row is one whose collective test decided."""
    spec = _spec()
    run_sweep(spec, tmp_path / "a", executor="serial", progress=False)
    run_sweep(spec, tmp_path / "b", executor=2, progress=False)
    a, b = _rows(tmp_path / "a"), _rows(tmp_path / "b")
    pd.testing.assert_frame_equal(a, b)
    assert len(a) == 12 and set(RECORD) - set(TIMES) <= set(a.columns)
    assert set(a.collective) <= {"jammed", "unjammed", "undecided"}
    assert (a.decided == (a.collective != "undecided")).all()
    for row in a.iloc[[0, 7, 11]].itertuples():
        direct = jamming_row(row.n, row.fraction, row.sample, 5)
        for key in ("contacts", "rattlers", "collective", "strict", "energy", "steps"):
            assert getattr(row, key) == direct[key], key
    # the dilute packings have no contacts; the dense ones are jammed at these sizes
    assert (a[a.fraction == 0.8].collective == "unjammed").all()
    assert (a[a.fraction == 0.87].collective == "jammed").all()


def test_a_packing_sweep_resumes_and_grows_keeping_its_rows(tmp_path):
    out = tmp_path / "r"
    spec = _spec(SPEC.replace("n = [16, 24]", "n = 16"))
    first = run_sweep(spec, out, executor="serial", progress=False)
    assert first.samples_run == 6
    again = run_sweep(spec, out, executor="serial", progress=False)
    assert again.samples_run == 0 and again.samples_reused == 6
    before = _rows(out)
    grown = _spec(SPEC.replace("n = [16, 24]", "n = 16").replace("samples = 3", "samples = 4"))
    more = run_sweep(grown, out, executor="serial", progress=False)
    assert more.samples_run == 2 and more.samples_reused == 6
    after = _rows(out)
    pd.testing.assert_frame_equal(after[after["sample"] <= 3].reset_index(drop=True), before)
    assert ResultStore(out).read().shape[0] == 8


def test_another_diameter_ratio_into_the_same_directory_is_refused(tmp_path, capsys):
    path, out = tmp_path / "a.toml", tmp_path / "o"
    path.write_text(SPEC.replace("n = [16, 24]", "n = 16"))
    assert main(["sweep", str(path), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    capsys.readouterr()
    path.write_text(
        SPEC.replace("n = [16, 24]", "n = 16").replace("dim = 2", "dim = 2\nratio = 1.2")
    )
    assert main(["sweep", str(path), "--out", str(out), "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert "different sweep" in err and "ratio" in err, err


def test_the_summary_counts_jammed_and_strict_packings_and_undecided_ones():
    rows = pd.DataFrame({
        "n": 16, "fraction": [0.84] * 5, "seed": 0,
        "collective": ["jammed", "jammed", "unjammed", "undecided", "jammed"],
        "strict": ["jammed", "unjammed", "unjammed", "undecided", "undecided"],
        "decided": [True, True, True, False, True],
    })  # fmt: skip
    table = probability_table(rows)
    line = table.iloc[0]
    assert (line.N, line.undecided, line.rigid, line.strict) == (4, 1, 3, 1)
    assert line.P == pytest.approx(0.75) and line.lo < 0.75 < line.hi
    text = format_table(table)
    assert "jammed" in text.splitlines()[0] and "strict" in text.splitlines()[0]


def test_the_estimate_prices_each_sample_by_the_measured_costs():
    spec = _spec()
    est = estimate(spec)
    assert est["rows"] == 12 and est["n_max"] == 24
    assert est["cpu_seconds"] == pytest.approx(6 * (sample_seconds(16) + sample_seconds(24)))
    assert sample_seconds(1024) > sample_seconds(64) > 0
    assert np.isfinite(est["sample_bytes"]) and est["sample_bytes"] > 0
