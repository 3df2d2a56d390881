"""Random small instances shared by the tests."""

from __future__ import annotations

import numpy as np

from benchmarks.near_threshold_set import CONFIGS
from tensegrity_rigidity import Instance, lattice_instance, random_periodic_network, strain_tensor
from tensegrity_rigidity.ensemble.thresholds import EventPath
from tensegrity_rigidity.model.elements import place_elements, site_uniforms
from tensegrity_rigidity.model.lattice import DEFAULT_DELTA
from tensegrity_rigidity.model.sampling import lattice_geometry

#: (p_t, f_c, strain) of the near-threshold set of issue 13, the benchmarks' own table (its
#: sample k of configuration c at size n has the seed [n, c, k])
NEAR_THRESHOLD = CONFIGS


def near_threshold_sample(n: int, seed, phi: str):
    """(network, u, v, strain) drawn as benchmarks/near_threshold_set.py draws a sample: the
    disordered lattice and site uniforms, then the strain angle, from ``default_rng(seed)``."""
    rng = np.random.default_rng(seed)
    net, u, v = lattice_geometry(n, DEFAULT_DELTA, rng)
    return net, u, v, strain_tensor(phi, float(rng.uniform(0, 2 * np.pi)))


def near_threshold_instance(n: int, seed, phi: str, p_t: float, f_c: float, event: int):
    """Configuration ``event`` of that sample on the "p_r" path at (p_t, f_c)."""
    net, u, v, eps = near_threshold_sample(n, seed, phi)
    return Instance(net.with_kinds(EventPath(u, v, "p_r", p_t, f_c).kinds(event)), eps)


def random_instance(rng: np.random.Generator, kind: str | None = None) -> Instance:
    """A random small instance: a disordered triangular lattice or a random periodic network in
    a skewed box, random elements, strain of random type, orientation and magnitude (1e-6..1e3).
    """
    kind = kind or ("lattice" if rng.random() < 0.5 else "random")
    p_r = rng.uniform(0.1, 0.95)
    p_t = rng.uniform(0.0, 1.0 - p_r)
    f_c = float(rng.choice([0.0, 0.5, 1.0, rng.random()]))
    phi, theta = rng.uniform(0, np.pi), rng.uniform(0, 2 * np.pi)
    gamma = 10 ** rng.uniform(-6, 3)
    if kind == "lattice":
        n = int(rng.integers(2, 7))
        return lattice_instance(
            n,
            p_r,
            p_t,
            f_c,
            phi=phi,
            theta=theta,
            gamma=gamma,
            delta=rng.uniform(0.05, 0.3),
            seed=rng,
        )
    n_nodes = int(rng.integers(2, 16))
    net = random_periodic_network(n_nodes, int(rng.integers(n_nodes, 4 * n_nodes)), rng)
    u, v = site_uniforms(net.n_sites, rng)
    return Instance(
        net.with_kinds(place_elements(u, v, p_r, p_t, f_c)), strain_tensor(phi, theta, gamma)
    )
