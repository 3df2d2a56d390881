"""The budget model's per-row costs against the rows of finished runs; writes the costs file.

`reproduce --estimate` prices a run from the measured costs in
`src/tensegrity_rigidity/paper/data/costs.toml` (read by `paper.budget`: seconds per threshold
search, grid solve and paper verdict by size, their p_t factors, the analysis of each study, the
error of one sample of each headline estimator), each with what it is and where it was measured.
This script writes that file.

Every stored row records the seconds its solve took (`solve_seconds`), so a finished run
measures the per-row constants on the work users actually run. The script reads the rows of one
or more run directories (the `--out` of `reproduce`), prices each row with the model (same mode,
n and p_t) and prints, per (mode, n), the measured and modelled means and their ratio: the
constant that would reproduce the measurement is the current one times that ratio (the p_t
factors pool the rows of different p_t). With `--write` it sets those constants in the costs
file, their source naming the runs; with `--analysis` it also times each study's analysis on
the stored rows of the runs (nothing is solved) and writes its seconds per 100 bootstrap
replicas. Constants it does not measure (the 3D ones, the error model) are
carried over unchanged. Rows of a run on a shared machine are slower by its load: use quiet runs.

Run: python benchmarks/calibrate_budget.py RUN_DIR [RUN_DIR ...] [--write] [--analysis]
     [--record]
"""

from __future__ import annotations

import argparse
import json
import time
import tomllib
from pathlib import Path

import pandas as pd
import tomli_w
from _record import machine, record, table

from tensegrity_rigidity.paper import budget

#: the p_t at which each mode's constant is stated (its p_t factor is 1 there)
REFERENCE_PT = {"threshold": 0.3, "pebble": 0.0, "grid": 0.15, "paper": 0.0}
#: the costs file's entry of each mode's per-row seconds
ENTRY = {"threshold": "threshold", "pebble": "pebble", "grid": "grid", "paper": "paper_verdict"}
HEADER = """\
# Measured costs of the budget model (tensegrity_rigidity.paper.budget), each with what it is
# and where it was measured. Written by benchmarks/calibrate_budget.py (--write), which
# measures the per-row seconds and the analysis times on finished runs and carries the other
# entries over; edit by hand only what the script does not measure, and say where it came from.
# Seconds are means of one row on one process of the reference machine (x86_64, 2 cores).

"""


def write_costs(costs: dict, path: Path = budget.DATA) -> None:
    """Write the costs file: its header, then the entries as TOML (sizes as keys)."""
    path.write_text(HEADER + tomli_w.dumps(costs))


def sweep_mode(spec_file: Path) -> str:
    """ "threshold", "pebble", "grid" or "paper" for a stored sweep (its ``_spec.json``)."""
    settings = json.loads(spec_file.read_text())["settings"]
    if settings["mode"] == "threshold":
        return "pebble" if settings.get("threshold_method") == "pebble" else "threshold"
    return "paper" if settings.get("verdict") == "paper" else "grid"


def priced_rows(run: Path) -> pd.DataFrame:
    """Every stored row of a run with its mode, measured and modelled seconds."""
    frames = []
    for spec_file in sorted(run.glob("studies/*/_spec.json")):
        parts = sorted(spec_file.parent.glob("part-*.parquet"))
        if not parts:
            continue
        mode = sweep_mode(spec_file)
        df = pd.concat([pd.read_parquet(p, columns=["n", "p_t", "solve_seconds"]) for p in parts])
        df["model"] = [
            budget.row_seconds(mode, int(n), float(p))[0] for n, p in zip(df.n, df.p_t, strict=True)
        ]
        df["mode"], df["run"], df["sweep"] = mode, run.name, spec_file.parent.name
        frames.append(df)
    if not frames:
        raise SystemExit(f"{run}: no stored rows under studies/")
    return pd.concat(frames, ignore_index=True)


def analysis_seconds(run: Path) -> dict[str, float]:
    """Seconds of each study's analysis on the stored rows of a finished run, per 100
    bootstrap replicas of its scale (the run's scale: the one whose sweeps are all stored)."""
    from tensegrity_rigidity.paper.registry import SCALES, STUDIES
    from tensegrity_rigidity.paper.studies import STORED

    out = {}
    for scale in SCALES.values():
        est = budget.estimate(scale, 1, out=run)
        for name in scale.studies:
            if any(s.new_rows for s in est.sweeps if s.study == name) or name in out:
                continue
            start = time.process_time()
            STUDIES[name](run, scale, workers=STORED, scheduler=None, progress=False)
            out[name] = (time.process_time() - start) * 100 / scale.bootstrap
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("runs", nargs="+", type=Path, help="reproduction output directories")
    ap.add_argument("--record", action="store_true", help="write the table into BENCHMARKS.md")
    ap.add_argument("--write", action="store_true", help="set the measured constants")
    ap.add_argument("--analysis", action="store_true", help="time each study's analysis too")
    args = ap.parse_args()
    rows = pd.concat([priced_rows(r) for r in args.runs], ignore_index=True)
    costs = tomllib.loads(budget.DATA.read_text())
    runs = ", ".join(map(str, args.runs))
    names = ", ".join(f"the {r.name} run" for r in args.runs)  # no machine's paths in the data
    out = []
    for (run, mode, n), g in rows.groupby(["run", "mode", "n"], sort=True):
        ratio = g.solve_seconds.sum() / g.model.sum()
        current, extrapolated = budget.row_seconds(mode, int(n), REFERENCE_PT[mode])
        entry = costs[ENTRY[mode]]
        entry["by_n"][str(int(n))] = float(f"{current * ratio:.4g}")
        entry["source"] = f"benchmarks/calibrate_budget.py on {names} ({machine(dated=False)})"
        out.append(
            [
                run,
                mode,
                int(n),
                len(g),
                f"{g.solve_seconds.mean():.4f}",
                f"{g.solve_seconds.median():.4f}",
                f"{g.model.mean():.4f}",
                f"{ratio:.2f}",
                f"{current:.4g}" + (" (extrapolated)" if extrapolated else ""),
                f"{current * ratio:.4g}",
            ]
        )
    if args.analysis:
        for run in args.runs:
            costs["analysis"]["per_100_replicas"] |= {
                k: float(f"{v:.3g}") for k, v in analysis_seconds(run).items()
            }
        costs["analysis"]["source"] = f"benchmarks/calibrate_budget.py --analysis on {runs}"
    if args.write:
        write_costs(costs)
    header = [
        "run",
        "mode",
        "n",
        "rows",
        "measured mean s",
        "median s",
        "model mean s",
        "measured / model",
        "model at reference p_t",
        "implied",
    ]
    body = (
        f"Machine: {machine()}. Rows of finished `reproduce` runs ({runs}) priced by the "
        "budget model (`paper.budget.row_seconds`, the same mode, n and p_t). 'implied': the "
        "model's per-row seconds at that n and its reference p_t (0.3 for thresholds, 0.15 "
        "for grid rows; its p_t factor is 1 there) times measured / model: the constant that "
        "would have priced these rows exactly.\n\n" + table(header, out)
    )
    if args.record:
        title = "Budget model against finished runs (benchmarks/calibrate_budget.py)"
        record("budget", title, body, raw=[dict(zip(header, r, strict=True)) for r in out])
    else:
        print(body)


if __name__ == "__main__":
    main()
