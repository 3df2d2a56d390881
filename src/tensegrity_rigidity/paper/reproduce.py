"""Reproduce the paper: run every study, draw every figure, write the report.

``tensegrity-rigidity reproduce --scale quick --out DIR`` is the package's main job. Samples
are stored under ``DIR/studies`` by the resumable sweep engine, so an interrupted reproduction
picks up where it stopped.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from ..ensemble.executors import local_workers
from ..errors import InputError
from .budget import estimate
from .figures import all_figures
from .progress import OverallProgress
from .registry import REGISTRY, SCALES, STUDIES
from .report import write_report
from .run_times import EXPECTED  # noqa: F401 (re-exported: each scale's run time)
from .studies.rows import STORED

#: the studies ``evidence`` reads from a finished finite-size run
EVIDENCE_STUDIES = tuple(s.name for s in REGISTRY if s.evidence)


def read_evidence(path) -> tuple[str, dict]:
    """The finite-size and node-disorder studies of a finished finite-size run, read only.

    Parameters
    ----------
    path : str or path-like
        The output directory of ``reproduce --scale fss`` (or ``fss-cluster``, ``tiny``): every
        sweep of its :data:`EVIDENCE_STUDIES` must be complete there. Nothing is computed.

    Returns
    -------
    scale : str
        The largest scale whose finite-size sweeps are all stored in ``path``.
    results : dict
        Study name -> its result, analysed from the stored samples.

    Raises
    ------
    InputError
        When no scale's finite-size sweeps are all stored in ``path`` (one line, with the
        command that finishes the run).
    """
    path = Path(path)
    candidates = [s for s in SCALES.values() if set(EVIDENCE_STUDIES) <= set(s.studies)]
    missing = {}
    for sc in reversed(candidates):
        est = estimate(sc, 1, list(EVIDENCE_STUDIES), out=path)
        missing[sc.name] = (sum(s.new_rows for s in est.sweeps), sum(s.rows for s in est.sweeps))
        if missing[sc.name][0] == 0:
            stored = dict(workers=STORED, scheduler=None, progress=False)
            return sc.name, {n: STUDIES[n](path, sc, **stored) for n in EVIDENCE_STUDIES}
    counts = ", ".join(f"{k}: {new:,} of {total:,}" for k, (new, total) in missing.items())
    raise InputError(
        f"{path} holds no finished finite-size run (rows missing per scale: {counts}); finish "
        f"one with: tensegrity-rigidity reproduce --scale NAME --out {path}"
    )


def reproduce(
    out,
    scale: str = "quick",
    workers=None,
    scheduler=None,
    progress=None,
    studies=None,
    evidence=None,
) -> dict:
    """Run the studies of a scale into ``out``, draw the figures and write the report.

    Parameters
    ----------
    out : str or path-like
        Output directory (created): samples under ``out/studies`` (resumable sweeps),
        figures under ``out/figures``, ``report.md`` and ``report.html``.
    scale : {"tiny", "quick", "paper", "fss"}
        System sizes and sample counts (:data:`~tensegrity_rigidity.paper.registry.SCALES`);
        :data:`EXPECTED` gives their run times.
    workers : int, optional
        Local worker processes (default: all cores).
    scheduler : str, optional
        Address of a running Dask scheduler, instead of local processes.
    progress : bool, optional
        One progress bar over all studies, with the time left (default: when stderr is a
        terminal); without it, one line per study.
    studies : list of str, optional
        Run only these studies (names of :data:`~tensegrity_rigidity.paper.registry.STUDIES`)
        instead of the scale's.
    evidence : str or path-like, optional
        The output directory of a finished ``--scale fss`` run: its finite-size and
        node-disorder studies (:func:`read_evidence`) join the report, so that its explanation
        column gives their evidence for the claims measured here.

    Returns
    -------
    dict
        ``results`` (study name -> its frozen result), ``figures`` (figure id -> [png, svg]
        paths), ``report`` (paths of ``md``, ``html`` and the CSV tables), ``timings``
        (study name -> seconds).

    Raises
    ------
    InputError
        On an unknown scale or study, or an ``evidence`` directory without a finished
        finite-size run (checked before anything runs).
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
    if evidence is not None and set(EVIDENCE_STUDIES) & set(names):
        raise InputError(
            f"scale {scale} runs the finite-size studies itself: --evidence is for the others"
        )
    found = read_evidence(evidence) if evidence is not None else None
    local = workers is None or workers == "serial" or isinstance(workers, int)
    w = 1  # on a Dask cluster the bar needs only the work, not the worker count
    if scheduler is None and local:
        w = 1 if workers == "serial" else local_workers(workers)
        if isinstance(workers, int):
            workers = w  # capped once at the usable cores (one warning), not per study
    est = estimate(sc, w, names, out=out)
    if scheduler is None and local:
        print(
            f"scale {scale}: estimated {est.wall_seconds / 60:.0f} min on {w} worker(s) for the "
            "samples not stored yet (from per-sample costs, not a measurement)",
            file=sys.stderr,
            flush=True,
        )
    show = sys.stderr.isatty() if progress is None else bool(progress)
    bar = OverallProgress(est, show)  # one bar with the time left, not one per sweep
    try:
        for i, name in enumerate(names, 1):
            if show:
                bar.study(i, len(names), name)
            else:
                print(
                    f"[{i}/{len(names)}] study {name} (scale {scale})", file=sys.stderr, flush=True
                )
            start = time.perf_counter()
            results[name] = STUDIES[name](
                out, sc, workers=workers, scheduler=scheduler, progress=bar if show else False
            )
            timings[name] = time.perf_counter() - start
            bar.study_done(name)
    finally:
        bar.close()
    if found is not None:
        print(
            f"read the finite-size evidence of --scale {found[0]} in {evidence}",
            file=sys.stderr,
            flush=True,
        )
        results |= found[1]
    print("drawing figures and writing the report", file=sys.stderr, flush=True)
    figures = all_figures(results, out / "figures")
    paths = write_report(out, results, figures, scale, timings)
    return {"results": results, "figures": figures, "report": paths, "timings": timings}
