"""The P table printed by sweep and info: Wilson intervals over decided samples only."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from tensegrity_rigidity.analysis.estimators import wilson
from tensegrity_rigidity.ensemble.summary import format_table, probability_table


def _rows(**cols):
    base = dict(n=6, delta=0.2, p_t=0.0, f_c=0.5, phi=math.pi, seed=1)
    size = len(next(iter(cols.values())))
    return pd.DataFrame({k: [v] * size for k, v in base.items()} | cols)


def test_grid_table_counts_undecided_apart():
    rows = _rows(
        p_r=[0.5] * 5 + [0.6] * 3,
        rigid=[True, False, False, True, False, True, True, True],
        decided=[True, True, True, True, False, True, True, True],
    )
    table = probability_table(rows)
    first = table.iloc[0]
    assert (first.N, first.undecided, first.rigid) == (4, 1, 2)
    p, lo, hi = wilson(2, 4)
    assert (first.P, first.lo, first.hi) == (p, lo, hi)
    text = format_table(table).splitlines()
    assert text[0].split()[:4] == ["p_r", "N", "undecided", "rigid"]  # only p_r varies
    assert text[1].split()[-3:] == [f"{p:.3f}", f"[{lo:.3f},", f"{hi:.3f}]"]
    p, lo, hi = wilson(3, 3)
    assert text[2].split()[-3:] == ["1.000", f"[{lo:.3f},", "1.000]"] and lo < 0.5
    # no grid point shown: the header and the count of the others, not a crash
    lines = format_table(table, max_rows=0).splitlines()
    assert lines[1:] == ["... 2 more grid points (load_results for all)"]


def test_threshold_table_median_with_never_rigid():
    rows = _rows(
        p_r=[np.nan] * 4,
        threshold_p_r=[0.4, np.nan, 0.6, 0.5],
        decided=[True, True, True, False],
    )
    table = probability_table(rows)
    assert table.iloc[0].N == 3 and table.iloc[0].never_rigid == 1
    assert table.iloc[0].median_p_r == 0.6  # median of 0.4, 0.6, inf
    assert "compression" not in format_table(table)  # a constant phi is left out
    assert format_table(pd.DataFrame()) == "(no rows)"
