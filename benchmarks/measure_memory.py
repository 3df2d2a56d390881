"""Memory per node of what a sweep and the API do with one sample, per lattice (and so dimension).

Each measurement runs in a fresh process: it first does the same work on a small sample (so
that the libraries' lazy start-up, numba's compiled kernels, CHOLMOD, HiGHS, is not charged to
nodes), then builds the sample it measures, resets the kernel's high-water mark of resident
memory (``/proc/self/clear_refs``) and reads it again after the work: the bytes the work added
at its peak, C libraries included (tracemalloc sees only Python's allocations). Stages:

* ``build``: ``lattice_instance`` (geometry, bonds, uniforms, kinds);
* ``solve``: ``solve`` (the verdict, the relaxed state, the minimum-norm displacements) of a
  built sample, over a few ``(p_r, p_t)`` at and away from the transition (the largest counts);
* ``threshold``: ``find_threshold`` along ``p_r`` (certified bisection: a dozen verdicts, the
  LP among them, and the certificates carried between them), as threshold sweeps run it;
* ``clusters``: ``rigid_clusters(..., as_rods=True)``, the pebble game (2D lattices only).

The guard of each (lattice, stage) is the largest bytes per node measured at any size times
:data:`MARGIN`, rounded up to 100 bytes. Where the cost per node grows with the size (3D
factorisations fill in as ``N^(4/3)``), the fitted exponent of ``bytes ~ N^e`` (at least 1) is
written too, and the guard grows with it from the largest size measured. The script WRITES the
package's data file ``src/tensegrity_rigidity/model/memory_costs.toml`` (read by
``model.limits``), its table into BENCHMARKS.md and its raw measurements to
``benchmarks/results/measure_memory.json``.

Run: python benchmarks/measure_memory.py [--quick] [--record]   (Linux only: /proc)
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
from _record import ROOT, machine, record, table

from tensegrity_rigidity.model.sampling import LATTICE_DIMENSIONS

#: the guard over the largest measured cost per node
MARGIN = 1.25
#: sizes that enter the growth fit: below these a measurement is mostly the allocator's
#: reuse of what the warm-up freed (a few MiB either way), not the work's own memory
FIT_NODES = 200
FIT_BYTES = 4 << 20
#: samples (seeds) measured per point: the memory of a verdict search varies from sample to
#: sample (a threshold at n = 10 in 3D took 48 to 72 kB per node)
SEEDS = {"build": (7,), "clusters": (7,), "solve": (7, 3), "threshold": (7, 3)}
#: where the costs are written (read by tensegrity_rigidity.model.limits)
COSTS = ROOT / "src" / "tensegrity_rigidity" / "model" / "memory_costs.toml"
#: linear sizes per lattice and stage (the default run; --quick: the two smallest)
SIZES = {
    ("triangular", "build"): [128, 256, 512],
    ("triangular", "solve"): [32, 64, 128],
    ("triangular", "threshold"): [16, 32, 64],
    ("triangular", "clusters"): [128, 256, 512],
    ("square", "build"): [128, 256, 512],
    ("square", "solve"): [32, 64, 128],
    ("square", "threshold"): [16, 32, 64],
    ("square", "clusters"): [128, 256, 512],
    ("fcc", "build"): [16, 32, 48],
    ("fcc", "solve"): [4, 6, 8, 10, 12],
    ("fcc", "threshold"): [6, 8, 10, 12],
}
QUICK = {key: sizes[:2] for key, sizes in SIZES.items()}
#: (p_r, p_t, phi) of the measured samples per stage: for a solve, rigid rods, rods near the
#: transition and mixed ones near it; for a threshold (p_r is its path), cables and struts
#: under dilation and compression
POINTS = {
    "build": {"*": [(0.6, 0.0, "shear")]},
    "clusters": {"*": [(0.6, 0.0, "shear")]},
    "solve": {
        "triangular": [(0.9, 0.0, "shear"), (0.66, 0.0, "shear"), (0.45, 0.35, "shear")],
        "square": [(0.9, 0.0, "shear"), (0.6, 0.3, "shear")],
        "fcc": [(0.9, 0.0, "shear"), (0.5, 0.0, "shear"), (0.2, 0.5, "dilation")],
    },
    "threshold": {"*": [(0.0, 0.3, "dilation"), (0.0, 0.3, "compression")]},
}
#: the size of the warm-up sample (same stage, same lattice): the smallest, so that little of
#: the memory it frees is there for the measured work to reuse unseen
WARM_UP = {"triangular": 4, "square": 4, "fcc": 2}

CHILD = r"""
import gc, json, sys
import numpy as np
from tensegrity_rigidity import find_threshold, lattice_instance, rigid_clusters, solve
from tensegrity_rigidity import strain_tensor
from tensegrity_rigidity.model.sampling import lattice_geometry

