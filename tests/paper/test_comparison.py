"""The comparison: one agreement rule for every claim, and explanations from the studies' data."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import pandas as pd
import pytest
from scipy.stats import norm

from tensegrity_rigidity.paper.claims import (
    CLAIMS,
    FACTORS,
    REPLICATION,
    ROUNDING_2DP,
    Measurement,
)
from tensegrity_rigidity.paper.comparison import (
    AGREE_BELOW,
    compare,
    comparison_frame,
    decimals,
    fmt,
    verdict,
    z_score,
)


def test_values_show_two_significant_digits_of_their_error():
    """The rods-only replication at n = 32 read 0.657 ± 0.001 where its error is 0.0008."""
    assert fmt(0.65662, 0.00078) == "0.65662 ± 0.00078"
    assert fmt(0.5, 0.013) == "0.500 ± 0.013"
    assert fmt(1.0, 1e-12) == "1.000000 ± 0.000000"  # at most 6 decimals
    assert fmt(2.0, 0.0) == "2.000 ± 0.000" and fmt(2.0) == "2.000"
    assert fmt(0.25, 0.004, 2) == "0.2500 ± 0.0040" and fmt(float("nan"), 0.1) == "n/a"


def test_a_second_error_takes_the_first_errors_decimals():
    """A fit-form systematic beside a statistical error is written to the same decimals (it was
    written to five whatever its size: ``0.01234`` beside ``0.0063``, ``0.00000`` for 3e-6)."""
    assert decimals(0.0063) == 4 and decimals(0.00013) == 5 and decimals(0.2) == 3
    assert decimals(float("nan")) == 3 and decimals(0.0) == 3 and decimals(1e-12) == 6


@dataclass(frozen=True)
class FakeResult:
    measured: tuple
    excluded: dict


def _rows(*measured):
    return {r.key: r for r in compare({"x": FakeResult(tuple(measured), {})})}


def _report(rows):
    """The report's numbers of these rows (its placeholders)."""
    from tensegrity_rigidity.paper.report import numbers

    return numbers({}, rows, "x", {}, {}, pd.DataFrame())


def test_the_headline_counts_add_up():
    """Every row is counted once: agree + disagree + inconclusive + no value = total, and the
    independent comparisons are the total less the pairs about one system (the headline read
    "6 agree, 3 do not, 18 inconclusive (28 independent comparisons of 31)")."""
    from tensegrity_rigidity.paper.comparison import verdict_counts

    ms = [
        Measurement.scalar("st_sr_half_shear", 0.5, 0.001, ""),  # agree
        Measurement.scalar("st_sr_cables_compression", 0.6, 0.01, ""),  # disagree
        Measurement.scalar("st_sr_struts_dilation", 0.6, 0.01, ""),  # its pair
        Measurement.scalar("st_sr_cables_dilation", 0.6, 0.5, ""),  # inconclusive
        Measurement.scalar("alpha_dilation_0.1", np.nan, np.nan, ""),  # no value
    ]
    c = verdict_counts(list(_rows(*ms).values()))
    assert (c["agree"], c["disagree"], c["inconclusive"], c["na"]) == (1, 2, 1, 1)
    assert c["agree"] + c["disagree"] + c["inconclusive"] + c["na"] == c["total"] == 5
    assert (c["shared"], c["independent"]) == (1, 4)


def test_z_uses_both_error_bars():
    c = CLAIMS["st_sr_cables_compression"]  # 0.372 +- 0.013
    m = Measurement.scalar(c.key, 0.451, 0.02, "n = 12")
    assert z_score(c, m) == pytest.approx(abs(0.451 - 0.372) / math.hypot(0.02, 0.013))
    row = _rows(m)[c.key]
    assert row.verdict == "disagree" and row.z > AGREE_BELOW


def test_values_printed_without_error_carry_their_rounding():
    c = CLAIMS["p_crit_compression_0.1"]
    assert c.error_kind == "rounding" and c.error == pytest.approx(ROUNDING_2DP)
    m = Measurement.scalar(c.key, 0.605, 0.0, "n = 12")
    assert z_score(c, m) == pytest.approx(0.005 / ROUNDING_2DP)


