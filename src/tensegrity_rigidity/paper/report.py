"""The reproduction report: our numbers beside the paper's, figures, tables.

The report renders; it computes nothing. The studies (:mod:`~tensegrity_rigidity.paper.studies`)
compute every statistic, :mod:`~tensegrity_rigidity.paper.comparison` pairs them with the
paper's claims (:mod:`~tensegrity_rigidity.paper.claims`) into typed rows.

:func:`write_report` writes ``report.md``, a self-contained ``report.html`` (figures embedded as
base64 PNG; no external reference of any kind) and the tables as CSV.
"""

from __future__ import annotations

import base64
import html
from pathlib import Path

import pandas as pd

from ..analysis.single_node import class_weights, qbar_table
from ..model.lattice import DEFAULT_DELTA
from .comparison import RULE, TABLE_COLUMNS, compare, comparison_frame


def _md_table(df: pd.DataFrame) -> str:
    cols = list(df.columns)
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for _, row in df.iterrows():
        lines.append("| " + " | ".join(str(row[c]).replace("|", "/") for c in cols) + " |")
    return "\n".join(lines)


def _html_table(df: pd.DataFrame) -> str:
    head = "".join(f"<th>{html.escape(str(c))}</th>" for c in df.columns)
    body = []
    for _, row in df.iterrows():
        cls = f' class="{row.get("verdict", "")}"' if "verdict" in df else ""
        body.append(
            f"<tr{cls}>"
            + "".join(f"<td>{html.escape(str(row[c]))}</td>" for c in df.columns)
            + "</tr>"
        )
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


FIGURE_CAPTIONS = {
    "1A": "A force-balanced rigid sample: rods solid, cables dashed, struts hollow; colour from "
    "red (pulling) through green (zero) to blue (pushing).",
    "1B": "Probability of rigidity under shear at f_c = 0.5 with the mean-field line.",
    "1C": "S_t/S_r versus f_c for dilation, shear, compression and the strain average.",
    "2A": "Nonaffine displacement field of a rods-and-cables network under compression.",
    "2B": "Nonaffinity versus p_r for several p_t (rods + cables, compression).",
    "2C": "Energy versus p_r under compression; inset: log-log with power-law fits.",
    "2D": "Energy versus p_r under dilation; inset: log-log with power-law fits.",
    "3B": "Single three-coordinated node: P_N versus f_c.",
    "4A": "P versus f_c for strains from dilation (phi = 0) to compression (phi = pi).",
    "4B": "Efficacies of cables and struts relative to rods, averaged over strains.",
    "4C": "Combined efficacy (S_c + S_s)/S_r versus f_c.",
}


def excluded_samples(results: dict) -> dict[str, int]:
    """Sweep name -> samples excluded as undecided, over every study result."""
    out: dict[str, int] = {}
    for r in results.values():
        out.update(r.excluded)
    return out


def tables_of(results: dict) -> dict[str, pd.DataFrame]:
    """The CSV tables written beside the report (name -> frame), from the study results."""
    extra = {}
    if "fig1c" in results:
        extra["efficacy_fits"] = results["fig1c"].fits
    if "fig2" in results:
        extra["energy_fits"] = results["fig2"].fits
        extra["fig2_curves"] = results["fig2"].curves
    if "fig3" in results:
        extra["single_node_qbar"] = pd.DataFrame(qbar_table())
        extra["single_node_simulation"] = results["fig3"].sim
        extra["single_node_class_weights"] = pd.DataFrame([class_weights()])
    if "fig4" in results:
        extra["fig4_average"] = results["fig4"].average
        extra["fig4_per_strain"] = results["fig4"].per_phi
    return extra


