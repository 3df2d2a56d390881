"""benchmarks/_record.py: a run is added to its section of BENCHMARKS.md, never replaces it."""

from __future__ import annotations

import re

import pytest

from benchmarks import _record

EARLIER = """# Benchmarks

Intro.

<!-- bench:solver -->
## Solver (old title)

**An analysis written by hand (2026-11-29).** Numbers that must survive.

Machine: old. | table |
<!-- /bench:solver -->

<!-- bench:sweep -->
## Sweep throughput

Sweep text.
<!-- /bench:sweep -->
"""


@pytest.fixture
def tmp_root(tmp_path, monkeypatch):
    monkeypatch.setattr(_record, "ROOT", tmp_path)
    # not raising where the attribute is missing: against a record() without them the tests
    # still run, and fail on what they check
    monkeypatch.setattr(_record, "_STARTED_AT", "abc1234", raising=False)
    monkeypatch.setattr(_record, "_written", {}, raising=False)
    return tmp_path


def test_a_run_is_added_above_the_earlier_ones_and_keeps_them(tmp_root):
    (tmp_root / "BENCHMARKS.md").write_text(EARLIER)
    _record.record("solver", "Solver: new title", "Machine: new.\n\n| new table |")
    text = (tmp_root / "BENCHMARKS.md").read_text()
    section = re.search(r"<!-- bench:solver -->\n(.*?)<!-- /bench:solver -->", text, re.S)
    assert section is not None
    body = section.group(1)
    # the earlier run and the text between the runs survive, below the new run
    assert "Numbers that must survive." in body and "Machine: old. | table |" in body
    assert body.index("| new table |") < body.index("Numbers that must survive.")
    assert body.startswith("## Solver: new title\n\n**Run of ")
    assert "at abc1234:** `python" in body
    assert body.count("## ") == 1  # the heading once, the old one replaced
    # the other section and the text around are untouched
    assert text.startswith("# Benchmarks\n\nIntro.\n\n<!-- bench:solver -->")
    assert "<!-- bench:sweep -->\n## Sweep throughput\n\nSweep text.\n<!-- /bench:sweep -->" in text


def test_two_runs_stack_and_a_missing_section_is_appended(tmp_root, monkeypatch):
    _record.record("lp", "LP", "first")
    monkeypatch.setattr(_record, "_written", {}, raising=False)  # the second run: another process
    _record.record("lp", "LP", "second")
    _record.record("other", "Other", "third")
    text = (tmp_root / "BENCHMARKS.md").read_text()
    assert text.startswith("# Benchmarks\n")
    assert text.count("<!-- bench:lp -->") == 1 and text.count("<!-- /bench:lp -->") == 1
    assert text.index("second") < text.index("first") < text.index("<!-- bench:other -->")
    assert text.rstrip().endswith("third\n<!-- /bench:other -->")


def test_the_commit_is_named_as_it_was_at_the_start():
    assert _record._STARTED_AT == _record._commit() or "+ changes" in _record._commit()
    commit = _record._STARTED_AT
    assert re.fullmatch(r"[0-9a-f]{7,}( \+ changes)?|no git checkout", commit)


def test_a_process_updates_its_own_entry(tmp_root, monkeypatch):
    (tmp_root / "BENCHMARKS.md").write_text(EARLIER)
    _record.record("solver", "Solver", "| n = 16 |")
    _record.record("solver", "Solver", "| n = 16 |\n| n = 32 |")
    text = (tmp_root / "BENCHMARKS.md").read_text()
    assert "Numbers that must survive." in text
    assert text.count("| n = 16 |") == 1 and "| n = 32 |" in text
    assert text.index("| n = 32 |") < text.index("Numbers that must survive.")
    assert text.count("**Run of ") == 1
    monkeypatch.setattr(_record, "_written", {}, raising=False)  # another process: a new entry
    _record.record("solver", "Solver", "| n = 64 |")
    text = (tmp_root / "BENCHMARKS.md").read_text()
    assert text.count("**Run of ") == 2
    assert text.index("| n = 64 |") < text.index("| n = 32 |")


def test_steadiness_is_summarised_in_the_machine_line(monkeypatch):
    steadiness = _record.Steadiness(size=1000)
    monkeypatch.setattr(_record, "STEADINESS", steadiness)
    assert "Steadiness" not in _record.machine()  # not probed: not claimed
    for _ in range(3):
        _record.probe()
    line = _record.machine()
    assert "Steadiness: a fixed workload timed 3 times" in line
    assert re.search(r"\(max / min \d+\.\d\)$", line)
