"""Instance files: ``.npz`` archives with exactly the keys ``box``, ``positions``, ``bonds``,
``shifts``, ``kinds`` (0 empty, 1 rod, 2 cable, 3 strut), ``strain`` (2x2 symmetric, magnitude
included) and optionally ``stiffness``.

Reading trusts nothing in the file: every member's ``.npy`` header (shape, dtype) is read and
checked against the bytes the member holds, and against this machine's memory, *before* an array
is allocated; a corrupt member (a bad CRC, a broken deflate stream), a plain ``.npy`` file or an
archive of pickled objects ends in one :class:`~tensegrity_rigidity.errors.InputError`.
"""

from __future__ import annotations

import contextlib
import math
import os
import secrets
import stat
import tokenize
import zipfile
import zlib
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from .limits import check_memory, format_bytes
from .network import Instance, show

#: characters of an output file's stem and suffix kept in its temporary file's name
TMP_STEM = 32

REQUIRED_KEYS = ("box", "positions", "bonds", "shifts", "kinds", "strain")
OPTIONAL_KEYS = ("stiffness",)

_NPY_MAGIC = b"\x93NUMPY"
_READ_ERRORS = (
    OSError,
    ValueError,
    EOFError,
    SyntaxError,  # a cut .npy header (NumPy parses it as a Python literal)
    tokenize.TokenError,
    zipfile.BadZipFile,
    zlib.error,
)


def check_input_file(path: str | os.PathLike, what: str) -> Path:
    """A path to read: an existing regular file (a directory, FIFO or device is refused).

    Parameters
    ----------
    path : str or path-like
        What was passed.
    what : str
        What the file should be, for the message ("an instance file").

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InputError
        When nothing is there, or something other than a regular file.
    """
    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: no such file")
    if not path.is_file():
        kind = "a directory" if path.is_dir() else "not a regular file (a FIFO or a device?)"
        raise InputError(f"{path}: is {kind}, not {what}")
    return path


