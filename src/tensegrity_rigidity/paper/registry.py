"""Every study a reproduction can run, by name, and the sweeps each runs at a scale.

The paper's figures (:mod:`~tensegrity_rigidity.paper.studies`), the paper's method beside ours
(:mod:`~tensegrity_rigidity.paper.method`), finite size and node disorder
(:mod:`~tensegrity_rigidity.paper.finite_size`), the 3D study beyond the paper
(:mod:`~tensegrity_rigidity.paper.studies.three_d`). A
:class:`~tensegrity_rigidity.paper.studies.Scale` names the studies it runs. :data:`SWEEPS`
gives, per study, the function that returns its sweep specs at a scale (sweep name -> spec):
the studies run exactly these, and :mod:`~tensegrity_rigidity.paper.budget` counts them.
"""

from __future__ import annotations

from .finite_size import delta_sweeps, fss_sweeps, study_delta, study_fss
from .method import method_sweeps, study_method
from .studies import STUDIES as FIGURE_STUDIES
from .studies import SWEEPS as FIGURE_SWEEPS
from .studies import three_d

STUDIES = {**FIGURE_STUDIES, "method": study_method, "fss": study_fss, "delta": study_delta}
SWEEPS = {**FIGURE_SWEEPS, "method": method_sweeps, "fss": fss_sweeps, "delta": delta_sweeps}
# beyond the paper: the disordered FCC lattice in 3D
STUDIES["three_d"] = three_d.study
SWEEPS["three_d"] = three_d.sweeps