lattice, stage, n, p_r, p_t, phi, warm, seed = sys.argv[1:9]
n, p_r, p_t, warm, seed = int(n), float(p_r), float(p_t), int(warm), int(seed)


def status(field):
    for line in open("/proc/self/status"):
        if line.startswith(field + ":"):
            return int(line.split()[1]) * 1024
    raise RuntimeError(field)


def prepare(size):
    # what the stage starts from, and the work itself
    if stage == "build":
        return None, lambda: lattice_instance(size, p_r, p_t, 0.5, phi, lattice=lattice, seed=seed)
    if stage == "threshold":
        net, u, v = lattice_geometry(size, 0.2, np.random.default_rng(seed), lattice)
        eps = strain_tensor(phi, dim=net.dim)
        return net, lambda: find_threshold(net, u, v, eps, p_t, 0.5)
    inst = lattice_instance(size, p_r, p_t, 0.5, phi, lattice=lattice, seed=seed)
    if stage == "solve":
        return inst.network, lambda: solve(inst)
    return inst.network, lambda: rigid_clusters(inst, as_rods=True)


prepare(warm)[1]()
net, work = prepare(n)
gc.collect()
before = status("VmRSS")
with open("/proc/self/clear_refs", "w") as fh:
    fh.write("5")  # the high-water mark starts again from the current resident memory
result = work()
peak = status("VmHWM")
nodes = (result.network if stage == "build" else net).n_nodes
extra = {"status": result.status} if stage == "solve" else {}
if stage == "threshold":
    extra = {"solves": result.solves}
