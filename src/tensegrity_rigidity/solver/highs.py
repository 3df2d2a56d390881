"""The one place the solver calls HiGHS: every linear program names its algorithm.

HiGHS's own choices depend on what is installed (``solver = "ipm"`` runs HiPO instead of IPX when
the plugin ``highspy-extras`` is importable), so every call here names one (``"simplex"`` with a
``simplex_strategy``, ``"ipx"``, ``"hipo"``), runs on one thread, and logs nowhere.
"""

from __future__ import annotations

import numpy as np

#: HiGHS's algorithms a call may name (``"choose"`` and ``"ipm"`` would leave the choice to it).
ALGORITHMS = ("simplex", "ipx", "hipo", "pdlp")


def run_lp(A, cost, col_lower, col_upper, row_lower, row_upper, basis=None, **options):
    """HiGHS on ``min cost . x`` s.t. ``row_lower <= A x <= row_upper``, ``col_lower <= x <=
    col_upper``, from an optional starting ``basis``; the solved ``highspy.Highs``.

    ``A`` is a (rows, columns) SciPy sparse matrix; ``options`` are HiGHS options and must name
    the algorithm (``solver``). HiGHS logs into a disabled sink rather than with its output
    switched off: with ``output_flag = False`` its dual simplex stops at once with an error on
    some verdict LPs that it solves when logging.
    """
    import highspy

    if options.get("solver") not in ALGORITHMS:
        raise ValueError(f"a HiGHS call must name its algorithm, one of {ALGORITHMS}")
    A = A.tocsc()
    lp = highspy.HighsLp()
    lp.num_col_, lp.num_row_ = A.shape[1], A.shape[0]
    lp.col_cost_ = np.asarray(cost, dtype=float)
    lp.col_lower_, lp.col_upper_ = col_lower, col_upper
    lp.row_lower_, lp.row_upper_ = row_lower, row_upper
    lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
    lp.a_matrix_.start_, lp.a_matrix_.index_, lp.a_matrix_.value_ = A.indptr, A.indices, A.data
    h = highspy.Highs()
    quiet = {"output_flag": True, "log_to_console": False, "log_file": "", "threads": 1}
    for key, value in (quiet | options).items():
        h.setOptionValue(key, value)
    h.passModel(lp)
    if basis is not None:
        h.setBasis(basis)
    h.run()
    return h
