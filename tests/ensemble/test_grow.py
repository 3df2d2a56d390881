"""Extendable sweeps (issue 16 item 4): rows keyed by state point, golden-angle strains."""

from __future__ import annotations

import math
import textwrap
import tomllib

import numpy as np
import pandas as pd
import pytest

import tensegrity_rigidity.ensemble.sweep as sweep_mod
from tensegrity_rigidity.ensemble.runner import run_chunk
from tensegrity_rigidity.ensemble.spec import GOLDEN, parse_spec, strain_angle
from tensegrity_rigidity.ensemble.sweep import load_results, run_sweep

BASE = """
n = 5
p_r = {p_r}
p_t = 0.2
f_c = [0.0, 1.0]
phi = ["dilation", "compression"]
samples = {samples}
seed = 7
[output]
chunk_size = {chunk}
"""


def _spec(p_r=(0.5,), samples=6, chunk=4, extra=""):
    text = BASE.format(p_r=list(p_r), samples=samples, chunk=chunk) + extra
    return parse_spec(tomllib.loads(textwrap.dedent(text)))


@pytest.fixture
def solved(monkeypatch):
    """Records every (grid point, sample, theta) solved by a sweep in this process."""
    seen = []

    def recording(spec, point, samples):
        seen.extend((point, k, spec.angle(k)) for k in samples)
        return run_chunk(spec, point, samples)

    monkeypatch.setattr(sweep_mod, "run_chunk", recording)
    return seen


def _rows(out, spec=None):
    return load_results(out, spec).drop(columns=["solve_seconds"])


def test_growing_twice_solves_only_new_samples_and_equals_a_fresh_run(tmp_path, solved):
    out = tmp_path / "grow"
    first = _spec(samples=6)
    run_sweep(first, out, executor="serial", progress=False)
    assert len(solved) == 2 * 2 * 6
    # more samples: only samples 7..10 of every point
    more = _spec(samples=10, chunk=3)
    solved.clear()
    rep = run_sweep(more, out, executor="serial", progress=False)
    assert sorted({k for _, k, _ in solved}) == [7, 8, 9, 10] and len(solved) == 2 * 2 * 4
    assert (rep.samples_reused, rep.samples_run) == (24, 16)
    # one more p_r value: only its points
    wider = _spec(p_r=(0.5, 0.65), samples=10, chunk=5)
    solved.clear()
    rep = run_sweep(wider, out, executor="serial", progress=False)
    assert {p.p_r for p, _, _ in solved} == {0.65} and len(solved) == 2 * 2 * 10
    assert (rep.samples_reused, rep.samples_run) == (40, 40)
    # nothing solved twice over the three runs, and the rows equal one run from scratch
    solved.clear()
    run_sweep(wider, tmp_path / "fresh", executor="serial", progress=False)
    pd.testing.assert_frame_equal(_rows(out), _rows(tmp_path / "fresh"))
    assert len(_rows(out)) == 2 * 2 * 2 * 10


def test_chunk_size_and_worker_count_do_not_change_what_is_done(tmp_path, solved):
    out = tmp_path / "o"
    run_sweep(_spec(samples=8, chunk=3), out, executor="serial", progress=False)
    solved.clear()
    rep = run_sweep(_spec(samples=8, chunk=5), out, executor=2, progress=False)
    assert rep.samples_run == 0 and rep.samples_reused == 2 * 2 * 8 and not solved


def test_smaller_spec_reads_its_own_rows(tmp_path):
    """After a larger sweep, a smaller one computes nothing and load_results gives its rows."""
    out = tmp_path / "o"
    big, small = _spec(p_r=(0.5, 0.65), samples=8), _spec(samples=5)
    run_sweep(big, out, executor="serial", progress=False)
    rep = run_sweep(small, out, executor="serial", progress=False)
    assert rep.samples_run == 0
    rows = _rows(out)  # the latest spec run into the directory
    assert len(rows) == 2 * 2 * 5 and set(rows.p_r) == {0.5} and rows["sample"].max() == 5
    assert len(load_results(out, all_rows=True)) == 2 * 2 * 2 * 8
    assert len(_rows(out, big)) == 2 * 2 * 2 * 8


def test_uniform_angles_depend_on_the_count_so_nothing_is_reused(tmp_path, solved):
    out = tmp_path / "u"
    extra = "[strain]\nangles = 'uniform'\n"
    run_sweep(_spec(samples=4, extra=extra), out, executor="serial", progress=False)
    thetas = sorted({t for _, _, t in solved})
    assert thetas == pytest.approx([0, math.pi / 2, math.pi, 3 * math.pi / 2])
    solved.clear()
    rep = run_sweep(_spec(samples=6, extra=extra), out, executor="serial", progress=False)
    # samples 1 (theta = 0) keeps its angle; every other sample moves, so it is solved again
    assert rep.samples_reused == 2 * 2 * 1 and rep.samples_run == 2 * 2 * 5
    assert sorted({k for _, k, _ in solved}) == [2, 3, 4, 5, 6]


