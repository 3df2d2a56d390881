"""The reproduction report: the summary table first, then each study's section, its figures
beside its claims, then how claims are compared and what was excluded.

The report renders; it computes nothing. The studies compute every number
(:attr:`~tensegrity_rigidity.paper.study.Study.numbers`), the comparison pairs them with the
paper's claims, and the templates (``templates/report.md`` and one per study) hold every
sentence: this module fills them, in the order they stand, and loops over the registry.

:func:`write_report` writes ``report.md``, a self-contained ``report.html`` (figures embedded as
base64 PNG) and the tables as CSV.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from ..model.io import atomic_output
from ..model.lattice import DEFAULT_DELTA
from .claims import TARGETS
from .comparison import (
    AGREE_BELOW,
    RESOLVES_WITHIN,
    compare,
    comparison_frame,
    evidence_frame,
    paper_against_itself,
    shared_measurements,
    summary_frame,
    verdict_counts,
)
from .registry import STUDIES
from .render import to_html, to_markdown
from .studies.rows import ENERGY_BRACKETED, undecided_by_kind
from .template import Template, fill, load

REPORT = load("report")


def excluded_samples(results: dict) -> dict[str, int]:
    """Sweep name -> samples excluded as undecided, over every study result."""
    return {k: v for r in results.values() for k, v in r.excluded.items()}


def bracketed_rows(results: dict) -> dict[str, int]:
    """Sweep name -> undecided grid rows that still enter the energy analyses."""
    return {k: v for r in results.values() for k, v in getattr(r, "bracketed", {}).items()}


def tables_of(results: dict) -> dict[str, pd.DataFrame]:
    """The CSV tables written beside the report (name -> frame), from every study's result."""
    return {k: v for name, r in results.items() for k, v in STUDIES[name].tables(r).items()}


def _renamed(df: pd.DataFrame, template: Template) -> pd.DataFrame:
    """A table with its column headers from the template's labels (``col.<key>``)."""
    return df.rename(columns={c: template.column(str(c)) for c in df.columns})


def _names(rows, ours: str, theirs: str) -> dict:
    named = [r.claim for r in rows if r.verdict == ours and r.replication == theirs]
    return {"count": len(named) or None, "names": "; ".join(named) or None}


def openings(results: dict) -> list[str]:
    """What each study that ran measures, in its own template's words (its ``opening`` block,
    filled with its numbers; a block named after a number only where that number is present),
    in the order of the results. The report's opening names them where it compares no claim."""
    out = []
    for name, r in results.items():
        study = STUDIES.get(name)
        blocks = [b for b in study.template.blocks if b.kind == "opening"] if study else []
        if study is None or not blocks:
            continue
        values = study.numbers(r)
        out += [" ".join(fill(b.text, values)) for b in blocks
                if not b.name or values.get(b.name) is not None]  # fmt: skip
    return [o for o in out if o]


def numbers(results: dict, rows: list, scale: str, timings: dict, extra: dict, itself) -> dict:
    """The report's own placeholders: the headline counts, the rule, the exclusions."""
    counts = verdict_counts(rows)
    text = {r.key: r.claim for r in rows}
    pairs = [REPORT.label("pair", a=text[a], b=text[b], z=z)
             for a, b, z in shared_measurements(rows)]  # fmt: skip
    contradicted, unrepeated = _names(rows, "agree", "disagree"), _names(rows, "disagree", "agree")
    straddling = {k: r.straddling for k, r in results.items() if r.straddling is not None}
    excluded, bracketed = excluded_samples(results), bracketed_rows(results)
    return {
        "scale": scale, **(counts if rows else {}), "no_claims": None if rows else "",
        "openings": "; ".join(openings(results)) or None,
        "contradicted": contradicted["names"], "contradicted_count": contradicted["count"],
        "unrepeated": unrepeated["names"], "unrepeated_count": unrepeated["count"],
        "pairs": "; ".join(pairs) or None, "evidence": "" if rows else None,
        "itself": "" if len(itself) else None, "agree_below": AGREE_BELOW,
        "times": RESOLVES_WITHIN, "deviation": 2 * RESOLVES_WITHIN, **TARGETS,
        "excluded": sum(excluded.values()), "bracketed": sum(bracketed.values()) or None,
        "energy_bracketed": ENERGY_BRACKETED,
        "straddling": "; ".join(f"{k}: {v}" for k, v in straddling.items()) or None,
        "node_disorder": DEFAULT_DELTA,
        "tables": [f"`tables/{n}.csv`" for n in ["comparison", *extra]],
        "timings": [REPORT.label("timing", study=k, seconds=v) for k, v in timings.items()],
    }  # fmt: skip


