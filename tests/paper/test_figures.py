"""Figures drawn from hand-made study results."""

import math
from types import SimpleNamespace

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from tensegrity_rigidity.paper import style
from tensegrity_rigidity.paper.studies import fig1c, fig2


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
    bars = fig2.median_brackets(ax, s, "tab:blue")
    plt.close(fig)
    assert bars == [(0.55, 10.0, 100.0), (0.6, 4.0, 3.0 * 300.0)]


def test_median_brackets_absent_without_the_columns_or_open_brackets():
    s = _curve([8.0, 40.0, 12.0], [8.0, 40.0, 12.0])
    fig, ax = plt.subplots()
    assert fig2.median_brackets(ax, s, "k") == []
    assert fig2.median_brackets(ax, s.drop(columns=["gamma_median_low"]), "k") == []
    plt.close(fig)


def test_fig2b_with_brackets_is_written(tmp_path):
    curves = _curve([8.0, 10.0, 0.0], [8.0, 100.0, np.inf])
    crit = pd.DataFrame({"phi": [math.pi], "p_t": [0.2], "p_crit": [0.55]})
    curves["N"] = 8
    paths = fig2.fig2b(SimpleNamespace(curves=curves, crit=crit, n=16, samples=8), tmp_path)
    assert all(p.exists() and p.stat().st_size > 0 for p in paths)


def test_figures_share_one_colour_blind_safe_style_and_draw_the_paper_s_values(monkeypatch):
    """Fig. 1C in the figures' style: Okabe-Ito colours, mathtext axis labels, the sample count
    of each point under it, the paper's four values as open stars with the paper's error bars
    beside ours, and a value whose error exceeds it drawn open without its bar."""
    drawn = {}
    monkeypatch.setattr(fig1c, "save", lambda fig, figdir, fid: drawn.setdefault(fid, fig))
    strains = ["dilation", "shear", "compression", "average"]
    fits = pd.DataFrame(
        {
            "f_c": [f for _ in strains for f in (0.0, 0.5, 1.0)],
            "strain": [s for s in strains for _ in range(3)],
            "lam": 0.45,
            "lam_err": [0.01] * 11 + [2.0],  # the average at f_c = 1: not resolved
            "n_samples": [24, 12, 24] * 4,
        }
    )
    with plt.rc_context(style.STYLE):
        fig1c.figures(SimpleNamespace(fits=fits, n=12, samples=24), None)
    ax = drawn["1C"].axes[0]
    palette = {c.lower() for c in style.OKABE_ITO}
    lines = [line for line in ax.lines if np.asarray(line.get_xdata()).size]
    lines = [line for line in lines if line.get_color() != "grey"]  # the reference line at 0.5
    assert lines and all(str(line.get_color()).lower() in palette for line in lines)
    stars = [line for line in lines if line.get_marker() == "*"]
    assert sorted(float(s.get_ydata()[0]) for s in stars) == [0.359, 0.372, 0.5, 0.67]
    bars = [c for c in ax.collections if len(c.get_segments()) == 1]
    assert {round(float(np.ptp(c.get_segments()[0][:, 1])) / 2, 3) for c in bars} >= {0.013, 0.015}
    opened = [line for line in lines if line.get_markerfacecolor() == "white"]
    assert [float(line.get_ydata()[0]) for line in opened] == [0.45]
    assert "$f_c$" in ax.get_xlabel() and "$S_t / S_r$" in ax.get_ylabel()
    assert "$n$ = 12" in ax.get_title()
    assert sorted(t.get_text() for t in ax.texts) == ["12"] * 1 + ["24"] * 2
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "paper" in legend and any("not resolved" in t for t in legend)
    plt.close(drawn["1C"])


def test_a_figure_is_written_whole_or_not_at_all(tmp_path, monkeypatch):
    """A figure whose writing fails half way (a full disk, an interrupt) leaves neither a torn
    file under its name nor a temporary file."""
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])

    def torn(path, **kwargs):
        with open(path, "wb") as fh:
            fh.write(b"\x89PNG half")
        raise KeyboardInterrupt

    monkeypatch.setattr(fig, "savefig", torn)
    try:
        style.save(fig, tmp_path, "X")
    except KeyboardInterrupt:
        pass
    plt.close(fig)
    assert list(tmp_path.iterdir()) == []


def test_a_figure_drawn_twice_is_the_same_bytes(tmp_path):
    """No date and no random SVG ids: a report re-rendered from the same rows leaves its
    figures unchanged in git."""

    def draw(where):
        fig, ax = plt.subplots()
        ax.plot([0, 1], [1, 0], label="a")
        ax.legend()
        return style.save(fig, where, "x")

    first = [p.read_bytes() for p in draw(tmp_path / "a")]
    assert first == [p.read_bytes() for p in draw(tmp_path / "b")]
