"""Figures drawn from hand-made study results."""

import math
from types import SimpleNamespace

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from tensegrity_rigidity.paper import figures


def _curve(low, high):
    return pd.DataFrame(
        {
            "phi": math.pi,
            "p_t": 0.2,
            "p_r": [0.5, 0.55, 0.6],
            "gamma": [20.0, 300.0, 50.0],
            "gamma_median": [8.0, 40.0, 12.0],
            "gamma_q25": [4.0, 15.0, 6.0],
            "gamma_q75": [12.0, 90.0, 30.0],
            "gamma_median_low": low,
            "gamma_median_high": high,
        }
    )


def test_median_brackets_drawn_where_samples_are_known_only_from_below():
    """A closed bracket (low = high) draws nothing; a finite one is drawn as it is; one open
    above ends just above the curves, and one without a bound starts at the lowest value."""
    s = _curve([8.0, 10.0, 0.0], [8.0, 100.0, np.inf])
    fig, ax = plt.subplots()
    ax.set_yscale("log")
    bars = figures.median_brackets(ax, s, "tab:blue")
    plt.close(fig)
    assert bars == [(0.55, 10.0, 100.0), (0.6, 4.0, 3.0 * 300.0)]


def test_median_brackets_absent_without_the_columns_or_open_brackets():
    s = _curve([8.0, 40.0, 12.0], [8.0, 40.0, 12.0])
    fig, ax = plt.subplots()
    assert figures.median_brackets(ax, s, "k") == []
    assert figures.median_brackets(ax, s.drop(columns=["gamma_median_low"]), "k") == []
    plt.close(fig)


def test_fig2b_with_brackets_is_written(tmp_path):
    curves = _curve([8.0, 10.0, 0.0], [8.0, 100.0, np.inf])
    crit = pd.DataFrame({"phi": [math.pi], "p_t": [0.2], "p_crit": [0.55]})
    paths = figures.fig2b(SimpleNamespace(curves=curves, crit=crit, n=16), tmp_path)
    assert all(p.exists() and p.stat().st_size > 0 for p in paths)
