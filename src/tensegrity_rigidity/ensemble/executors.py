"""Where chunks run: serially, in local processes, or on a Dask distributed cluster.

:func:`open_pool` turns what the user gave (``None``/an int = local processes, ``"serial"``, a
``concurrent.futures.Executor``, a ``distributed.Client`` or a scheduler address) into a small
:class:`Pool` with ``submit``, ``wait_first`` and ``cancel``. Results are returned to the
calling process, which alone writes files, so workers need no shared file system. A pool has a
``window``: how many tasks the sweep keeps submitted at once (a few per worker), so that a grid
of any size costs memory and time in proportion to the chunks running, not to the grid.

Local processes are bounded: never more than the usable cores (a larger request is capped, with
one warning line) nor than the chunks to run (the pool starts its processes only once
:meth:`Pool.start` is told how many chunks there are). They are started with SIGINT and SIGTERM
blocked, and each unblocks them only after installing its own handlers, so that a Ctrl-C or a
SIGTERM at any moment of the start-up is handled by the main process alone.

Local worker processes die with the process that started them: on Linux the kernel sends them
SIGKILL when their parent dies (``PR_SET_PDEATHSIG``), and everywhere a watchdog thread ends a
worker whose parent has changed (re-parented after a SIGKILL of the main process). If the main
process leaves by an exception (Ctrl-C, SIGTERM through the command line, a full disk), the
workers are killed at once instead of finishing chunks nobody will save.
"""

from __future__ import annotations

import concurrent.futures as cf
import ctypes
import logging
import os
import signal
import sys
import threading
import time
import warnings
from collections.abc import Callable, Iterable
from contextlib import contextmanager
from typing import Any

from .. import interrupts
from ..errors import SpecError


class _LazyFuture:
    """A future computed when its result is asked for (serial execution)."""

    def __init__(self, fn: Callable, args: tuple):
        self._fn, self._args = fn, args

    def result(self):
        return self._fn(*self._args)

    def cancel(self) -> bool:
        return True


class Pool:
    """Uniform face of an executor.

    ``wait_first(futures)`` blocks until at least one of ``futures`` is done and returns the
    done ones; ``window`` is how many tasks to keep submitted at once.
    """

    def __init__(
        self,
        submit: Callable,
        wait_first: Callable,
        close: Callable | None = None,
        description: str = "",
        worker_memory: int | None = None,
        window: int = 1,
    ):
        self._submit, self._wait_first, self._close = submit, wait_first, close
        self.description = description
        #: memory of one worker in bytes when the executor says (Dask), else None
        self.worker_memory = worker_memory
        #: tasks kept submitted at once: enough to keep every worker busy
        self.window = window

    def start(self, tasks: int) -> None:
        """Get ready to run ``tasks`` tasks (local processes start here, at most one per task)."""

    def submit(self, fn: Callable, *args: Any):
        return self._submit(fn, *args)

    def wait_first(self, futures: list) -> list:
        """The futures of ``futures`` that are done, in their order (at least one; blocks)."""
        done = self._wait_first(futures)
        return [f for f in futures if f in done]

    def cancel(self, futures: Iterable) -> None:
        for f in futures:
            f.cancel()

    def close(self, abort: bool = False) -> None:
        """Release the executor; ``abort`` kills local workers instead of letting them finish."""
        if self._close is not None:
            self._close(abort)


#: Tasks kept submitted per worker: one running, the next ready, and some slack for uneven
#: chunk times; more only costs memory (and pickles) for work nobody may wait for.
TASKS_PER_WORKER = 4


def _first_of(futures: list) -> set:
    """Serial execution: the first future (computed when its result is asked for)."""
    return {futures[0]}


def _first_completed(futures: list) -> set:
    return cf.wait(futures, return_when=cf.FIRST_COMPLETED).done


_PR_SET_PDEATHSIG = 1  # from <linux/prctl.h>


def _watch_parent(parent: int, period: float = 1.0) -> None:
    """End this process once its parent is gone (it was re-parented)."""
    while True:
        time.sleep(period)
        if os.getppid() != parent:
            os._exit(1)


def die_with_parent() -> None:
    """Make this process end when its parent dies, however the parent dies.

    On Linux ``prctl(PR_SET_PDEATHSIG, SIGKILL)`` asks the kernel to kill it; everywhere a
    daemon thread polls the parent pid once a second. Safe to call in any child process.
    """
    parent = os.getppid()
    if sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent:  # the parent died during the call
        os._exit(1)
    threading.Thread(target=_watch_parent, args=(parent,), daemon=True).start()


