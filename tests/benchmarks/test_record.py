"""benchmarks/_record.py: a run replaces its section of BENCHMARKS.md, appends its raw results."""

from __future__ import annotations

import json
import re

import numpy as np
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
    monkeypatch.setattr(_record, "_appended", {}, raising=False)
    monkeypatch.setattr(_record.sys, "argv", ["benchmarks/bench_solver.py", "--sizes", "16"])
    return tmp_path


def _section(text: str, name: str) -> str:
    match = re.search(rf"<!-- bench:{name} -->\n(.*?)<!-- /bench:{name} -->", text, re.S)
    assert match is not None, name
    return match.group(1)


def test_a_run_replaces_its_section_and_leaves_the_others(tmp_root):
    (tmp_root / "BENCHMARKS.md").write_text(EARLIER)
    _record.record("solver", "Solver: new title", "Machine: new.\n\n| new table |")
    text = (tmp_root / "BENCHMARKS.md").read_text()
    body = _section(text, "solver")
    # the section holds the new run only: the earlier run and its analysis are gone (git has
    # them)
    assert "Numbers that must survive." not in body and "Machine: old." not in body
    assert body.startswith("## Solver: new title\n\n**Run of ")
    assert "at abc1234:** `python benchmarks/bench_solver.py --sizes 16`" in body
    assert body.rstrip().endswith("| new table |")
    assert body.count("## ") == 1
    # the other section and the text around are untouched
    assert text.startswith("# Benchmarks\n\nIntro.\n\n<!-- bench:solver -->")
    assert "<!-- bench:sweep -->\n## Sweep throughput\n\nSweep text.\n<!-- /bench:sweep -->" in text


def test_a_second_run_replaces_the_first_and_a_missing_section_is_appended(tmp_root):
    _record.record("lp", "LP", "first")
    _record.record("lp", "LP", "second")
    _record.record("other", "Other", "third")
    text = (tmp_root / "BENCHMARKS.md").read_text()
    assert text.startswith("# Benchmarks\n")
    assert text.count("<!-- bench:lp -->") == 1 and text.count("<!-- /bench:lp -->") == 1
    assert "first" not in text and text.index("second") < text.index("<!-- bench:other -->")
    assert text.rstrip().endswith("third\n<!-- /bench:other -->")


def test_raw_results_are_appended_with_date_commit_and_command(tmp_root, monkeypatch):
    path = tmp_root / "benchmarks" / "results" / "bench_solver.json"
    _record.record("solver", "Solver", "| n = 16 |", raw=[{"n": 16, "ms": np.float64(4.25)}])
    _record.record("solver", "Solver", "| n = 32 |", raw=[{"n": 16}, {"n": 32, "ms": 9.5}])
    runs = json.loads(path.read_text())
    # a process that records after each part of its run updates its own run
    assert len(runs) == 1
    run = runs[0]
    assert run["commit"] == "abc1234" and run["section"] == "solver"
    assert run["command"] == "python benchmarks/bench_solver.py --sizes 16"
    assert re.fullmatch(r"\d{4}-\d\d-\d\d", run["date"])
    assert run["results"] == [{"n": 16}, {"n": 32, "ms": 9.5}]
    # another process (another run) appends: the history of raw results is kept as data
    monkeypatch.setattr(_record, "_appended", {})
    _record.record("solver", "Solver", "| n = 64 |", raw={"arr": np.arange(3)})
    runs = json.loads(path.read_text())
    assert len(runs) == 2 and runs[0]["results"][1]["n"] == 32
    assert runs[1]["results"] == {"arr": [0, 1, 2]}
    # the markdown holds only the newest table
    text = (tmp_root / "BENCHMARKS.md").read_text()
    assert "| n = 64 |" in text and "| n = 32 |" not in text


def test_without_raw_results_no_file_is_written(tmp_root):
    _record.record("sweep", "Sweep", "| table |")
    assert not (tmp_root / "benchmarks" / "results").exists()


def test_the_commit_is_named_as_it_was_at_the_start():
    assert _record._STARTED_AT == _record._commit() or "+ changes" in _record._commit()
    commit = _record._STARTED_AT
    assert re.fullmatch(r"[0-9a-f]{7,}( \+ changes)?|no git checkout", commit)


def test_steadiness_is_summarised_in_the_machine_line(monkeypatch):
    steadiness = _record.Steadiness(size=1000)
    monkeypatch.setattr(_record, "STEADINESS", steadiness)
    assert "Steadiness" not in _record.machine()  # not probed: not claimed
    for _ in range(3):
        _record.probe()
    line = _record.machine()
    assert "Steadiness: a fixed workload timed 3 times" in line
    assert re.search(r"\(max / min \d+\.\d\)$", line)