def test_sign_claims_measure_the_distance_to_the_claimed_side():
    rises = CLAIMS["fig4a_dilation_rises"]
    assert z_score(rises, Measurement.scalar(rises.key, 0.3, 0.1, "")) == 0.0
    assert z_score(rises, Measurement.scalar(rises.key, -0.3, 0.1, "")) == pytest.approx(3.0)
    falls = CLAIMS["fig4a_compression_falls"]
    assert z_score(falls, Measurement.scalar(falls.key, 0.05, 0.1, "")) == pytest.approx(0.5)


def test_several_points_use_the_largest_z_family_wise():
    c = CLAIMS["fig4c_sum_one"]
    one = Measurement(c.key, np.array([1.2]), np.array([[0.01]]), "")
    two = Measurement(c.key, np.array([1.2, 1.2]), np.diag([0.01, 0.01]), "")
    nine = Measurement(c.key, np.full(9, 1.0), np.diag(np.full(9, 0.01)), "")
    assert z_score(c, one) == pytest.approx(2.0)
    # two points each 2 sigma off are less surprising than one: Sidak, 1 - (1 - p)^2
    p = 2 * norm.sf(2.0)
    assert z_score(c, two) == pytest.approx(norm.isf((1 - (1 - p) ** 2) / 2))
    assert z_score(c, two) < AGREE_BELOW
    assert z_score(c, nine) == 0.0
    # the covariance's off-diagonal (nearly singular for smooth curves) is not inverted
    corr = Measurement(c.key, np.array([1.2, 1.2]), np.array([[0.01, 0.01], [0.01, 0.01]]), "")
    assert z_score(c, corr) == pytest.approx(z_score(c, two))
    # non-finite points (a ratio where P does not vary) are left out
    partial = Measurement(c.key, np.array([np.nan, 1.0]), np.diag([np.nan, 0.01]), "")
    assert z_score(c, partial) == 0.0


def test_explanation_names_every_factor_with_its_evidence():
    key = "st_sr_cables_compression"
    ours = Measurement.scalar(key, 0.451, 0.01, "n = 12")
    method = Measurement.scalar(key, 0.38, 0.01, "n = 12", factor="method", label="paper's verdict")
    estimator = Measurement.scalar(
        key, 0.46, 0.01, "n = 12", factor="estimator", label="contour slope"
    )
    row = _rows(ours, method, estimator)[key]
    assert row.verdict == "disagree"
    clauses = row.explanation.split("; ")
    assert [c.split(":")[0] for c in clauses] == list(FACTORS)
    assert "finite size: not yet tested" in clauses and "delta: not yet tested" in clauses
    assert "paper's verdict" in row.explanation and "then agrees" in clauses[2]
    assert "still disagrees" in clauses[3]


def test_agreeing_rows_need_no_explanation_and_missing_values_are_na():
    key = "st_sr_half_shear"
    rows = _rows(
        Measurement.scalar(key, 0.51, 0.02, ""),
        Measurement.scalar("alpha_dilation_0.1", np.nan, np.nan, ""),
    )
    assert rows[key].verdict == "agree" and rows[key].explanation == ""
    assert rows["alpha_dilation_0.1"].verdict == "n/a"
    frame = comparison_frame(list(rows.values()))
    assert {"z", "verdict", "explanation", "source"} <= set(frame.columns)


def test_alternatives_alone_make_no_row():
    key = "rods_only_pc"
    alt = Measurement.scalar(key, 0.66, 0.01, "", factor="finite size", label="n -> inf")
    assert key not in _rows(alt)


def test_a_small_z_from_a_large_error_is_inconclusive_not_agreement():
    c = CLAIMS["fig4c_sum_one"]  # exact 1, resolution 0.1 (the Fig. 4C target)
    assert c.resolution == pytest.approx(0.1)
    sharp = Measurement(c.key, np.array([1.05, 0.98]), np.diag([0.08**2, 0.08**2]), "")
    wide = Measurement(c.key, np.array([1.05, 0.5]), np.diag([0.08**2, 0.4**2]), "")
    assert verdict(c, sharp)[1] == "agree" and verdict(c, wide)[1] == "inconclusive"
    row = _rows(wide)[c.key]
    assert row.verdict == "inconclusive" and "at 1 of 2 points" in row.explanation
    # not "would not have been detected": a point may still show a deviation on its own
    assert row.explanation.endswith("a deviation of 0.6 could have passed as agreement")
    # a z of 2 or more is a disagreement however wide the errors
    far = Measurement(c.key, np.array([5.0]), np.array([[1.0]]), "")
    assert verdict(c, far)[1] == "disagree"
    # the paper's own error sets the resolution where it is the larger
    alpha = CLAIMS["alpha_compression_0.3"]  # 1.806 +- 0.130
    assert alpha.resolution == pytest.approx(0.130)
    assert verdict(alpha, Measurement.scalar(alpha.key, 1.7, 0.35, ""))[1] == "agree"
    assert verdict(alpha, Measurement.scalar(alpha.key, 1.7, 0.45, ""))[1] == "inconclusive"
    # a sign has no resolution: a wide error on the claimed side still agrees
    rises = CLAIMS["fig4a_dilation_rises"]
    assert verdict(rises, Measurement.scalar(rises.key, 0.3, 10.0, ""))[1] == "agree"


