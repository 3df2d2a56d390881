"""benchmarks/bench_solver.py: the methods take turns on each instance."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest

BENCHMARKS = Path(__file__).parents[2] / "benchmarks"


@pytest.fixture
def bench(monkeypatch):
    monkeypatch.syspath_prepend(str(BENCHMARKS))
    import bench_solver

    calls: list[str] = []
    monkeypatch.setattr(bench_solver, "decide", lambda inst: calls.append("first") or "v")
    return bench_solver, calls


def stub(name, calls, result=None):
    return name, lambda inst: calls.append(name) or (name if result is None else result())


def test_three_rounds_in_turn_when_the_first_verdict_is_fast(bench):
    bench_solver, calls = bench
    methods = [stub(m, calls) for m in ("decide", "solve", "clarabel")]
    times, out = bench_solver.interleaved(object(), methods)
    assert calls == ["first"] + ["decide", "solve", "clarabel"] * 3
    assert {k: len(v) for k, v in times.items()} == {"decide": 3, "solve": 3, "clarabel": 3}
    assert out == {"decide": "decide", "solve": "solve", "clarabel": "clarabel"}


def test_one_round_when_the_first_verdict_is_slow_and_it_counts(bench, monkeypatch):
    bench_solver, calls = bench
    monkeypatch.setattr(bench_solver, "REPEAT_BELOW", 0.0)
    methods = [stub(m, calls) for m in ("decide", "solve+u", "clarabel")]
    times, out = bench_solver.interleaved(object(), methods)
    assert calls == ["first", "solve+u", "clarabel"]  # decide is not run again
    assert {k: len(v) for k, v in times.items()} == {"decide": 1, "solve+u": 1, "clarabel": 1}
    assert out["decide"] == "v"


def test_a_failed_lp_has_no_time(bench):
    bench_solver, calls = bench
    methods = [stub("decide", calls), stub("highs-lp", calls, lambda: None)]
    times, out = bench_solver.interleaved(object(), methods)
    assert "highs-lp" not in times and out["highs-lp"] is None
    assert calls.count("highs-lp") == 3


def test_the_methods_follow_the_size_limits(bench):
    bench_solver, _ = bench
    args = SimpleNamespace(max_baseline=64, lp_max=32)
    names = [name for name, _ in bench_solver.methods(32, args, 32)]
    assert names == ["decide", "solve", "solve+u", "highs-lp", "clarabel", "l-bfgs-b"]
    names = [name for name, _ in bench_solver.methods(64, args, 32)]
    assert names == ["decide", "solve", "solve+u", "clarabel"]
    assert [name for name, _ in bench_solver.methods(128, args, 32)][-1] == "solve+u"