print(json.dumps({"nodes": nodes, "bytes": peak - before, **extra}))
"""


def measure(
    lattice: str, stage: str, n: int, p_r: float, p_t: float, phi: str, seed: int = 7
) -> dict:
    """One measurement in a fresh process."""
    args = [lattice, stage, str(n), str(p_r), str(p_t), phi, str(WARM_UP[lattice]), str(seed)]
    out = subprocess.run(
        [sys.executable, "-c", CHILD, *args], capture_output=True, text=True, check=True
    )
    row = json.loads(out.stdout.strip().splitlines()[-1])
    point = {"p_r": p_r, "p_t": p_t, "phi": phi, "seed": seed}
    return {"lattice": lattice, "stage": stage, "n": n, **point, **row}


def guard(rows: list[dict]) -> tuple[int, float, int]:
    """(bytes per node, exponent, nodes of the largest size) of one lattice and stage.

    The worst point and sample at each size; the guard is the largest cost per node of any
    size times MARGIN, rounded up to 100 bytes. The exponent of ``bytes ~ N^e`` is fitted (least
    squares in logarithms) over the sizes whose measurement is above the noise of the
    allocator (:data:`FIT_NODES` nodes and :data:`FIT_BYTES` bytes at least), and taken as 1
    unless the cost per node grows or when fewer than two sizes qualify.
    """
    by_size: dict[int, float] = {}
    for r in rows:
        by_size[r["nodes"]] = max(by_size.get(r["nodes"], 0.0), r["bytes"])
    nodes = np.array(sorted(by_size), dtype=float)
    worst = np.array([by_size[int(k)] for k in nodes])
    fit = (nodes >= FIT_NODES) & (worst >= FIT_BYTES)
    exponent = 1.0
    if np.count_nonzero(fit) >= 2:
        slope = float(np.polyfit(np.log(nodes[fit]), np.log(worst[fit]), 1)[0])
        exponent = max(1.0, round(slope, 2))
    per_node = float((worst / nodes).max())
    return int(math.ceil(per_node * MARGIN / 100.0) * 100), exponent, int(nodes[-1])


def write_costs(guards: dict, about: str) -> None:
    """The data file model.limits reads."""
    lines = [
        "# Memory per node of one sample, per lattice: written by benchmarks/measure_memory.py",
        "# (do not edit by hand; run it again). Bytes per node at the largest size measured",
        f"# (`nodes`), the worst of the measured points times {MARGIN}; where the cost per node",
        "# grows with the size, `*_exponent` e > 1 scales it as (N / nodes)^(e - 1) above it.",
        f"# {about}",
        "",
    ]
    for lattice, stages in guards.items():
        lines.append(f"[{lattice}]")
        lines.append(f"dim = {LATTICE_DIMENSIONS[lattice]}")
        for stage, (per_node, exponent, nodes) in stages.items():
            lines.append(f"{stage} = {per_node}")
            lines.append(f"{stage}_exponent = {exponent}")
            lines.append(f"{stage}_nodes = {nodes}")
        lines.append("")
    COSTS.write_text("\n".join(lines))


def main() -> None:
    if not Path("/proc/self/clear_refs").exists():
        raise SystemExit("needs Linux (/proc/self/clear_refs)")
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true", help="the two smallest sizes only")
    ap.add_argument("--record", action="store_true", help="write the table into BENCHMARKS.md")
    args = ap.parse_args()
    sizes = QUICK if args.quick else SIZES
    rows = []
    for (lattice, stage), ns in sizes.items():
        points = POINTS[stage].get(lattice) or POINTS[stage]["*"]
        for n in ns:
            for (p_r, p_t, phi), seed in itertools.product(points, SEEDS[stage]):
                row = measure(lattice, stage, n, p_r, p_t, phi, seed)
                rows.append(row)
                print(json.dumps(row), flush=True)
    guards: dict[str, dict] = {}
    for (lattice, stage), _ in sizes.items():
        mine = [r for r in rows if r["lattice"] == lattice and r["stage"] == stage]
        guards.setdefault(lattice, {})[stage] = guard(mine)
    about = machine()
    write_costs(guards, about)
    out = [
        [
            r["lattice"],
            r["stage"],
            r["n"],
            r["nodes"],
            f"{r['p_r']:g}, {r['p_t']:g}, {r['phi']}, {r['seed']}",
            r.get("status", r.get("solves", "")),
            f"{r['bytes'] / 2**20:.1f}",
            f"{r['bytes'] / r['nodes']:,.0f}",
        ]
        for r in rows
    ]
    body = (
        f"Machine: {about}.\n\n"
        + table(
            [
                "lattice",
                "stage",
                "n",
                "nodes",
                "p_r, p_t, phi, seed",
                "verdict / solves",
                "MiB",
                "bytes / node",
            ],
            out,
        )
        + "\n\nGuards written to `src/tensegrity_rigidity/model/memory_costs.toml` (bytes per "
        + "node, exponent): "
        + "; ".join(
            f"{lat} {st} {g[0]:,} B ({g[1]:g})" for lat, s in guards.items() for st, g in s.items()
        )
        + "."
    )
    if args.record:
        record("memory", "Memory per node (measure_memory.py)", body, rows)
    else:
        print(body)


if __name__ == "__main__":
    main()
