"""The energy of given extensions (model.mechanics)."""

from __future__ import annotations

import numpy as np
from threadpoolctl import threadpool_limits

from tensegrity_rigidity.model.mechanics import energy_from_extensions
from tensegrity_rigidity.model.network import Element


def test_the_energy_of_extensions_does_not_depend_on_the_blas_threads():
    # 20,000 sites: a multithreaded BLAS splits a dot product this long between its threads
    # and adds the parts in another order (with np.dot, 8 of these 20 draws differed in
    # their last digits between one and two threads)
    rng = np.random.default_rng(3)
    m = 20_000
    energies: dict[int, list[float]] = {1: [], 2: []}
    for _ in range(20):
        kinds = rng.choice([Element.ROD, Element.CABLE, Element.STRUT, Element.EMPTY], size=m)
        k = rng.uniform(0.5, 2.0, m)
        e = rng.normal(size=m)
        for threads in (1, 2):
            with threadpool_limits(limits=threads, user_api="blas"):
                energies[threads].append(energy_from_extensions(kinds, k, e))
    assert energies[1] == energies[2]


def test_the_energy_of_extensions_counts_engaged_elements_only():
    kinds = np.array([Element.ROD, Element.CABLE, Element.CABLE, Element.STRUT, Element.STRUT,
                      Element.EMPTY])  # fmt: skip
    k = np.array([1.0, 2.0, 2.0, 3.0, 3.0, 5.0])
    e = np.array([-1.0, 0.5, -0.5, -2.0, 2.0, 1.0])
    # rod 1/2 * 1; stretched cable 1/2 * 2 * 0.25; compressed strut 1/2 * 3 * 4
    assert energy_from_extensions(kinds, k, e) == 0.5 + 0.25 + 6.0
