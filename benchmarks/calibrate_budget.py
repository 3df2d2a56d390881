"""The budget model's per-row costs against the rows of finished reproduction runs.

`reproduce --estimate` prices a run from per-row constants (`paper.budget`: THRESHOLD_SECONDS,
GRID_SECONDS, PAPER_VERDICT_SECONDS and their p_t factors). Every stored row records the seconds
its solve took (`solve_seconds`), so a finished run measures those constants on the work users
actually run. This script reads the rows of one or more run directories (the `--out` of
`reproduce`), prices each row with the model (`budget.row_seconds`, same mode, n and p_t) and
prints, per (mode, n), the measured and modelled means and their ratio: the constant that would
reproduce the measurement is the current one times that ratio (the p_t factors pool the rows of
different p_t). Rows of a run on a shared machine are slower by its load: use quiet runs.

Run: python benchmarks/calibrate_budget.py RUN_DIR [RUN_DIR ...] [--record]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import pandas as pd
from _record import machine, record, table

from tensegrity_rigidity.paper import budget

#: the p_t at which each mode's constant is stated (its p_t factor is 1 there)
REFERENCE_PT = {"threshold": 0.3, "grid": 0.15, "paper": 0.0}


def sweep_mode(spec_file: Path) -> str:
    """ "threshold", "grid" or "paper" for a stored sweep (its ``_spec.json``)."""
    settings = json.loads(spec_file.read_text())["settings"]
    if settings["mode"] == "threshold":
        return "threshold"
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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("runs", nargs="+", type=Path, help="reproduction output directories")
    ap.add_argument("--record", action="store_true", help="write the table into BENCHMARKS.md")
    args = ap.parse_args()
    rows = pd.concat([priced_rows(r) for r in args.runs], ignore_index=True)
    out = []
    for (run, mode, n), g in rows.groupby(["run", "mode", "n"], sort=True):
        ratio = g.solve_seconds.sum() / g.model.sum()
        current, extrapolated = budget.row_seconds(mode, int(n), REFERENCE_PT[mode])
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
    runs = ", ".join(map(str, args.runs))
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
