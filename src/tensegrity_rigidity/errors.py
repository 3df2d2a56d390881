"""Named exceptions and warnings of the package.

Every mistake a user can make with their input (a probability outside [0, 1], a bond index out of
range, a file that is not an instance) raises :class:`InputError` with one sentence that says what
is wrong. The command line turns it into a one-line message and a non-zero exit.
"""

from __future__ import annotations


class TensegrityError(Exception):
    """Base class of every error raised by tensegrity_rigidity."""


class InputError(TensegrityError, ValueError):
    """Bad user input: parameters, arrays, files or specs that do not describe a valid problem."""


class SpecError(InputError):
    """A sweep specification (TOML) that cannot be run."""


class UndecidedWarning(UserWarning):
    """Neither a rigidity nor a floppiness certificate could be produced to tolerance."""
