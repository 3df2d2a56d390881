"""A tiny end-to-end reproduction: every figure, the report, the tables, no external links."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from tensegrity_rigidity.cli.main import main

FIGURES = ["1A", "1B", "1C", "2A", "2B", "2C", "2D", "2E", "3B", "4A", "4B", "4C", "FS"]


@pytest.fixture(scope="module")
def tiny(tiny_out):
    """The session's tiny reproduction (tests/paper/conftest.py)."""
    return tiny_out


def test_every_figure_as_png_and_svg(tiny):
    for fid in FIGURES:
        for ext in ("png", "svg"):
            path = tiny / "figures" / f"fig{fid}.{ext}"
            assert path.exists() and path.stat().st_size > 1000, path


def test_report_has_comparison_and_every_figure(tiny):
    md = (tiny / "report.md").read_text()
    html = (tiny / "report.html").read_text()
    assert "Comparison with the paper" in md and "0.372 ± 0.013" in md
    for fid in FIGURES:
        assert f'id="fig{fid}"' in html and f"![Figure {fid}]" in md
    assert (tiny / "tables" / "comparison.csv").exists()
    assert (tiny / "tables" / "single_node_qbar.csv").exists()


def test_report_is_self_contained(tiny):
    html = (tiny / "report.html").read_text()
    assert html.count("data:image/png;base64,") == len(FIGURES)
    text = re.sub(r'src="data:image/png;base64,[A-Za-z0-9+/=]+"', "", html)
    text = re.sub(r'href="#[a-z0-9-]+"', "", text)  # the table of contents' in-page links
    assert not re.search(r"(https?:|ftp:|src=|href=|url\(|<link|<script|@import)", text, re.I)


def test_rerun_resumes_without_new_samples(tiny, monkeypatch):
    """Every study's sweeps resume; the figures and the report (half the re-run's time, tested
    on the first run) are not drawn again."""
    import tensegrity_rigidity.paper.reproduce as reproduce_mod

    drawn = []
    monkeypatch.setattr(reproduce_mod, "all_figures", lambda results, figdir: drawn.append(1))
    monkeypatch.setattr(reproduce_mod, "write_report", lambda *args: {})
    before = sorted(p.stat().st_mtime_ns for p in (tiny / "studies").rglob("part-*.parquet"))
    reproduce_mod.reproduce(tiny, "tiny", workers=1, progress=False)
    after = sorted(p.stat().st_mtime_ns for p in (tiny / "studies").rglob("part-*.parquet"))
    assert before == after and drawn == [1]


def test_one_agreement_rule_stated_once_and_an_explanation_column(tiny):
    import pandas as pd

    md = (tiny / "report.md").read_text()
    assert md.count("A claim agrees when z") == 1 and md.count("## How claims are compared") == 1
    comp = pd.read_csv(tiny / "tables" / "comparison.csv")
    assert {"z", "verdict", "explanation", "source"} <= set(comp.columns)
    dis = comp[comp.verdict == "disagree"]
    assert dis.explanation.str.contains("finite size").all()


def test_evidence_of_a_finished_fss_run_joins_another_scales_report(tiny, tmp_path):
    import shutil

    from tensegrity_rigidity.paper.comparison import compare
    from tensegrity_rigidity.paper.reproduce import reproduce

    out = tmp_path / "with_evidence"
    shutil.copytree(tiny / "studies", out / "studies")  # fig1c's samples: nothing is solved
    before = sorted(p.stat().st_mtime_ns for p in (tiny / "studies").rglob("*"))
    res = reproduce(out, "tiny", workers="serial", progress=False, studies=["fig1c"], evidence=tiny)
    assert after_is_before(tiny, before)
    assert {"fig1c", "fss", "delta"} <= set(res["results"])
    fss_claims = {m.claim for m in res["results"]["fss"].measured}
    assert fss_claims & {m.claim for m in res["results"]["fig1c"].measured}
    (pc,) = [m for m in res["results"]["fig1c"].measured if m.claim == "rods_only_pc"]
    assert pc.system.endswith("6 samples x 5 strains")  # a sample's strains: one unit
    for row in compare(res["results"]):
        if row.key in fss_claims and row.verdict == "disagree":
            assert "finite size: extrapolated" in row.explanation, row.explanation
        if row.key in fss_claims:  # fig1c's size (5) is one of the finite-size study's
            assert row.replication in ("agree", "disagree", "inconclusive"), row
            if row.verdict in ("disagree", "inconclusive"):
                assert row.explanation.startswith("replication: the same size"), row
    assert "![Figure FS]" in (out / "report.md").read_text()


def after_is_before(path, before) -> bool:
    return sorted(p.stat().st_mtime_ns for p in (path / "studies").rglob("*")) == before


