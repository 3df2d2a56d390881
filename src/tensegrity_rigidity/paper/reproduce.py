"""Reproduce the paper: run every study, draw every figure, write the report.

``tensegrity-rigidity reproduce --scale quick --out DIR`` is the package's main job. Samples
are stored under ``DIR/studies`` by the resumable sweep engine, so an interrupted reproduction
picks up where it stopped.
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

from ..errors import InputError
from .budget import estimate
from .figures import all_figures
from .registry import STUDIES
from .report import write_report
from .studies import SCALES

#: wall times of each scale on 2 cores of the reference machine: measured where stated, else the
#: estimate of :mod:`~tensegrity_rigidity.paper.budget` (``reproduce --estimate``; the tests keep
#: the two in step) until someone times a run
EXPECTED = {
    "tiny": "about a minute",
    "quick": "14 minutes measured on 2026-11-23 (estimated 9 minutes)",
    "paper": "37 minutes measured on 2026-11-23 (estimated 44 minutes)",
    "fss": "180 CPU minutes measured on 2026-11-23: 2 h 04 min wall on 2 shared cores, about "
    "95 minutes alone (estimated 92 minutes; resumable: re-run to continue)",
    "fss-cluster": "for a Dask cluster (--scheduler): fss plus n = 128, estimated 47 CPU hours "
    "(--estimate --workers N gives the wall time on N workers)",
}


def reproduce(
    out, scale: str = "quick", workers=None, scheduler=None, progress=None, studies=None
) -> dict:
    """Run the studies of a scale into ``out``, draw the figures and write the report.

    Parameters
    ----------
    out : str or path-like
        Output directory (created): samples under ``out/studies`` (resumable sweeps),
        figures under ``out/figures``, ``report.md`` and ``report.html``.
    scale : {"tiny", "quick", "paper", "fss"}
        System sizes and sample counts (:data:`~tensegrity_rigidity.paper.studies.SCALES`);
        :data:`EXPECTED` gives their run times.
    workers : int, optional
        Local worker processes (default: all cores).
    scheduler : str, optional
        Address of a running Dask scheduler, instead of local processes.
    progress : bool, optional
        Progress bars (default: when stderr is a terminal).
    studies : list of str, optional
        Run only these studies (names of :data:`~tensegrity_rigidity.paper.registry.STUDIES`)
        instead of the scale's.

    Returns
    -------
    dict
        ``results`` (study name -> its frozen result), ``figures`` (figure id -> [png, svg]
        paths), ``report`` (paths of ``md``, ``html`` and the CSV tables), ``timings``
        (study name -> seconds).

    Raises
    ------
    InputError
        On an unknown scale or study.
    SweepInterrupted
        On Ctrl-C; finished samples are kept and a re-run resumes.
    """
    if scale not in SCALES:
        raise InputError(f"unknown scale {scale!r}; choose from {', '.join(SCALES)}")
    sc = SCALES[scale]
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    results, timings = {}, {}
    names = list(studies or sc.studies)
    unknown = [n for n in names if n not in STUDIES]
    if unknown:
        raise InputError(f"unknown study {unknown[0]!r}; choose from {', '.join(STUDIES)}")
    local = workers is None or workers == "serial" or isinstance(workers, int)
    if scheduler is None and local:
        w = 1 if workers == "serial" else workers or os.cpu_count() or 1
        est = estimate(sc, w, names)
        print(
            f"scale {scale}: estimated {est.wall_seconds / 60:.0f} min for all of it on {w} "
            "worker(s) (paper.budget; stored samples are reused)",
            file=sys.stderr,
            flush=True,
        )
    for i, name in enumerate(names, 1):
        print(f"[{i}/{len(names)}] study {name} (scale {scale})", file=sys.stderr, flush=True)
        start = time.perf_counter()
        results[name] = STUDIES[name](
            out, sc, workers=workers, scheduler=scheduler, progress=progress
        )
        timings[name] = time.perf_counter() - start
    print("drawing figures and writing the report", file=sys.stderr, flush=True)
    figures = all_figures(results, out / "figures")
    paths = write_report(out, results, figures, scale, timings)
    return {"results": results, "figures": figures, "report": paths, "timings": timings}