def _init_worker() -> None:
    """Set up a local worker process: die with the parent, one BLAS thread, no Ctrl-C.

    SIGTERM ends a worker (the pool then reports it dead); the main process handles its own.

    Each worker is one core's worth of work, so the BLAS libraries (NumPy's and CVXOPT's
    OpenBLAS) get one thread: with one per core they spin and oversubscribe, which cost 7-11% of
    the sweep throughput on 2 workers (BENCHMARKS.md). Dask's nanny does the same for its
    workers. Ctrl-C is left to the main process, which cancels the work and keeps what is saved.
    """
    from threadpoolctl import threadpool_limits

    die_with_parent()
    threadpool_limits(limits=1, user_api="blas")
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)  # not the command line's handler (forked)
    # forked with both blocked (:func:`_signals_blocked`): a signal that arrived since is
    # delivered now, to these handlers
    signal.pthread_sigmask(signal.SIG_UNBLOCK, _START_SIGNALS)


#: The signals blocked while local worker processes are forked.
_START_SIGNALS = {signal.SIGINT, signal.SIGTERM}


@contextmanager
def _signals_blocked():
    """Block SIGINT and SIGTERM in this thread (a forked child inherits the mask and unblocks
    them in :func:`_init_worker`, after its own handlers are set); restored on exit, where a
    signal that arrived meanwhile is delivered to the main process's handler."""
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, _START_SIGNALS)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


class _LocalPool(Pool):
    """Local worker processes, started by :meth:`start` (at most one per task; in this process
    when that is one)."""

    def __init__(self, workers: int):
        super().__init__(self._submit_local, self._wait_local, self._close_local)
        self.workers = workers
        self.description = f"{workers} local processes"
        self._executor: cf.ProcessPoolExecutor | None = None

    def start(self, tasks: int) -> None:
        count = min(self.workers, max(int(tasks), 1))
        self.description = f"{count} local processes" if count > 1 else "serial"
        self.window = TASKS_PER_WORKER * count if count > 1 else 1
        if count > 1 and self._executor is None:
            with _signals_blocked():
                executor = cf.ProcessPoolExecutor(max_workers=count, initializer=_init_worker)
                self._executor = executor
                # with the fork start method the first submit forks every process
                executor.submit(int).result()

    def _submit_local(self, fn: Callable, *args: Any):
        if self._executor is None:
            return _LazyFuture(fn, args)
        return self._executor.submit(fn, *args)

    def _wait_local(self, futures: list) -> set:
        if self._executor is None:
            return _first_of(futures)
        return _first_completed(futures)

    def cancel(self, futures: Iterable) -> None:
        """Nothing: a sweep that stops raises next, which aborts the pool (its processes are
        killed, and the executor's own thread fails every future it holds). Cancelling those
        futures here as well raced with that thread: an ``InvalidStateError`` traceback in it
        (a group SIGTERM kills the workers at the same moment), after which the pool's queues
        were never closed and the interpreter waited for them at exit."""

    def _close_local(self, abort: bool) -> None:
        if self._executor is not None:
            _shutdown(self._executor, abort)


def _shutdown(executor: cf.Executor, abort: bool) -> None:
    """Shut an executor down; ``abort`` kills its processes first (nobody will save what they
    compute now)."""
    if not abort:
        executor.shutdown(wait=True, cancel_futures=True)
        return
    for proc in list((getattr(executor, "_processes", None) or {}).values()):
        try:
            proc.kill()
        except (OSError, ValueError, AttributeError):
            pass
    # its processes are dead, so this ends; a second Ctrl-C (or the group's SIGTERM reaching
    # us twice) cutting it short would lose the report of what was saved
    with interrupts.deferred(deliver=False):
        executor.shutdown(wait=True, cancel_futures=True)


def _serial_pool() -> Pool:
    return Pool(lambda fn, *a: _LazyFuture(fn, a), _first_of, None, "serial")


#: Tasks kept submitted to an executor that does not say how many workers it has
UNKNOWN_WORKERS = 4


def _futures_pool(executor: cf.Executor, owned: bool) -> Pool:
    def close(abort: bool):
        if owned:
            _shutdown(executor, abort)

    workers = getattr(executor, "_max_workers", None) or UNKNOWN_WORKERS
    window = TASKS_PER_WORKER * int(workers)
    return Pool(executor.submit, _first_completed, close, type(executor).__name__, None, window)


def _dask_pool(client, owned: bool) -> Pool:
    from distributed import as_completed

    def submit(fn, *args):
        return client.submit(fn, *args, pure=False)

    # one iterator for the whole sweep, each future added once: it also yields the futures
    # that a scheduler gone away cancelled (distributed.wait raises on those instead)
    completed = as_completed()
    waiting: set = set()

    def wait_first(futures: list) -> set:
        for f in futures:
            if f not in waiting:
                waiting.add(f)
                completed.add(f)
        done = {next(completed)}
        if completed.has_ready():
            done.update(completed.next_batch(block=False))
        waiting.difference_update(done)
        return done

    def close(abort: bool):
        if not owned:
            return
        if not abort:
            client.close()
            return
        # After a failure (the scheduler gone) the client's reconnection attempts end in
        # logged tracebacks while it closes; the sweep reports the failure in one line.
        names = ["distributed"] + [
            n for n in logging.root.manager.loggerDict if n.startswith("distributed.")
        ]
        levels = {n: logging.getLogger(n).level for n in names}
        for n in names:
            logging.getLogger(n).setLevel(logging.CRITICAL + 1)
        try:
            client.close(timeout=5)
        except Exception:  # noqa: BLE001 (closing a client whose scheduler is gone)
            pass
        finally:
            for n, level in levels.items():
                logging.getLogger(n).setLevel(level)

    workers = client.scheduler_info()["workers"].values()
    limits = [w.get("memory_limit") or 0 for w in workers]
    memory = max(limits) if limits and max(limits) > 0 else None
    # workers may join later: never fewer than for UNKNOWN_WORKERS of them
    threads = max(sum(int(w.get("nthreads") or 1) for w in workers), UNKNOWN_WORKERS)
    description = f"dask {client.scheduler.address}"
    return Pool(submit, wait_first, close, description, memory, TASKS_PER_WORKER * threads)