def _claims(rows: list) -> list[tuple]:
    """A study's claims beside its figures, and the evidence for each disagreement and each
    agreement that a replication contradicts."""
    if not rows:
        return []
    out: list[tuple] = [("table", summary_frame(rows).drop(columns="reason"))]
    for r in rows:
        contradicted = r.verdict == "agree" and r.replication == "disagree"
        if r.evidence and (r.verdict == "disagree" or contradicted):
            out += [("h3", r.claim), ("table", evidence_frame(r))]
    return out


def render(template: Template, values: dict, figures: dict, tables: dict, claims: list,
           blocks=None) -> list:  # fmt: skip
    """A template's blocks (or ``blocks`` of it) in order, filled: headings, paragraphs (a
    sentence with a missing value dropped), figures with their captions, tables, the claims; a
    block left with nothing dropped."""
    out: list[tuple] = []
    for b in template.blocks if blocks is None else blocks:
        if b.kind in ("section", "subsection"):
            out.append(("h2" if b.kind == "section" else "h3", b.title))
        elif b.kind == "text" and (not b.name or values.get(b.name) is not None):
            out += [("p", p) for p in fill(b.text, values)]
        elif b.kind == "figure" and b.name in figures:
            out.append(("figure", b.name, figures[b.name][0], " ".join(fill(b.text, values))))
        elif b.kind == "table" and tables.get(b.name) is not None and len(tables[b.name]):
            out += [("p", p) for p in fill(b.text, values)]
            out.append(("table", _renamed(tables[b.name], template)))
        elif b.kind == "claims":
            out += claims
    return out


def _pruned(blocks: list[tuple]) -> list[tuple]:
    """Without the headings that nothing follows before the next heading of their level."""
    rank = {"h2": 2, "h3": 3}
    out: list[tuple] = []
    for block in reversed(blocks):
        level = rank.get(block[0])
        nxt = rank.get(out[0][0], 4) if out else 0
        if level is not None and nxt <= level:
            continue
        out.insert(0, block)
    return out


def report_blocks(results: dict, figures: dict, scale: str, timings: dict, extra: dict) -> list:
    """The report as blocks (:mod:`~tensegrity_rigidity.paper.render`), top down; ``extra``:
    the CSV tables written beside it."""
    rows, itself = compare(results), paper_against_itself(results)
    values = numbers(results, rows, scale, timings, extra, itself)
    tables = {
        "summary": summary_frame(rows) if rows else None,
        "itself": itself,
        "excluded": _excluded(results),
        "undecided": extra.get("undecided_by_kind"),
    }
    blocks: list[tuple] = []
    for b in REPORT.blocks:
        if b.kind != "studies":
            blocks += render(REPORT, values, {}, tables, [], (b,))
            continue
        for name, r in results.items():
            study = STUDIES[name]
            mine = [row for row in rows if row.study == name]
            blocks += render(study.template, study.numbers(r), figures, study.report_tables(r),
                             _claims(mine))  # fmt: skip
    return _pruned(blocks)


def _excluded(results: dict) -> pd.DataFrame:
    undecided, bracketed = excluded_samples(results), bracketed_rows(results)
    return pd.DataFrame(
        [
            {"sweep": k, "excluded": v, "still": bracketed.get(k, 0)}
            for k, v in undecided.items()
            if v
        ],
        columns=["sweep", "excluded", "still"],
    )


def _write_csv(df, path: Path) -> None:
    """``df`` as CSV at ``path``, whole or not at all (an interrupted report leaves no torn
    table)."""
    with atomic_output(path, "the report table", "table.csv") as tmp:
        df.to_csv(tmp, index=False)


def _write_text(text: str, path: Path) -> None:
    """``text`` at ``path``, whole or not at all."""
    with atomic_output(path, "the report", "report.md") as tmp:
        tmp.write_text(text)


def write_report(out: Path, results: dict, figures: dict, scale_name: str,
                 timings: dict[str, float]) -> dict[str, Path]:  # fmt: skip
    """Write report.md, report.html and the CSV tables; returns their paths. ``results`` maps
    study names to their results, ``figures`` figure ids to their [png, svg] paths."""
    out = Path(out)
    tables = out / "tables"
    tables.mkdir(parents=True, exist_ok=True)
    _write_csv(comparison_frame(compare(results)), tables / "comparison.csv")
    extra = tables_of(results)
    if (out / "studies").is_dir():
        extra["undecided_by_kind"] = undecided_by_kind(out / "studies")
    for name, df in extra.items():
        _write_csv(df, tables / f"{name}.csv")
    blocks = report_blocks(results, figures, scale_name, timings, extra)
    title = REPORT.label("title")
    _write_text(to_markdown(title, blocks), out / "report.md")
    _write_text(to_html(title, blocks), out / "report.html")
    return {"md": out / "report.md", "html": out / "report.html",
            "comparison": tables / "comparison.csv"}  # fmt: skip