def test_alternatives_with_large_errors_are_inconclusive_not_explanations():
    key = "st_sr_cables_compression"
    ours = Measurement.scalar(key, 0.451, 0.01, "n = 32")
    loose = Measurement.scalar(key, 0.40, 0.06, "n = 32", factor="method", label="paper's verdict")
    row = _rows(ours, loose)[key]
    assert "inconclusive" in row.explanation.split("; ")[2]
    assert "then agrees" not in row.explanation


def test_an_alternative_that_agrees_only_through_its_error_is_named_so():
    """An alternative whose value is as far from the paper as ours (0.44 against 0.372 +-
    0.013) agrees only because its error (0.038) is larger: at our error (0.01) it would still
    disagree, and the explanation says so instead of "then agrees". One that moves towards the
    paper (0.39) does agree."""
    key = "st_sr_cables_compression"
    ours = Measurement.scalar(key, 0.451, 0.01, "n = 32")
    wide = Measurement.scalar(key, 0.44, 0.038, "n = 8", factor="finite size", label="n -> inf")
    near = Measurement.scalar(key, 0.39, 0.02, "n = 32", factor="delta", label="delta = 0.1")
    assert verdict(CLAIMS[key], wide)[1] == "agree"
    clauses = _rows(ours, wide, near)[key].explanation.split("; ")
    assert "agrees only through its larger error: at our error z = 4.15" in clauses[0]
    assert "then agrees" not in clauses[0] and "z = 1.69" in clauses[0]
    assert "then agrees" in clauses[1]


def test_an_agreement_that_a_replication_at_the_same_size_contradicts_says_so():
    """The case of the paper-scale report: rods-only p_c at n = 32 from 24 samples (0.6565 +-
    0.002) agrees with the paper's value (z < 2), while 400 samples of the same size give
    0.6567 +- 0.0008 (z = 4.1). The row stays "agree" by the rule; its explanation
    gives the replication and the factors' evidence, and records the replication's verdict.
    A replication of another size is not ours to compare with."""
    key = "rods_only_pc"
    ours = Measurement.scalar(key, 0.6565, 0.002, "n = 32, 24 samples", size=32)
    same = Measurement.scalar(
        key, 0.6567, 0.0008, "n = 32, 400 samples per point", factor=REPLICATION,
        label="the same size", size=32,
    )  # fmt: skip
    other = Measurement.scalar(
        key, 0.6487, 0.0008, "n = 8", factor=REPLICATION, label="another size", size=8
    )
    limit = Measurement.scalar(key, 0.6601, 0.0008, "", factor="finite size", label="n -> inf")
    row = _rows(ours, same, other, limit)[key]
    assert row.verdict == "agree" and row.replication == "disagree"
    assert row.explanation.startswith("agrees at our precision only: replication: the same size")
    assert "z = 4.10: disagrees" in row.explanation and "another size" not in row.explanation
    # the factors in plain words: nothing "then agrees" or "still disagrees" in an agreement
    assert "finite size: n -> inf" in row.explanation and "z = 0.12: agrees)" in row.explanation
    assert "then agrees" not in row.explanation and "still" not in row.explanation
    # a replication no more precise than ours questions the sample set, not the precision
    loose = replace(same, cov=np.array([[0.003**2]]), value=np.array([0.6450]))
    row = _rows(ours, loose)[key]
    assert row.explanation.startswith("agrees on our samples only: replication")
    # a replication without a value is no replication
    empty = replace(same, value=np.array([np.nan]))
    assert _rows(ours, empty)[key].replication == "" == _rows(ours, empty)[key].explanation
    # without the replication, or with one of another size only, the agreement needs no words
    for alts in ((limit,), (other, limit)):
        row = _rows(ours, *alts)[key]
        assert row.explanation == "" and row.replication == ""
    # a replication that agrees too leaves an agreement unexplained; ours needs a size
    near = Measurement.scalar(key, 0.6598, 0.0008, "", factor=REPLICATION, label="r", size=32)
    assert _rows(ours, near)[key].explanation == ""
    assert _rows(ours, near)[key].replication == "agree"
    unsized = Measurement.scalar(key, 0.6565, 0.002, "n = 32")
    assert _rows(unsized, same)[key].replication == ""
    # the report counts and names the agreements a replication contradicts
    rows = list(_rows(ours, same).values()) + list(_rows(near).values())
    v = _report(rows)
    assert (v["contradicted_count"], v["contradicted"]) == (1, CLAIMS[key].text)
    assert _report(list(_rows(ours, near).values()))["contradicted"] is None


