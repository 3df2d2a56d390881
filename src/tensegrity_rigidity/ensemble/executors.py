"""Where chunks run: serially, in local processes, or on a Dask distributed cluster.

:func:`open_pool` turns what the user gave (``None``/an int = local processes, ``"serial"``, a
``concurrent.futures.Executor``, a ``distributed.Client`` or a scheduler address) into a small
:class:`Pool` with ``submit``, ``as_completed`` and ``cancel``. Results are returned to the
calling process, which alone writes files, so workers need no shared file system.
"""

from __future__ import annotations

import concurrent.futures as cf
import os
import signal
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
    ):
        self._submit, self._as_completed, self._close = submit, as_completed, close
        self.description = description

    def submit(self, fn: Callable, *args: Any):
        return self._submit(fn, *args)

    def as_completed(self, futures: Iterable) -> Iterator:
        return self._as_completed(futures)

    def cancel(self, futures: Iterable) -> None:
        for f in futures:
            f.cancel()

    def close(self) -> None:
        if self._close is not None:
            self._close()


def _init_worker() -> None:
    """Set up a local worker process: one BLAS thread, no Ctrl-C.

    Each worker is one core's worth of work, so the BLAS libraries (NumPy's and CVXOPT's
    OpenBLAS) get one thread: with one per core they spin and oversubscribe, which cost 7-11% of
    the sweep throughput on 2 workers (BENCHMARKS.md). Dask's nanny does the same for its
    workers. Ctrl-C is left to the main process, which cancels the work and keeps what is saved.
    """
    from threadpoolctl import threadpool_limits

    threadpool_limits(limits=1, user_api="blas")
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _serial_pool() -> Pool:
    return Pool(lambda fn, *a: _LazyFuture(fn, a), lambda fs: iter(list(fs)), None, "serial")


def _futures_pool(executor: cf.Executor, owned: bool) -> Pool:
    def close():
        if owned:
            executor.shutdown(wait=True, cancel_futures=True)

    return Pool(executor.submit, cf.as_completed, close, type(executor).__name__)


def _dask_pool(client, owned: bool) -> Pool:
    from distributed import as_completed

    def submit(fn, *args):
        return client.submit(fn, *args, pure=False)

    def close():
        if owned:
            client.close()

    return Pool(submit, as_completed, close, f"dask {client.scheduler.address}")


def connect(address: str, timeout: float = 5.0):
    """A Dask client for a running scheduler; SpecError (one line) if it cannot be reached."""
    from distributed import Client

    try:
        return Client(address, timeout=f"{timeout}s")
    except (OSError, TimeoutError, ValueError) as exc:
        raise SpecError(f"cannot reach the Dask scheduler at {address} ({exc})") from None


@contextmanager
def open_pool(executor: Any = None, scheduler: str | None = None):
    """Yield a :class:`Pool` for ``executor`` (see module docstring) or a scheduler address."""
    if scheduler is not None:
        pool = _dask_pool(connect(scheduler), owned=True)
    elif executor is None or isinstance(executor, int):
        workers = executor or os.cpu_count() or 1
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
    finally:
        pool.close()
