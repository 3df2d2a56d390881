"""Every study a reproduction can run, by name.

The paper's figures (:mod:`~tensegrity_rigidity.paper.studies`), the paper's method beside ours
(:mod:`~tensegrity_rigidity.paper.method`), finite size and node disorder
(:mod:`~tensegrity_rigidity.paper.finite_size`). A :class:`~tensegrity_rigidity.paper.studies.Scale`
names the studies it runs.
"""

from __future__ import annotations

from .finite_size import study_delta, study_fss
from .method import study_method
from .studies import STUDIES as FIGURE_STUDIES

STUDIES = {**FIGURE_STUDIES, "method": study_method, "fss": study_fss, "delta": study_delta}
