"""reproduce shows one bar over all its studies, with the time left (it showed about 60
sweep bars and no overall progress)."""

from __future__ import annotations

from pathlib import Path

import pytest

from tensegrity_rigidity.paper.budget import Estimate, SweepCost
from tensegrity_rigidity.paper.progress import OverallProgress
from tensegrity_rigidity.paper.reproduce import reproduce


def _estimate() -> Estimate:
    sweeps = (
        SweepCost("a", "cheap", "grid", 8, 100, 100, 10.0, 5.0, False),
        SweepCost("a", "dear", "threshold", 8, 10, 10, 80.0, 40.0, False),
        SweepCost("b", "cheap", "grid", 8, 100, 0, 0.0, 0.0, False),  # shared, stored
    )
    return Estimate("x", 2, ("a", "b"), sweeps, {"a": 6.0, "b": 4.0})


def test_the_bar_counts_estimated_work_not_samples():
    bar = OverallProgress(_estimate(), enabled=False)
    assert bar.total == pytest.approx(100.0)
    bar(Path("out/studies/cheap"), 50)  # 50 samples at 0.1 s
    assert bar.done == pytest.approx(5.0)
    bar(Path("out/studies/dear"), 5)  # 5 samples at 8 s
    assert bar.done == pytest.approx(45.0)
    bar.study_done("a")
    assert bar.done == pytest.approx(51.0)
    bar(Path("out/studies/unexpected"), 10)  # priced at the mean sample: 90 s / 110
    assert bar.done == pytest.approx(51.0 + 10 * 90 / 110)
    bar(Path("out/studies/dear"), 1000)  # an estimate too low never passes 100 %
    assert bar.done == pytest.approx(100.0)
    bar.close()


def test_reproduce_draws_one_bar_with_the_time_left(tmp_path, capsys):
    reproduce(tmp_path / "r", "tiny", workers="serial", progress=True, studies=["fig1b"])
    err = capsys.readouterr().err
    assert "reproduce [1/1] fig1b" in err and "left" in err
    assert "sweep " not in err  # no bar of its own per sweep
    assert "paper.budget" not in err
