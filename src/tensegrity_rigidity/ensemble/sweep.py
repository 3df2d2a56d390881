"""Running a sweep: find the rows still missing, run them in chunks, save each as it finishes.

:func:`run_sweep` is the API behind ``tensegrity-rigidity sweep``. Rows depend only on their
state point (see :mod:`~tensegrity_rigidity.ensemble.spec` on randomness and identity), never on
workers, chunk size, chunk order or restarts; a results directory can therefore be resumed after
any interruption and grown by samples or grid values, computing only what is new.

Failures. A chunk that raises, a worker process that dies, a Dask scheduler that goes away: every
chunk that finished is saved, the others are left for the next run, and :class:`SweepFailed`
says what happened in one sentence with a resume hint. A full disk ends the same way.
"""

from __future__ import annotations

import concurrent.futures as cf
import math
import os
import shutil
import sys
import time
from collections.abc import Callable
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd
from tqdm.auto import tqdm

from .. import interrupts
from ..errors import InputError, SpecError, TensegrityError
from ..model.limits import (
    format_bytes,
    lattice_dimension,
    lattice_nodes,
    physical_memory,
    stage_bytes,
)
from .executors import open_pool
from .jamming import sample_seconds
from .runner import run_chunk
from .spec import GridPoint, Spec, load_spec_text
from .store import ResultStore
from .summary import phi_name

#: memory of one row in a loaded frame (25 columns; measured 218 bytes)
ROW_MEMORY_BYTES = 300
#: disk of one row in a Parquet part, and of a part itself (its schema and footer): measured
#: 14.5 kB for a part of 4 rows, 16.6 kB for 32, 24 kB for 256
ROW_DISK_BYTES = 100
PART_DISK_BYTES = 15_000


@dataclass(frozen=True)
class SweepReport:
    """What a call to :func:`run_sweep` did.

    Attributes
    ----------
    samples_total : int
        Samples (rows) of the spec.
    samples_reused : int
        Rows found finished in the directory before this call.
    samples_run : int
        Rows computed and saved by this call.
    chunks_run : int
        Chunks saved by this call.
    chunks_failed : int
        Chunks that raised or were lost with a worker or the scheduler.
    seconds : float
        Wall time of the work.
    interrupted : bool
        Ctrl-C or SIGTERM ended the call.
    """

    samples_total: int
    samples_reused: int
    samples_run: int
    chunks_run: int
    chunks_failed: int = 0
    seconds: float = 0.0
    interrupted: bool = False

    @property
    def samples_saved(self) -> int:
        """Rows of the spec in the directory after this call."""
        return self.samples_reused + self.samples_run


class SweepInterrupted(KeyboardInterrupt):
    """Raised on Ctrl-C after pending work was cancelled; finished chunks are kept.

    Parameters
    ----------
    report : SweepReport
        What the sweep did before it was interrupted (kept as ``exc.report``).
    cause : BaseException, optional
        The interrupt that ended the sweep (a KeyboardInterrupt or a subclass, such as the
        command line's SIGTERM; kept as ``exc.cause``).
    """

    def __init__(self, report: SweepReport, cause: BaseException | None = None):
        super().__init__("interrupted")
        self.report = report
        self.cause = cause


class SweepFailed(TensegrityError):
    """Some chunks could not be computed or saved; every finished chunk is kept.

    Parameters
    ----------
    message : str
        What failed, one line.
    report : SweepReport
        What the sweep did (kept as ``exc.report``).
    exit_status : int, optional
        The command line's exit status (kept as ``exc.exit_status``): 2 when the cause is the
        user's to fix (a full or read-only disk), 1 otherwise (a chunk raised, a worker or the
        scheduler died).
    """

    def __init__(self, message: str, report: SweepReport, exit_status: int = 1):
        super().__init__(message)
        self.report = report
        self.exit_status = exit_status


def plan_chunks(
    spec: Spec, done: set | frozenset = frozenset()
) -> list[tuple[GridPoint, list[int]]]:
    """(point, sample indices) of every chunk still to compute.

    Parameters
    ----------
    spec : Spec
        The sweep.
    done : set of (point_key, sample, theta)
        Rows already saved (:attr:`ResultStore.done`).

    Returns
    -------
    list of (GridPoint, list of int)
        At most ``spec.chunk_size`` samples each, in increasing sample order per point.
    """
    ks = range(1, spec.samples + 1)
    thetas = [spec.angle(k) for k in ks]
    out = []
    for point in spec.points():
        pk = spec.point_key(point)
        missing = [k for k in ks if (pk, k, thetas[k - 1]) not in done] if done else list(ks)
        for start in range(0, len(missing), spec.chunk_size):
            out.append((point, missing[start : start + spec.chunk_size]))
    return out