def connect(address: str, timeout: float = 5.0, wait_for_workers: float = 60.0):
    """A Dask client for a running scheduler with at least one worker.

    Parameters
    ----------
    address : str
        Scheduler address, e.g. ``tcp://host:8786``.
    timeout : float
        Seconds to reach the scheduler.
    wait_for_workers : float
        Seconds to wait for a first worker when the scheduler has none (a warning says so).

    Raises
    ------
    SpecError
        One line when the scheduler cannot be reached or no worker joins in time.
    """
    from distributed import Client

    try:
        client = Client(address, timeout=f"{timeout}s")
    except (OSError, TimeoutError, ValueError) as exc:
        raise SpecError(f"cannot reach the Dask scheduler at {address} ({exc})") from None
    if not client.scheduler_info()["workers"]:
        warnings.warn(
            f"the Dask scheduler at {address} has no workers; waiting up to "
            f"{wait_for_workers:g} s for one",
            UserWarning,
            stacklevel=2,
        )
        try:
            client.wait_for_workers(1, timeout=wait_for_workers)
        except (TimeoutError, OSError):
            client.close()
            raise SpecError(
                f"no worker joined the Dask scheduler at {address} within {wait_for_workers:g} "
                f"s; start one (dask worker {address}) and run again"
            ) from None
    return client


def usable_cores() -> int:
    """The cores this process may run on (its CPU affinity where the system tells).

    Returns
    -------
    int
        At least 1.
    """
    try:
        return max(len(os.sched_getaffinity(0)), 1)
    except (AttributeError, OSError):  # not Linux
        return os.cpu_count() or 1


def check_workers(workers: int | None, option: str = "workers") -> None:
    """Refuse a worker count below 1 (or not an integer) in one line.

    Parameters
    ----------
    workers : int or None
        Requested processes (None: every usable core).
    option : str
        Its name in the message ("--workers" on the command line).

    Raises
    ------
    SpecError
        When ``workers`` is below 1 (0 does not mean "all cores": None does).
    """
    if workers is None:
        return
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise SpecError(f"{option} must be at least 1, got {workers!r}")


def local_workers(workers: int | None, option: str = "workers") -> int:
    """The number of local worker processes: ``workers``, at most the usable cores.

    Parameters
    ----------
    workers : int or None
        Requested processes (None: every usable core, :func:`usable_cores`).
    option : str
        Its name in messages.

    Returns
    -------
    int
        Between 1 and the usable cores. A request above them is capped, with one warning:
        more processes than cores only share them, and each one costs memory.

    Raises
    ------
    SpecError
        When ``workers`` is below 1.
    """
    check_workers(workers, option)
    cores = usable_cores()
    if workers is None:
        return cores
    if workers > cores:
        warnings.warn(
            f"{workers} worker processes asked for, more than the {cores} usable cores: "
            f"running at most {cores}",
            UserWarning,
            stacklevel=3,
        )
        return cores
    return workers


@contextmanager
def open_pool(executor: Any = None, scheduler: str | None = None, wait_for_workers: float = 60.0):
    """Yield a :class:`Pool` for ``executor`` (see module docstring) or a scheduler address.

    Local processes start at the pool's :meth:`~Pool.start`. Leaving the block by an exception
    aborts the pool (local workers are killed).
    """
    if scheduler is not None:
        pool = _dask_pool(connect(scheduler, wait_for_workers=wait_for_workers), owned=True)
    elif executor is None or (isinstance(executor, int) and not isinstance(executor, bool)):
        workers = local_workers(executor, "executor")
        pool = _serial_pool() if workers == 1 else _LocalPool(workers)
    elif executor == "serial":
        pool = _serial_pool()
    elif isinstance(executor, cf.Executor):
        pool = _futures_pool(executor, owned=False)
    elif type(executor).__name__ == "Client" and hasattr(executor, "submit"):
        pool = _dask_pool(executor, owned=False)
    else:
        raise SpecError(f"unsupported executor {executor!r}")
    try:
        yield pool
    except BaseException:
        pool.close(abort=True)
        raise
    pool.close()