def test_golden_angles_do_not_depend_on_the_count():
    ks = np.arange(1, 50)
    golden = [strain_angle(int(k), 49) for k in ks]
    assert golden == [strain_angle(int(k), 1000) for k in ks]
    np.testing.assert_allclose(golden, 2 * np.pi * (((ks - 1) * GOLDEN) % 1.0), rtol=0, atol=1e-12)
    uniform = [strain_angle(int(k), 49, "uniform") for k in ks]
    np.testing.assert_allclose(uniform, 2 * np.pi * (ks - 1) / 49)
    # spread: any 49 consecutive golden angles leave no gap wider than 3 / 49 of the circle
    gaps = np.diff(np.sort(np.r_[golden, 2 * np.pi]))
    assert gaps.max() < 3 * 2 * np.pi / 49
    # and modulo pi (eps(theta + pi) = eps(theta)) no two samples share a strain tensor
    assert len(set(np.round(np.mod(golden, np.pi), 9))) == len(golden)


def test_changed_tolerance_is_part_of_the_row_key():
    a = _spec()
    b = _spec(extra="[solver]\nviolation_tol = 1e-8\n")
    point = a.points()[0]
    assert a.point_key(point) != b.point_key(point)
    assert a.settings_digest() != b.settings_digest()
    # the chunk size is not a setting; every field of the solver options is
    assert _spec(chunk=7).point_key(point) == a.point_key(point)
    from dataclasses import fields

    from tensegrity_rigidity.solver.core import SolverOptions

    assert set(a.settings()["solver"]) - {"class"} == {f.name for f in fields(SolverOptions)}


def _changed(value, path):
    """``value`` (a field of the solver options, reached by ``path``) changed, still valid."""
    from dataclasses import is_dataclass, replace

    if is_dataclass(value):
        name, *rest = path
        return replace(value, **{name: _changed(getattr(value, name), rest)})
    if isinstance(value, tuple):
        i, *rest = path
        return value[:i] + (_changed(value[i], rest),) + value[i + 1 :]
    if isinstance(value, bool):
        return not value
    if isinstance(value, float) and 0 < value < 0.25:  # tolerances: stay in their range
        return value * 2
    if isinstance(value, (int, float)):
        return value * 2 + 1
    # a named choice becomes another valid one (LinearProgram.interior: the test extra installs
    # HiPO's plugin); a free name gets a suffix
    choices = {"auto": "cholmod", "dual+primal": "dual", "ipx": "hipo"}
    return choices.get(value, value + "-changed")


def _leaves(value, path=()):
    """The paths of every scalar field of ``value`` (dataclasses and tuples, recursively)."""
    from dataclasses import fields, is_dataclass

    if is_dataclass(value):
        for f in fields(value):
            yield from _leaves(getattr(value, f.name), (*path, f.name))
    elif isinstance(value, tuple):
        for i, x in enumerate(value):
            yield from _leaves(x, (*path, i))
    else:
        yield path


def test_every_field_of_the_solver_options_is_part_of_the_digest():
    """The settings hold the solver options as a whole: changing any field, however deep
    (a strategy's knob, the refiner's, a tolerance), changes the digest, so a resumed sweep
    never mixes rows of two searches."""
    from tensegrity_rigidity.ensemble.spec import _digest, solver_settings
    from tensegrity_rigidity.solver.core import SolverOptions

    a = _spec()
    opts = a.solver_options()
    assert a.settings()["solver"] == solver_settings(opts)
    before = _digest(solver_settings(opts))
    paths = list(_leaves(opts))
    assert len(paths) > 80  # strategies, refiner, tolerances
    for path in paths:
        changed = _changed(opts, path)
        assert isinstance(changed, SolverOptions)
        assert _digest(solver_settings(changed)) != before, path


def test_a_pebble_sweep_does_not_depend_on_the_solver_options():
    """The pebble game uses no solver option, so a change to one leaves a pebble sweep's
    digest (and its stored rows) as they were, while an LP threshold sweep's changes."""
    import tomllib

    from tensegrity_rigidity.ensemble.spec import parse_spec

    base = 'n = 8\np_t = 0.0\nf_c = 0.5\nphi = "dilation"\nsamples = 2\n'
    pebble = base + '[threshold]\npath = "p_r"\nmethod = "pebble"\n'
    lp = base + '[threshold]\npath = "p_r"\n'
    looser = "[solver]\nviolation_tol = 2e-9\n"

    def digest(text):
        return parse_spec(tomllib.loads(text)).settings_digest()

    assert digest(pebble) == digest(pebble + looser)
    assert digest(lp) != digest(lp + looser)
