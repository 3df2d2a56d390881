"""The ``info`` command: what a results directory holds (registered by :mod:`~.cli`)."""

from __future__ import annotations


def add_parser(sub) -> None:
    p = sub.add_parser(
        "info",
        help="say what a results directory holds",
        description="Print the spec of a results directory, how many of its samples are done "
        "and undecided, how many chunks a re-run would compute, and P per grid point.",
    )
    p.add_argument("dir", help="results directory of a sweep")
    p.add_argument("--rows", type=int, default=40, help="grid points shown in the table")
    p.set_defaults(handler=_run)


def _run(args) -> int:
    from ..ensemble.summary import format_table, phi_name, probability_table
    from ..ensemble.sweep import describe, estimate
    from ..errors import InputError
    from ..model.limits import format_bytes

    if args.rows < 1:
        raise InputError(f"--rows must be at least 1, got {args.rows}")
    d = describe(args.dir)
    spec = d["spec"]

    def values(key):
        shown = [phi_name(v) if key == "phi" else f"{v:g}" for v in spec.grid[key]]
        return shown[0] if len(shown) == 1 else "[" + ", ".join(shown) + "]"

    grid = ", ".join(f"{k} = {values(k)}" for k in spec.grid)
    print(f"{args.dir}: {spec.mode} sweep, {spec.n_points()} grid points x {spec.samples} samples")
    print(f"  grid      {grid}")
    path = f", path {spec.threshold['path']}" if spec.threshold else ""
    axes = "SO(3) sequence rotations" if spec.lattice == "fcc" else f"{spec.angles} angles"
    print(
        f"  settings  {spec.lattice} lattice, gamma = {spec.gamma:g}, {axes}"
        f"{path}, solver {spec.solver or 'defaults'}, chunks of {spec.chunk_size}"
    )
    print(
        f"  done      {d['done']} of {d['total']} samples ({d['undecided']} undecided); "
        f"{d['chunks_missing']} chunks missing"
    )
    other = d["rows"] - d["done"]
    extra = f", {other} rows of other specs run here before" if other else ""
    print(f"  stored    {d['parts']} parts, {format_bytes(d['bytes'])}{extra}")
    if d["damaged"]:
        print(f"  damaged   {len(d['damaged'])} parts fail their checksum (a re-run redoes them)")
    if d["chunks_missing"]:
        left = estimate(spec)["cpu_seconds"] * (1 - d["done"] / max(d["total"], 1))
        print(f"  left      about {left / 3600:.2g} CPU-hours (from the benchmark solve times)")
    if d["writer"]:
        print(f"  writer    being written now by {d['writer']}")
    print(format_table(probability_table(d["frame"]), max_rows=args.rows))
    return 0
