"""Where chunks run: serially, in local processes, or on a Dask distributed cluster.

:func:`open_pool` turns what the user gave (``None``/an int = local processes, ``"serial"``, a
``concurrent.futures.Executor``, a ``distributed.Client`` or a scheduler address) into a small
:class:`Pool` with ``submit``, ``as_completed`` and ``cancel``. Results are returned to the
calling process, which alone writes files, so workers need no shared file system.

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
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from typing import Any

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
    """Uniform face of an executor."""

    def __init__(
        self,
        submit: Callable,
        as_completed: Callable,
        close: Callable | None = None,
        description: str = "",
        worker_memory: int | None = None,
    ):
        self._submit, self._as_completed, self._close = submit, as_completed, close
        self.description = description
        #: memory of one worker in bytes when the executor says (Dask), else None
        self.worker_memory = worker_memory

    def submit(self, fn: Callable, *args: Any):
        return self._submit(fn, *args)

    def as_completed(self, futures: Iterable) -> Iterator:
        return self._as_completed(futures)

    def cancel(self, futures: Iterable) -> None:
        for f in futures:
            f.cancel()

    def close(self, abort: bool = False) -> None:
        """Release the executor; ``abort`` kills local workers instead of letting them finish."""
        if self._close is not None:
            self._close(abort)


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


def _serial_pool() -> Pool:
    return Pool(lambda fn, *a: _LazyFuture(fn, a), lambda fs: iter(list(fs)), None, "serial")


def _futures_pool(executor: cf.Executor, owned: bool) -> Pool:
    def close(abort: bool):
        if not owned:
            return
        if abort:  # nobody will save what the workers compute now: stop them
            for proc in list((getattr(executor, "_processes", None) or {}).values()):
                try:
                    proc.kill()
                except (OSError, ValueError, AttributeError):
                    pass
        executor.shutdown(wait=True, cancel_futures=True)

    return Pool(executor.submit, cf.as_completed, close, type(executor).__name__)


def _dask_pool(client, owned: bool) -> Pool:
    from distributed import as_completed

    def submit(fn, *args):
        return client.submit(fn, *args, pure=False)

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

    limits = [w.get("memory_limit") or 0 for w in client.scheduler_info()["workers"].values()]
    memory = max(limits) if limits and max(limits) > 0 else None
    return Pool(submit, as_completed, close, f"dask {client.scheduler.address}", memory)


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


def local_workers(workers: int | None, option: str = "workers") -> int:
    """The number of local worker processes: ``workers``, or every core when it is None.

    Parameters
    ----------
    workers : int or None
        Requested processes.
    option : str
        Its name in error messages ("--workers" on the command line).

    Returns
    -------
    int
        At least 1.

    Raises
    ------
    SpecError
        When ``workers`` is below 1 (0 does not mean "all cores": None does).
    """
    if workers is None:
        return os.cpu_count() or 1
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise SpecError(f"{option} must be at least 1, got {workers!r}")
    return workers


@contextmanager
def open_pool(executor: Any = None, scheduler: str | None = None, wait_for_workers: float = 60.0):
    """Yield a :class:`Pool` for ``executor`` (see module docstring) or a scheduler address.

    Leaving the block by an exception aborts the pool (local workers are killed).
    """
    if scheduler is not None:
        pool = _dask_pool(connect(scheduler, wait_for_workers=wait_for_workers), owned=True)
    elif executor is None or isinstance(executor, int):
        workers = local_workers(executor, "executor")
        if workers == 1:
            pool = _serial_pool()
        else:
            pool = _futures_pool(
                cf.ProcessPoolExecutor(max_workers=workers, initializer=_init_worker), owned=True
            )
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
