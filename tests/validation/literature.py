"""Literature values the reproduction is checked against, each with where it comes from.

Typed in here independently of the package (which holds the values it needs in
``tensegrity_rigidity.paper.claims.REFERENCES``), so that a typo on either side fails a test.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class LiteratureValue:
    """A published value: what it is, its uncertainty, the citation and how it was obtained."""

    quantity: str
    value: float
    error: float | None
    citation: str
    method: str


LITERATURE = {
    "pc_jacobs_thorpe": LiteratureValue(
        "rigidity threshold p_c of the generic bond-diluted triangular lattice (central forces)",
        0.6602,
        0.0003,
        "D. J. Jacobs and M. F. Thorpe, Phys. Rev. Lett. 75, 4051 (1995)",
        "pebble game on generic (disordered) triangular lattices; the paper cites it as "
        "jacobs1995generic",
    ),
    "pc_javerzat_notarmuzi": LiteratureValue(
        "rigidity threshold p_c of the generic bond-diluted triangular lattice",
        0.6602741,
        0.0000004,
        "Javerzat & Notarmuzi (2025), arXiv:2507.00741 (abstract of its current version read; "
        "version 1's abstract states no value)",
        "pebble game in Newman-Ziff order with wrapping detection, up to 5e8 nodes",
    ),
    "pc_dynamic_pebble": LiteratureValue(
        "rigidity threshold p_c of the generic bond-diluted triangular lattice",
        0.6602778,
        0.0000010,
        "High-precision Dynamic Monte Carlo Study of Rigidity Percolation (2026), "
        "arXiv:2601.21399 (abstract read)",
        "a dynamic pebble game adding bonds one at a time, event-based ensemble",
    ),
    "nu_dynamic_pebble": LiteratureValue(
        "correlation-length exponent nu of generic rigidity percolation in 2D",
        1.1765,
        0.0042,
        "High-precision Dynamic Monte Carlo Study of Rigidity Percolation (2026), "
        "arXiv:2601.21399 (abstract read)",
        "1/nu = 0.850(3) inverted: 1/0.850 = 1.1765, error 0.003/0.850^2 = 0.0042",
    ),
    "df_dynamic_pebble": LiteratureValue(
        "fractal dimension of the rigid clusters at p_c",
        1.850,
        0.002,
        "High-precision Dynamic Monte Carlo Study of Rigidity Percolation (2026), "
        "arXiv:2601.21399 (abstract read)",
        "the same runs' cluster masses at the threshold",
    ),
    "nu_javerzat_notarmuzi": LiteratureValue(
        "correlation-length exponent nu of generic rigidity percolation in 2D",
        1.1694,
        0.0008,
        "Javerzat & Notarmuzi (2025), arXiv:2507.00741 (abstract of its current version read)",
        "finite-size scaling of the same runs",
    ),
    "df_rigid_javerzat_notarmuzi": LiteratureValue(
        "fractal dimension of the rigid cluster at p_c",
        1.8423,
        0.0007,
        "Javerzat & Notarmuzi (2025), arXiv:2507.00741 (abstract of its current version read)",
        "mass of the rigid cluster against size at the threshold",
    ),
    "df_rigid_jacobs_thorpe": LiteratureValue(
        "fractal dimension of the spanning rigid cluster at p_c",
        1.86,
        None,
        "D. J. Jacobs and M. F. Thorpe, Phys. Rev. Lett. 75, 4051 (1995)",
        "about 1.86 as quoted in the project's brief; the abstract gives p_c, nu and beta only",
    ),
    "df_stressed_jacobs_thorpe": LiteratureValue(
        "fractal dimension of the stressed backbone at p_c",
        1.78,
        None,
        "D. J. Jacobs and M. F. Thorpe, Phys. Rev. Lett. 75, 4051 (1995)",
        "about 1.78 as quoted in the project's brief; the abstract gives p_c, nu and beta only",
    ),
    "nu_jacobs_thorpe": LiteratureValue(
        "correlation-length exponent nu of generic rigidity percolation in 2D",
        1.21,
        0.06,
        "D. J. Jacobs and M. F. Thorpe, Phys. Rev. Lett. 75, 4051 (1995)",
        "finite-size scaling of the pebble-game results",
    ),
    "nu_moukarzel_duxbury": LiteratureValue(
        "correlation-length exponent nu of generic rigidity percolation in 2D",
        1.16,
        0.03,
        "C. Moukarzel and P. M. Duxbury, Phys. Rev. E 59, 2614 (1999), arXiv:cond-mat/9702249",
        "generic rigidity algorithm on lattices up to L = 4096",
    ),
    "pc_fcc_chubynsky_thorpe": LiteratureValue(
        "rigidity threshold p_c of the bond-diluted FCC lattice (central forces)",
        0.495,
        None,
        "M. V. Chubynsky and M. F. Thorpe, Phys. Rev. E 76, 041135 (2007), arXiv:cond-mat/0702635",
        "a 3D pebble game, argued to be essentially exact for bond-diluted FCC; a first-order "
        "transition. The value as quoted by a secondary source (not read in the paper's text)",
    ),
    "pc_fcc_maxwell": LiteratureValue(
        "mean-field (Maxwell counting) rigidity threshold of the FCC lattice",
        0.5,
        None,
        "J. C. Maxwell, Phil. Mag. 27, 294 (1864); constraint counting z = 2d = 6 of z_max = 12",
        "a node has 3 degrees of freedom and each bond, shared by two nodes, removes one: "
        "rigid when 12 p / 2 >= 3",
    ),
    "phi_j_ohern": LiteratureValue(
        "jamming point of 50:50 bidisperse disks (diameter ratio 1.4, harmonic repulsion) in 2D",
        0.842,
        None,
        "C. S. O'Hern, L. E. Silbert, A. J. Liu and S. R. Nagel, Phys. Rev. E 68, 011306 (2003)",
        "energy minimisation from random positions, the large-N limit of the packing fraction "
        "at which half the packings jam; the value as commonly quoted (not read in the paper's "
        "text): approximate, no error",
    ),
    "pc_maxwell": LiteratureValue(
        "mean-field (Maxwell counting) rigidity threshold of the triangular lattice",
        2 / 3,
        None,
        "J. C. Maxwell, Phil. Mag. 27, 294 (1864); constraint counting z = 2d = 4 of z_max = 6",
        "a node has 2 degrees of freedom and each bond, shared by two nodes, removes one: "
        "rigid when 6 p / 2 >= 2",
    ),
}
