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


def test_a_signal_inside_a_deferred_block_is_delivered_after_it():
    """A sweep writes a part, lists it and counts it inside ``deferred()``: a SIGTERM there used
    to leave the count one chunk short of what was on disk. The block runs to its end, then the
    signal's own handler raises."""
    import os
    import signal

    import pytest

    from tensegrity_rigidity.interrupts import deferred, on_sigterm, reset

    previous = {
        signal.SIGTERM: signal.signal(signal.SIGTERM, on_sigterm),
        signal.SIGINT: signal.signal(signal.SIGINT, signal.default_int_handler),
    }
    try:
        for sig, exc in ((signal.SIGTERM, Terminated), (signal.SIGINT, KeyboardInterrupt)):
            steps = []
            with pytest.raises(exc):
                with deferred():
                    os.kill(os.getpid(), sig)
                    steps.append("after the signal")
                    steps.append("end of the block")
            assert steps == ["after the signal", "end of the block"]
        assert signal.getsignal(signal.SIGTERM) is on_sigterm
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
        with deferred():  # nothing arrives: nothing is raised
            pass
        # the clean-up after an interrupt: a second Ctrl-C (a group's signals arrive more than
        # once) cut the pool's shutdown short and lost the "N of M samples saved" line
        with deferred(deliver=False):
            os.kill(os.getpid(), signal.SIGINT)
            os.kill(os.getpid(), signal.SIGTERM)
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        reset()
