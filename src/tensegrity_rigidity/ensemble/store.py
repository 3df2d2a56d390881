"""A sweep's results directory: Parquet parts keyed by state point, one writer, checksummed.

Layout of DIR::

    _spec.json        format, the settings (fixed for the directory), the latest spec
    _spec.toml        the latest spec file as given, for people
    _manifest.jsonl   one line per finished part: name, SHA-256, size, rows
    _lock             the writer's lock (filelock); _writer names its pid and host
    part-<point>-<first sample>-<hash>.parquet

Rows. Each row carries ``point_key`` (a digest of the settings and its grid point, see
:meth:`~tensegrity_rigidity.ensemble.spec.Spec.point_key`), ``sample`` and ``theta``; these three
identify it. A sweep computes only the rows whose keys are missing, so growing ``samples``,
adding grid values or changing the chunk size reuses every finished row. The settings are fixed
per directory: a spec with other settings is refused before anything is touched.

One writer. :meth:`ResultStore.writing` takes an exclusive lock (``filelock``; the operating
system releases it when the process dies, even by SIGKILL). A second sweep into a busy directory
ends with one line; it deletes nothing. Stale temporary files are removed only under the lock,
only after the spec was accepted, and only if the process named in them is gone.

Crash safety and checksums. A part is written to a hidden temporary file, flushed, renamed into
place, and only then listed in the manifest (one appended, flushed line). On resume every listed
part is checked against its size and SHA-256; a damaged part is deleted and recomputed (with a
warning), a part the manifest does not list (a kill between the rename and the manifest line) is
deleted and recomputed. Readers (:meth:`ResultStore.read`) take no lock, read only listed parts
and refuse a part whose checksum does not match.

``pandas.read_parquet(DIR)`` reads every part (files starting with "_" or "." are ignored by
Parquet dataset discovery), including rows of other, larger specs run into DIR before; use
:func:`~tensegrity_rigidity.ensemble.sweep.load_results` for the rows of one spec.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import re
import socket
import warnings
from collections.abc import Iterator
from pathlib import Path

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
from filelock import FileLock, Timeout

from ..errors import InputError, SpecError
from ..model.network import show
from .spec import Spec, parse_spec

FORMAT = 2
#: What the rows of a given spec contain, per mode ("grid": one solve per sample, "threshold":
#: one threshold search per sample). Bumped whenever a change of the package changes the rows
#: the same spec produces, so that a resumed or grown sweep never mixes rows of two versions
#: silently (a directory records the revision its rows were written under; one without a record
#: is revision 1). Threshold rows hold only verdicts, so changes of the relaxed state leave
#: them, and the runs that stored them, valid. History: 2 (both modes) -- ``min_norm_ok`` and
#: the nonaffinity need a certified relaxed energy (rows of revision 1 can carry ``min_norm_ok``
#: True and a nonaffinity read off an unconverged relaxation near a sample's own threshold).
#: 3 (grid) -- a longer interior point certifies relaxed energies the short one left
#: uncertified (``RELAX_IPM``): such rows now carry ``min_norm_ok`` True and a nonaffinity
#: where revision 2 stored NaN, and their energy can be lower. 4 (grid) -- that longer run
#: works on a Newton matrix shifted by 1e-15 instead of 1e-12 and keeps the lower energy
#: (``RELAX_LONG_SHIFT``): near a sample's own threshold rows certify more energies and
#: nonaffinities, and uncertified energies can be lower (by up to 870 times). 5 (grid) -- the
#: minimum-norm projection's interior point solves its steps through a reduced system
#: (``displacements._ReducedKKT``): its displacements change in their last digits, and a
#: projection near a sample's own threshold can be certified where it was not (or the reverse).
#: 6 (grid) -- rigid samples' projection is first tried by a primal-dual active set
#: (``displacements.active_set``) instead of an augmented Lagrangian: their displacements change
#: in their last digits. 7 (grid) -- the projection's interior point stops at the first
#: iterate its certificate accepts with a margin (``displacements.CERTIFY_BELOW``), and the
#: energy's lower bound comes from the relaxed tensions' one purification: floppy samples'
#: ``|u|^2`` moves by 5e-11 to 1e-9 relative (n = 64 phase diagram; the certificate allows
#: 2e-9), lower bounds in their last digits. 8 (grid) and 3 (threshold) -- purification stops
#: after two balanced rounds doing no positive work and skips its extended-precision steps after
#: a hopeless round (``selfstress.purify``): it returns other rejected candidates, so a search
#: can take another path and a probe within resolution of the boundary be decided otherwise.
#: 9 (grid) -- the projection's interior point no longer refines its predictor's solve
#: (``displacements.min_norm_minimizer``): displacements change in their last digits, and a
#: projection near a sample's own threshold can be certified where it was not (or the reverse).
#: 10 (grid) and 4 (threshold) -- purification counts a round whose work is at most the
#: resolution's (round-off work of a self-stress of rods) as doing none, and so stops earlier
#: (``selfstress.purify``'s ``work_floor``), and rigid candidates are balanced only when a
#: bounded reduction of their residual would certify them (``stages.Balance.takes``): a search
#: can take another path and a probe within resolution of the boundary be decided otherwise.
#: 11 (grid) -- where the relaxed tensions' purification leaves the energy uncertified, they
#: are moved onto the best self-stress of their support for the energy's dual
#: (``selfstress.optimal_on_support``): near a sample's own threshold rows certify more
#: energies (their lower bounds rise) and so carry more nonaffinities; relaxed tensions that
#: already balance the nodes are no longer purified, so lower bounds change in their last digits.
#: 12 (grid) -- the affine energy is summed by NumPy's pairwise summation instead of a BLAS dot
#: product (``model.mechanics.energy_from_extensions``), whose last digits depended on the BLAS
#: thread count at n >= 64: rows' ``affine_energy`` changes in its last digits.
#: 13 (grid) -- a projection whose interior point ends feasible but uncertified has its
#: multipliers refined in extended precision (``displacements._refined_certificate``): rows
#: near a sample's own threshold certify more minimum-norm displacements and so carry more
#: nonaffinities (4 of the 10 missing at n = 64 in ``bench_sweep.py``).
#: 14 (grid) -- rows carry ``nonaffinity_lower``: the nonaffinity where it is certified, and a
#: certified lower bound on it where the projection ran uncertified (weak duality from its
#: multipliers, ``displacements.norm_lower_bound``), so that those samples are bracketed.
#: Packing rows (one soft packing and its jamming tests per sample): 1.
ROWS_REVISION = {"grid": 14, "threshold": 4, "packing": 1}


def rows_revision(spec: Spec) -> int:
    """The revision of the rows ``spec`` produces (:data:`ROWS_REVISION` of its mode).

    Parameters
    ----------
    spec : Spec
        The sweep.

    Returns
    -------
    int
        The revision.
    """
    return ROWS_REVISION[spec.mode]


KEY_COLUMNS = ["point_key", "sample", "theta"]


class CorruptPartWarning(UserWarning):
    """A part of a results directory failed its checksum; its rows are recomputed."""


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError):
        return True
    return True


#: what a part's file name looks like (:meth:`ResultStore.part_name`): a name in DIR, never a path
_PART_NAME = re.compile(r"part-[0-9a-f]{16}-[0-9]{6,}-[0-9a-f]{12}\.parquet")


def _valid_entry(entry) -> bool:
    """Whether a manifest line is an entry this package wrote: a part's name in DIR (a path
    such as ``../x`` would have a damaged "part" outside DIR deleted), its size, checksum and
    row count of the right types."""
    return (
        isinstance(entry, dict)
        and isinstance(entry.get("part"), str)
        and _PART_NAME.fullmatch(entry["part"]) is not None
        and isinstance(entry.get("bytes"), int)
        and isinstance(entry.get("sha256"), str)
        and isinstance(entry.get("rows", 0), int)
    )


def spec_from_canonical(canonical: dict) -> Spec:
    """The :class:`Spec` recorded in a directory's ``_spec.json``."""
    data: dict = dict(canonical["grid"])
    data["samples"] = canonical["samples"]
    if canonical.get("packing") is not None:
        data["packing"] = canonical["packing"]
        data["output"] = {"chunk_size": canonical["chunk_size"]}
        return parse_spec(data)
    data["lattice"] = {"kind": canonical["lattice"]}
    data["strain"] = {"gamma": canonical["gamma"], "angles": canonical["angles"]}
    data["solver"] = canonical["solver"]
    data["output"] = {"chunk_size": canonical["chunk_size"]}
    if canonical["threshold"] is not None:
        data["threshold"] = canonical["threshold"]
    if "verdict" in canonical:
        data["verdict"] = canonical["verdict"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # its warnings were shown when it was run
        return parse_spec(data)


def _differences(old: dict, new: dict, prefix: str = "") -> list[str]:
    """Settings that differ, as "name: old there, new in this spec" phrases, each value cut to a
    few words (a whole solver's options would fill a screen)."""
    out = []
    for key in sorted(set(old) | set(new)):
        a, b = old.get(key, _DEFAULT), new.get(key, _DEFAULT)
        if isinstance(a, dict) and isinstance(b, dict):
            out += _differences(a, b, f"{prefix}{key}.")
        elif a != b:
            out.append(f"{prefix}{key}: {_shown(a)} there, {_shown(b)} in this spec")
    return out


#: A setting a spec leaves at its default is absent from its settings.
_DEFAULT = object()


def _shown(value) -> str:
    return "the default" if value is _DEFAULT or value is None else show(value)


class ResultStore:
    """Results of sweeps under one directory (see the module docstring).

    Parameters
    ----------
    root : path
        The directory; created by :meth:`writing` when missing.
    """

    def __init__(self, root: str | os.PathLike):
        if not isinstance(root, (str, os.PathLike)):
            raise SpecError(
                f"the results directory must be a str or path, got {type(root).__name__}"
            )
        if not os.fspath(root):
            raise SpecError("the results directory is empty; give one, e.g. --out runs/a")
        self.root = Path(root)
        self.done: set[tuple[str, int, float]] = set()
        self._entries: dict[str, dict] = {}
        self._locked = False

    # ------------------------------------------------------------------ the writer's lock

    @contextlib.contextmanager
    def writing(self) -> Iterator[ResultStore]:
        """Create DIR if needed and hold its writer's lock; one line if DIR is busy or unusable."""
        if self.root.exists() and not self.root.is_dir():
            raise SpecError(f"{self.root} is a file, not a directory; choose another --out")
        try:
            self.root.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise SpecError(f"cannot create {self.root} ({exc.strerror or exc})") from None
        lock = FileLock(self.root / "_lock")
        try:
            lock.acquire(timeout=1.0)  # (a reader's brief probe, see busy(), is waited out)
        except Timeout:
            raise SpecError(
                f"{self.root} is being written by another sweep ({self.writer() or 'unknown'});"
                " wait for it to finish or choose another --out"
            ) from None
        except OSError as exc:
            raise SpecError(
                f"{self.root} is not writable ({exc.strerror or exc}); choose another --out"
            ) from None
        try:
            try:
                self._atomic_write(
                    self.root / "_writer",
                    f"pid {os.getpid()} on {socket.gethostname()}".encode(),
                )
            except OSError as exc:
                raise SpecError(
                    f"{self.root} is not writable ({exc.strerror or exc}); choose another --out"
                ) from None
            self._locked = True
            yield self
        finally:
            self._locked = False
            with contextlib.suppress(OSError):
                (self.root / "_writer").unlink()
            lock.release()

    def writer(self) -> str | None:
        """Who holds the lock, as recorded by the writer ("pid 123 on host"), if anyone."""
        try:
            return (self.root / "_writer").read_text().strip() or None
        except OSError:
            return None

    def busy(self) -> bool:
        """Whether another process holds the writer's lock now."""
        if not (self.root / "_lock").exists():
            return False
        lock = FileLock(self.root / "_lock")
        try:
            lock.acquire(timeout=0)
        except (Timeout, OSError):
            return True
        lock.release()
        return False

    # ------------------------------------------------------------------ spec and resume

    def recorded(self) -> dict | None:
        """The parsed ``_spec.json`` (None when absent); InputError when unreadable."""
        meta = self.root / "_spec.json"
        if not meta.exists():
            return None
        try:
            data = json.loads(meta.read_text())
        except (OSError, ValueError):
            raise InputError(f"{meta} is unreadable; remove it or choose another --out") from None
        if not isinstance(data, dict) or data.get("format") != FORMAT:
            raise InputError(
                f"{self.root} holds results written by an older version of tensegrity-rigidity "
                "(no row keys or checksums); choose another --out"
            )
        return data

    def recorded_spec(self) -> Spec | None:
        """The latest spec run into DIR, or None; InputError (one line) when it is malformed."""
        data = self.recorded()
        if data is None:
            return None
        try:
            return spec_from_canonical(data["spec"])
        except (KeyError, TypeError, ValueError, AttributeError) as exc:
            what = f"no {exc}" if isinstance(exc, KeyError) else str(exc).splitlines()[0]
            raise InputError(
                f"{self.root / '_spec.json'} does not describe a sweep ({what}); remove it or "
                "choose another --out"
            ) from None

    def prepare(self, spec: Spec, source_text: str | None = None) -> None:
        """Check that DIR may hold this spec, then make it ready to resume (lock held).

        The spec is checked first; only then are stale temporary files removed and the parts
        verified against the manifest (a damaged part is deleted, with a warning, so that its
        rows are recomputed). Finally the spec is recorded as the directory's latest.
        """
        if not self._locked:
            raise RuntimeError("prepare() needs the writer's lock: use `with store.writing():`")
        settings = spec.settings()
        old = self.recorded()
        if old is not None:
            if old.get("settings_digest") != spec.settings_digest():
                recorded = old.get("settings")
                recorded = recorded if isinstance(recorded, dict) else {}
                diff = "; ".join(_differences(recorded, settings)[:3])
                raise SpecError(
                    f"{self.root} holds results of a different sweep ({diff}); choose another "
                    "--out or delete that directory"
                )
            revision = old.get("rows_revision", 1)
            if revision != rows_revision(spec) and self._has_rows():
                raise SpecError(
                    f"{self.root} holds rows of revision {revision}, written by another "
                    f"version of tensegrity-rigidity; this version writes revision "
                    f"{rows_revision(spec)} (see ROWS_REVISION), and resuming would mix the two: "
                    "choose another --out or delete that directory"
                )
        elif self._has_rows():
            raise SpecError(f"{self.root} holds results without a spec; choose another --out")
        self._remove_stale_temporaries()
        self._verify()
        record = {
            "format": FORMAT,
            "rows_revision": rows_revision(spec),
            "settings": settings,
            "settings_digest": spec.settings_digest(),
            "spec": spec.canonical(),
        }
        self._atomic_write(
            self.root / "_spec.json", json.dumps(record, indent=2, sort_keys=True).encode()
        )
        if source_text is not None:
            self._atomic_write(self.root / "_spec.toml", source_text.encode())

    def _has_rows(self) -> bool:
        return any(p.name.startswith("part-") or p.name == "_manifest.jsonl" for p in self._ls())

    def _ls(self) -> list[Path]:
        try:
            return list(self.root.iterdir())
        except OSError:
            return []

    def _remove_stale_temporaries(self) -> None:
        """Hidden ``.<name>.<pid>.tmp`` files whose writer is gone (never a live process's)."""
        for tmp in self._ls():
            name = tmp.name
            if not (name.startswith(".") and name.endswith(".tmp")):
                continue
            try:
                pid = int(name[:-4].rsplit(".", 1)[1])
            except (IndexError, ValueError):
                continue
            if pid != os.getpid() and _pid_alive(pid):
                continue
            tmp.unlink(missing_ok=True)

    def manifest(self) -> dict[str, dict]:
        """Entries of ``_manifest.jsonl`` by part name (a torn last line is ignored)."""
        path = self.root / "_manifest.jsonl"
        entries: dict[str, dict] = {}
        try:
            # a line with bytes that are not UTF-8 is damaged, skipped as a torn one is
            text = path.read_bytes().decode("utf-8", errors="replace")
        except FileNotFoundError:
            return entries
        except OSError as exc:
            raise InputError(f"{path}: cannot read ({exc.strerror})") from None
        for line in text.splitlines():
            try:
                entry = json.loads(line)
            except ValueError:
                continue
            if _valid_entry(entry):
                entries[entry["part"]] = entry
        return entries

    def check_part(self, entry: dict) -> bytes | None:
        """The part's bytes if it exists with the manifest's size and checksum, else None."""
        try:
            data = (self.root / entry["part"]).read_bytes()
        except OSError:
            return None
        if len(data) != entry.get("bytes") or _sha256(data) != entry.get("sha256"):
            return None
        return data

    def _verify(self) -> None:
        """Keep the parts that match the manifest, learn their keys, delete the rest."""
        self.done = set()
        self._entries = {}
        for name, entry in self.manifest().items():
            data = self.check_part(entry)
            if data is None:
                what = "damaged (checksum mismatch)" if (self.root / name).exists() else "missing"
                warnings.warn(
                    f"{self.root / name} is {what}: its {entry.get('rows', '?')} rows are "
                    "recomputed",
                    CorruptPartWarning,
                    stacklevel=3,
                )
                (self.root / name).unlink(missing_ok=True)
                continue
            keys = self._table(name, data, KEY_COLUMNS)
            self.done.update(
                zip(
                    keys.column("point_key").to_pylist(),
                    keys.column("sample").to_pylist(),
                    keys.column("theta").to_pylist(),
                    strict=True,
                )
            )
            self._entries[name] = entry
        for path in self._ls():  # complete parts renamed in place but never listed
            if path.name.startswith("part-") and path.name not in self._entries:
                path.unlink(missing_ok=True)
        lines = "".join(json.dumps(e, sort_keys=True) + "\n" for e in self._entries.values())
        self._atomic_write(self.root / "_manifest.jsonl", lines.encode())

    # ------------------------------------------------------------------ writing and reading

    @staticmethod
    def part_name(frame: pd.DataFrame) -> str:
        """A part's file name from its rows' keys (one grid point per part)."""
        pk = str(frame["point_key"].iloc[0])
        ident = json.dumps([pk, frame["sample"].tolist(), [float(t).hex() for t in frame["theta"]]])
        first = int(frame["sample"].iloc[0])
        return f"part-{pk[:16]}-{first:06d}-{_sha256(ident.encode())[:12]}.parquet"

    def write(self, frame: pd.DataFrame) -> str:
        """Save one chunk's rows as a part and list it in the manifest; returns its name."""
        if not self._locked:
            raise RuntimeError("write() needs the writer's lock: use `with store.writing():`")
        table = pa.Table.from_pandas(frame, preserve_index=False)
        sink = pa.BufferOutputStream()
        pq.write_table(table, sink)
        data = sink.getvalue().to_pybytes()
        name = self.part_name(frame)
        self._atomic_write(self.root / name, data)
        entry = {"part": name, "sha256": _sha256(data), "bytes": len(data), "rows": len(frame)}
        with open(self.root / "_manifest.jsonl", "a") as fh:
            fh.write(json.dumps(entry, sort_keys=True) + "\n")
            fh.flush()
            os.fsync(fh.fileno())
        self._entries[name] = entry
        self.done.update(
            zip(frame["point_key"], frame["sample"].astype(int), frame["theta"], strict=True)
        )
        return name

    def scan(self) -> tuple[pd.DataFrame, list[str], int]:
        """Rows of every listed part that passes its checksum, the damaged parts, total bytes.

        Returns
        -------
        rows : pandas.DataFrame
            Empty when there are none.
        damaged : list of str
            Listed parts that are missing or fail their size or SHA-256.
        size : int
            Bytes of the listed parts, as recorded.
        """
        tables, damaged, size = [], [], 0
        for name, entry in sorted(self.manifest().items()):
            size += int(entry.get("bytes", 0))
            data = self.check_part(entry)
            if data is None:
                damaged.append(name)
            else:
                tables.append(self._table(name, data))
        if not tables:
            return pd.DataFrame(), damaged, size
        try:
            rows = pa.concat_tables(tables, promote_options="default").to_pandas()
        except pa.ArrowException as exc:
            raise InputError(f"{self.root}: parts with different columns ({exc})") from None
        return rows, damaged, size

    def _table(self, name: str, data: bytes, columns: list[str] | None = None) -> pa.Table:
        """A listed part's rows (``columns`` only, if given); a part that matches its checksum
        but is not a results table (written by something else) is refused by name."""
        try:
            return pq.read_table(pa.BufferReader(data), columns=columns)
        except pa.ArrowException as exc:
            raise InputError(
                f"{self.root / name}: not a results part ({str(exc).splitlines()[0]})"
            ) from None

    def read(self) -> pd.DataFrame:
        """Every row of every listed part (empty frame if none); InputError on a damaged part."""
        rows, damaged, _ = self.scan()
        if damaged:
            raise InputError(
                f"{self.root / damaged[0]} is missing or damaged (checksum mismatch); run the "
                "sweep again to recompute it"
            )
        return rows

    def rows_of(self, spec: Spec, frame: pd.DataFrame | None = None) -> pd.DataFrame:
        """The rows of ``frame`` (default: all rows of DIR) that belong to ``spec``."""
        df = self.read() if frame is None else frame
        if df.empty:
            return df
        want = expected_keys(spec)
        return df.merge(want, on=KEY_COLUMNS, how="inner")

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


def expected_keys(spec: Spec) -> pd.DataFrame:
    """The key columns of every row of ``spec``: (point_key, sample, theta), one row each."""
    ks = list(range(1, spec.samples + 1))
    thetas = [spec.angle(k) for k in ks]
    keys = [spec.point_key(p) for p in spec.points()]
    return pd.DataFrame(
        {
            "point_key": [pk for pk in keys for _ in ks],
            "sample": ks * len(keys),
            "theta": thetas * len(keys),
        }
    )
