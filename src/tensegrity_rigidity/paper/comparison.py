"""Our measurements beside the paper's claims: one typed row per claim, one agreement rule.

:func:`compare` pairs each claim of :mod:`~tensegrity_rigidity.paper.claims` with the
:class:`~tensegrity_rigidity.paper.claims.Measurement` objects the studies produced and returns
:class:`ComparisonRow` objects, which the report renders. The rule, the same for every claim:
``z = |ours - paper| / sqrt(err_ours^2 + err_paper^2)``, agree when z < 2, unless our error
exceeds :data:`RESOLVES_WITHIN` times the claim's resolution somewhere (then inconclusive); a
claim about several points uses its largest z at the family-wise level, one about a sign our
distance to the claimed side. A disagreement's explanation gives, per factor the claim declares
(:attr:`~tensegrity_rigidity.paper.claims.Claim.factors`), the same claim measured with that
factor changed, and the replication at the same size first. A factor accounts for the
disagreement only under the evidence rule (:func:`credit`): the change moves our value
significantly by its own z, Holm-corrected over the rows tried for that disagreement, the gap
then closes, the row is not a control, and the same change opens no gap among the claims of
its family that agree (:func:`family_opened`). docs/guide/reproduction.md ("How claims are
compared") states the rules in full.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields, replace

import numpy as np
import pandas as pd
from scipy import stats

from ..analysis.estimators import agreement_z, holm_adjusted, sign_z
from .claims import CLAIMS, REPLICATION, Claim, Measurement
from .template import load

WORDS = load("comparison")

#: z below which a measurement agrees with the paper
AGREE_BELOW = 2.0

#: our error, in units of the claim's resolution, beyond which a small z is inconclusive
RESOLVES_WITHIN = 3.0

#: the longest a cell of the report's summary table may be (characters)
CELL_CHARS = 160

#: the family-wise level at which a factor's change of our value counts as a move: the
#: two-sided tail of the agreement rule's z (2), so that "moves" and "disagrees" need the same
#: strength of evidence
MOVES_ALPHA = float(2 * stats.norm.sf(AGREE_BELOW))


@dataclass(frozen=True)
class Evidence:
    """One measurement of a claim with one factor changed, beside ours.

    Attributes
    ----------
    factor : str
        One of :data:`~tensegrity_rigidity.paper.claims.FACTORS` or the replication.
    label : str
        What was changed ("" for a factor not yet tested).
    value : str
        Its value with its error, formatted ("" when not tested).
    system : str
        System size and samples behind it.
    z : float
        Its agreement statistic with the paper (NaN when not tested).
    verdict : str
        How it reads: "then agrees", "still disagrees", "agrees only through its larger error:
        ...", "not yet tested", ...
    resolved : bool
        False when its error exceeds its value at every point (see
        :attr:`ComparisonRow.resolved`).
    short : str
        The label as the report's tables show it (the measurement's ``short``, else ``label``).
    moved_z : float
        How far the change moves our value, in units of the errors of both (NaN where not
        comparable point by point, and for a replication or an untested factor).
    moved_p : float
        Its two-sided p-value, Holm-adjusted over the rows tried for the disagreement (NaN
        where not judged).
    credited : bool
        True when the row accounts for the disagreement (:func:`credit`).
    control : bool
        A control row (the factor at our own setting): shown, never credited.
    sizes : tuple of int
        The sizes behind an extrapolation (the measurement's ``sizes``).
    """

    factor: str
    label: str
    value: str
    system: str
    z: float
    verdict: str
    resolved: bool = True
    short: str = ""
    moved_z: float = float("nan")
    moved_p: float = float("nan")
    credited: bool = False
    control: bool = False
    sizes: tuple[int, ...] = ()

    def clause(self) -> str:
        """The measurement as the explanation's words put it."""
        return WORDS.label("clause", label=self.label, value=self.value, system=self.system,
                           z=self.z, verdict=self.verdict)  # fmt: skip


@dataclass(frozen=True)
class ComparisonRow:
    """One claim of the paper beside our measurement.

    Attributes
    ----------
    key : str
        The claim's key in :data:`~tensegrity_rigidity.paper.claims.CLAIMS`.
    claim, paper : str
        The claim and the paper's value as printed.
    ours : str
        Our value with its uncertainty, formatted.
    system : str
        System size and sample counts behind our value.
    z : float
        The agreement statistic (NaN when ours is missing).
    verdict : str
        "agree", "disagree", "inconclusive" or "n/a" (:func:`verdict`).
    explanation : str
        For a disagreement, the evidence for each factor; for an inconclusive comparison, why;
        either preceded by the replication of the same size where there is one. Empty when
        the claim agrees, unless a replication disagrees: then the replication and every
        factor's evidence.
    note : str
        How our value is defined, where that matters.
    source : str
        Where in the paper the claim is made.
    replication : str
        The verdict of the replications at our size ("disagree" when any disagrees, else
        "agree" when any agrees, else "inconclusive"); empty without one that has a value.
    reason : str
        The verdict's reason in one line (at most :data:`CELL_CHARS` characters): the z, and for
        a disagreement which factors account for it, for an inconclusive one why.
    evidence : tuple of Evidence
        The rows of the explanation as data: one per measurement of another factor (or per
        factor not yet tested), for the report's table per claim.
    value, err : tuple of float
        Our value(s) and standard error(s) (k points).
    study : str
        The study whose measurement is ours.
    """

    key: str
    claim: str
    paper: str
    ours: str
    system: str
    z: float
    verdict: str
    explanation: str
    note: str
    source: str
    replication: str = ""
    reason: str = ""
    evidence: tuple[Evidence, ...] = ()
    value: tuple[float, ...] = ()
    err: tuple[float, ...] = ()
    study: str = ""

    @property
    def resolved(self) -> bool:
        """False when an error exceeds the size of its value at every point: such a value is
        not resolved at this precision, and the report says so instead of printing it."""
        return _resolved(self.value, self.err)


#: columns of the summary table that opens the report
SUMMARY_COLUMNS = ["claim", "paper", "ours", "verdict", "reason"]


def decimals(err, digits=3) -> int:
    """The decimals that show an error ``err`` to two significant digits: ``digits``, more (up
    to 6) for a small error."""
    if err is None or not np.isfinite(err) or err <= 0:
        return digits
    return int(np.clip(1 - np.floor(np.log10(err)), digits, max(digits, 6)))


def fmt(value, err=None, digits=3) -> str:
    """``value ± err`` to :func:`decimals` ("n/a" for a missing or non-finite value):
    ``0.65662 ± 0.00078``, not ``0.657 ± 0.001``."""
    if value is None or not np.isfinite(value):
        return "n/a"
    if err is None or not np.isfinite(err):
        return f"{value:.{digits}f}"
    digits = decimals(err, digits)
    return f"{value:.{digits}f} ± {err:.{digits}f}"


def fit_form(row) -> str:
    """A limit's fit-form systematic as a table prints it (``row``: ``limit_syst`` and
    ``limit_laws``, the laws the data allow, comma-separated): "-" where they allow one law
    alone (a 0 there read as a spread over laws that was measured and found null)."""
    return f"{row.limit_syst:.2g}" if "," in str(row.limit_laws) else "-"


def z_score(claim: Claim, m: Measurement) -> float:
    """The agreement statistic of one measurement of a claim (see the module docstring).

    Points whose value or error is not finite are left out (a derivative ratio at a point where
    P does not vary); NaN when none is left.
    """
    if claim.relation in ("positive", "negative"):
        sign = 1 if claim.relation == "positive" else -1
        return sign_z(float(m.value[0]), float(m.err[0]), sign)
    ref = m.reference if m.reference is not None else np.full(m.value.size, claim.value)
    ok = np.isfinite(m.value) & np.isfinite(m.err) & np.isfinite(ref)
    if not ok.any():
        return float("nan")
    return agreement_z(m.value[ok], m.cov[np.ix_(ok, ok)], ref[ok], claim.error)


def unresolved(claim: Claim, m: Measurement) -> int:
    """How many of the compared points have an error above the claim's resolution allowance.

    Points left out of the z (non-finite value or error) are not counted; a claim without a
    resolution (a sign, a computed reference) has none.
    """
    if claim.relation != "equal" or claim.resolution <= 0:
        return 0
    ok = np.isfinite(m.value) & np.isfinite(m.err)
    return int(np.sum(m.err[ok] > RESOLVES_WITHIN * claim.resolution))


def verdict(claim: Claim, m: Measurement) -> tuple[float, str]:
    """The agreement statistic and the verdict of one measurement (the module's rule).

    Returns
    -------
    z : float
        :func:`z_score` (NaN when no point has a finite value and error).
    verdict : str
        "disagree" when z >= 2; "inconclusive" when z < 2 but our error exceeds
        :data:`RESOLVES_WITHIN` times the claim's resolution at some point compared; "agree"
        otherwise; "n/a" without a value.
    """
    z = z_score(claim, m)
    if not np.isfinite(z):
        return z, "n/a"
    if z >= AGREE_BELOW:
        return z, "disagree"
    return z, "inconclusive" if unresolved(claim, m) else "agree"


def _why_inconclusive(claim: Claim, m: Measurement) -> str:
    ok = np.isfinite(m.value) & np.isfinite(m.err)
    return WORDS.label(
        "inconclusive", times=RESOLVES_WITHIN, resolution=claim.resolution,
        count=unresolved(claim, m) if m.value.size > 1 else None, points=int(ok.sum()),
        deviation=2 * RESOLVES_WITHIN * claim.resolution,
    )  # fmt: skip


#: a measurement of more points than this is shown by its count and worst deviation (each
#: point's value is in its study's tables): a table cell of nine "f_c = 0.375: -31.33 ± 5998.41"
#: runs to 250 characters
MAX_LISTED_POINTS = 4


def _ours(m: Measurement, claim: Claim, digits: int = 3) -> str:
    if m.value.size == 1:
        return fmt(float(m.value[0]), float(m.err[0]), digits)
    if m.value.size > MAX_LISTED_POINTS:
        ref = m.reference if m.reference is not None else np.full(m.value.size, claim.value)
        with np.errstate(divide="ignore", invalid="ignore"):
            dev = np.abs(m.value - ref) / m.err
        dev = dev[np.isfinite(dev)]
        return WORDS.label("points", count=m.value.size, worst=dev.max() if dev.size else None)
    parts = [
        f"{lab}: {fmt(v, e, 2)}" if lab else fmt(v, e, 2)
        for lab, v, e in zip(m.points or [""] * m.value.size, m.value, m.err, strict=True)
    ]
    return ", ".join(parts)


def _applied(ours: Measurement, shift: Measurement) -> Measurement:
    """Our measurement moved by a measured shift (errors of both added)."""
    if shift.value.size != ours.value.size:
        return replace(shift, value=np.full(shift.value.size, np.nan))
    return replace(shift, value=ours.value + shift.value, cov=ours.cov + shift.cov, shift=False)


def _at_our_error(claim: Claim, ours: Measurement, alt: Measurement) -> float:
    """z of an alternative's value with our covariance instead of its own.

    An alternative can agree with the paper only because its error is larger than ours (fewer
    samples, an extrapolation, an added shift) while its value stays as far from the paper as
    ours, or moves away. At our error its value would still disagree: the factor does not
    account for the difference, its measurement just cannot resolve it. NaN when the two
    cover different points.
    """
    if alt.value.size != ours.value.size:
        return float("nan")
    return z_score(claim, replace(alt, cov=ours.cov))


def _words(v: str, plain: bool) -> str:
    """How an alternative's verdict reads: plainly ("agrees"), or beside a disagreement of
    ours ("then agrees", "still disagrees")."""
    key = f"reads.{v}.plain" if plain and v in ("agree", "disagree") else f"reads.{v}"
    return WORDS.label(key if key in WORDS.labels else "reads.none", times=RESOLVES_WITHIN)


def _resolved(value, err) -> bool:
    """True when some point's error is at most the size of its value."""
    v, e = np.abs(np.asarray(value, float)), np.asarray(err, float)
    ok = np.isfinite(v) & np.isfinite(e)
    return bool(ok.any() and (e[ok] <= v[ok]).any())


def _part(claim: Claim, a: Measurement, z: float, judged: str, factor: str = "", **kw) -> Evidence:
    """One alternative in an explanation: its label, value, system, z and verdict (``kw``:
    the evidence rule's fields)."""
    resolved = _resolved(a.value, a.err)
    return Evidence(factor or a.factor, a.label, _ours(a, claim), a.system, z, judged, resolved,
                    a.short or a.label, control=a.control, sizes=a.sizes, **kw)  # fmt: skip


def moved_z(ours: Measurement, alt: Measurement) -> float:
    """How far a factor's change moves our value: the change in units of its error.

    A shift (``alt.shift``, measured on our samples) is its own change, with its own
    covariance; another measurement is compared with ours with both errors added, which is
    conservative where the two share samples (their difference then varies less). A claim
    about several points takes the largest point, family-wise (:func:`agreement_z`). NaN where
    the two cover different points.
    """
    if alt.shift:
        return agreement_z(alt.value, alt.cov, np.zeros(alt.value.size))
    if alt.value.size != ours.value.size:
        return float("nan")
    ok = (
        np.isfinite(alt.value)
        & np.isfinite(ours.value)
        & np.isfinite(alt.err)
        & np.isfinite(ours.err)
    )
    if not ok.any():
        return float("nan")
    var = alt.err[ok] ** 2 + ours.err[ok] ** 2
    return agreement_z(alt.value[ok], var, ours.value[ok])


def credit(moved_p: float, closes: bool, control: bool, alpha: float = MOVES_ALPHA) -> bool:
    """The evidence rule: does one row account for a disagreement?

    Parameters
    ----------
    moved_p : float
        The Holm-adjusted p-value of the row's move of our value (NaN: not judged).
    closes : bool
        The row's value agrees with the paper (z < 2), and not only through a larger error.
    control : bool
        The row is a control (the factor at our own setting).
    alpha : float
        The family-wise level of a move (:data:`MOVES_ALPHA`).

    Returns
    -------
    bool
        True only for a row that is not a control, moves our value significantly and closes
        the gap: a factor that closes the gap without moving our value shows only that its
        measurement is too loose to disagree, and a control changes nothing.
    """
    return bool(not control and closes and np.isfinite(moved_p) and moved_p <= alpha)


def _replicated(claim: Claim, replications: list[Measurement]) -> tuple[str, str, list[Evidence]]:
    """The replications' clause for an explanation, their overall verdict (see
    :attr:`ComparisonRow.replication`) and their evidence rows; empty without one with a
    value."""
    replications = [a for a in replications if np.isfinite(a.value).any()]
    if not replications:
        return "", "", []
    parts, verdicts = [], []
    for a in replications:
        z, v = verdict(claim, a)
        verdicts.append(v)
        parts.append(_part(claim, a, z, _words(v, plain=True)))
    overall = next((v for v in ("disagree", "agree", "inconclusive") if v in verdicts), "")
    return f"{REPLICATION}: " + " / ".join(p.clause() for p in parts), overall, parts


def _rule(credited: bool, moved: float, adjusted: float) -> str:
    """The template label of how the evidence rule judged one row."""
    if credited:
        return "rule.credited"
    if np.isfinite(adjusted) and adjusted <= MOVES_ALPHA:
        return "rule.moved"
    return "rule.not_moved" if np.isfinite(moved) else "rule.incomparable"


def _evidence(
    claim: Claim,
    ours: Measurement,
    alternatives: list[Measurement],
    agreeing: bool = False,
    opened=None,
) -> tuple[str, list[Evidence]]:
    """One clause per factor: the alternative measurements and whether they agree.

    For a disagreement (the default) an alternative "then agrees" or "still disagrees", and
    one that agrees only because its error is larger than ours is named so. For an agreement
    (``agreeing``: one that a replication contradicts) the words are plain, "agrees" or
    "disagrees": our error is not the yardstick there, since it is what is in question.
    For a disagreement each row is judged by the evidence rule (:func:`credit`): its move of
    our value (:func:`moved_z`) is tested at :data:`MOVES_ALPHA` with Holm's correction over
    every non-control row of the claim's factors (a move from the factor's control row, where
    it has one, else from ours); a row the rule would credit is not credited
    where ``opened(claim, row)`` names agreeing claims of the claim's family that the same
    change makes disagree (:func:`family_opened`). Returns the clauses joined, and the
    evidence rows behind them.
    """
    tried = [(factor, a) for factor in claim.factors for a in alternatives if a.factor == factor]
    # a change is measured against its factor's control row where one exists (the factor at
    # our setting on the change's own samples), else against ours: the control's own distance
    # from ours is sample noise, not the factor's effect
    control = {f: a for f, a in reversed(tried) if a.control}
    moves = np.array([moved_z(ours if a.control else control.get(f, ours), a) for f, a in tried])
    judged_rows = [not agreeing and not a.control for _, a in tried]
    raw_p = np.where(judged_rows, 2 * stats.norm.sf(moves), np.nan)
    adjusted = holm_adjusted(raw_p)
    count = int(np.isfinite(raw_p).sum())
    clauses, rows = [], []
    for factor in claim.factors:
        mine = [i for i, (f, _) in enumerate(tried) if f == factor]
        if not mine:
            clauses.append(f"{factor}: {WORDS.label('untested')}")
            rows.append(Evidence(factor, "", "", "", float("nan"), WORDS.label("untested")))
            continue
        parts = []
        for i in mine:
            raw = tried[i][1]
            a = _applied(ours, raw) if raw.shift else raw
            z, v = verdict(claim, a)
            judged = _words(v, plain=agreeing)
            closes = v == "agree"
            if closes and not agreeing:
                z_ours = _at_our_error(claim, ours, a)
                if z_ours >= AGREE_BELOW:
                    judged, closes = WORDS.label("larger_error", z=z_ours), False
            credited = credit(adjusted[i], closes, raw.control)
            broken = opened(claim, raw) if credited and opened else []
            credited = credited and not broken
            if raw.control:
                judged = WORDS.label("judged", reads=judged, rule=WORDS.label("rule.control"))
            elif not agreeing:
                rule = "rule.opens" if broken else _rule(credited, moves[i], adjusted[i])
                words = WORDS.label(rule, z=moves[i], p=adjusted[i], tried=count,
                                    opened=len(broken))  # fmt: skip
                judged = WORDS.label("judged", reads=judged, rule=words)
            parts.append(_part(claim, a, z, judged, factor, moved_z=float(moves[i]),
                               moved_p=float(adjusted[i]), credited=credited))  # fmt: skip
        rows += parts
        clauses.append(f"{factor}: " + " / ".join(p.clause() for p in parts))
    return "; ".join(clauses), rows


def shared_measurements(rows: list[ComparisonRow]) -> list[tuple[str, str, float]]:
    """Pairs of rows whose claims are about one system (:attr:`Claim.same_as`).

    Our measurement of such a pair is one number compared with two values of the paper, so the
    pair is one independent comparison, not two; and the paper's two values can disagree with
    each other.

    Returns
    -------
    list of (key, same_as, z)
        Each pair present in ``rows``, with ``z`` the paper's two values against each other,
        ``|a - b| / sqrt(err_a^2 + err_b^2)`` with the errors of the agreement rule (NaN for a
        claim without a value).
    """
    present = {r.key for r in rows}
    out = []
    for r in rows:
        c = CLAIMS[r.key]
        if not c.same_as or c.same_as not in present:
            continue
        o = CLAIMS[c.same_as]
        if c.value is None or o.value is None:
            z = float("nan")
        else:
            z = abs(c.value - o.value) / float(np.hypot(c.error, o.error))
        out.append((r.key, c.same_as, z))
    return out


def _explain(claim: Claim, m: Measurement, others: list[Measurement], opened=None) -> tuple:
    """(verdict, z, explanation, reason, replication, evidence) of our measurement ``m``
    (``opened``: see :func:`_evidence`)."""
    z, v = verdict(claim, m)
    same_size = [a for a in others if a.factor == REPLICATION and a.size is not None
                 and a.size == m.size]  # fmt: skip
    replicated, replication, evidence = _replicated(claim, same_size)
    explanation = ""
    reason = WORDS.label("reason", z=z) if np.isfinite(z) else WORDS.label("reads.none")
    if v == "disagree":
        said, rows = _evidence(claim, m, others, opened=opened)
        evidence += rows
        explanation = "; ".join(filter(None, [replicated, said]))
        reason = _reason_disagree(z, evidence)
    elif v == "inconclusive":
        explanation = "; ".join(filter(None, [replicated, _why_inconclusive(claim, m)]))
        reason = WORDS.label("reason.inconclusive", z=z, times=RESOLVES_WITHIN,
                             resolution=claim.resolution)  # fmt: skip
    elif v == "agree" and replication == "disagree":
        # "precision" where the replication is the more precise, else the sample set
        sharper = any(np.all(a.err < m.err) for a in same_size)
        only = WORDS.label("only.precision" if sharper else "only.samples")
        said, rows = _evidence(claim, m, others, agreeing=True)
        evidence += rows
        explanation = WORDS.label("agrees_only", only=only, replicated=replicated, said=said)
        reason = WORDS.label("reason.agrees_only", z=z, only=only)
    return v, z, explanation, reason, replication, evidence


def family_opened(claim: Claim, change: Measurement, by_claim: dict) -> list[str]:
    """The claims of ``claim``'s family (:attr:`Claim.target`) that our measurements agree
    with and that the same change makes disagree.

    A factor that closes one gap while opening another in the same family does not account
    for the gap: it is credited only where it is consistent with every claim of the family it
    was measured on. The same change is the factor's measurement there with the same label
    where one has it (a node disorder of 0.1 is not one of 0.3), else every non-control
    measurement of the factor there; a claim opens when every such reading disagrees. A claim
    without a family is checked against none, and one about the same system (:attr:`Claim.same_as`)
    is not checked: it differs only by the paper's other value.
    """
    if not claim.target:
        return []
    out = []
    for key, other in CLAIMS.items():
        if (
            other.target != claim.target
            or claim.key in (key, other.same_as)
            or key == claim.same_as
        ):
            continue
        ms = by_claim.get(key, [])
        ours = next((m for m in ms if m.factor == "ours"), None)
        if ours is None or verdict(other, ours)[1] != "agree":
            continue
        same = [a for a in ms if a.factor == change.factor and not a.control]
        readings = [a for a in same if a.label == change.label] or same
        moved = [_applied(ours, a) if a.shift else a for a in readings]
        if moved and all(verdict(other, m)[1] == "disagree" for m in moved):
            out.append(other.text)
    return out


def compare(results: dict) -> list[ComparisonRow]:
    """One row per claim measured by the studies in ``results`` (study name -> result): every
    result's ``measured`` is read; a claim without a measurement of factor "ours" gets none."""
    by_claim: dict[str, list[Measurement]] = {}
    study: dict[str, str] = {}
    for name, r in results.items():
        for m in getattr(r, "measured", ()):
            by_claim.setdefault(m.claim, []).append(m)
            if m.factor == "ours":
                study.setdefault(m.claim, name)
    rows = []
    for key, claim in CLAIMS.items():
        ms = by_claim.get(key, [])
        ours = [m for m in ms if m.factor == "ours"]
        if not ours:
            continue
        m = ours[0]
        v, z, explanation, reason, replication, evidence = _explain(
            claim,
            m,
            [a for a in ms if a.factor != "ours"],
            lambda c, a: family_opened(c, a, by_claim),
        )
        rows.append(ComparisonRow(
            key=key, claim=claim.text, paper=claim.paper, ours=_ours(m, claim), system=m.system,
            z=z, verdict=v, explanation=explanation, note=m.note, source=claim.source,
            replication=replication, reason=reason[:CELL_CHARS], evidence=tuple(evidence),
            value=tuple(float(x) for x in m.value), err=tuple(float(x) for x in m.err),
            study=study[key],
        ))  # fmt: skip
    return rows


def verdict_counts(rows: list[ComparisonRow]) -> dict[str, int]:
    """How many rows have each verdict ("agree", "disagree", "inconclusive", "n/a"), the
    total, and the pairs about one system (:func:`shared_measurements`): the counts add up."""
    out = {v: sum(r.verdict == v for r in rows) for v in ("agree", "disagree", "inconclusive")}
    out["na"] = len(rows) - sum(out.values())
    shared = len(shared_measurements(rows))
    return out | {"total": len(rows), "shared": shared, "independent": len(rows) - shared}


#: the kinds of factor in a disagreement's reason, in the order it lists them
KINDS = ("accounted", "not_by", "unresolved", "untested")


def _reason_disagree(z: float, evidence: list[Evidence]) -> str:
    """One line: the z, and which factors account for the disagreement (a row credited by the
    evidence rule, :func:`credit`), which do not, which are unresolved and which are not yet
    tested; a factor is listed once, by its most telling measurement, with the sizes an
    extrapolation was tested over. A control row tells nothing about its factor: a factor
    with only controls is not yet tested."""
    untested = (WORDS.label("untested"), WORDS.label("reads.none"))
    # measured without a resolved value (an extrapolation no law fits): unresolved, not "not by"
    unresolved = (
        WORDS.label("reads.inconclusive", times=RESOLVES_WITHIN),
        WORDS.label("reads.none"),
    )
    by: dict[str, list[str]] = {k: [] for k in KINDS}
    sizes: dict[str, set[int]] = {}
    factors = [e.factor for e in evidence if e.factor != REPLICATION]
    for e in evidence:
        if e.factor == REPLICATION or e.control:
            continue
        sizes.setdefault(e.factor, set()).update(e.sizes)
        kind = ("accounted" if e.credited
                else "untested" if e.verdict in untested
                else "unresolved" if e.verdict.startswith(unresolved) else "not_by")  # fmt: skip
        if e.factor not in by[kind]:
            by[kind].append(e.factor)
    listed = {f for names in by.values() for f in names}
    by["untested"] += [f for f in dict.fromkeys(factors) if f not in listed]
    by["untested"].sort(key=factors.index)
    seen: set[str] = set()
    parts = [WORDS.label("reason", z=z)]
    for kind in KINDS:
        names = [f for f in by[kind] if f not in seen]
        seen |= set(names)
        if names:
            shown = [WORDS.label("factor.sizes", factor=f, sizes=sorted(sizes[f]))
                     if sizes.get(f) else f for f in names]  # fmt: skip
            parts.append(WORDS.label(f"kind.{kind}", factors=shown))
    return "; ".join(parts)


def summary_cell(row: ComparisonRow) -> str:
    """Our value with its error and system, as the summary table shows it (at most
    :data:`CELL_CHARS` characters): "not resolved at this precision" where every error exceeds
    its value; the system shortened to its first clause where the cell would be too long."""
    finite = np.isfinite(np.asarray(row.value, float)).any()
    ours = row.ours if row.resolved or not finite else WORDS.label("unresolved")
    if len(row.value) > 1 and len(ours) > CELL_CHARS // 2:
        v, e = np.abs(np.asarray(row.value)), np.asarray(row.err)
        bad = int(np.sum(~(e <= v)))
        ours = WORDS.label("points.unresolved", count=len(row.value), bad=bad or None)
    cell = f"{ours} ({row.system})"
    if len(cell) > CELL_CHARS:
        cell = f"{ours} ({row.system.split(';')[0]})"
    return cell if len(cell) <= CELL_CHARS else cell[: CELL_CHARS - 3] + "..."


def summary_frame(rows: list[ComparisonRow]) -> pd.DataFrame:
    """The report's opening table: claim, paper, ours (value ± error, system), verdict and a
    one-line reason."""
    return pd.DataFrame(
        {
            "claim": [r.claim for r in rows],
            "paper": [r.paper for r in rows],
            "ours": [summary_cell(r) for r in rows],
            "verdict": [r.verdict for r in rows],
            "reason": [r.reason for r in rows],
        },
        columns=SUMMARY_COLUMNS,
    )


def evidence_frame(row: ComparisonRow) -> pd.DataFrame:
    """The evidence for one claim's verdict, numbers in columns: factor, what changed, value,
    system, z and how it reads; our own measurement first. A value whose error exceeds it is
    "not resolved at this precision"."""
    ours = Evidence("ours", "", row.ours, row.system, row.z, row.verdict, row.resolved)
    rows = [ours, *row.evidence]
    return pd.DataFrame(
        {
            "factor": [e.factor for e in rows],
            "changed": [e.short for e in rows],
            "value": [e.value if e.resolved else WORDS.label("unresolved") for e in rows],
            "system": [e.system for e in rows],
            "z": [f"{e.z:.2f}" if np.isfinite(e.z) else "" for e in rows],
            "moves ours (z)": [f"{e.moved_z:.2f}" if np.isfinite(e.moved_z) else "" for e in rows],
            "Holm p": [f"{e.moved_p:.2g}" if np.isfinite(e.moved_p) else "" for e in rows],
            "reads": [e.verdict for e in rows],
        }
    )


def comparison_frame(rows: list[ComparisonRow]) -> pd.DataFrame:
    """The rows as a table (every field but the evidence rows, one column each); z rounded
    for display; a report that compares no claim gets the header alone (an empty file read
    as having no columns)."""
    columns = [f.name for f in fields(ComparisonRow) if f.name != "evidence"]
    df = pd.DataFrame([{k: v for k, v in asdict(r).items() if k != "evidence"} for r in rows],
                      columns=columns)  # fmt: skip
    df["z"] = df.z.astype(float).round(2)
    return df


#: the p_t whose p_crit the paper's tables give beside p_t = 0, for lambda from p_crit
SELF_P_T = 0.3
#: strain -> the claims that state S_t/S_r of rods + cables twice: p_crit at p_t = 0 and at
#: :data:`SELF_P_T` (under P = F(p_r + lambda p_t), lambda = (p_crit(0) - p_crit(0.3)) / 0.3),
#: and the headline efficacy
SELF_CONSISTENCY = {
    "compression": ("p_crit_compression_0.0", "p_crit_compression_0.3", "st_sr_cables_compression"),
    "dilation": ("p_crit_dilation_0.0", "p_crit_dilation_0.3", "st_sr_cables_dilation"),
}


def _difference_quotient(a: tuple[float, float], b: tuple[float, float]) -> tuple[float, float]:
    """(a - b) / SELF_P_T with the errors added in quadrature."""
    return (a[0] - b[0]) / SELF_P_T, float(np.hypot(a[1], b[1])) / SELF_P_T


def paper_against_itself(results: dict) -> pd.DataFrame:
    """Where the paper states S_t/S_r of rods + cables twice, both readings beside ours.

    Under P = F(p_r + lambda p_t) the paper's own p_crit tables give lambda = (p_crit(0) -
    p_crit(0.3)) / 0.3: (0.66 - 0.51) / 0.3 = 0.50 under compression and (0.65 - 0.46) / 0.3 =
    0.63 under dilation, against its headline S_t/S_r of 0.372 and about 0.67. Ours comes from
    the same p_crit estimator (our median thresholds; errors in quadrature, an upper bound since
    the thresholds at both p_t share samples) and from the collapse fit; "agrees with" applies
    the agreement rule (z < 2) to the collapse fit against each of the paper's readings.

    Returns
    -------
    DataFrame
        One row per strain whose claims were measured (empty without Figs. 1C and 2).
    """
    ours = {
        m.claim: (float(m.value[0]), float(m.err[0]))
        for r in results.values()
        for m in getattr(r, "measured", ())
        if m.factor == "ours" and m.value.size == 1
    }
    rows = []
    for strain, (k0, k3, headline) in SELF_CONSISTENCY.items():
        if not {k0, k3, headline} <= set(ours):
            continue
        c0, c3, ch = CLAIMS[k0], CLAIMS[k3], CLAIMS[headline]
        assert c0.value is not None and c3.value is not None and ch.value is not None
        tables = _difference_quotient((c0.value, c0.error), (c3.value, c3.error))
        from_pc = _difference_quotient(ours[k0], ours[k3])
        fit = ours[headline]
        z_tables = agreement_z(fit[0], fit[1] ** 2, tables[0], tables[1])
        z_head = agreement_z(fit[0], fit[1] ** 2, ch.value, ch.error)
        agrees = [WORDS.label(f"itself.{name}", z=z) for name, z in
                  (("tables", z_tables), ("headline", z_head)) if z < AGREE_BELOW]  # fmt: skip
        neither = WORDS.label("itself.neither", tables=z_tables, headline=z_head)
        rows.append({"strain": strain, "tables": fmt(*tables, digits=2), "headline": ch.paper,
                     "ours_pc": fmt(*from_pc), "ours_fit": fmt(*fit),
                     "agrees": f" {WORDS.label('and')} ".join(agrees) or neither})  # fmt: skip
    return pd.DataFrame(rows)