def test_evidence_without_a_finished_fss_run_is_refused_before_anything_runs(tmp_path, capsys):
    (tmp_path / "empty").mkdir()
    for evidence, expected in (
        ("empty", "holds no finished finite-size run"),
        ("nothing", "no such directory"),
    ):
        code = main(
            ["reproduce", "--scale", "quick", "--out", str(tmp_path / "o"), "--no-progress"]
            + ["--evidence", str(tmp_path / evidence)]
        )
        err = capsys.readouterr().err.strip().splitlines()
        assert code == 2 and expected in err[-1]
        assert not (tmp_path / "o" / "studies").exists()


def _paragraphs(md: str) -> list[str]:
    """The prose paragraphs of a Markdown report (not headings, tables, lists or images)."""
    blocks = [b.strip() for b in md.split("\n\n")]
    return [b for b in blocks if b and b[0] not in "#|-!" and not b.startswith("Contents:")]


def test_the_report_reads_top_down_in_short_pieces(tiny):
    """It opens with one summary table of at most 6 columns, no cell over 160 characters and no
    paragraph over about 120 words; the evidence follows in one table per claim."""
    from tensegrity_rigidity.paper.render import MAX_WORDS

    md = (tiny / "report.md").read_text()
    first = md.index("\n| ")
    header = md[first + 1 :].split("\n", 1)[0]
    assert header == "| claim | paper | ours | verdict | reason |"
    assert md.index("## Comparison with the paper") < first < md.index("## How claims are compared")
    for line in md.splitlines():
        if line.startswith("| ") and not line.startswith("|---"):
            cells = line.strip("|").split(" | ")
            assert len(cells) <= 6 and max(map(len, cells)) <= 160, line
            break
    table = md[first:].split("\n\n", 1)[0].splitlines()[2:]
    assert table and all(max(len(c) for c in row.strip("|").split(" | ")) <= 160 for row in table)
    longest = max(len(p.split()) for p in _paragraphs(md))
    # a paragraph is split at sentence ends: only a single long sentence may exceed the limit
    assert longest <= MAX_WORDS + 40, longest
    assert (
        "extrapolated to n -> infinity from n =" not in md
        or md.count("extrapolated to n -> infinity from n =") <= 2
    )


def test_the_html_report_has_contents_and_no_raw_markdown(tiny):
    """The rendered page: a table of contents linking every section, and no Markdown markup
    left in its text (it used to print "at scale **tiny**")."""
    page = (tiny / "report.html").read_text()
    assert '<nav id="contents">' in page
    heads = re.findall(r'<h2 id="([a-z0-9-]+)">', page)
    assert len(heads) >= 5 and all(f'href="#{h}"' in page for h in heads)
    body = re.sub(r"<[^>]+>", " ", re.sub(r'src="data:[^"]+"', "", page))
    assert "**" not in body and "](" not in body and "`" not in body
    assert not re.search(r"^#+ ", body, re.M)
    assert "<strong>tiny</strong>" in page and "<em>Rigidity of generic" in page


CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


@pytest.mark.skipif(CHROMIUM is None, reason="headless Chromium is not installed")
def test_the_html_report_renders_in_a_real_browser(tiny, tmp_path):
    """Headless Chromium (Debian's package) loads the page: its DOM has the contents and no raw
    Markdown, and its first screen is drawn (docs/report-first-screen.png is such a shot)."""
    url = (tiny / "report.html").resolve().as_uri()
    flags = ["--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars"]
    dom = subprocess.run(
        [CHROMIUM, *flags, "--dump-dom", url], capture_output=True, text=True, timeout=120
    ).stdout
    assert '<nav id="contents">' in dom and "Comparison with the paper" in dom
    text = re.sub(r"<[^>]+>", " ", re.sub(r'src="data:[^"]+"', "", dom))
    assert "**" not in text and "`" not in text
    shot = tmp_path / "first-screen.png"
    subprocess.run(
        [CHROMIUM, *flags, "--window-size=1280,900", f"--screenshot={shot}", url],
        capture_output=True,
        timeout=120,
    )
    assert shot.stat().st_size > 20_000  # a drawn page, not a blank one


@pytest.mark.parametrize(
    "report",
    [
        pytest.param(path, id=path.parent.name)
        for path in sorted((Path(__file__).parents[2] / "reports").glob("*/report.md"))
    ],
)
def test_the_committed_reports_keep_the_budgets(report):
    """Every committed report (paper-n32, fss, pc, 3d): no table cell over 160 characters and
    no paragraph over about 120 words, as the tiny one."""
    from tensegrity_rigidity.paper.render import MAX_WORDS

    md = report.read_text()
    cells = [
        c.strip()
        for line in md.splitlines()
        if line.startswith("| ") and not line.startswith("|---")
        for c in line.strip("|").split(" | ")
    ]
    assert cells and max(map(len, cells)) <= 160, max(cells, key=len)
    longest = max(len(p.split()) for p in _paragraphs(md))
    assert longest <= MAX_WORDS + 40, longest
