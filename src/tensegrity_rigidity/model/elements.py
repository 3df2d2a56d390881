"""Random placement of rods, cables and struts with the monotone coupling of docs/model.md.

Each bond site carries two uniforms ``U, V`` in [0, 1), drawn once per sample:

* rod if ``U < p_r``;
* one-sided element if ``p_r <= U < p_r + p_t``: a cable if ``V < f_c``, else a strut;
* empty otherwise.

With the uniforms fixed, raising ``p_r`` or ``p_t`` only adds elements or turns a cable or strut
into a rod, so rigidity is monotone along such paths and every sample has an exact threshold
(:mod:`tensegrity_rigidity.ensemble.thresholds`). Raising ``f_c`` turns struts into cables.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .network import Element, check_real


def check_probabilities(p_r: float, p_t: float, f_c: float) -> tuple[float, float, float]:
    """Validate (p_r, p_t, f_c): each finite in [0, 1] and p_r + p_t <= 1.

    Parameters
    ----------
    p_r, p_t, f_c : float
        Rod probability, one-sided probability, cable fraction.

    Returns
    -------
    (float, float, float)
        The three values as floats.

    Raises
    ------
    InputError
        On a value that is not a finite number in [0, 1], or ``p_r + p_t > 1``.
    """
    out = []
    for name, value in (("p_r", p_r), ("p_t", p_t), ("f_c", f_c)):
        v = check_real(name, value)
        if not 0.0 <= v <= 1.0:
            raise InputError(f"{name} must lie in [0, 1], got {v}")
        out.append(v)
    if out[0] + out[1] > 1.0 + 1e-12:
        raise InputError(
            f"p_r + p_t must not exceed 1, got {out[0]} + {out[1]} = {out[0] + out[1]}"
        )
    return out[0], out[1], out[2]


def site_uniforms(m: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """The per-site uniforms (U, V) of one sample.

    Parameters
    ----------
    m : int
        Number of bond sites.
    rng : numpy.random.Generator
        Source; ``U`` is drawn first, then ``V``.

    Returns
    -------
    u, v : (m,) float
        Uniforms in [0, 1): ``U`` decides rod / one-sided / empty, ``V`` cable or strut.
    """
    u = rng.random(m)
    v = rng.random(m)
    return u, v


def place_elements(u: np.ndarray, v: np.ndarray, p_r: float, p_t: float, f_c: float) -> np.ndarray:
    """Element kinds from site uniforms.

    Parameters
    ----------
    u, v : (m,) float
        Site uniforms in [0, 1).
    p_r, p_t, f_c : float
        Rod probability, one-sided probability (``p_r + p_t <= 1``), cable fraction.

    Returns
    -------
    kinds : (m,) int64
        :class:`~tensegrity_rigidity.model.network.Element` codes.

    Raises
    ------
    InputError
        On probabilities outside [0, 1] or ``p_r + p_t > 1``.
    """
    p_r, p_t, f_c = check_probabilities(p_r, p_t, f_c)
    kinds = np.full(u.shape, Element.EMPTY, dtype=np.int64)
    one_sided = (u >= p_r) & (u < p_r + p_t)
    kinds[u < p_r] = Element.ROD
    kinds[one_sided & (v < f_c)] = Element.CABLE
    kinds[one_sided & (v >= f_c)] = Element.STRUT
    return kinds