def test_a_disagreement_that_a_replication_at_the_same_size_does_not_repeat_is_counted():
    """The headline names the disagreements the finite-size study's samples of the same size
    do not repeat, as it names the agreements they contradict: 0.40 +- 0.005 against the
    paper's 0.372 +- 0.013 disagrees (z = 2.01), 0.39 +- 0.01 of the replication agrees."""
    key = "st_sr_cables_compression"
    ours = Measurement.scalar(key, 0.40, 0.005, "n = 32", size=32)
    rep = Measurement.scalar(key, 0.39, 0.01, "", factor=REPLICATION, label="fss", size=32)
    row = _rows(ours, rep)[key]
    assert (row.verdict, row.replication) == ("disagree", "agree")
    v = _report([row])
    assert (v["unrepeated_count"], v["unrepeated"], v["contradicted"]) == (
        1,
        CLAIMS[key].text,
        None,
    )
    # replicated, it is not named
    same = Measurement.scalar(key, 0.41, 0.005, "", factor=REPLICATION, label="fss", size=32)
    assert _report(list(_rows(ours, same).values()))["unrepeated"] is None


def test_a_disagreement_lists_its_replication_first():
    key = "st_sr_cables_compression"
    ours = Measurement.scalar(key, 0.451, 0.01, "n = 32", size=32)
    rep = Measurement.scalar(key, 0.466, 0.005, "", factor=REPLICATION, label="fss", size=32)
    clauses = _rows(ours, rep)[key].explanation.split("; ")
    assert clauses[0].startswith("replication: fss") and clauses[0].endswith("disagrees)")
    assert [c.split(":")[0] for c in clauses[1:]] == list(FACTORS)
    # and so does an inconclusive comparison, before its reason
    wide = Measurement.scalar(key, 0.40, 0.05, "n = 32", size=32)
    row = _rows(wide, rep)[key]
    assert row.verdict == "inconclusive" and row.replication == "disagree"
    assert row.explanation.startswith("replication: fss")
    assert row.explanation.endswith("could have passed as agreement")


def test_claims_about_one_system_are_paired_with_the_papers_own_z():
    """Rods only is one system under compression and dilation, and rods + struts under
    dilation is rods + cables under compression (e -> -e): our value is one number for each
    pair. The paper gives alpha = 1.100 +- 0.015 and 1.257 +- 0.029 for the first."""
    from tensegrity_rigidity.paper.comparison import shared_measurements

    keys = ["alpha_compression_0.0", "alpha_dilation_0.0", "st_sr_struts_dilation"]
    rows = [r for r in _rows(*(Measurement.scalar(k, 1.3, 0.1, "") for k in keys)).values()]
    pairs = shared_measurements(rows)
    assert [(a, b) for a, b, _ in pairs] == [("alpha_dilation_0.0", "alpha_compression_0.0")]
    assert pairs[0][2] == pytest.approx(0.157 / math.hypot(0.015, 0.029))
    v = _report(rows)
    assert (v["shared"], v["total"], v["independent"]) == (1, 3, 2)
    assert v["pairs"].count("' is '") == 1 and "z = 4.8" in v["pairs"]
    assert _report(rows[:1])["pairs"] is None


