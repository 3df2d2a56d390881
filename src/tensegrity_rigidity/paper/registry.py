"""Every study a reproduction can run, by name, and the sweeps each runs at a scale.

The paper's figures, the paper's method beside ours, finite size and node disorder, and the 3D
study beyond the paper: one module each in :mod:`~tensegrity_rigidity.paper.studies`. A
:class:`~tensegrity_rigidity.paper.studies.Scale` names the studies it runs. :data:`SWEEPS`
gives, per study, the function that returns its sweep specs at a scale (sweep name -> spec):
the studies run exactly these, and :mod:`~tensegrity_rigidity.paper.budget` counts them.
"""

from __future__ import annotations

from .studies import MODULES as FIGURE_MODULES
from .studies import delta, fss, method, three_d

#: study name -> its module (``sweeps``, ``analyse``, ``claims``, ``study``)
MODULES = {**FIGURE_MODULES, "method": method, "fss": fss, "delta": delta, "three_d": three_d}
#: study name -> ``study(out, scale, **kw)``: run its sweeps and analyse them
STUDIES = {name: module.study for name, module in MODULES.items()}
#: study name -> the sweeps it runs at a scale (name -> spec)
SWEEPS = {name: module.sweeps for name, module in MODULES.items()}