def check_output_file(
    path: str | os.PathLike, what: str = "the output path", example: str = "sample.npz"
) -> Path:
    """Refuse, in one line, a path that output files may not go to.

    Output is written to a temporary file beside the path and renamed over it (so that a
    failure leaves nothing), which would replace whatever node is there by a regular file: a
    device (``/dev/full`` as root), a FIFO, a socket, a symbolic link. So an output path must
    be a regular file or nothing yet, in an existing directory.

    Parameters
    ----------
    path : str or path-like
        The file to write.
    what : str
        Its name in the message for an empty path ("the figure path").
    example : str
        A file name to suggest when the path is a directory.

    Returns
    -------
    pathlib.Path
        The path.

    Raises
    ------
    InputError
        If the path is empty, a directory, a symbolic link, a device, a FIFO or a socket, or
        its directory does not exist.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise InputError(f"{what} must be a str or path, got {show(path)}")
    if not os.fspath(path).strip():
        raise InputError(f"{what} is empty; give a file name")
    p = Path(path)
    try:
        mode = os.lstat(p).st_mode
    except FileNotFoundError:
        mode = None
    except OSError as exc:
        raise InputError(f"{p}: cannot be written ({exc.strerror or exc})") from None
    if mode is not None and stat.S_ISLNK(mode):
        raise InputError(
            f"{p}: is a symbolic link (to {os.readlink(p)}); output goes to regular files only "
            "(writing would replace the link by a file): give the target's path"
        )
    if mode is not None and stat.S_ISDIR(mode):
        raise InputError(f"{p}: is a directory; give a file name in it, such as {p / example}")
    if mode is not None and not stat.S_ISREG(mode):
        kind = "a FIFO" if stat.S_ISFIFO(mode) else "a socket" if stat.S_ISSOCK(mode) else None
        kind = kind or "a device"
        raise InputError(
            f"{p}: is {kind}, not a regular file; output goes to regular files only (writing "
            "would replace it by a file)"
        )
    if not p.parent.is_dir():
        raise InputError(f"{p}: directory {p.parent} does not exist")
    return p


@contextmanager
def atomic_output(
    path: str | os.PathLike, what: str = "the output path", example: str = "sample.npz"
) -> Iterator[Path]:
    """Write a file whole or not at all: yield a temporary path beside ``path``, rename it over
    ``path`` when the block ends, remove it on any failure (a full disk, an interrupt).

    Parameters
    ----------
    path : str or path-like
        The file to write (:func:`check_output_file` first).
    what, example : str
        As :func:`check_output_file`.

    Yields
    ------
    pathlib.Path
        The temporary file to write: hidden, in the same directory, with the same suffix (a
        figure's format follows from it).

    Raises
    ------
    InputError
        As :func:`check_output_file`, or when the file cannot be written (one line).
    """
    p = check_output_file(path, what, example)
    # a name of bounded length: the file's own name plus a tag can pass the file system's
    # limit (255 bytes) where the name itself does not
    tag = f"{os.getpid()}.{secrets.token_hex(4)}"
    tmp = p.with_name(f".{p.stem[:TMP_STEM]}.{tag}.tmp{p.suffix[:TMP_STEM]}")
    try:
        yield tmp
        with open(tmp, "rb+") as fh:  # on the disk before it takes the name
            os.fsync(fh.fileno())
        check_output_file(p, what, example)  # still no device, FIFO or link there
        os.replace(tmp, p)
    except OSError as exc:
        with contextlib.suppress(OSError):
            tmp.unlink(missing_ok=True)
        raise InputError(f"{p}: cannot write ({exc.strerror or exc})") from None
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink(missing_ok=True)
        raise


def save_instance(path: str | os.PathLike, instance: Instance) -> None:
    """Write an instance to ``path`` (.npz), atomically.

    The archive is written to a hidden temporary file next to ``path`` and renamed into place
    (:func:`atomic_output`); on any failure (a directory in the way, no permission, a full
    disk) the temporary file is removed and nothing is left behind. ``path`` must be a
    regular file or not exist (:func:`check_output_file`).

    Parameters
    ----------
    path : str or path-like
        The file to write (its directory must exist); conventionally ``*.npz``.
    instance : Instance
        What to store: ``box`` (d, d), ``positions`` (N, d), ``bonds`` (m, 2), ``shifts``
        (m, d), ``kinds`` (m,) as int8, ``strain`` (d, d) and ``stiffness`` (m,) when set
        (``d = 2`` or ``3``).

    Raises
    ------
    InputError
        If ``path`` is empty, a directory, a device, a FIFO, a symbolic link, in a missing
        directory, or cannot be written.
    """
    if not isinstance(instance, Instance):
        raise InputError("save_instance needs an Instance")
    net = instance.network
    arrays: dict[str, Any] = {
        "box": net.box,
        "positions": net.positions,
        "bonds": net.bonds,
        "shifts": net.shifts,
        "kinds": net.kinds.astype(np.int8),
        "strain": instance.strain,
    }
    if net.stiffness is not None:
        arrays["stiffness"] = net.stiffness
    with atomic_output(path) as tmp, open(tmp, "wb") as fh:
        np.savez(fh, **arrays)


def _read_member(zf: zipfile.ZipFile, info: zipfile.ZipInfo, path: Path) -> np.ndarray:
    """One ``.npy`` member, its header checked before anything is allocated."""
    key = info.filename[:-4]
    fmt = np.lib.format
    with zf.open(info) as fh:
        version = fmt.read_magic(fh)
        if version == (1, 0):
            shape, fortran, dtype = fmt.read_array_header_1_0(fh)
        elif version == (2, 0):
            shape, fortran, dtype = fmt.read_array_header_2_0(fh)
        else:
            raise InputError(f"{path}: member {key!r} has unsupported .npy version {version}")
        header = fh.tell()
        if dtype.hasobject or dtype.kind not in "biufc":
            raise InputError(f"{path}: member {key!r} holds {dtype}, not numbers")
        declared = math.prod(shape) * dtype.itemsize
        held = info.file_size - header
        if declared != held:
            raise InputError(
                f"{path}: member {key!r} declares shape {shape} ({format_bytes(declared)}) but "
                f"holds {format_bytes(max(held, 0))}: the file is corrupt"
            )
        check_memory(declared, f"{path}: member {key!r} of shape {shape}")
    with zf.open(info) as fh:
        return fmt.read_array(fh, allow_pickle=False)


def _read_npz(path: Path) -> dict[str, np.ndarray]:
    """Every member of an instance archive, validated one by one."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(len(_NPY_MAGIC))
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror or exc})") from None
    if head == _NPY_MAGIC:
        raise InputError(
            f"{path}: is a plain .npy array, not an .npz instance archive "
            "(write one with save_instance)"
        )
    try:
        with zipfile.ZipFile(path) as zf:
            infos = [i for i in zf.infolist() if not i.is_dir()]
            other = sorted(i.filename for i in infos if not i.filename.endswith(".npy"))
            if other:
                raise InputError(f"{path}: unknown member(s) {', '.join(other)}")
            keys = {i.filename[:-4] for i in infos}
            missing = [k for k in REQUIRED_KEYS if k not in keys]
            if missing:
                raise InputError(f"{path}: missing key(s) {', '.join(missing)}")
            unknown = sorted(keys - set(REQUIRED_KEYS) - set(OPTIONAL_KEYS))
            if unknown:
                raise InputError(f"{path}: unknown key(s) {', '.join(unknown)}")
            return {i.filename[:-4]: _read_member(zf, i, path) for i in infos}
    except InputError:
        raise
    except _READ_ERRORS as exc:
        raise InputError(f"{path}: not a readable .npz instance file ({exc})") from None


def load_instance(path: str | os.PathLike) -> Instance:
    """Read and validate an instance file written by :func:`save_instance` (or by hand).

    Parameters
    ----------
    path : str or path-like
        An ``.npz`` archive with the keys of the module docstring.

    Returns
    -------
    Instance
        The validated instance.

    Raises
    ------
    InputError
        If the file is missing, unreadable or corrupt, keys are missing or unknown, a member's
        header declares more data than it holds, or the arrays do not describe a valid instance.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise InputError(f"an instance file's path must be a str or path, got {show(path)}")
    path = check_input_file(path, "an instance file")
    arrays = _read_npz(path)
    try:
        return Instance.from_arrays(
            arrays["box"],
            arrays["positions"],
            arrays["bonds"],
            arrays["shifts"],
            arrays["kinds"],
            arrays["strain"],
            arrays.get("stiffness"),
        )
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None
