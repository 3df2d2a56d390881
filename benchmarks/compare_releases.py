"""Verdicts of two releases side by side on the same instances: the refactoring check.

Exports the source of ``--old`` (a git revision, default the commit the solver refactoring
started from) into a temporary directory and runs :func:`~tensegrity_rigidity.decide` and
:func:`~tensegrity_rigidity.solve` on every instance in both releases,
each release in its own subprocess with ``PYTHONPATH`` pointing at its ``src``. The new side is
this working tree (uncommitted changes included) unless ``--new`` names a revision too.

Instances (written once as ``.npz`` files by the old release, read by both):

* ``--small`` random small lattice samples (n in 4..10, p_r, p_t, f_c and the strain random,
  seeded by their index), a fifth of them again with random stiffnesses;
* ``--suite`` instances of the test suite's generator (``tests/instances.py``);
* the near-threshold set (``near_threshold_set.py``) at the sizes ``--near-sizes``:
  ``--near`` samples per size cycling through its six configurations, five events around each
  sample's threshold (found by the old release).

Per instance and side it records status, stage, factorisations, iterations, a digest of the
certificates' bits, the wall time and the CPU time (``time.process_time``); it prints the number
of instances whose status, stage, work counts or certificate bits differ. The instances run in
``--batches`` interleaved batches, old and new in turn, so that both sides share the machine's
load. ``--searches`` threshold searches of the near-threshold set at each of ``--search-sizes``
run on both sides, sample by sample in turn: their brackets are compared and their CPU times
recorded. Everything is written as JSON (``--out``).

Run: python benchmarks/compare_releases.py [--old 5454841] [--small 300] [--suite 100]
     [--near 12 2 1] [--near-sizes 16 32 64] [--searches 4 2] [--search-sizes 32 64]
     [--batches 4] [--out benchmarks/results/compare_releases.json]
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import json
import os
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
BASE = "5454841"


def _export(rev: str, dest: Path) -> Path:
    """``src``, ``tests`` and ``benchmarks`` of revision ``rev`` under ``dest``."""
    dest.mkdir(parents=True)
    archive = subprocess.run(
        ["git", "-C", str(ROOT), "archive", rev, "src", "tests", "benchmarks"],
        check=True,
        capture_output=True,
    ).stdout
    subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
    return dest


def _worker(root: Path, mode: str, *args: str) -> None:
    env = dict(os.environ, PYTHONPATH=f"{root / 'src'}{os.pathsep}{root}")
    env["OMP_NUM_THREADS"] = env["OPENBLAS_NUM_THREADS"] = "1"
    subprocess.run(
        [sys.executable, __file__, "--worker", mode, "--root", str(root), *args],
        env=env,
        check=True,
    )


# --------------------------------------------------------------------------- worker side


def _check_import(root: Path) -> None:
    import tensegrity_rigidity

    where = Path(tensegrity_rigidity.__file__).resolve()
    if not where.is_relative_to((root / "src").resolve()):
        raise SystemExit(f"imported {where}, expected the package under {root / 'src'}")


def _generate(folder: Path, small: int, suite: int, near: list[int], sizes: list[int]) -> None:
    """Write the instances as ``.npz`` files (names sort in the order they are run)."""
    from tensegrity_rigidity import Instance, find_threshold, lattice_instance, save_instance
    from tensegrity_rigidity.ensemble.thresholds import EventPath

    folder.mkdir(parents=True, exist_ok=True)
    for i in range(small):
        rng = np.random.default_rng([74, i])
        n = int(rng.integers(4, 11))
        p_r = float(rng.uniform(0.2, 0.9))
        p_t = float(rng.uniform(0.0, 1.0 - p_r))
        f_c = float(rng.choice([0.0, 0.5, 1.0, rng.random()]))
        inst = lattice_instance(
            n, p_r, p_t, f_c, phi=float(rng.uniform(0, np.pi)),
            theta=float(rng.uniform(0, 2 * np.pi)), seed=rng,
        )  # fmt: skip
        save_instance(folder / f"small-{i:04d}.npz", inst)
        if i % 5 == 0:  # a fifth again with random stiffnesses (the relaxation's own problem)
            k = 10 ** rng.uniform(-1, 1, inst.network.n_sites)
            net = dataclasses.replace(inst.network, stiffness=k)
            save_instance(folder / f"small-{i:04d}-k.npz", Instance(net, inst.strain))
    if suite:
        from tests.instances import random_instance

        for i in range(suite):
            save_instance(folder / f"suite-{i:04d}.npz", random_instance(np.random.default_rng(i)))
    from benchmarks.near_threshold_set import samples

    for n, count in zip(sizes, near, strict=True):
        for c, k, (net, u, v, eps, p_t, f_c) in samples(n, count):
            th = find_threshold(net, u, v, eps, p_t, f_c)
            path = EventPath(u, v, "p_r", p_t, f_c)
            if not np.isfinite(th.s):
                continue
            mid = int(np.searchsorted(path.positions, th.s))
            for event in range(max(mid - 2, 0), min(mid + 3, path.n_events + 1)):
                inst = Instance(net.with_kinds(path.kinds(event)), eps)
                save_instance(folder / f"near{n}-c{c}-k{k}-e{event:05d}.npz", inst)


def _bits(*arrays) -> str:
    h = hashlib.sha256()
    for a in arrays:
        if a is None:
            continue
        a = np.ascontiguousarray(a)
        if a.dtype == np.longdouble and a.dtype.itemsize > 10:  # x87: 10 bytes and padding
            a = a.reshape(-1, 1).view(np.uint8)[:, :10]
        h.update(a.tobytes())
    return h.hexdigest()[:16]


def _run(folder: Path, out: Path, batch: int, batches: int) -> None:
    """decide() and solve() on every ``batches``-th instance from the ``batch``-th."""
    from tensegrity_rigidity import decide, load_instance, solve

    warnings.simplefilter("ignore")
    rows = {}
    for f in sorted(folder.glob("*.npz"))[batch::batches]:
        inst = load_instance(f)
        t0, c0 = time.perf_counter(), time.process_time()
        v = decide(inst)
        seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
        rc, fc = v.rigid, v.floppy
        row = {
            "status": v.status,
            "stage": v.stage,
            "work": [v.factorizations, v.iterations],
            "bits": _bits(
                None if rc is None else rc.t,
                None if fc is None else fc.u,
                np.array([getattr(rc, "work", 0.0), getattr(rc, "residual", 0.0)]),
                np.array([getattr(fc, "violation", 0.0), getattr(fc, "size", 0.0)]),
            ),
            "seconds": seconds,
            "cpu": cpu,
        }
        t0, c0 = time.perf_counter(), time.process_time()
        r = solve(inst)
        row["solve_seconds"] = time.perf_counter() - t0
        row["solve_cpu"] = time.process_time() - c0
        row["solve"] = [r.status, r.method, r.factorizations, r.iterations, r.min_norm_ok]
        row["solve_bits"] = _bits(
            r.tensions,
            r.displacements,
            np.array([r.energy, r.energy_lower, *r.min_norm_residuals, r.min_norm_lower]),
        )
        row["solve_message"] = r.message
        rows[f.stem] = row
    out.write_text(json.dumps(rows))


def _search(out: Path, n: int, index: int) -> None:
    """The threshold search of near-threshold sample ``index`` at size ``n``: its bracket,
    probes and CPU time."""
    from benchmarks.near_threshold_set import samples
    from tensegrity_rigidity import find_threshold

    warnings.simplefilter("ignore")
    *_, (_, _, (net, u, v, eps, p_t, f_c)) = samples(n, index + 1)
    c0 = time.process_time()
    th = find_threshold(net, u, v, eps, p_t, f_c)
    cpu = time.process_time() - c0
    row = {"s": th.s, "s_low": th.s_low, "s_high": th.s_high, "solves": th.solves}
    out.write_text(json.dumps({**row, "undecided": th.undecided, "cpu": cpu}))


# --------------------------------------------------------------------------- driver


def compare(old: dict, new: dict) -> dict:
    """Counts of instances whose results differ, by kind, and the names of those that do."""
    keys = {
        "status": ["status"],
        "stage": ["stage"],
        "work": ["work"],
        "certificate_bits": ["bits"],
        "solve": ["solve", "solve_message"],
        "solve_bits": ["solve_bits"],
    }
    differ: dict[str, list[str]] = {k: [] for k in keys}
    for name in sorted(old):
        a, b = old[name], new.get(name, {})
        for kind, fields in keys.items():
            if any(a.get(x) != b.get(x) for x in fields):
                differ[kind].append(name)
    return {"counts": {k: len(v) for k, v in differ.items()}, "differing": differ}


def _by_kind(rows: dict, key: str) -> dict:
    """Sums of ``key`` over the rows of each instance kind (the name up to its first '-')."""
    out: dict[str, float] = {}
    for name, row in rows.items():
        kind = name.split("-")[0]
        out[kind] = out.get(kind, 0.0) + row[key]
    return out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", default=BASE, help="git revision of the old release")
    ap.add_argument("--new", default=None, help="git revision (default: this working tree)")
    ap.add_argument("--small", type=int, default=300)
    ap.add_argument("--suite", type=int, default=100)
    ap.add_argument("--near", type=int, nargs="+", default=[12], help="samples per near size")
    ap.add_argument("--near-sizes", type=int, nargs="+", default=[16])
    ap.add_argument("--searches", type=int, nargs="+", default=[], help="searches per size")
    ap.add_argument("--search-sizes", type=int, nargs="+", default=[])
    ap.add_argument("--batches", type=int, default=4, help="interleaved batches of instances")
    ap.add_argument("--out", type=Path, default=ROOT / "benchmarks/results/compare_releases.json")
    ap.add_argument("--worker", choices=["generate", "run", "search"], help=argparse.SUPPRESS)
    ap.add_argument("--root", type=Path, help=argparse.SUPPRESS)
    ap.add_argument("--folder", type=Path, help=argparse.SUPPRESS)
    ap.add_argument("--result", type=Path, help=argparse.SUPPRESS)
    ap.add_argument("--batch", type=int, default=0, help=argparse.SUPPRESS)
    ap.add_argument("--index", type=int, default=0, help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if len(a.searches) != len(a.search_sizes):
        ap.error("--searches needs one count per size of --search-sizes")
    if a.worker:
        _check_import(a.root)
        if a.worker == "generate":
            _generate(a.folder, a.small, a.suite, a.near, a.near_sizes)
        elif a.worker == "run":
            _run(a.folder, a.result, a.batch, a.batches)
        else:
            _search(a.result, a.near_sizes[0], a.index)
        return
    sides: dict[str, dict] = {"old": {}, "new": {}}
    searches: dict[str, dict] = {"old": {}, "new": {}}
    with tempfile.TemporaryDirectory(prefix="compare-releases-") as tmp:
        tmp_path = Path(tmp)
        roots = {"old": _export(a.old, tmp_path / "old")}
        roots["new"] = ROOT if a.new is None else _export(a.new, tmp_path / "new")
        folder = tmp_path / "instances"
        counts = ["--small", str(a.small), "--suite", str(a.suite)]
        counts += ["--near", *map(str, a.near), "--near-sizes", *map(str, a.near_sizes)]
        _worker(roots["old"], "generate", "--folder", str(folder), *counts)
        # old and new in turn, each batch in the other order, so both share the load alike
        for batch in range(a.batches):
            for side in ("old", "new") if batch % 2 == 0 else ("new", "old"):
                out = tmp_path / f"{side}-{batch}.json"
                args = ["--folder", str(folder), "--result", str(out)]
                _worker(
                    roots[side], "run", *args, "--batch", str(batch), "--batches", str(a.batches)
                )
                sides[side].update(json.loads(out.read_text()))
            print(f"batch {batch + 1} of {a.batches} done", flush=True)
        for n, count in zip(a.search_sizes, a.searches, strict=True):
            for i in range(count):
                for side in ("old", "new") if i % 2 == 0 else ("new", "old"):
                    out = tmp_path / f"search-{side}.json"
                    args = ["--result", str(out), "--near-sizes", str(n), "--index", str(i)]
                    _worker(roots[side], "search", *args)
                    searches[side][f"n{n}-{i}"] = json.loads(out.read_text())
                print(f"search n = {n} sample {i}: " + ", ".join(
                    f"{side} {searches[side][f'n{n}-{i}']['cpu']:.1f} s" for side in searches
                ), flush=True)  # fmt: skip
    result = compare(sides["old"], sides["new"])
    brackets = ("s", "s_low", "s_high", "undecided")
    search_differ = [
        key
        for key in searches["old"]
        if any(searches["old"][key][x] != searches["new"][key][x] for x in brackets)
    ]
    commit = subprocess.run(
        ["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True
    ).stdout.strip()
    dirty = bool(
        subprocess.run(
            ["git", "-C", str(ROOT), "status", "--porcelain", "src"], capture_output=True, text=True
        ).stdout.strip()
    )
    record = {
        "old": a.old,
        "new": a.new or f"working tree at {commit}" + (" (modified)" if dirty else ""),
        "instances": len(sides["old"]),
        **result,
        "decide_cpu_by_kind": {side: _by_kind(rows, "cpu") for side, rows in sides.items()},
        "solve_cpu_by_kind": {side: _by_kind(rows, "solve_cpu") for side, rows in sides.items()},
        "total_seconds": {
            side: sum(row["seconds"] for row in rows.values()) for side, rows in sides.items()
        },
        "searches": searches,
        "search_brackets_differing": search_differ,
        "rows": sides,
    }
    a.out.parent.mkdir(parents=True, exist_ok=True)
    a.out.write_text(json.dumps(record, indent=1))
    print(f"{record['instances']} instances; differences: {result['counts']}")
    for what in ("decide_cpu_by_kind", "solve_cpu_by_kind"):
        for kind in record[what]["old"]:
            old, new = record[what]["old"][kind], record[what]["new"].get(kind, float("nan"))
            print(f"{what} {kind}: old {old:.2f} s, new {new:.2f} s")
    for key in searches["old"]:
        old, new = searches["old"][key], searches["new"][key]
        print(f"search {key}: cpu old {old['cpu']:.1f} s, new {new['cpu']:.1f} s; same bracket "
              f"{key not in search_differ}")  # fmt: skip
    print(f"written {a.out}")


if __name__ == "__main__":
    main()