def estimate(spec: Spec) -> dict:
    """What a spec asks for: rows, memory per sample and of the loaded rows, disk, CPU time.

    Parameters
    ----------
    spec : Spec
        The sweep.

    Returns
    -------
    dict
        ``rows``, ``points``, ``n_max``, ``sample_bytes`` (memory of one sample at the largest
        n), ``rows_bytes`` (memory of the loaded rows), ``disk_bytes`` (all parts),
        ``cpu_seconds``.

    Notes
    -----
    The memory of one sample is :func:`sample_bytes`. CPU seconds per solve follow the
    benchmark medians (4 ms at n = 16, 0.37 s at n = 128 on the reference machine: about
    ``4e-3 (n / 16)^2.2``); a threshold costs about ``log2(3 n^2) + 2`` solves. A packing
    sweep's are the measured per-sample costs of :func:`~.jamming.sample_seconds`.
    """
    rows = spec.n_samples()
    n_max = max(spec.grid["n"])
    per_point = spec.samples * spec.n_points() // len(spec.grid["n"])
    solves = 1.0
    cpu = 0.0
    if spec.packing is not None:
        cpu = per_point * sum(sample_seconds(n, spec.packing["dim"]) for n in spec.grid["n"])
    for n in spec.grid["n"] if spec.packing is None else ():
        if spec.mode == "threshold":
            solves = math.log2(3 * n * n) + 2
        cpu += per_point * solves * 4e-3 * (n / 16) ** 2.2
    return {
        "rows": rows,
        "points": spec.n_points(),
        "sample_bytes": sample_bytes(spec, n_max),
        "n_max": n_max,
        "rows_bytes": ROW_MEMORY_BYTES * float(rows),
        "disk_bytes": ROW_DISK_BYTES * float(rows)
        + PART_DISK_BYTES * float(spec.n_points()) * math.ceil(spec.samples / spec.chunk_size),
        "cpu_seconds": cpu,
    }


def sample_bytes(spec: Spec, n: int) -> float:
    """Memory of one sample of ``spec`` at linear size ``n``: building it, then its work.

    Parameters
    ----------
    spec : Spec
        The sweep: its lattice fixes the nodes (``n^2``, or ``n^3`` on the FCC lattice) and
        the measured costs (:mod:`~tensegrity_rigidity.model.limits`), its mode the work (a
        solve, a threshold search, or the pebble game).
    n : int
        Linear size.

    Returns
    -------
    float
        Bytes.
    """
    if spec.packing is not None:  # an N-node contact network in its dimension, tested by LPs
        dim = spec.packing["dim"]
        return stage_bytes("build", float(n), dim=dim) + stage_bytes("solve", float(n), dim=dim)
    work = "solve"
    if spec.threshold is not None:
        work = "clusters" if spec.threshold.get("method") == "pebble" else "threshold"
    nodes = lattice_nodes(spec.lattice, n)
    return stage_bytes("build", nodes, spec.lattice) + stage_bytes(work, nodes, spec.lattice)


def check_size(spec: Spec, out: str | os.PathLike, worker_memory: int | None = None) -> dict:
    """Refuse a sweep that cannot fit in memory, before anything starts; returns :func:`estimate`.

    The disk is checked once the missing rows are known (:func:`check_disk`).

    Parameters
    ----------
    spec : Spec
        The sweep.
    out : str or path-like
        Results directory.
    worker_memory : int, optional
        Memory of one worker in bytes (a Dask worker's limit); default this machine's.

    Returns
    -------
    dict
        :func:`estimate` of the spec.

    Raises
    ------
    SpecError
        One sentence saying how much is asked and how much there is.
    """
    est = estimate(spec)
    have = worker_memory or physical_memory()
    if est["sample_bytes"] > have:
        where = "a Dask worker has" if worker_memory else "this machine has"
        n = est["n_max"]
        what = (
            f"{n} particles"
            if spec.packing is not None
            else f"{n}^{lattice_dimension(spec.lattice)} nodes of the {spec.lattice} lattice"
        )
        raise SpecError(
            f"n = {n} needs about {format_bytes(est['sample_bytes'])} of memory per sample "
            f"({what}); {where} {format_bytes(have)}"
        )  # fmt: skip
    ram = physical_memory()
    if est["rows_bytes"] > ram:
        raise SpecError(
            f"the sweep asks for {est['rows']:,} samples ({est['points']:,} grid points x "
            f"{spec.samples:,}); their rows need about {format_bytes(est['rows_bytes'])} of "
            f"memory to load, this machine has {format_bytes(ram)}"
        )
    return est


