"""Running a sweep: split the spec into chunks, skip finished ones, run the rest, save each.

:func:`run_sweep` is the API behind ``tensegrity-rigidity sweep``. Rows depend only on the
spec (see :mod:`~tensegrity_rigidity.ensemble.spec` on randomness), never on workers, chunk
order or restarts.
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass
from typing import Any

import pandas as pd
from tqdm.auto import tqdm

from .executors import open_pool
from .runner import run_chunk
from .spec import GridPoint, Spec, load_spec
from .store import ResultStore


@dataclass(frozen=True)
class SweepReport:
    """What a call to :func:`run_sweep` did."""

    chunks_total: int
    chunks_skipped: int
    chunks_run: int
    samples_run: int
    seconds: float
    interrupted: bool = False


class SweepInterrupted(KeyboardInterrupt):
    """Raised on Ctrl-C after pending work was cancelled; finished chunks are kept."""

    def __init__(self, report: SweepReport):
        super().__init__("interrupted")
        self.report = report


def plan_chunks(spec: Spec) -> list[tuple[GridPoint, int, list[int]]]:
    """(point, chunk index, sample indices) for every chunk of the sweep."""
    out = []
    ks = list(range(1, spec.samples + 1))
    for point in spec.points():
        for c, start in enumerate(range(0, len(ks), spec.chunk_size)):
            out.append((point, c, ks[start : start + spec.chunk_size]))
    return out


def run_sweep(
    spec: Spec | str | os.PathLike,
    out: str | os.PathLike,
    executor: Any = None,
    scheduler: str | None = None,
    progress: bool | None = None,
) -> SweepReport:
    """Run (or resume) a sweep into the directory ``out``.

    Parameters
    ----------
    spec : Spec or path of a TOML file
    out : directory of results (created; reopened to resume)
    executor : None/int (local processes, default all cores), "serial",
        a concurrent.futures.Executor or a distributed.Client
    scheduler : address of a running Dask scheduler (tcp://host:port), instead of executor
    progress : show a progress bar (default: when stderr is a terminal)
    """
    import time

    source = None
    if not isinstance(spec, Spec):
        source = open(spec).read() if os.path.exists(spec) else None
        spec = load_spec(spec)
    store = ResultStore(out)
    start = time.perf_counter()
    # Reach the executor (a remote scheduler may be down) before touching the directory.
    with open_pool(executor, scheduler) as pool:
        store.prepare(spec, source)
        chunks = plan_chunks(spec)
        todo = [(p, c, ks) for p, c, ks in chunks if not store.is_done(p, c, len(ks))]
        if not todo:
            return SweepReport(len(chunks), len(chunks), 0, 0, 0.0)
        n_todo = sum(len(ks) for _, _, ks in todo)
        show = sys.stderr.isatty() if progress is None else progress
        bar = tqdm(
            total=n_todo,
            unit="sample",
            disable=not show,
            dynamic_ncols=True,
            desc=f"sweep {os.fspath(out)}",
        )
        done_chunks = done_samples = 0
        futures = {pool.submit(run_chunk, spec, p, ks): (p, c, ks) for p, c, ks in todo}
        try:
            for fut in pool.as_completed(list(futures)):
                point, c, ks = futures[fut]
                store.write(point, c, fut.result())
                done_chunks += 1
                done_samples += len(ks)
                bar.update(len(ks))
        except KeyboardInterrupt:
            pool.cancel(futures)
            bar.close()
            raise SweepInterrupted(
                SweepReport(
                    len(chunks),
                    len(chunks) - len(todo),
                    done_chunks,
                    done_samples,
                    time.perf_counter() - start,
                    interrupted=True,
                )
            ) from None
    bar.close()
    return SweepReport(
        len(chunks), len(chunks) - len(todo), done_chunks, done_samples, time.perf_counter() - start
    )


def load_results(out: str | os.PathLike) -> pd.DataFrame:
    """All rows of a sweep directory, sorted by grid point and sample."""
    df = ResultStore(out).read()
    if df.empty:
        return df
    keys = [c for c in ("n", "delta", "p_r", "p_t", "f_c", "phi", "seed", "sample") if c in df]
    return df.sort_values(keys, kind="stable").reset_index(drop=True)
