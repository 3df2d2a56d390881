"""A sweep's results directory: one Parquet file per finished chunk, renamed into place.

Layout of DIR::

    _spec.json                  the canonical spec (a different spec is refused)
    _spec.toml                  the spec file as given, for people
    part-<point>-<chunk>.parquet

``pandas.read_parquet(DIR)`` reads every part (files starting with "_" or "." are ignored by
Parquet dataset discovery). A chunk is written to a hidden temporary file, flushed to disk and
renamed, so a part either exists whole or not at all; a part that fails to read or has the wrong
number of rows is deleted and redone.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from ..errors import SpecError
from .spec import GridPoint, Spec


class ResultStore:
    """Results of one sweep under a directory."""

    def __init__(self, root: str | os.PathLike):
        self.root = Path(root)

    def prepare(self, spec: Spec, source_text: str | None = None) -> None:
        """Create DIR for this spec, or check that DIR already belongs to it."""
        meta = self.root / "_spec.json"
        canonical = {"digest": spec.digest(), "spec": spec.canonical()}
        if self.root.exists():  # temporary files of a killed run
            for stale in self.root.glob(".part-*.tmp"):
                stale.unlink(missing_ok=True)
        if meta.exists():
            try:
                old = json.loads(meta.read_text())
            except (OSError, ValueError):
                raise SpecError(
                    f"{meta} is unreadable; remove it or choose another --out"
                ) from None
            if old.get("digest") != canonical["digest"]:
                raise SpecError(
                    f"{self.root} holds results of a different sweep; choose another --out "
                    "or delete that directory"
                )
            return
        if self.root.exists() and any(p.name.startswith("part-") for p in self.root.iterdir()):
            raise SpecError(f"{self.root} holds results without a spec; choose another --out")
        self.root.mkdir(parents=True, exist_ok=True)
        self._atomic_write(meta, json.dumps(canonical, indent=2, sort_keys=True).encode())
        if source_text is not None:
            self._atomic_write(self.root / "_spec.toml", source_text.encode())

    def part_path(self, point: GridPoint, chunk: int) -> Path:
        return self.root / f"part-{point.key()}-{chunk:05d}.parquet"

    def is_done(self, point: GridPoint, chunk: int, rows: int) -> bool:
        """Whether the part exists whole; a corrupt or partial part is deleted."""
        path = self.part_path(point, chunk)
        if not path.exists():
            return False
        try:
            ok = pq.read_metadata(path).num_rows == rows
        except Exception:  # noqa: BLE001 (any unreadable file is redone)
            ok = False
        if not ok:
            path.unlink(missing_ok=True)
        return ok

    def write(self, point: GridPoint, chunk: int, frame: pd.DataFrame) -> None:
        table = pa.Table.from_pandas(frame, preserve_index=False)
        sink = pa.BufferOutputStream()
        pq.write_table(table, sink)
        self._atomic_write(self.part_path(point, chunk), sink.getvalue().to_pybytes())

    def read(self) -> pd.DataFrame:
        """All finished rows (empty frame if none)."""
        parts = sorted(self.root.glob("part-*.parquet"))
        if not parts:
            return pd.DataFrame()
        return pd.read_parquet(self.root)

    @staticmethod
    def _atomic_write(path: Path, data: bytes) -> None:
        tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        try:
            with open(tmp, "wb") as fh:
                fh.write(data)
                fh.flush()
                os.fsync(fh.fileno())
            os.replace(tmp, path)
        except BaseException:  # Ctrl-C or a full disk mid-write: leave no partial file
            tmp.unlink(missing_ok=True)
            raise
        try:
            dir_fd = os.open(path.parent, os.O_RDONLY)
            try:
                os.fsync(dir_fd)
            finally:
                os.close(dir_fd)
        except OSError:
            pass
