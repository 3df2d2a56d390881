"""Pieces shared by the command modules: SIGTERM as an interrupt, argument checks."""

from __future__ import annotations

from ..errors import InputError
from ..interrupts import Terminated, on_sigterm

__all__ = ["Terminated", "check_out", "interrupt_status", "on_sigterm"]


def interrupt_status(exc: BaseException | None) -> int:
    """Exit status of an interrupt: 143 for SIGTERM, 130 for Ctrl-C."""
    return 143 if isinstance(exc, Terminated) else 130


def check_out(value: str, option: str = "--out") -> str:
    """An output path given on the command line must not be empty (it would mean '.')."""
    if not value or not value.strip():
        raise InputError(f"{option} is empty; give a path")
    return value
