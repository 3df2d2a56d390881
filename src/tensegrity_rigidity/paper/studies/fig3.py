"""Fig. 3: a single node, the analytic P_N versus f_c against a direct simulation."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ...analysis import estimators as an
from ...analysis.single_node import simulate_single_node, single_node_probability
from ..claims import Measurement
from .rows import Rows
from .scales import Scale

#: seed of the single-node simulation's trials
SIMULATION_SEED = 31
#: p_r of the curves and the simulated points
P_RS = [0.1, 0.3, 0.5, 0.7]


@dataclass(frozen=True, eq=False)
class Fig3Result:
    """Single node: analytic P_N versus f_c and its simulation.

    Attributes
    ----------
    f_c : (F,) float
        Grid of the analytic curves.
    analytic : dict
        p_r -> (F,) analytic P_N.
    sim : DataFrame
        Simulated points: p_r, f_c, P with its Wilson interval (lo, hi), the analytic value and
        ``z = (P - analytic) / binomial standard error`` (the error from the Wilson interval).
    trials : int
        Trials per simulated point.
    """

    f_c: np.ndarray
    analytic: dict
    sim: pd.DataFrame
    trials: int
    excluded: dict[str, int] = field(default_factory=dict)
    measured: tuple[Measurement, ...] = ()


def sweeps(scale: Scale) -> dict[str, dict]:
    """Fig. 3 runs no sweep: its ``scale.node_trials`` single-node trials run in-process."""
    return {}


def analyse(rows: Rows, scale: Scale) -> Fig3Result:
    """Single node: analytic P_N versus f_c, and simulation with Wilson intervals (``rows`` is
    empty: Fig. 3 has no sweep)."""
    rng = np.random.default_rng(SIMULATION_SEED)
    f_c = np.linspace(0, 1, 41)
    p_rs = P_RS
    analytic = {
        p: np.array([single_node_probability(p, f * (1 - p), (1 - f) * (1 - p)) for f in f_c])
        for p in p_rs
    }
    sim = []
    for p in p_rs:
        for f in np.linspace(0, 1, 9):
            k, n = simulate_single_node(p, f * (1 - p), (1 - f) * (1 - p), scale.node_trials, rng)
            P, lo, hi = an.wilson(k, n)
            sim.append(
                {
                    "p_r": p,
                    "f_c": f,
                    "P": float(P),
                    "lo": float(lo),
                    "hi": float(hi),
                    "analytic": single_node_probability(p, f * (1 - p), (1 - f) * (1 - p)),
                }
            )
    sim = pd.DataFrame(sim)
    se = (sim.hi - sim.lo) / (2 * 1.96)
    sim["z"] = (sim.P - sim.analytic) / se
    result = Fig3Result(f_c=f_c, analytic=analytic, sim=sim, trials=scale.node_trials)
    return dataclasses.replace(result, measured=claims(result))


def claims(result: Fig3Result) -> tuple[Measurement, ...]:
    """The single-node simulation against the analytic P_N at every point."""
    sim = result.sim
    # the test of "simulation = formula" uses the binomial variance under the formula
    var = sim.analytic * (1 - sim.analytic) / result.trials
    return (
        Measurement(
            "single_node",
            sim.P.to_numpy(),
            np.diag(var.to_numpy()),
            f"{result.trials} trials per point",
            points=tuple(
                f"p_r = {a}, f_c = {b:.3f}" for a, b in zip(sim.p_r, sim.f_c, strict=True)
            ),
            reference=sim.analytic.to_numpy(),
            note="simulated against analytic P_N at every point; binomial errors at the "
            "analytic value",
        ),
    )


def study(out, scale: Scale, **kw) -> Fig3Result:
    """Fig. 3 at ``scale`` (nothing is stored in ``out``)."""
    return analyse({}, scale)
