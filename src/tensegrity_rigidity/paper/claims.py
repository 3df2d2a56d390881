"""The paper's quantitative claims as data, each with where it comes from.

One :class:`Claim` per number or statement of *Rigidity of generic random tensegrity structures*
(Sudhakar, McInerney, Rocklin, Stephenson) that the reproduction tests: the value, the paper's
error where it gives one, where in the paper it is stated (``source``; "SM" is the supplement
of ``/work/shared/seed``, "main" the main text) and which study measures it (a key of
:data:`tensegrity_rigidity.paper.studies.STUDIES`). This module is the only place the paper's
values are typed in; the comparison (:mod:`~tensegrity_rigidity.paper.comparison`) and the
report read them from here.

Literature values the paper relies on (:data:`REFERENCES`) carry their citation the same way.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: standard error of a value printed to two decimals and given without an error: the rounding,
#: uniform over one unit of the last digit (0.01 / sqrt(12))
ROUNDING_2DP = 0.01 / math.sqrt(12)


@dataclass(frozen=True)
class Reference:
    """A value from the literature.

    Attributes
    ----------
    value, error : float
        The value and its quoted uncertainty (None when none is quoted).
    citation : str
        Who, where, and how the value was obtained.
    """

    value: float
    error: float | None
    citation: str


#: literature values used by the comparison and the finite-size study
REFERENCES = {
    "pc_jacobs_thorpe": Reference(
        0.6602,
        0.0003,
        "Jacobs & Thorpe, Phys. Rev. Lett. 75, 4051 (1995), 'Generic rigidity percolation: the "
        "pebble game': generic bond-diluted triangular lattice, pebble game (cited by the paper "
        "as jacobs1995generic)",
    ),
    "pc_javerzat_notarmuzi": Reference(
        0.6602741,
        0.0000004,
        "Javerzat & Notarmuzi (2025), generic rigidity percolation of the bond-diluted "
        "triangular lattice: pebble game in Newman-Ziff order with wrapping detection, up to "
        "5e8 nodes; 0.6602741(4) as quoted in the project's brief (not found among the sources "
        "searched here, so not verified against the paper)",
    ),
    "nu_javerzat_notarmuzi": Reference(
        1.1694,
        0.0008,
        "Javerzat & Notarmuzi (2025), correlation-length exponent, 1.1694(8) as quoted in the "
        "project's brief (not verified against the paper)",
    ),
    "df_rigid_javerzat_notarmuzi": Reference(
        1.8423,
        0.0007,
        "Javerzat & Notarmuzi (2025), fractal dimension of the rigid cluster at p_c, 1.8423(7) "
        "as quoted in the project's brief (not verified against the paper)",
    ),
    "df_rigid_jacobs_thorpe": Reference(
        1.86,
        None,
        "Jacobs & Thorpe, Phys. Rev. Lett. 75, 4051 (1995): spanning rigid cluster, about 1.86 "
        "as quoted in the project's brief; the abstract (checked) gives p_c, nu and beta only, "
        "so this value and its error are not verified",
    ),
    "df_stressed_jacobs_thorpe": Reference(
        1.78,
        None,
        "Jacobs & Thorpe, Phys. Rev. Lett. 75, 4051 (1995): stressed backbone, about 1.78 as "
        "quoted in the project's brief; the abstract (checked) gives p_c, nu and beta only, so "
        "this value and its error are not verified",
    ),
    "nu_jacobs_thorpe": Reference(
        1.21, 0.06, "Jacobs & Thorpe, Phys. Rev. Lett. 75, 4051 (1995): correlation-length exponent"
    ),
    "pc_fcc_chubynsky_thorpe": Reference(
        0.495,
        None,
        "Chubynsky & Thorpe, Phys. Rev. E 76, 041135 (2007), arXiv:cond-mat/0702635, "
        "'Algorithms for three-dimensional rigidity analysis and a first-order percolation "
        "transition': bond-diluted central-force FCC, a 3D pebble game they argue is "
        "essentially exact there, and a first-order rigidity transition (the largest rigid "
        "cluster jumps on a single bond). The abstract was read here; the value 0.495 is as "
        "quoted from that paper by a secondary source (a public prior-art memo), not read in "
        "its text: treat it as approximate, no error quoted",
    ),
    "pc_fcc_maxwell": Reference(
        0.5,
        None,
        "Maxwell's count for bond-diluted FCC: z = 12 neighbours, rigidity needs a mean "
        "coordination 2d = 6, so p = 6/12 (mean field; exact for the count, not the threshold)",
    ),
    "nu_moukarzel_duxbury": Reference(
        1.16,
        0.03,
        "Moukarzel & Duxbury, Phys. Rev. E 59, 2614 (1999), arXiv:cond-mat/9702249: generic "
        "rigidity percolation on lattices up to L = 4096",
    ),
}


#: our own 2D values of the quantities the 3D study measures (paper.studies.three_d), set
#: beside the 3D ones in the report: the n -> infinity extrapolations of the committed
#: finite-size report, reports/fss/tables/fss_extrapolated.csv (written at 13780ee; n = 8 to
#: 64, rods-only p_c from n = 8 to 64 with 4000 to 100 samples), column y_inf (nu fitted, 0.58)
TWO_D_OURS = {
    key: Reference(value, error, "reports/fss/tables/fss_extrapolated.csv (13780ee), y_inf")
    for key, value, error in (
        ("rods_only_pc", 0.657684, 0.001369),
        ("st_sr_half_dilation", 0.499619, 0.002437),
        ("st_sr_half_shear", 0.499855, 0.002387),
        ("st_sr_half_compression", 0.499686, 0.002364),
        ("st_sr_cables_compression", 0.466844, 0.004954),
        ("st_sr_cables_dilation", 0.539143, 0.011472),
    )
}


#: the precision the reproduction aims at per family of claims (paper.budget chooses
#: sample counts from them): S_t/S_r +-0.013 (the paper's error on cables under compression),
#: p_crit and p_c +-0.005, the fraction of taut cables +-0.02, Fig. 4C +-0.1 (the paper prints no
#: number: a third of the 0.28 deviation the quick run measured at f_c = 0 and 1)
TARGETS = {"st_sr": 0.013, "p_crit": 0.005, "taut": 0.02, "fig4c": 0.1}


@dataclass(frozen=True)
class Claim:
    """One claim of the paper.

    Attributes
    ----------
    key : str
        Stable identifier (used by the studies' measurements).
    text : str
        The claim as the comparison table states it.
    paper : str
        The paper's value as printed.
    value : float or None
        The number our measurement is compared with (None for a qualitative claim or one whose
        reference value the study computes, as the single-node formula).
    error : float
        The paper's standard error (see ``error_kind``).
    error_kind : str
        "stated" (the paper's error bar), "rounding" (a value printed without one: the rounding
        of its last digit, :data:`ROUNDING_2DP`), "exact" (a theoretical value, error 0) or
        "computed" (the reference value is computed by the study, error 0).
    source : str
        Where in the paper the claim is made.
    study : str
        The study that measures it.
    relation : str
        "equal", or "positive" / "negative" for a claim about a sign (a trend).
    target : str
        The claim's family in :data:`TARGETS` ("" for none): the precision it is measured to.
    same_as : str
        The key of an earlier claim about a system identical to this one by an exact symmetry
        ("" for none): our measurement of the two is one number, compared with two values of
        the paper. Rods only (p_t = 0) under compression and dilation is one system (a rod
        resists both signs of strain); rods + struts under dilation is rods + cables under
        compression with e -> -e. The report counts such a pair once and gives the paper's
        own two values' z against each other.
    """

    key: str
    text: str
    paper: str
    value: float | None
    error: float
    error_kind: str
    source: str
    study: str
    relation: str = "equal"
    target: str = ""
    same_as: str = ""

    @property
    def resolution(self) -> float:
        """The smallest deviation the comparison is meant to detect (0: not stated).

        The larger of the paper's error and the family's target precision (:data:`TARGETS`).
        A measurement whose error is much larger than this cannot tell the claim from a
        deviation of that size (:func:`~tensegrity_rigidity.paper.comparison.verdict`).
        """
        return max(self.error, TARGETS.get(self.target, 0.0))


#: the factors that can account for a disagreement, in the order the report lists them
FACTORS = ("finite size", "delta", "method", "estimator")

#: the factor of a measurement that repeats ours at the same size on independent samples (the
#: finite-size study's, usually with more of them): not a factor that could explain a
#: difference, but a check of whether our value holds up at another sample set and precision
REPLICATION = "replication"


@dataclass(frozen=True, eq=False)
class Measurement:
    """What a study measured for one claim.

    Attributes
    ----------
    claim : str
        Key of the claim in :data:`CLAIMS`.
    value : (k,) float
        Our value(s); k > 1 for a claim about several points (e.g. every f_c).
    cov : (k, k) float
        Their covariance.
    system : str
        System size and samples behind the value.
    factor : str
        "ours" for the reproduction's own measurement, else one of :data:`FACTORS`: the same
        claim measured another way, as evidence of what moves it (e.g. "method": with the
        paper's verdict; "estimator": with the paper's estimator); or :data:`REPLICATION`.
    label : str
        What was changed, for the explanation (e.g. "paper's verdict (L-BFGS-B)").
    points : tuple of str
        Labels of the k points (empty for k = 1).
    reference : (k,) float or None
        The reference values when the claim's are computed by the study (single node).
    note : str
        How the value is defined, where that matters.
    shift : bool
        True when ``value`` is a change of the claim's value (an alternative measured as
        "paper's way minus ours" on the same samples): the comparison adds it to our own
        measurement, with both covariances.
    size : int or None
        The lattice size n behind the value: set on the figure studies' own measurements of
        the claims the finite-size study also measures, and on replications; None elsewhere.
        A :data:`REPLICATION` is compared only with our measurement of the same size.
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

    @classmethod
    def scalar(cls, claim: str, value: float, err: float, system: str, **kw) -> Measurement:
        """A single value with its standard error."""
        return cls(claim, np.array([value], float), np.array([[err**2]], float), system, **kw)

    @property
    def err(self) -> np.ndarray:
        """(k,) standard errors."""
        return np.sqrt(np.diag(self.cov))