def test_a_value_whose_error_exceeds_it_is_not_printed_in_the_summary():
    """Fig. 4C's sum at a few samples printed "3.41 ± 84.67": the summary says it is not
    resolved at this precision instead, and every cell stays within CELL_CHARS."""
    from tensegrity_rigidity.paper.comparison import CELL_CHARS, summary_cell, summary_frame

    key = "st_sr_cables_compression"
    wide = _rows(Measurement.scalar(key, 3.41, 84.67, "n = 12, 8 samples per point"))[key]
    assert not wide.resolved
    assert summary_cell(wide) == "not resolved at this precision (n = 12, 8 samples per point)"
    sharp = _rows(Measurement.scalar(key, 0.40, 0.005, "n = 32"))[key]
    assert sharp.resolved and summary_cell(sharp).startswith("0.4000 ± 0.0050 (n = 32)")
    assert sharp.reason.startswith("z = 2.") and "not yet tested" in sharp.reason
    long = Measurement.scalar(key, 0.40, 0.005, "n = 32; " + "x" * 300)
    row = _rows(long)[key]
    assert len(summary_cell(row)) <= CELL_CHARS and len(row.reason) <= CELL_CHARS
    frame = summary_frame([wide, sharp])
    assert list(frame.columns) == ["claim", "paper", "ours", "verdict", "reason"]


def test_the_evidence_of_a_disagreement_is_a_table_with_numbers_in_columns():
    from tensegrity_rigidity.paper.comparison import evidence_frame

    key = "st_sr_cables_compression"
    ours = Measurement.scalar(key, 0.45, 0.008, "n = 32", size=32)
    fss = Measurement.scalar(key, 0.38, 0.01, "n -> inf", factor="finite size", label="fit")
    row = _rows(ours, fss)[key]
    frame = evidence_frame(row)
    assert list(frame.columns) == ["factor", "changed", "value", "system", "z", "moves ours (z)",
                                   "Holm p", "reads"]  # fmt: skip
    fs = frame[frame.factor == "finite size"].iloc[0]
    assert fs.value == "0.380 ± 0.010" and fs.reads.startswith("then agrees") and float(fs.z) < 2
    assert float(fs["moves ours (z)"]) == pytest.approx(0.07 / math.hypot(0.008, 0.01), abs=0.01)
    assert set(frame.factor) >= {"finite size", "method", "estimator"}
    assert row.reason.startswith("z = ") and "accounted for by finite size" in row.reason


def test_the_paper_against_itself_shows_both_of_its_readings_beside_ours():
    """Its p_crit tables give lambda = (0.66 - 0.51) / 0.3 = 0.50 under compression, its
    headline 0.372: a collapse fit of 0.49 +- 0.01 agrees with the tables only."""
    from tensegrity_rigidity.paper.comparison import paper_against_itself

    ms = (
        Measurement.scalar("p_crit_compression_0.0", 0.667, 0.003, "n = 32"),
        Measurement.scalar("p_crit_compression_0.3", 0.52, 0.004, "n = 32"),
        Measurement.scalar("st_sr_cables_compression", 0.49, 0.01, "n = 32"),
    )
    table = paper_against_itself({"x": FakeResult(ms, {})})
    assert len(table) == 1 and len(table.columns) <= 6
    row = table.iloc[0]
    assert (row["tables"], row["headline"]) == ("0.500 ± 0.014", "0.372 ± 0.013")
    assert row["ours_pc"] == "0.490 ± 0.017"
    assert row["agrees"].startswith("its p_crit tables (z = ")
    assert "headline" not in row["agrees"]
    # without the dilation claims there is no dilation row; without any, no table
    assert paper_against_itself({}).empty


def test_the_single_node_text_and_its_claim_quote_one_largest_deviation():
    """Fig. 3's text and the claim's row once printed 1.60 and 1.59 for one comparison (a
    Wilson-interval z beside the binomial one under the formula): both now use the latter."""
    from tensegrity_rigidity.paper.comparison import _ours
    from tensegrity_rigidity.paper.studies import fig3

    r = fig3.analyse({}, fig3.Scale(name="t", params={fig3.NAME: fig3.Params(trials=400)}))
    (m,) = fig3.claims(r)
    quoted = _ours(m, CLAIMS["single_node"])
    assert f"{fig3.numbers(r)['largest_z']:.2f}" in quoted


def test_a_report_without_claims_writes_the_comparison_header():
    """Six reports wrote comparison.csv as one byte, read back as a table without columns."""
    df = comparison_frame([])
    assert list(df.columns[:7]) == ["key", "claim", "paper", "ours", "system", "z", "verdict"]