def check_disk(out: str | os.PathLike, rows: int, parts: int) -> None:
    """Refuse to start when the parts still to write cannot fit on the disk of ``out``.

    Parameters
    ----------
    out : str or path-like
        Results directory (or the nearest existing parent).
    rows, parts : int
        Rows and part files still to write.

    Raises
    ------
    SpecError
        One sentence saying how much disk is needed and how much is free.
    """
    need = ROW_DISK_BYTES * float(rows) + PART_DISK_BYTES * float(parts)
    parent = Path(out).absolute()
    while not parent.exists() and parent != parent.parent:
        parent = parent.parent
    try:
        free = shutil.disk_usage(parent).free
    except OSError:
        return
    if need > free:
        raise SpecError(
            f"the sweep's {rows:,} missing rows need about {format_bytes(need)} of disk; "
            f"{parent} has {format_bytes(free)} free"
        )


def _describe_chunk(point: GridPoint, ks: list[int]) -> str:
    where = ", ".join(
        f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}"
        for k, v in vars(point).items()
        if not (isinstance(v, float) and math.isnan(v))
    )
    return f"{where}, samples {ks[0]}-{ks[-1]}"


def _lost_with(exc: BaseException) -> str | None:
    """Why a chunk was lost with its worker or scheduler (None: the chunk itself raised)."""
    name = type(exc).__name__
    if isinstance(exc, BrokenProcessPool):
        return "a worker process died (killed, or out of memory)"
    if name == "KilledWorker":
        return "a Dask worker died (killed, or out of memory)"
    if name in (
        "CancelledError",
        "FutureCancelledError",
        "CommClosedError",
        "ClosedClientError",
    ) or isinstance(exc, cf.CancelledError):
        return "the Dask scheduler or its workers went away"
    return None


def _failure_message(failed: list, n_chunks: int, saved: int, root: Path) -> str:
    """One sentence: what failed, what is saved, how to resume."""
    lost = [(c, _lost_with(e)) for c, e in failed]
    raised = [(c, e) for (c, e), (_, why) in zip(failed, lost, strict=True) if why is None]
    parts = []
    if raised:
        (point, ks), exc = raised[0]
        text = str(exc).splitlines()[0] if str(exc) else ""
        what = f"{type(exc).__name__}: {text}" if text else type(exc).__name__
        parts.append(
            f"{len(raised)} of {n_chunks} chunks failed (first: {_describe_chunk(point, ks)}: "
            f"{what})"
        )
    gone = [why for _, why in lost if why is not None]
    if gone:
        parts.append(f"{gone[0]}: {len(gone)} of {n_chunks} chunks not computed")
    if not gone and all(isinstance(e, InputError) for _, e in raised):
        # the solver refused the input: a verdict is a function of it, so a resume would fail
        # the same way
        return "; ".join(parts) + (
            f"; the {saved} finished samples are saved in {root}; change the spec (running "
            "the same command again would fail the same way)"
        )
    return (
        "; ".join(parts) + f"; the {saved} finished samples are saved in {root}: run the same "
        "command again to resume"
    )


class _Advance:
    """A progress bar's ``update`` and ``close`` that report to a caller's function instead."""

    def __init__(self, report: Callable[[Path, int], object], out: Path) -> None:
        self.report, self.out = report, out

    def update(self, samples: int) -> None:
        self.report(self.out, samples)

    def close(self) -> None:
        pass