def _quoted_error(key: str) -> float:
    """The quoted uncertainty of a literature value that has one."""
    error = REFERENCES[key].error
    if error is None:
        raise ValueError(f"the literature value {key!r} quotes no uncertainty")
    return error


def _claims() -> list[Claim]:
    out = []
    for strain in ("dilation", "shear", "compression", "average"):
        out.append(
            Claim(
                f"st_sr_half_{strain}",
                f"S_t/S_r = 0.5 at f_c = 0.5 ({strain})",
                "0.5",
                0.5,
                0.0,
                "exact",
                "main text on Fig. 1C: 'the nonlinear elements always count as half the linear "
                "elements in all types of metric strain'; Fig. 1C caption",
                "fig1c",
                target="st_sr",
            )
        )
    out += [
        Claim(
            "st_sr_cables_compression",
            "rods + cables, compression: S_t/S_r",
            "0.372 ± 0.013",
            0.372,
            0.013,
            "stated",
            "Fig. 1C caption: 'cables ... contribute about 37.2 % ± 1.3 %'",
            "fig1c",
            target="st_sr",
        ),
        Claim(
            "st_sr_struts_dilation",
            "rods + struts, dilation: S_t/S_r",
            "0.359 ± 0.015",
            0.359,
            0.015,
            "stated",
            "Fig. 1C caption: '(struts) ... 35.9 % ± 1.5 %'",
            "fig1c",
            target="st_sr",
            same_as="st_sr_cables_compression",
        ),
        Claim(
            "st_sr_cables_dilation",
            "rods + cables, dilation: S_t/S_r",
            "about 0.67",
            0.67,
            ROUNDING_2DP,
            "rounding",
            "main text on Fig. 1C: 'cables under dilation ... count as much as 67 % as much as "
            "rods'",
            "fig1c",
            target="st_sr",
        ),
        Claim(
            "rods_only_pc",
            "rods only: p_c (Jacobs & Thorpe 1995: 0.6602)",
            "0.66 (compared: {0.value} ± {0.error}, Jacobs & Thorpe)".format(
                REFERENCES["pc_jacobs_thorpe"]
            ),
            REFERENCES["pc_jacobs_thorpe"].value,
            _quoted_error("pc_jacobs_thorpe"),
            "stated",
            "SM tables of the energy fits, p_t = 0 rows (p_crit 0.66, 0.65); compared with the "
            "literature value the paper cites, " + REFERENCES["pc_jacobs_thorpe"].citation,
            "fig1c",
            target="p_crit",
        ),
        Claim(
            "collapse_shear_half",
            "shear, f_c = 0.5: P depends on p_r + p_t/2 only (Fig. 1B), i.e. S_t/S_r = 0.5",
            "P = 1/2 contour along p_r + p_t/2 = const",
            0.5,
            0.0,
            "exact",
            "Fig. 1B caption: 'The contour aligns with the theory (orange line)'; main text: "
            "'the probability is a function of p_r + p_t/2 only'",
            "fig1b",
            target="st_sr",
        ),
    ]
    for strain, table in (("compression", PCRIT_COMPRESSION), ("dilation", PCRIT_DILATION)):
        label = f"SM table of the energy fits, rods + cables, {strain} (Fig. 2" + (
            "C)" if strain == "compression" else "D)"
        )
        for p_t, (pc, alpha, alpha_err) in table.items():
            out.append(
                Claim(
                    f"p_crit_{strain}_{p_t}",
                    f"p_crit, rods + cables, {strain}, p_t = {p_t}",
                    f"{pc:.2f}",
                    pc,
                    ROUNDING_2DP,
                    "rounding",
                    f"{label}, p_t = {p_t}: p_crit, 'the value of p_r at which E first becomes "
                    "positive'",
                    "fig2",
                    target="p_crit",
                    same_as="p_crit_compression_0.0" if (strain, p_t) == ("dilation", 0.0) else "",
                )
            )
            out.append(
                Claim(
                    f"alpha_{strain}_{p_t}",
                    f"energy exponent alpha, {strain}, p_t = {p_t}",
                    f"{alpha:.3f} ± {alpha_err:.3f}",
                    alpha,
                    alpha_err,
                    "stated",
                    f"{label}, p_t = {p_t}: alpha of ln E = alpha ln(p_r - p_crit) + beta",
                    "fig2",
                    same_as="alpha_compression_0.0" if (strain, p_t) == ("dilation", 0.0) else "",
                )
            )
    out += [
        Claim(
            "taut_cables_transition",
            "cables under tension at the transition (rods + cables, compression)",
            "about 37 %",
            0.37,
            ROUNDING_2DP,
            "rounding",
            "main text on Fig. 2B: 'about 37 % of the cables are under positive tension'",
            "fig2",
            target="taut",
        ),
        Claim(
            "gamma_peak",
            "nonaffinity Gamma peaks at the transition (compression): peak - p_crit = 0",
            "peak at p_crit",
            0.0,
            0.0,
            "exact",
            "Fig. 2B caption: 'Gamma, reaching peaks at the rigidity transition (dashed line)'",
            "fig2",
            target="p_crit",
        ),
        Claim(
            "fig4a_dilation_rises",
            "Fig. 4A: P rises with f_c under dilation",
            "rises",
            0.0,
            0.0,
            "exact",
            "Fig. 4A caption and main text: 'the probability of rigidity increases ... as we "
            "increase f_c for more dilational strains'",
            "fig4",
            relation="positive",
        ),
        Claim(
            "fig4a_compression_falls",
            "Fig. 4A: P falls with f_c under compression",
            "falls",
            0.0,
            0.0,
            "exact",
            "Fig. 4A caption and main text: '(decreases) ... for more compressional strains'",
            "fig4",
            relation="negative",
        ),
        Claim(
            "fig4c_sum_one",
            "Fig. 4C: (S_c + S_s)/S_r = 1, strain average, every f_c",
            "1 for every f_c",
            1.0,
            0.0,
            "exact",
            "Fig. 4C caption and main text: 'the combined efficacies of a cable and a strut add "
            "up to that of a rod when averaged over all strain, irrespective of f_c'",
            "fig4",
            target="fig4c",
        ),
        Claim(
            "single_node",
            "single node: analytic P_N equals simulation",
            "agree (Fig. 3B)",
            None,
            0.0,
            "computed",
            "Fig. 3B caption: 'The analytical solutions are shown as solid lines with error bars "
            "generated from simulation data'; SM section B (the formula, evaluated by "
            "analysis.single_node)",
            "fig3",
        ),
    ]
    return out


#: SM tables of the energy fits (rods + cables): p_t -> (p_crit, alpha, alpha error)
PCRIT_COMPRESSION = {
    0.0: (0.66, 1.100, 0.015),
    0.1: (0.60, 1.478, 0.070),
    0.2: (0.56, 1.582, 0.085),
    0.3: (0.51, 1.806, 0.130),
}
PCRIT_DILATION = {
    0.0: (0.65, 1.257, 0.029),
    0.1: (0.59, 1.033, 0.032),
    0.2: (0.53, 0.867, 0.019),
    0.3: (0.46, 0.673, 0.025),
}

#: every claim, in the order of the comparison table
CLAIMS: dict[str, Claim] = {c.key: c for c in _claims()}
