"""The near-threshold sample set of issue 13, shared by the benchmarks.

Triangular lattice, delta = 0.2, path "p_r" at fixed p_t; six configurations
(p_t, f_c, strain) and a random strain angle per sample. Sample k of size n and configuration c
draws its geometry, uniforms and angle from ``default_rng([n, c, k])``.
"""

from __future__ import annotations

import numpy as np

from tensegrity_rigidity.ensemble.thresholds import EventPath
from tensegrity_rigidity.model.lattice import DEFAULT_DELTA
from tensegrity_rigidity.model.sampling import lattice_geometry
from tensegrity_rigidity.model.strain import strain_tensor

#: (p_t, f_c, strain) of the six configurations
CONFIGS = [
    (0.3, 1.0, "compression"),
    (0.3, 1.0, "dilation"),
    (0.3, 0.5, "shear"),
    (0.1, 0.0, "compression"),
    (0.6, 0.5, "shear"),
    (0.2, 0.0, "dilation"),
]

#: the rods-only threshold (p_t = 0) of the p_c extrapolation (one strain: a rods-only
#: threshold does not depend on it); not part of the issue-13 set
RODS_ONLY = [(0.0, 0.5, "dilation")]


def sample(n: int, c: int, k: int, configs=CONFIGS):
    """(network, U, V, strain, p_t, f_c) of sample k of configuration c (of ``configs``) at
    size n."""
    rng = np.random.default_rng([n, c, k] if configs is CONFIGS else [n, 100 + c, k])
    p_t, f_c, phi = configs[c]
    net, u, v = lattice_geometry(n, DEFAULT_DELTA, rng)
    theta = float(rng.uniform(0, 2 * np.pi))
    return net, u, v, strain_tensor(phi, theta), p_t, f_c


def interval_events(u, v, p_t: float, f_c: float, th) -> int:
    """Width in events of a threshold's interval [s_low, s_high] on the "p_r" path (0 when
    the threshold is a single event or not finite)."""
    if not (np.isfinite(th.s_low) and np.isfinite(th.s_high)):
        return 0
    positions = EventPath(u, v, "p_r", p_t, f_c).positions
    return int(np.searchsorted(positions, th.s_high)) - int(np.searchsorted(positions, th.s_low))


def samples(n: int, count: int, configs=CONFIGS):
    """``count`` samples cycling through ``configs``: yields (c, k, sample(n, c, k))."""
    for i in range(count):
        c, k = i % len(configs), i // len(configs)
        yield c, k, sample(n, c, k, configs)
