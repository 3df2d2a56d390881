"""Every study a reproduction can run, in the order it runs them, and the scales.

Each study is one module of :mod:`~tensegrity_rigidity.paper.studies` ending with a
:class:`~tensegrity_rigidity.paper.study.Study`; this is the only place that lists them.
:data:`SCALES` joins the scale-level settings of ``data/scales.toml`` with each study's
parameters at that scale (its ``params``): a scale runs the studies that have some.
"""

from __future__ import annotations

from pathlib import Path

from .run_times import SCALES_FILE, read_scales
from .studies import (
    delta,
    efficacy_limit,
    fig1b,
    fig1c,
    fig2,
    fig3,
    fig4,
    fss,
    jamming_onset,
    method,
    three_d,
)
from .study import Scale, Study

#: every study, in the order a reproduction runs them and the report shows them
REGISTRY: tuple[Study, ...] = tuple(
    m.STUDY
    for m in (
        fig1b,
        fig1c,
        fig2,
        fig3,
        fig4,
        method,
        fss,
        delta,
        three_d,
        efficacy_limit,
        jamming_onset,
    )
)
#: study name -> the study (called as ``study(out, scale, **kw)``)
STUDIES = {s.name: s for s in REGISTRY}
#: study name -> the sweeps it runs at a scale (name -> spec)
SWEEPS = {s.name: s.sweeps for s in REGISTRY}


def _scales(path: Path) -> dict[str, Scale]:
    """The scales of the data file, each with every study's parameters (its default where the
    scale does not run it); a study naming a scale the file lacks is refused."""
    settings = read_scales(path)
    for s in REGISTRY:
        unknown = set(s.params) - set(settings)
        if unknown:
            raise ValueError(f"study {s.name} has parameters for unknown scales {sorted(unknown)}")
    return {
        name: Scale(
            name=name,
            params={s.name: s.params.get(name, s.default) for s in REGISTRY},
            studies=tuple(s.name for s in REGISTRY if name in s.params),
            **fields,
        )  # fmt: skip
        for name, fields in settings.items()
    }


#: scale name -> :class:`~tensegrity_rigidity.paper.study.Scale`
SCALES = _scales(SCALES_FILE)
