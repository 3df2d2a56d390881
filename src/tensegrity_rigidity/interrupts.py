"""SIGTERM as an interrupt that cannot be lost.

The command line turns SIGTERM into :class:`Terminated` (handled like Ctrl-C: finished work is
kept). Python runs a signal handler in the main thread at the next bytecode, which may be inside
Python code that a C extension calls back and whose exception the extension swallows; a sweep
then ran on to its end (1 of 41 SIGTERMs of a serial sweep at n = 8). So the handler also records
the request, and long loops call :func:`check` between units of work: the exception is raised
again there, at the latest one chunk later.
"""

from __future__ import annotations

_requested = False


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
