"""The ``info`` command: what a results directory holds (registered by :mod:`~.cli`)."""

from __future__ import annotations

from pathlib import Path

#: the file that makes a directory a sweep's results directory
SPEC_FILE = "_spec.json"


def add_parser(sub) -> None:
    p = sub.add_parser(
        "info",
        help="say what a results directory holds",
        description="Print the spec of a results directory, how many of its samples are done "
        "and undecided, how many chunks a re-run would compute, and P per grid point. On the "
        "output directory of reproduce: the same counts per sweep of its studies.",
    )
    p.add_argument("dir", help="results directory of a sweep, or the output directory of reproduce")
    p.add_argument(
        "--rows", type=int, default=40, help="grid points (or sweeps) shown in the table"
    )
    p.set_defaults(handler=_run)


def _run(args) -> int:
    from ..ensemble.summary import format_table, phi_name, probability_table
    from ..ensemble.sweep import describe, estimate
    from ..errors import InputError
    from ..model.limits import format_bytes

    if args.rows < 1:
        raise InputError(f"--rows must be at least 1, got {args.rows}")
    sweeps = _sub_sweeps(Path(args.dir))
    if sweeps:
        return _reproduction(Path(args.dir), sweeps, args.rows)
    d = describe(args.dir)
    spec = d["spec"]

    def values(key):
        shown = [phi_name(v) if key == "phi" else f"{v:g}" for v in spec.grid[key]]
        return shown[0] if len(shown) == 1 else "[" + ", ".join(shown) + "]"

    grid = ", ".join(f"{k} = {values(k)}" for k in spec.grid)
    print(f"{args.dir}: {spec.mode} sweep, {spec.n_points()} grid points x {spec.samples} samples")
    print(f"  grid      {grid}")
    path = ""
    if spec.threshold:
        method = spec.threshold.get("method", "lp")
        path = f", path {spec.threshold['path']} by {method}"
        if method == "pebble":  # the pebble game solves nothing: no solver options apply
            path += " (combinatorial)"
    axes = "SO(3) sequence rotations" if spec.lattice == "fcc" else f"{spec.angles} angles"
    if spec.packing is not None:
        dim, ratio = spec.packing["dim"], spec.packing["ratio"]
        print(f"  settings  bidisperse soft packings in {dim}D, diameter ratio {ratio:g}, "
              f"chunks of {spec.chunk_size}")  # fmt: skip
    else:
        print(
            f"  settings  {spec.lattice} lattice, gamma = {spec.gamma:g}, {axes}"
            f"{path}, solver {_solver(spec)}, chunks of {spec.chunk_size}"
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


def _sub_sweeps(root: Path) -> list[Path]:
    """The sweep directories of a ``reproduce`` output directory (``root/studies/*``); empty
    when ``root`` is not one (a sweep's own directory, or neither)."""
    studies = root / "studies"
    if not studies.is_dir() or (root / SPEC_FILE).exists():
        return []
    return sorted(d for d in studies.iterdir() if d.is_dir() and (d / SPEC_FILE).exists())


def _kind(spec) -> str:
    if spec.mode == "packing":
        return "packing (jamming)"
    if spec.mode == "threshold":
        method = (spec.threshold or {}).get("method")
        return "threshold (pebble)" if method == "pebble" else "threshold"
    return "grid (paper's verdict)" if spec.verdict == "paper" else "grid"


def _reproduction(root: Path, sweeps: list[Path], max_rows: int) -> int:
    """``info`` on the output directory of ``reproduce``: one line per sweep and the totals."""
    from ..ensemble.sweep import describe
    from ..errors import InputError
    from ..model.limits import format_bytes

    lines, done, total, undecided, missing, size, damaged = [], 0, 0, 0, 0, 0, 0
    for path in sweeps:
        try:
            d = describe(path)
        except InputError as exc:
            lines.append((path.name, "unreadable", "-", "-", "-", str(exc)))
            continue
        done, total, undecided = done + d["done"], total + d["total"], undecided + d["undecided"]
        missing, size, damaged = (
            missing + d["chunks_missing"],
            size + d["bytes"],
            damaged + len(d["damaged"]),
        )
        note = "being written now" if d["writer"] else ""
        note = f"{len(d['damaged'])} damaged parts" if d["damaged"] else note
        lines.append(
            (
                path.name,
                _kind(d["spec"]),
                f"{d['done']} / {d['total']}",
                str(d["undecided"]),
                str(d["chunks_missing"]),
                note,
            )
        )
    reports = [name for name in ("report.md", "report.html") if (root / name).is_file()]
    written = f"{' and '.join(reports)} written" if reports else "no report yet"
    print(f"{root}: the output of reproduce, {len(sweeps)} sweeps under studies/, {written}")
    print(f"  samples   {done} of {total} done ({undecided} undecided); {missing} chunks missing")
    print(
        f"  stored    {format_bytes(size)}"
        + (f", {damaged} damaged parts (a re-run redoes them)" if damaged else "")
    )
    head = ("sweep", "mode", "done / asked", "undecided", "chunks missing", "")
    shown = [head, *lines[:max_rows]]
    widths = [max(len(row[i]) for row in shown) for i in range(len(head))]
    for row in shown:
        print("  ".join(cell.ljust(w) for cell, w in zip(row, widths, strict=True)).rstrip())
    if len(lines) > max_rows:
        more = len(lines) - max_rows
        print(f"... {more} more {'sweep' if more == 1 else 'sweeps'} (--rows to show them)")
    return 0


def _solver(spec) -> str:
    """The solver options a spec sets, in a line ("defaults", "unused" for the pebble game)."""
    from ..model.network import show

    if spec.threshold and spec.threshold.get("method") == "pebble":
        return "unused"
    return show(spec.solver) if spec.solver else "defaults"
