"""Table bug 3: the Fig. 1C claim "one type beats a mixture under shear" is missing.

The paper (main text after Fig. 3): "This effect is also evident in Fig. 1C, in which (averaged
over all types of strain) nonlinear elements contribute more to rigidity under shear strains
when f_c > 0.5 and f_c < 0.5 than at f_c = 0.5." Nothing in ``paper.claims.CLAIMS`` states it and
``fig1c.claims`` measures nothing for it, so the comparison (which gives a row only to a claim
with a measurement of factor "ours") never shows it.

Proposed measurement (a sign claim, relation "positive"): the contrast
(lam_shear(f_c = 0) + lam_shear(f_c = 1)) / 2 - lam_shear(f_c = 1/2) of the study's own fits,
its error from one bootstrap over samples that refits the three on the same resampled samples.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tensegrity_rigidity.paper.claims import CLAIMS
from tensegrity_rigidity.paper.studies import fig1c

from .test_fig1c_collapse import CABLES_DILATION, CABLES_SHEAR, analyse


def _shear_claims():
    return [
        c
        for c in CLAIMS.values()
        if "Fig. 1C" in c.source and c.relation == "positive" and "shear" in c.text.lower()
    ]


def test_the_claim_is_registered():
    """Exactly one Fig. 1C sign claim about shear (key of the implementer's choosing, e.g.
    ``st_sr_shear_one_type_beats_mixture``), quoting where the paper makes it."""
    found = _shear_claims()
    assert len(found) == 1, [c.key for c in CLAIMS.values() if "Fig. 1C" in c.source]
    assert "Fig. 1C" in found[0].source


def test_the_study_measures_it_from_its_own_fits():
    """The study's measurement of factor "ours" is the contrast of its shear fits, with an error."""
    (claim,) = _shear_claims()
    result = analyse({(1.0, math.pi / 2): CABLES_SHEAR, (0.0, math.pi / 2): CABLES_DILATION})
    ours = [m for m in fig1c.claims(result) if m.claim == claim.key and m.factor == "ours"]
    assert len(ours) == 1

    def lam(f_c):
        return result.lam(f_c, "shear")[0]

    contrast = (lam(0.0) + lam(1.0)) / 2 - lam(0.5)
    assert ours[0].value[0] == pytest.approx(contrast, abs=1e-12)
    assert np.isfinite(ours[0].err[0]) and ours[0].err[0] > 0


def test_the_strain_average_is_the_declared_alternative_reading():
    """The claim declares one factor, "reading", and the study measures the strain average's
    contrast under it: the alternative is fixed in the data, not chosen after the numbers."""
    (claim,) = _shear_claims()
    assert claim.factors == ("reading",)
    result = analyse({(1.0, math.pi / 2): CABLES_SHEAR, (0.0, math.pi / 2): CABLES_DILATION})
    (alt,) = [m for m in fig1c.claims(result) if m.claim == claim.key and m.factor == "reading"]
    value, err = result.one_type["average"]
    lam = {f: result.lam(f, "average")[0] for f in (0.0, 0.5, 1.0)}
    assert value == pytest.approx((lam[0.0] + lam[1.0]) / 2 - lam[0.5], abs=1e-12)
    assert alt.value[0] == value and np.isfinite(err) and err > 0
