"""The samples drawn in Figs. 1A and 2A: rebuilt from sweep samples and solved again."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ...ensemble.runner import sample_geometry, sample_strain
from ...ensemble.spec import parse_spec
from ...model.elements import place_elements
from ...model.lattice import DEFAULT_DELTA
from ...model.network import Instance
from ...solver.core import SolveResult, solve
from .rows import Rows


@dataclass(frozen=True, eq=False)
class DisplacementField:
    """Samples drawn in Figs. 1A and 2A, rebuilt from sweep samples and solved.

    Attributes
    ----------
    instance, result : Instance, SolveResult
        A rods + cables sample under compression just above its own threshold (Fig. 2A), or
        None when no sample of the field sweep qualified.
    p_r, p_t : float
        Where that sample was solved.
    mixed_instance, mixed_result : Instance, SolveResult
        A rigid sample of rods, cables and struts under shear (Fig. 1A), or None.
    """

    instance: Instance | None
    result: SolveResult | None
    p_r: float
    p_t: float
    mixed_instance: Instance | None
    mixed_result: SolveResult | None


#: samples of the sweeps that supply the drawn samples of Figs. 1A and 2A
FIELD_SAMPLES = 8
#: Fig. 2A's sample: rods + cables under compression at p_t = 0.2, solved at its own threshold
#: plus this step in p_r (rigid there by monotonicity)
FIELD_P_T, FIELD_STEP = 0.2, 0.02


def displacement_field(rows: Rows, specs: dict[str, dict]) -> tuple[DisplacementField, int, int]:
    """The samples drawn in Figs. 2A and 1A, taken from small sweeps and solved again.

    Fig. 2A: the first sample of a threshold sweep (rods + cables, compression, p_t = 0.2) whose
    threshold s* is positive and leaves room for s* + 0.02 <= 1 - p_t; it is rigid at
    p_r = s* + 0.02. Fig. 1A: the first rigid sample of a grid sweep at (p_r, p_t, f_c) =
    (0.55, 0.4, 0.5) under shear. Each is rebuilt with the sweep's own sample geometry and solved
    with the minimum-norm displacements.

    Parameters
    ----------
    rows : Rows
        The rows of the sweeps ``fig2_field`` and ``fig1a_field``.
    specs : dict
        Their specs (Fig. 2's ``sweeps(scale)``), from which the samples are rebuilt.

    Returns
    -------
    field, excluded_2a, excluded_1a : DisplacementField, int, int
    """
    spec_2a = specs["fig2_field"]
    th, ex_2a = rows["fig2_field"]
    inst = res = None
    p_r = float("nan")
    ok = th[(th.threshold_p_r > 0) & (th.threshold_p_r + FIELD_STEP <= 1 - FIELD_P_T)]
    if len(ok):
        row = ok.iloc[0]
        p_r = float(row.threshold_p_r) + FIELD_STEP
        inst = _rebuild(spec_2a, row, p_r)
        res = solve(inst)
    spec_1a = specs["fig1a_field"]
    grid, ex_1a = rows["fig1a_field"]
    inst2 = res2 = None
    rigid = grid[grid.rigid]
    if len(rigid):
        row = rigid.iloc[0]
        inst2 = _rebuild(spec_1a, row, float(row.p_r))
        res2 = solve(inst2)
    field_ = DisplacementField(inst, res, p_r, FIELD_P_T, inst2, res2)
    return field_, ex_2a, ex_1a


def _rebuild(spec: dict, row: pd.Series, p_r: float) -> Instance:
    """The instance of one sweep row's sample at ``p_r`` (its geometry, uniforms and strain)."""
    sp = parse_spec(dict(delta=DEFAULT_DELTA) | spec)
    point = next(
        q for q in sp.points() if np.isclose(q.p_t, row.p_t) and np.isclose(q.phi, row.phi)
    )
    k = int(row["sample"])
    net, u, v, theta = sample_geometry(sp, point, k)
    kinds = place_elements(u, v, p_r, point.p_t, point.f_c)
    return Instance(net.with_kinds(kinds), sample_strain(sp, point, k, theta, net.dim))