def write_report(
    out: Path,
    results: dict,
    figures: dict,
    scale_name: str,
    timings: dict[str, float],
) -> dict[str, Path]:
    """Write report.md, report.html and the CSV tables; returns their paths.

    ``results`` maps study names to the studies' frozen results; the samples each study
    excluded travel inside them.
    """
    out = Path(out)
    tables = out / "tables"
    tables.mkdir(parents=True, exist_ok=True)
    rows = compare(results)
    full = comparison_frame(rows)
    full.to_csv(tables / "comparison.csv", index=False)
    comp = full[TABLE_COLUMNS] if len(full) else pd.DataFrame(columns=TABLE_COLUMNS)
    extra = tables_of(results)
    for name, df in extra.items():
        df.to_csv(tables / f"{name}.csv", index=False)
    undecided = excluded_samples(results)

    n_agree = sum(r.verdict == "agree" for r in rows)
    n_dis = sum(r.verdict == "disagree" for r in rows)
    intro = (
        f"Reproduction of *Rigidity of generic random tensegrity structures* at scale "
        f"**{scale_name}**. Every verdict is exact (certified by an admissible self-stress or a "
        f"zero-energy displacement), so differences from the paper are statistical, finite-size "
        f"or definitional, not solver noise. {n_agree} claims agree, {n_dis} do not. "
        f"{RULE} Study wall times: "
        + ", ".join(f"{k} {v:.0f} s" for k, v in timings.items())
        + ". "
        + (
            f"Samples excluded because a configuration's verdict lay below double-precision "
            f"resolution (no certificate to tolerance): {sum(undecided.values())}"
            + (
                " (" + ", ".join(f"{k}: {v}" for k, v in undecided.items() if v) + ")"
                if any(undecided.values())
                else ""
            )
            + "."
        )
    )
    notes = (
        f"Conventions (MODEL.md): node disorder delta = {DEFAULT_DELTA}; f_c is the cable fraction "
        "(rods + cables is f_c = 1; the supplement's tables say 0.0); energies are totals at "
        "gamma = 1, so the intercept beta depends on system size and is not compared; p_crit is "
        "the median per-sample threshold (P = 1/2) while the paper takes the first p_r with "
        "positive mean energy; the single-node class labels follow the table, not the prose."
    )
    md = [
        "# Tensegrity rigidity: reproduction report",
        "",
        intro,
        "",
        notes,
        "",
        "## Comparison with the paper",
        "",
        _md_table(comp),
        "",
    ]
    for fid, paths in figures.items():
        md += [
            f"## Figure {fid}",
            "",
            FIGURE_CAPTIONS.get(fid, ""),
            "",
            f"![Figure {fid}](figures/{paths[0].name})",
            "",
        ]
    md += ["## Tables", ""] + [f"- `tables/{n}.csv`" for n in ["comparison", *extra]]
    (out / "report.md").write_text("\n".join(md) + "\n")

    figs_html = []
    for fid, paths in figures.items():
        data = base64.b64encode(paths[0].read_bytes()).decode()
        figs_html.append(
            f'<figure id="fig{fid}"><img alt="Figure {fid}" src="data:image/png;base64,{data}">'
            f"<figcaption><b>{fid}</b> {html.escape(FIGURE_CAPTIONS.get(fid, ''))}"
            "</figcaption></figure>"
        )
    style = (
        "body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em}"
        "table{border-collapse:collapse;font-size:13px}td,th{border:1px solid #ccc;"
        "padding:3px 6px;text-align:left}tr.agree td:nth-child(5){color:#060}"
        "tr.disagree td:nth-child(5){color:#a00;font-weight:bold}"
        "figure{display:inline-block;width:48%;margin:0.5%}img{width:100%}"
    )
    page = (
        f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>Tensegrity rigidity "
        f"report</title><style>{style}</style></head><body>"
        f"<h1>Tensegrity rigidity: reproduction report</h1><p>{html.escape(intro)}</p>"
        f"<p>{html.escape(notes)}</p><h2>Comparison with the paper</h2>{_html_table(comp)}"
        f"<h2>Figures</h2>{''.join(figs_html)}</body></html>"
    )
    (out / "report.html").write_text(page)
    return {
        "md": out / "report.md",
        "html": out / "report.html",
        "comparison": tables / "comparison.csv",
    }
