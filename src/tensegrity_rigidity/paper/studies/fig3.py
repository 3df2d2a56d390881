"""Fig. 3: a single node, the analytic P_N versus f_c against a direct simulation."""

from __future__ import annotations

from dataclasses import dataclass

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ...analysis import estimators as an
from ...analysis.single_node import (
    class_weights,
    qbar_table,
    simulate_single_node,
    single_node_probability,
)
from ..claims import Measurement
from ..study import Result, Scale, Study
from ..style import COLUMN, WORDS, save
from ..template import load
from .rows import Rows

NAME = "fig3"
T = load(NAME)
#: seed of the simulation's trials, and p_r of the curves and the simulated points
SIMULATION_SEED = 31
P_RS = [0.1, 0.3, 0.5, 0.7]


@dataclass(frozen=True, kw_only=True)
class Params:
    trials: int = 0  # single-node trials per point


PARAMS = {"tiny": Params(trials=300), "quick": Params(trials=4000), "paper": Params(trials=10000)}


@dataclass(frozen=True, eq=False)
class Fig3Result(Result):
    """Single node: ``analytic`` p_r -> (F,) P_N on the grid ``f_c``; ``sim``: the simulated
    points (p_r, f_c, P with its Wilson interval lo, hi, the analytic value and z), each of
    ``trials`` trials."""

    f_c: np.ndarray
    analytic: dict
    sim: pd.DataFrame
    trials: int


def _p(p: float, f: float) -> tuple[float, float, float]:
    return p, f * (1 - p), (1 - f) * (1 - p)


def analyse(rows: Rows, scale: Scale) -> Fig3Result:
    """The analytic P_N and its simulation (no sweep: the trials run in-process)."""
    rng, trials = np.random.default_rng(SIMULATION_SEED), scale[NAME].trials
    f_c = np.linspace(0, 1, 41)
    analytic = {p: np.array([single_node_probability(*_p(p, f)) for f in f_c]) for p in P_RS}
    sim = []
    for p in P_RS:
        for f in np.linspace(0, 1, 9):
            k, n = simulate_single_node(*_p(p, f), trials, rng)
            P, lo, hi = an.wilson(k, n)
            sim.append({"p_r": p, "f_c": f, "P": float(P), "lo": float(lo), "hi": float(hi),
                        "analytic": single_node_probability(*_p(p, f))})  # fmt: skip
    sim = pd.DataFrame(sim)
    # the binomial standard error under the formula: the claim's comparison uses the same
    sim["z"] = (sim.P - sim.analytic) / np.sqrt(sim.analytic * (1 - sim.analytic) / trials)
    return Fig3Result(f_c=f_c, analytic=analytic, sim=sim, trials=trials)


def claims(r: Fig3Result) -> tuple[Measurement, ...]:
    """The simulation against the analytic P_N at every point; the variance is the binomial
    one under the formula."""
    var = r.sim.analytic * (1 - r.sim.analytic) / r.trials
    points = tuple(f"p_r = {a}, f_c = {b:.3f}" for a, b in zip(r.sim.p_r, r.sim.f_c, strict=True))
    return (Measurement(
        "single_node", r.sim.P.to_numpy(), np.diag(var.to_numpy()),
        T.label("system", trials=r.trials), points=points,
        reference=r.sim.analytic.to_numpy(), note=T.label("note"),
    ),)  # fmt: skip


def numbers(r: Fig3Result) -> dict:
    return {"trials": r.trials, "largest_z": np.abs(r.sim.z).max(), "points": len(r.sim)}


def figures(r: Fig3Result, figdir) -> dict:
    fig, ax = plt.subplots(figsize=(COLUMN, 2.6))
    for p_r, curve in r.analytic.items():
        line = ax.plot(r.f_c, curve, label=T.label("p_r", p_r=p_r))
        s = r.sim[np.isclose(r.sim.p_r, p_r)]
        err = [np.clip(s.P - s.lo, 0, None), np.clip(s.hi - s.P, 0, None)]
        ax.errorbar(s.f_c, s.P, yerr=err, fmt="o", ms=3, color=line[0].get_color())
    ax.set(xlabel=WORDS.label("f_c"), ylabel=T.label("ylabel"))
    ax.set_title(T.label("title", trials=r.trials))
    ax.legend()
    return {"3B": save(fig, figdir, "3B")}


def tables(r: Fig3Result) -> dict:
    return {"single_node_qbar": pd.DataFrame(qbar_table()), "single_node_simulation": r.sim,
            "single_node_class_weights": pd.DataFrame([class_weights()])}  # fmt: skip


def cost(scale: Scale, costs) -> float:
    """The trials: 36 points of ``trials`` each."""
    trials = costs.analysis(NAME) * scale.bootstrap / 100
    return trials + 36 * scale[NAME].trials * costs.seconds("node_trial")


STUDY = Study(
    name=NAME, params=PARAMS, default=Params(), sweeps=lambda scale: {}, analyse=analyse,
    claims=claims, cost=cost, numbers=numbers, figures=figures, tables=tables,
)  # fmt: skip
