"""The claims data file: read once, validated, every value with its source."""

from __future__ import annotations

import pytest

from tensegrity_rigidity.paper import claims
from tensegrity_rigidity.paper.claims import CLAIMS, REFERENCES, ROUNDING_2DP


def _entry(**kw):
    return {"key": "k", "text": "t", "paper": "0.5", "value": 0.5, "error": "exact",
            "source": "s"} | kw  # fmt: skip


def test_errors_are_stated_rounded_exact_or_computed():
    kinds = {c.error_kind for c in CLAIMS.values()}
    assert kinds == {"stated", "rounding", "exact", "computed", "about"}
    assert CLAIMS["p_crit_compression_0.1"].error == ROUNDING_2DP
    assert CLAIMS["alpha_compression_0.3"].error == 0.130
    pc = CLAIMS["rods_only_pc"]  # from the literature value it names
    assert (pc.value, pc.error) == (REFERENCES["pc_jacobs_thorpe"].value, 0.0003)


@pytest.mark.parametrize(
    "bad",
    [
        {"error": "roughly"},
        {"value": None, "error": "exact"},
        {"relation": "sideways"},
        {"target": "nothing"},
        {"same_as": "no_such_claim"},
        {"factors": ["no such factor"]},
        {"error": "about"},  # "about" needs an "about" value printed
    ],
)
def test_a_malformed_claim_is_refused(bad):
    entry = {k: v for k, v in _entry(**bad).items() if v is not None}
    with pytest.raises(ValueError, match="claim k"):
        claims._claims([entry], REFERENCES)


def test_a_repeated_key_is_refused():
    with pytest.raises(ValueError, match="repeated"):
        claims._claims([_entry(), _entry()], REFERENCES)
