"""The paper's claims and the literature's values, read from ``data/claims.toml``; measurements.

The data file holds one entry per number or statement of *Rigidity of generic random tensegrity
structures* (Sudhakar, McInerney, Rocklin, Stephenson) that the reproduction tests, each with
where the paper states it, and the literature values the studies compare with, each with its
citation. It is read once, validated (:func:`load`), and nothing else types these values in.
A study reports what it measured for a claim as a :class:`Measurement`.
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: the data file
DATA = Path(__file__).with_name("data") / "claims.toml"
#: standard error of a value printed to two decimals and given without an error: the rounding,
#: uniform over one unit of the last digit (0.01 / sqrt(12))
ROUNDING_2DP = 0.01 / math.sqrt(12)
#: how a claim's error is stated in the data file (besides a number: the paper's error bar)
ERROR_KINDS = {"rounding": ROUNDING_2DP, "exact": 0.0, "computed": 0.0}
#: an "about" value: the paper's printed number, a percentage or a plain number
_ABOUT = re.compile(r"about\s+(\d+(?:\.(\d+))?)\s*(%?)")


def about_tolerance(printed: str) -> float:
    """The tolerance an "about" value carries: half a unit of its last stated digit.

    Parameters
    ----------
    printed : str
        The paper's value as printed, e.g. "about 37 %" or "about 0.67".

    Returns
    -------
    float
        In the units the claim is compared in (a percentage as a fraction): 0.005 for both
        examples.
    """
    found = _ABOUT.search(printed)
    if found is None:
        raise ValueError(f"no 'about' value in {printed!r}")
    unit = 10.0 ** -len(found.group(2) or "")
    return 0.5 * unit * (0.01 if found.group(3) else 1.0)


RELATIONS = ("equal", "positive", "negative")


@dataclass(frozen=True)
class Reference:
    """A value from the literature: ``value``, ``error`` (None when none is quoted),
    ``citation`` (who, where, how it was obtained) and ``who``, the short name tables and
    sentences quote (the citation's first clause unless the data file names one)."""

    value: float
    error: float | None
    citation: str
    who: str = ""

    def __post_init__(self) -> None:
        if not self.who:
            object.__setattr__(self, "who", self.citation.split(",")[0].split(" (")[0])

    @property
    def tolerance(self) -> float:
        """The error a comparison gives the value: the quoted one, or for a value quoted
        without one half a unit of its last printed digit (1.86: 0.005), as an "about" claim
        of the paper (:func:`about_tolerance`); never 0, which would take it as exact."""
        return self.error if self.error is not None else about_tolerance(f"about {self.value!r}")


@dataclass(frozen=True)
class Claim:
    """One claim of the paper.

    Attributes
    ----------
    key, text, paper : str
        Stable identifier, the claim as the comparison states it, the paper's value as printed.
    value : float or None
        The number compared with (None where the study computes the reference, as the
        single-node formula).
    error : float
        The paper's standard error (``error_kind``: "stated", "rounding", "exact", "computed"),
        or for a value the paper gives as "about" one (``error_kind`` "about") the tolerance
        its last digit implies (:func:`about_tolerance`).
    source : str
        Where in the paper the claim is made.
    relation : str
        "equal", or "positive" / "negative" for a claim about a sign.
    target : str
        The claim's family in :data:`TARGETS` ("" for none).
    same_as : str
        An earlier claim about a system identical to this one by an exact symmetry ("" for
        none): our measurement of the two is one number, compared with two of the paper's.
    factors : tuple of str
        The factors tried for a disagreement of this claim, in the report's order: the data
        file's ``factors`` unless the entry declares its own (fixed before any number of it was
        seen).
    reference : str
        The literature value (a key of :data:`REFERENCES`) the claim's value and error are
        taken from ("" where the paper states them itself).
    """

    key: str
    text: str
    paper: str
    value: float | None
    error: float
    error_kind: str
    source: str
    relation: str = "equal"
    target: str = ""
    same_as: str = ""
    factors: tuple[str, ...] = ()
    reference: str = ""

    @property
    def figure(self) -> str:
        """The first figure of the paper the source names ("1C", "2D"; "" for none)."""
        found = _FIGURE.search(self.source)
        return found.group(1) if found else ""

    @property
    def resolution(self) -> float:
        """The smallest deviation the comparison is meant to detect: the larger of the paper's
        error and the family's target precision (0: not stated)."""
        return max(self.error, TARGETS.get(self.target, 0.0))


#: a figure of the paper as the sources name it: "Fig. 2C"
_FIGURE = re.compile(r"\bFig\. (\d+[A-Z]?)\b")


def _claim(entry: dict, references: dict[str, Reference], earlier: dict) -> Claim:
    """One ``[[claims]]`` entry, checked against the references and the earlier claims."""
    e = dict(entry)
    key = e.pop("key")
    ref, error = e.get("reference"), e.pop("error", None)
    if ref is not None:
        e["value"], error = references[ref].value, references[ref].error
    kind = error if isinstance(error, str) else "stated"
    if kind not in {*ERROR_KINDS, "about", "stated"} or error is None:
        raise ValueError(
            f"claim {key}: error must be a number, 'about' or one of {list(ERROR_KINDS)}"
        )
    if kind == "about" and not _ABOUT.search(e.get("paper", "")):
        raise ValueError(f"claim {key}: error 'about' needs a value printed as 'about x'")
    if (e.get("value") is None) != (kind == "computed"):
        raise ValueError(f"claim {key}: a value is needed unless the error is 'computed'")
    if e.get("relation", "equal") not in RELATIONS or e.get("target", "") not in {"", *TARGETS}:
        raise ValueError(f"claim {key}: unknown relation or target")
    if e.get("same_as", "") not in {"", *earlier} or key in earlier:
        raise ValueError(f"claim {key}: repeated, or same_as names no earlier claim")
    factors = tuple(e.pop("factors", FACTORS))
    if not set(factors) <= set(KNOWN_FACTORS):
        raise ValueError(
            f"claim {key}: unknown factors {sorted(set(factors) - set(KNOWN_FACTORS))}"
        )
    err = (about_tolerance(e["paper"]) if kind == "about"
           else ERROR_KINDS[kind] if kind in ERROR_KINDS else float(error))  # fmt: skip
    return Claim(key=key, error=err, error_kind=kind, value=e.pop("value", None), factors=factors,
                 **e)  # fmt: skip


def _claims(entries: list[dict], references: dict[str, Reference]) -> dict[str, Claim]:
    claims: dict[str, Claim] = {}
    for entry in entries:
        claims[entry["key"]] = _claim(entry, references, claims)
    return claims


_DATA = tomllib.loads(DATA.read_text())
#: the precision the reproduction aims at per family of claims
TARGETS: dict[str, float] = dict(_DATA["targets"])
#: the factors that can account for a disagreement, in the order the report lists them
FACTORS: tuple[str, ...] = tuple(_DATA["factors"])
#: every factor a claim may declare (:attr:`Claim.factors`)
KNOWN_FACTORS: tuple[str, ...] = tuple(_DATA["known_factors"])
#: the factor of a measurement that repeats ours at the same size on independent samples
REPLICATION: str = _DATA["replication"]
#: literature values, by key
REFERENCES = {
    key: Reference(v["value"], v.get("error"), v["citation"], v.get("who", ""))
    for key, v in _DATA["references"].items()
}
#: every claim, in the order of the comparison table
CLAIMS = _claims(_DATA["claims"], REFERENCES)
#: our own 2D values of the quantities the 3D study measures (extrapolated: reports/fss, the
#: rods-only threshold from the calibration of reports/pc)
TWO_D_OURS = {
    key: Reference(v["value"], v["error"], v.get("source", _DATA["two_d_ours"]["source"]))
    for key, v in _DATA["two_d_ours"]["values"].items()
}


@dataclass(frozen=True, eq=False)
class Measurement:
    """What a study measured for one claim.

    Attributes
    ----------
    claim : str
        Key of the claim in :data:`CLAIMS` (or a study's own quantity).
    value : (k,) float
        Our value(s); k > 1 for a claim about several points (e.g. every f_c).
    cov : (k, k) float
        Their covariance.
    system : str
        System size and samples behind the value.
    factor : str
        "ours" for the reproduction's own measurement, else one of :data:`FACTORS` (the same
        claim measured another way, as evidence of what moves it) or :data:`REPLICATION`.
    label : str
        What was changed, for the explanation.
    points : tuple of str
        Labels of the k points (empty for k = 1).
    reference : (k,) float or None
        The reference values when the study computes them (single node).
    note : str
        How the value is defined, where that matters.
    shift : bool
        True when ``value`` is a change of the claim's value on the same samples: the
        comparison adds it to our own measurement, with both covariances.
    size : int or None
        The lattice size behind the value, where a replication may be compared with it.
    short : str
        A shorter ``label`` for the report's tables, where a section says the rest ("" for the
        label itself).
    control : bool
        True for a control row: the factor at our own setting (e.g. our node disorder on other
        samples). It is shown, and never credited with accounting for a disagreement.
    sizes : tuple of int
        The lattice sizes behind an extrapolation (empty otherwise): where a factor is judged,
        the report names the sizes it was tested over.
    """

    claim: str
    value: np.ndarray
    cov: np.ndarray
    system: str
    factor: str = "ours"
    label: str = ""
    points: tuple[str, ...] = ()
    reference: np.ndarray | None = None
    note: str = ""
    shift: bool = False
    size: int | None = None
    short: str = ""
    control: bool = False
    sizes: tuple[int, ...] = ()

    @classmethod
    def scalar(cls, claim: str, value: float, err: float, system: str, **kw) -> Measurement:
        """A single value with its standard error."""
        return cls(claim, np.array([value], float), np.array([[err**2]], float), system, **kw)

    @property
    def err(self) -> np.ndarray:
        """(k,) standard errors."""
        return np.sqrt(np.diag(self.cov))