def run_sweep(
    spec: Spec | str | os.PathLike,
    out: str | os.PathLike,
    executor: Any = None,
    scheduler: str | None = None,
    progress: bool | Callable[[Path, int], object] | None = None,
    wait_for_workers: float = 60.0,
) -> SweepReport:
    """Run (or resume, or grow) a sweep into the directory ``out``.

    Parameters
    ----------
    spec : Spec or str or path-like
        The sweep, or the path of its TOML file (:func:`load_spec`; its text is kept as
        ``out/_spec.toml``).
    out : str or path-like
        Results directory: created, or reopened to resume or grow (only rows whose keys are
        missing are computed).
    executor : None, int, "serial", concurrent.futures.Executor or distributed.Client
        Where chunks run: None or an int for that many local processes (None: all cores),
        "serial" in this process, or an executor or Dask client of your own (not shut down).
    scheduler : str, optional
        Address of a running Dask scheduler (``tcp://host:8786``), instead of ``executor``.
    progress : bool or callable, optional
        Show a progress bar (default: when stderr is a terminal). A callable replaces the bar:
        it is called as ``progress(out, samples)`` each time a chunk of ``samples`` samples is
        saved (one bar over many sweeps, as ``reproduce`` shows).
    wait_for_workers : float
        Seconds to wait for a first worker of a Dask scheduler that has none.

    Returns
    -------
    SweepReport
        Rows reused and run, chunks run and failed, wall time.

    Raises
    ------
    SpecError
        A bad spec, a sweep too large for this machine, a busy or unusable directory, a
        directory holding another sweep (nothing is touched).
    SweepInterrupted
        Ctrl-C (or SIGTERM via the command line); finished chunks are kept.
    SweepFailed
        Chunks failed or could not be saved; finished chunks are kept.
    """
    source = None
    if not isinstance(spec, (Spec, str, os.PathLike)):
        raise SpecError(
            f"spec must be a Spec (parse_spec(dict)) or the path of a TOML file, got "
            f"{type(spec).__name__}"
        )
    if not isinstance(spec, Spec):
        spec, source = load_spec_text(spec)
    store = ResultStore(out)
    check_size(spec, out)
    start = time.perf_counter()
    # Reach the executor (a remote scheduler may be down) before touching the directory.
    with open_pool(executor, scheduler, wait_for_workers) as pool, store.writing():
        if pool.worker_memory:
            check_size(spec, out, pool.worker_memory)
        store.prepare(spec, source)
        todo = plan_chunks(spec, store.done)
        total = spec.n_samples()
        reused = total - sum(len(ks) for _, ks in todo)
        if not todo:
            return SweepReport(total, reused, 0, 0)
        check_disk(store.root, total - reused, len(todo))
        if callable(progress):
            bar: Any = _Advance(progress, Path(out))
        else:
            show = sys.stderr.isatty() if progress is None else progress
            bar = tqdm(
                total=total - reused,
                unit="sample",
                disable=not show,
                dynamic_ncols=True,
                desc=f"sweep {os.fspath(out)}",
            )
        done_chunks = done_samples = 0
        failed: list[tuple[tuple[GridPoint, list[int]], BaseException]] = []

        def report(interrupted: bool = False) -> SweepReport:
            return SweepReport(
                total,
                reused,
                done_samples,
                done_chunks,
                len(failed),
                time.perf_counter() - start,
                interrupted,
            )

        futures: dict = {}  # the tasks submitted and not yet saved (at most pool.window)
        tasks = iter(todo)

        lost: list[BaseException] = []  # why the pool can run nothing more, once it cannot

        def submit_more() -> None:
            # each task carries its grid point, not the grid: pickling the whole spec made
            # every task as large as the grid (1.8 MB at 200,000 values of p_r)
            while len(futures) < pool.window:
                chunk = next(tasks, None)
                if chunk is None:
                    return
                if lost:  # a worker or the scheduler is gone: the rest is not computed
                    failed.extend((c, lost[0]) for c in [chunk, *tasks])
                    return
                try:
                    futures[pool.submit(run_chunk, spec.at(chunk[0]), *chunk)] = chunk
                except Exception as exc:  # noqa: BLE001 (a broken pool: nothing more runs)
                    failed.extend((c, exc) for c in [chunk, *tasks])
                    return

        def save(fut, chunk: tuple[GridPoint, list[int]]) -> None:
            nonlocal done_chunks, done_samples
            try:
                frame = fut.result()
            except Exception as exc:  # noqa: BLE001 (reported below, the rest is saved)
                failed.append((chunk, exc))
                if _lost_with(exc) is not None:
                    lost.append(exc)
                interrupts.check()
                return
            try:
                with interrupts.deferred():  # saved and counted, or neither
                    store.write(frame)
                    done_chunks += 1
                    done_samples += len(chunk[1])
            except OSError as exc:
                pool.cancel(futures)
                bar.close()
                raise SweepFailed(
                    f"cannot write {store.root} ({exc.strerror or exc}); "
                    f"{total - reused - done_samples} samples not saved, the "
                    f"{reused + done_samples} finished are kept: free space and run the "
                    "same command again to resume",
                    report(),
                    exit_status=2,
                ) from None
            bar.update(len(chunk[1]))
            interrupts.check()  # a SIGTERM whose exception was swallowed in a C extension

        try:
            pool.start(len(todo))  # local processes: at most one per chunk
            submit_more()
            while futures:
                for fut in pool.wait_first(list(futures)):
                    save(fut, futures.pop(fut))
                submit_more()
        except KeyboardInterrupt as exc:
            with interrupts.deferred(deliver=False):  # a second signal changes nothing now
                pool.cancel(futures)
                bar.close()
            raise SweepInterrupted(report(interrupted=True), exc) from None
        bar.close()
        if failed:
            raise SweepFailed(
                _failure_message(failed, len(todo), reused + done_samples, store.root), report()
            )
    return report()


