"""SIGTERM handling shared by the commands (``tensegrity_rigidity.interrupts``)."""

import gc
import sys

from tensegrity_rigidity.interrupts import Terminated, quiet_unraisable


class _RaisesOnDelete:
    def __init__(self, exc: BaseException):
        self.exc = exc

    def __del__(self):
        raise self.exc


def test_a_terminated_lost_in_a_finalizer_is_not_printed(monkeypatch, capsys):
    """A SIGTERM whose handler runs inside a ``__del__`` (pyarrow's ``ParquetWriter.__del__``
    while a sweep writes a part) cannot propagate; Python prints it as "Exception ignored in"
    with a traceback, which a terminated sweep must not show. The wrapped hook drops it and
    still prints any other exception lost that way."""
    monkeypatch.setattr(sys, "unraisablehook", quiet_unraisable(sys.__unraisablehook__))
    obj = _RaisesOnDelete(Terminated())
    del obj
    gc.collect()
    assert capsys.readouterr().err == ""
    obj = _RaisesOnDelete(ValueError("kept"))
    del obj
    gc.collect()
    err = capsys.readouterr().err
    assert "Traceback" in err and "ValueError: kept" in err
