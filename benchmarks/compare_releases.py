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
* the near-threshold set at n = 16 (``near_threshold_set.py``): ``--near`` samples cycling
  through its six configurations, five events around each sample's threshold (found by the
  old release).

Per instance and side it records status, stage, factorisations, iterations, a digest of the
certificates' bits and the wall time; it prints the number of instances whose status, stage,
work counts or certificate bits differ, and writes everything as JSON (``--out``).

Run: python benchmarks/compare_releases.py [--old 5454841] [--small 300] [--suite 100]
     [--near 12] [--out benchmarks/results/compare_releases.json]
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


def _generate(folder: Path, small: int, suite: int, near: int) -> None:
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
    if near:
        from benchmarks.near_threshold_set import samples

        for c, k, (net, u, v, eps, p_t, f_c) in samples(16, near):
            th = find_threshold(net, u, v, eps, p_t, f_c)
            path = EventPath(u, v, "p_r", p_t, f_c)
            if not np.isfinite(th.s):
                continue
            mid = int(np.searchsorted(path.positions, th.s))
            for event in range(max(mid - 2, 0), min(mid + 3, path.n_events + 1)):
                inst = Instance(net.with_kinds(path.kinds(event)), eps)
                save_instance(folder / f"near-c{c}-k{k}-e{event:05d}.npz", inst)


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


def _run(folder: Path, out: Path, solve_prefix: tuple[str, ...]) -> None:
    """decide() (and solve() on files starting with one of ``solve_prefix``) on every
    instance."""
    from tensegrity_rigidity import decide, load_instance, solve

    warnings.simplefilter("ignore")
    rows = {}
    for f in sorted(folder.glob("*.npz")):
        inst = load_instance(f)
        t0 = time.perf_counter()
        v = decide(inst)
        seconds = time.perf_counter() - t0
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
        }
        if f.name.startswith(solve_prefix):
            t0 = time.perf_counter()
            r = solve(inst)
            row["solve_seconds"] = time.perf_counter() - t0
            row["solve"] = [r.status, r.method, r.factorizations, r.iterations, r.min_norm_ok]
            row["solve_bits"] = _bits(
                r.tensions,
                r.displacements,
                np.array([r.energy, r.energy_lower, *r.min_norm_residuals, r.min_norm_lower]),
            )
            row["solve_message"] = r.message
        rows[f.stem] = row
    out.write_text(json.dumps(rows))


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


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", default=BASE, help="git revision of the old release")
    ap.add_argument("--new", default=None, help="git revision (default: this working tree)")
    ap.add_argument("--small", type=int, default=300)
    ap.add_argument("--suite", type=int, default=100)
    ap.add_argument("--near", type=int, default=12, help="near-threshold samples at n = 16")
    ap.add_argument("--out", type=Path, default=ROOT / "benchmarks/results/compare_releases.json")
    ap.add_argument("--worker", choices=["generate", "run"], help=argparse.SUPPRESS)
    ap.add_argument("--root", type=Path, help=argparse.SUPPRESS)
    ap.add_argument("--folder", type=Path, help=argparse.SUPPRESS)
    ap.add_argument("--result", type=Path, help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.worker:
        _check_import(a.root)
        if a.worker == "generate":
            _generate(a.folder, a.small, a.suite, a.near)
        else:
            _run(a.folder, a.result, ("small-", "suite-", "near-"))
        return
    with tempfile.TemporaryDirectory(prefix="compare-releases-") as tmp:
        tmp_path = Path(tmp)
        old_root = _export(a.old, tmp_path / "old")
        new_root = ROOT if a.new is None else _export(a.new, tmp_path / "new")
        folder = tmp_path / "instances"
        counts = ["--small", str(a.small), "--suite", str(a.suite), "--near", str(a.near)]
        _worker(old_root, "generate", "--folder", str(folder), *counts)
        sides = {}
        for side, root in (("old", old_root), ("new", new_root)):
            t0 = time.perf_counter()
            out = tmp_path / f"{side}.json"
            _worker(root, "run", "--folder", str(folder), "--result", str(out))
            sides[side] = json.loads(out.read_text())
            print(f"{side}: {len(sides[side])} instances in {time.perf_counter() - t0:.1f} s")
    result = compare(sides["old"], sides["new"])
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
        "seconds": {
            side: {name: row["seconds"] for name, row in rows.items()}
            for side, rows in sides.items()
        },
        "total_seconds": {
            side: sum(row["seconds"] for row in rows.values()) for side, rows in sides.items()
        },
        "rows": sides,
    }
    a.out.parent.mkdir(parents=True, exist_ok=True)
    a.out.write_text(json.dumps(record, indent=1))
    print(f"{record['instances']} instances; differences: {result['counts']}")
    print(
        "decide() seconds in all: "
        + ", ".join(f"{k} {v:.1f}" for k, v in record["total_seconds"].items())
    )
    print(f"written {a.out}")


if __name__ == "__main__":
    main()
