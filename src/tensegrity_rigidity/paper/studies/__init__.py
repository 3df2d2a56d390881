"""The paper's studies, one module per figure, and the scales they run at.

Each figure module (:mod:`.fig1b`, :mod:`.fig1c`, :mod:`.fig2`, :mod:`.fig3`, :mod:`.fig4`)
offers the same three functions:

* ``sweeps(scale)``: sweep name -> spec (run by
  :func:`~tensegrity_rigidity.ensemble.sweep.run_sweep` into ``DIR/studies/<name>``, so an
  interrupted reproduction resumes; :mod:`~tensegrity_rigidity.paper.budget` counts them);
* ``analyse(rows, scale) -> Result``: a frozen result from the rows of those sweeps
  (:func:`.rows.load_sweeps`), holding the numbers the figures and the comparison need and the
  samples it excluded (``excluded``: sweep name -> count), so nothing is shared through module
  state;
* ``claims(result)``: the :class:`~tensegrity_rigidity.paper.claims.Measurement` of each claim
  it tests (also in ``result.measured``);

and ``study(out, scale, **kw)``, the three in a row. Sizes, sample counts and the bootstrap
generators come from a :class:`.scales.Scale`; shared reading of the rows (undecided samples,
threshold intervals) is in :mod:`.rows`.
"""

from __future__ import annotations

from . import fig1b, fig1c, fig2, fig3, fig4
from .energy import TAUT_PT, energy_exponent, taut_at_transition, taut_with_error
from .field import FIELD_P_T, FIELD_SAMPLES, FIELD_STEP, DisplacementField
from .fig1b import FIG1B_PT, Fig1bResult
from .fig1c import FIG1C_FC, FIG1C_FC_CURVE, FIG1C_PHI, FIG1C_PT, Fig1cResult
from .fig2 import Fig2Result
from .fig3 import Fig3Result
from .fig4 import FIG4_CENTRE, FIG4_FC, FIG4_PHI, Fig4Result
from .nonaffinity import (
    gamma_median_brackets,
    mask_min_norm,
    mask_uncertified_tensions,
    tail_statistics,
    worst_tail,
)
from .rows import (
    ENERGY_BRACKETED,
    FC5,
    INTERVAL,
    PHI5,
    PT4,
    STORED,
    STRAIN_NAMES,
    Rows,
    energy_bracketed,
    interval_straddles,
    keep_decided,
    load_sweeps,
    p_r_grid,
    per_sample,
    strain_name,
    sweep_rows,
    threshold_matrix,
)
from .scales import BOOTSTRAP_STREAMS, ENERGY_SAMPLES, FIGURES, FSS_PC, SCALES, Scale, stream

#: figure id -> its module
MODULES = {"fig1b": fig1b, "fig1c": fig1c, "fig2": fig2, "fig3": fig3, "fig4": fig4}
#: study name -> the sweeps it runs at a scale (name -> spec)
SWEEPS = {name: module.sweeps for name, module in MODULES.items()}
#: study name -> ``study(out, scale, **kw)``: run its sweeps and analyse them
STUDIES = {name: module.study for name, module in MODULES.items()}

__all__ = [
    "BOOTSTRAP_STREAMS",
    "DisplacementField",
    "ENERGY_BRACKETED",
    "ENERGY_SAMPLES",
    "FC5",
    "FIELD_P_T",
    "FIELD_SAMPLES",
    "FIELD_STEP",
    "FIG1B_PT",
    "FIG1C_FC",
    "FIG1C_FC_CURVE",
    "FIG1C_PHI",
    "FIG1C_PT",
    "FIG4_CENTRE",
    "FIG4_FC",
    "FIG4_PHI",
    "FIGURES",
    "FSS_PC",
    "Fig1bResult",
    "Fig1cResult",
    "Fig2Result",
    "Fig3Result",
    "Fig4Result",
    "INTERVAL",
    "MODULES",
    "PHI5",
    "PT4",
    "Rows",
    "SCALES",
    "STORED",
    "STRAIN_NAMES",
    "STUDIES",
    "SWEEPS",
    "Scale",
    "TAUT_PT",
    "energy_bracketed",
    "energy_exponent",
    "gamma_median_brackets",
    "interval_straddles",
    "keep_decided",
    "load_sweeps",
    "mask_min_norm",
    "mask_uncertified_tensions",
    "p_r_grid",
    "per_sample",
    "strain_name",
    "stream",
    "sweep_rows",
    "tail_statistics",
    "taut_at_transition",
    "taut_with_error",
    "threshold_matrix",
    "worst_tail",
]
