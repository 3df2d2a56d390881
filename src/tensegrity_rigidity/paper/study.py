"""The Study protocol: one module per study, its results on one base, the scales they run at.

A study is a vertical slice of the reproduction. Its module (``studies/<name>.py``) defines its
parameters at each scale, the sweeps it runs, how it analyses their rows, the claims it
measures, the numbers its report section quotes, its figures, its tables and its cost; its
template (``templates/<name>.md``) holds its words. The module ends with one :class:`Study`,
which :mod:`~tensegrity_rigidity.paper.registry` lists; figures, report sections, tables, the
budget and the comparison are loops over the registry. ``docs/guide/adding-a-study.md`` says
how to add one.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from .claims import Measurement
from .studies.rows import Rows, load_sweeps
from .template import Template, load

#: the bootstrap stream of each estimator (:meth:`Scale.rng`): the seeds each estimator has
#: always drawn from (a few estimators of different quantities share a seed)
BOOTSTRAP_STREAMS = {
    "collapse": 0, "critical_point": 1, "peaks": 2, "contour": 3, "first_positive": 4,
    "efficacies": 5, "energy_exponent": 5, "taut": 6, "crossing": 6, "paired": 7,
    "finite_size": 8, "widths": 9, "fractal": 10, "disagreement": 1, "transition": 11,
    "binomial_widths": 12, "jamming_point": 13,
}  # fmt: skip


def stream(estimator: str, offset: int = 0) -> np.random.Generator:
    """A fresh generator on one estimator's bootstrap stream (:data:`BOOTSTRAP_STREAMS`)."""
    return np.random.default_rng(BOOTSTRAP_STREAMS[estimator] + offset)


@dataclass(frozen=True, kw_only=True)
class Scale:
    """A reproduction's size: the studies it runs, each one's parameters, the bootstrap.

    Attributes
    ----------
    name : str
    params : mapping
        Study name -> its parameters at this scale (every registered study: its default where
        the scale does not run it). ``scale[name]`` reads them.
    studies : tuple of str
        The studies ``reproduce`` runs at this scale, in the registry's order.
    bootstrap, bootstrap_seed : int
        Replicas of every error bar; an offset added to each estimator's stream (0 draws the
        replicas every release so far drew).
    budget_minutes : float or None
        The estimated wall time on 2 workers stays below (:mod:`~.budget`).
    expected : str
        The run time on 2 cores, as measured or estimated.
    """

    name: str
    params: Mapping[str, Any] = field(default_factory=dict)
    studies: tuple[str, ...] = ()
    bootstrap: int = 200
    bootstrap_seed: int = 0
    budget_minutes: float | None = None
    expected: str = ""

    def __getitem__(self, study: str) -> Any:
        return self.params[study]

    def rng(self, estimator: str, offset: int = 0) -> np.random.Generator:
        """A fresh generator for one estimator's bootstrap replicas: its stream plus
        :attr:`bootstrap_seed` and ``offset`` (one stream per subset an estimator is applied
        to), so every estimate is reproducible and the estimators draw independent replicas."""
        return stream(estimator, self.bootstrap_seed + offset)


@dataclass(frozen=True, kw_only=True)
class Result:
    """What every study's result carries besides its own numbers.

    Attributes
    ----------
    excluded : dict
        Sweep name -> samples excluded as undecided.
    bracketed : dict
        Sweep name -> of those, undecided grid rows whose E* is bracketed, which still enter
        the energy analyses (:func:`~.studies.rows.energy_bracketed`).
    straddling : int or None
        Threshold samples whose interval straddles a grid value (None: no threshold grid).
    measured : tuple of Measurement
        What the study measured for each claim (:attr:`Study.claims`).
    """

    excluded: dict[str, int] = field(default_factory=dict)
    bracketed: dict[str, int] = field(default_factory=dict)
    straddling: int | None = None
    measured: tuple[Measurement, ...] = ()


def _none(*_: Any) -> dict:
    return {}


@dataclass(frozen=True)
class Study:
    """One study of the reproduction (see the module docstring); called as
    ``study(out, scale, workers=, scheduler=, progress=)`` it runs (or resumes) its sweeps
    into ``out/studies`` and returns its analysed result.

    Attributes
    ----------
    name : str
        Its key in the registry and the name of its template.
    params : mapping
        Scale name -> its parameters there; a scale runs the studies that have an entry.
    default : object
        Its parameters where a scale names none.
    sweeps : callable
        ``sweeps(scale) -> {sweep name: spec}``: what it runs.
    analyse : callable
        ``analyse(rows, scale) -> Result``: its result from the rows of its sweeps.
    claims : callable
        ``claims(result) -> tuple of Measurement``.
    cost : callable
        ``cost(scale, costs) -> seconds`` of in-process work (analysis, trials): with its sweeps
        priced row by row, its cost model (:mod:`~.budget`).
    numbers : callable
        ``numbers(result) -> {placeholder: value}``: the numbers its template quotes.
    figures : callable
        ``figures(result, figdir) -> {figure id: [png, svg]}``.
    tables : callable
        ``tables(result) -> {name: frame}``: the CSV tables written beside the report.
    report_tables : callable
        ``report_tables(result) -> {name: frame}``: tables its template places (``table NAME``).
    errors : callable
        ``errors(scale) -> [(claim, where, estimator, n, samples, pool), ...]``: the error
        bars its sample counts buy (:func:`~.budget.expected_errors`).
    energy : callable
        ``energy(specs) -> sweep names`` whose rows feed energy analyses (bracketed rows kept).
    evidence : bool
        Its result from a finished run may join another scale's report (``--evidence``).
    """

    name: str
    params: Mapping[str, Any]
    default: Any
    sweeps: Callable[[Scale], dict[str, dict]]
    analyse: Callable[[Rows, Scale], Any]
    claims: Callable[[Any], tuple[Measurement, ...]]
    cost: Callable[[Scale, Any], float]
    numbers: Callable[[Any], dict] = _none
    figures: Callable[[Any, Path], dict[str, list[Path]]] = _none
    tables: Callable[[Any], dict[str, pd.DataFrame]] = _none
    report_tables: Callable[[Any], dict[str, pd.DataFrame]] = _none
    errors: Callable[[Scale], list[tuple]] = lambda scale: []
    energy: Callable[[dict], tuple[str, ...]] = lambda specs: ()
    evidence: bool = False

    @property
    def template(self) -> Template:
        return load(self.name)

    def __call__(self, out, scale: Scale, **kw) -> Any:
        specs = self.sweeps(scale)
        result = self.analyse(load_sweeps(Path(out), specs, energy=self.energy(specs), **kw), scale)
        return replace(result, measured=self.claims(result))
