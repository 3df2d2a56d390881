"""Instance files: ``.npz`` archives with exactly the keys ``box``, ``positions``, ``bonds``,
``shifts``, ``kinds`` (0 empty, 1 rod, 2 cable, 3 strut), ``strain`` (2x2 symmetric, magnitude
included) and optionally ``stiffness``."""

from __future__ import annotations

import os
import zipfile
from pathlib import Path

import numpy as np

from ..errors import InputError
from .network import Instance

REQUIRED_KEYS = ("box", "positions", "bonds", "shifts", "kinds", "strain")
OPTIONAL_KEYS = ("stiffness",)


def save_instance(path: str | os.PathLike, instance: Instance) -> None:
    """Write an instance to ``path`` (.npz), atomically (a temporary file renamed into place)."""
    if not isinstance(instance, Instance):
        raise InputError("save_instance needs an Instance")
    path = Path(path)
    net = instance.network
    arrays = {
        "box": net.box,
        "positions": net.positions,
        "bonds": net.bonds,
        "shifts": net.shifts,
        "kinds": net.kinds.astype(np.int8),
        "strain": instance.strain,
    }
    if net.stiffness is not None:
        arrays["stiffness"] = net.stiffness
    tmp = path.with_name(path.name + ".tmp")
    with open(tmp, "wb") as fh:
        np.savez(fh, **arrays)
    os.replace(tmp, path)


def load_instance(path: str | os.PathLike) -> Instance:
    """Read and validate an instance file written by :func:`save_instance` (or by hand).

    Raises
    ------
    InputError
        If the file is missing or unreadable, keys are missing or unknown, or the arrays do not
        describe a valid instance.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    try:
        with np.load(path, allow_pickle=False) as data:
            keys = set(data.files)
            arrays = {key: data[key] for key in keys}
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        raise InputError(f"{path}: not a readable .npz instance file ({exc})") from None
    missing = [k for k in REQUIRED_KEYS if k not in keys]
    if missing:
        raise InputError(f"{path}: missing key(s) {', '.join(missing)}")
    unknown = sorted(keys - set(REQUIRED_KEYS) - set(OPTIONAL_KEYS))
    if unknown:
        raise InputError(f"{path}: unknown key(s) {', '.join(unknown)}")
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
