"""SIGTERM as an interrupt that cannot be lost.

The command line turns SIGTERM into :class:`Terminated` (handled like Ctrl-C: finished work is
kept). Python runs a signal handler in the main thread at the next bytecode, which may be inside
Python code that a C extension calls back and whose exception the extension swallows; a sweep
then ran on to its end (1 of 41 SIGTERMs of a serial sweep at n = 8). So the handler also records
the request, and long loops call :func:`check` between units of work: the exception is raised
again there, at the latest one chunk later. When the handler runs inside a finalizer (a
``__del__``, such as pyarrow's ``ParquetWriter.__del__`` while a part is written), Python cannot
raise the exception and prints it as "Exception ignored in ...", with a traceback;
:func:`quiet_unraisable` wraps ``sys.unraisablehook`` so that a :class:`Terminated` lost there
is not printed (the recorded request still raises it at the next :func:`check`).

A few lines must not be cut in two by an interrupt: a sweep writes a part, lists it and counts
it; an interrupt between listing and counting made its last line say "3 samples saved" beside
4 on disk. :func:`deferred` holds SIGINT and SIGTERM back for such a block and delivers them
after it.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager

_requested = False

#: the signals :func:`deferred` holds back
_DEFERRED = (signal.SIGINT, signal.SIGTERM)


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread and handled like Ctrl-C: finished work is kept."""


def on_sigterm(signum, frame):
    """Signal handler: record the request and raise :class:`Terminated`."""
    global _requested
    _requested = True
    raise Terminated


def check() -> None:
    """Raise :class:`Terminated` if a SIGTERM arrived (even if its first raise was lost)."""
    if _requested:
        raise Terminated


def reset() -> None:
    """Forget a recorded request (a new command starts)."""
    global _requested
    _requested = False


def quiet_unraisable(hook):
    """A ``sys.unraisablehook`` that drops :class:`Terminated` and passes anything else on.

    Parameters
    ----------
    hook : callable
        The hook to pass other unraisable exceptions to (``sys.unraisablehook`` before).

    Returns
    -------
    callable
        The wrapped hook.
    """

    def quiet(unraisable) -> None:
        if not isinstance(unraisable.exc_value, Terminated):
            hook(unraisable)

    return quiet


@contextmanager
def deferred(deliver: bool = True) -> Iterator[None]:
    """Hold SIGINT and SIGTERM back while the block runs; deliver them after it.

    A signal that arrives inside the block is recorded; when the block ends (normally or by
    an exception) the handlers in place before are restored and the first recorded signal is
    passed to its handler (raising :class:`Terminated` or ``KeyboardInterrupt``), or raised
    again when that handler is the default. With ``deliver=False`` the recorded signals are
    dropped instead: for the clean-up after an interrupt, which a second Ctrl-C or the same
    SIGTERM sent to the whole process group must not cut short. Outside the main thread (where
    handlers cannot be set) the block runs as it is.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[signal.Signals] = []

    def hold(signum, frame) -> None:
        caught.append(signal.Signals(signum))

    previous = {sig: signal.signal(sig, hold) for sig in _DEFERRED}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        if caught and deliver:
            handler = previous[caught[0]]
            if callable(handler):
                handler(caught[0], None)
            elif handler == signal.SIG_DFL:
                signal.raise_signal(caught[0])