def load_results(
    out: str | os.PathLike, spec: Spec | str | os.PathLike | None = None, all_rows: bool = False
) -> pd.DataFrame:
    """Rows of a sweep directory, sorted by grid point and sample.

    Parameters
    ----------
    out : path
        Results directory.
    spec : Spec or path, optional
        Return the rows of this spec (or of the TOML file at this path); default the latest
        spec run into ``out``.
    all_rows : bool
        Return every row in ``out`` (also those of earlier, larger specs).

    Returns
    -------
    pandas.DataFrame
        One row per sample (empty when there are none). Beside ``phi`` (radians), ``strain``
        names it: "dilation", "shear", "compression", or the angle to 12 digits.

    Raises
    ------
    InputError
        When ``out`` is not a results directory or one of its parts is damaged, or holds no
        row of the ``spec`` given (another sweep's directory).
    """
    if spec is not None and not isinstance(spec, Spec):
        if not isinstance(spec, (str, os.PathLike)):
            kind = type(spec).__name__
            raise InputError(f"spec must be a Spec or a TOML file's path, got a {kind}")
        spec = load_spec_text(spec)[0]
    store = ResultStore(out)
    if not store.root.is_dir():
        raise InputError(f"{store.root}: no such results directory")
    df = store.read()
    if df.empty:
        return df
    if not all_rows:
        given = spec is not None
        spec = spec or _recorded_spec(store)
        if spec is not None:
            df = store.rows_of(spec, df)
        if given and df.empty:
            raise InputError(
                f"{store.root} holds no row of the spec given (another sweep's directory, or "
                "other settings): pass all_rows=True to read every row"
            )
    keys = [c for c in ("n", "delta", "p_r", "p_t", "f_c", "phi", "fraction", "seed", "sample")
            if c in df]  # fmt: skip
    df = df.sort_values(keys, kind="stable").reset_index(drop=True)
    if "phi" in df and "strain" not in df:  # derived on reading: the stored parts are unchanged
        df.insert(df.columns.get_loc("phi") + 1, "strain", df["phi"].map(phi_name))
    return df


def _recorded_spec(store: ResultStore) -> Spec | None:
    """The directory's latest spec, refused in one line when no sweep could have run it (its
    rows could not even be listed: a ``_spec.json`` edited by hand)."""
    spec = store.recorded_spec()
    if spec is not None:
        try:
            check_size(spec, store.root)
        except SpecError as exc:
            raise InputError(
                f"{store.root / '_spec.json'} asks for more than fits: {exc}"
            ) from None
    return spec


def describe(out: str | os.PathLike) -> dict:
    """What a results directory holds (for ``tensegrity-rigidity info``).

    Parameters
    ----------
    out : str or path-like
        Results directory (read only: no lock is taken, a running sweep may be writing it).

    Returns
    -------
    dict
        ``spec`` (the latest spec, a :class:`Spec`), ``rows`` (all rows in DIR), ``done``
        (rows of the spec), ``total`` (rows the spec asks for), ``undecided`` (rows of the
        spec without a verdict), ``chunks_missing`` (chunks a re-run computes), ``parts``,
        ``damaged`` (parts failing their checksum), ``bytes`` (size of the parts), ``writer``
        (who is writing now, or None), ``frame`` (the spec's rows).

    Raises
    ------
    InputError
        When ``out`` is not a results directory.
    """
    store = ResultStore(out)
    if not store.root.is_dir():
        raise InputError(f"{store.root}: no such results directory")
    spec = _recorded_spec(store)
    if spec is None:
        raise InputError(f"{store.root}: not a results directory (no _spec.json)")
    everything, damaged, size = store.scan()
    mine = store.rows_of(spec, everything) if not everything.empty else everything
    done = set()
    if not mine.empty:
        done = set(zip(mine["point_key"], mine["sample"], mine["theta"], strict=True))
    undecided = int((~mine["decided"].astype(bool)).sum()) if not mine.empty else 0
    return {
        "spec": spec,
        "rows": len(everything),
        "done": len(mine),
        "total": spec.n_samples(),
        "undecided": undecided,
        "chunks_missing": len(plan_chunks(spec, done)),
        "parts": len(store.manifest()),
        "damaged": damaged,
        "bytes": size,
        "writer": store.writer() if store.busy() else None,
        "frame": mine,
    }
