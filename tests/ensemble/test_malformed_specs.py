"""Malformed specs and results directories: one line (a TensegrityError), never a traceback.

Every key of a spec is tried with values of every wrong type and range (a table), then with
whatever Hypothesis draws; a recorded ``_spec.json`` and ``_manifest.jsonl`` likewise.
"""

from __future__ import annotations

import copy
import json
import os
import shutil
import warnings

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tensegrity_rigidity import InputError, SpecError, TensegrityError, parse_spec, run_sweep
from tensegrity_rigidity.cli.main import main
from tensegrity_rigidity.ensemble.spec import FLAT_KEYS, SECTIONS
from tensegrity_rigidity.ensemble.sweep import describe, load_results

#: values of every wrong type and range: tables, lists of lists, bools, huge, NaN, infinite
MALFORMED = [
    None,
    "",
    "x",
    [],
    [1, [2]],
    {},
    {"name": "fcc"},
    ["fcc"],
    True,
    -1,
    0,
    1.5,
    5,
    -0.1,
    float("nan"),
    float("inf"),
    -float("inf"),
    10**30,
    10**400,
    -(10**19),
    1e300,
    [0.5, 0.5],
]
GRID = {"n": 4, "p_r": 0.5, "samples": 2}
THRESHOLD = {"n": 4, "p_t": 0.0, "samples": 2, "threshold": {"path": "p_r"}}


def _outcome(data) -> str:
    """ "ok", or the one-line message; anything else fails the test."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            parse_spec(data)
        except TensegrityError as exc:
            text = str(exc)
            assert "\n" not in text and len(text) < 300, text
            return text
    return "ok"


def _every_key():
    for base in (GRID, THRESHOLD):
        for key in FLAT_KEYS:
            yield base, (key,)
        for section, keys in SECTIONS.items():
            yield base, (section,)
            for key in sorted(keys):
                yield base, (section, key)


@pytest.mark.parametrize("base, where", list(_every_key()))
def test_every_key_with_every_malformed_value_is_one_line(base, where):
    """Before: `[lattice] kind = ["fcc"]` or `{name = "fcc"}` (unhashable), an integer beyond
    a double (OverflowError) ended in tracebacks; long values made multi-line messages."""
    for value in MALFORMED:
        data = copy.deepcopy(base)
        if len(where) == 1:
            data[where[0]] = value
        else:
            data.setdefault(where[0], {})[where[1]] = value
        _outcome(data)


@pytest.mark.parametrize(
    "extra, needle",
    [
        ({"lattice": {"kind": ["fcc"]}}, "[lattice] kind must be one of"),
        ({"lattice": {"kind": {"name": "fcc"}}}, "[lattice] kind must be one of"),
        ({"solver": {"stages": {"lp": 1}}}, "stages must be a list"),
        ({"solver": {"stages": "lp"}}, "stages must be a list"),
        ({"lattice": {"kind": "fcc"}, "strain": {"angles": "uniform"}}, "sequence_rotation"),
        ({"p_r": 10**400}, "'p_r' must be finite"),
        ({"threshold": {"path": ["p_r"]}}, "[threshold] path must be one of"),
        ({"solver": {"regularization": 0}}, "regularization must be at least 1e-14"),
        ({"solver": {"regularization": 1e-17}}, "regularization must be at least 1e-14"),
        # the pebble game on an undisordered lattice gave median thresholds 0.97 against the
        # LP's 0.60 (square, n = 6): its positions are not generic
        (
            {"delta": 0.0, "p_t": 0.0, "threshold": {"path": "p_r", "method": "pebble"}},
            "method 'pebble' decides generic positions",
        ),
    ],
)
def test_the_reported_malformed_specs_are_refused(extra, needle):
    """`stages = {lp = 1}` was taken as the list ["lp"]; `angles = "uniform"` on the FCC
    lattice changed only the digest (3D axes are sequence_rotation(k))."""
    data = copy.deepcopy(GRID) | extra
    if "threshold" in extra:
        data.pop("p_r")
    with pytest.raises(SpecError) as info:
        parse_spec(data)
    assert needle in str(info.value)


def test_valid_3d_and_2d_angle_specs_are_still_accepted():
    parse_spec(GRID | {"lattice": {"kind": "fcc"}, "strain": {"angles": "golden"}})
    parse_spec(GRID | {"strain": {"angles": "uniform"}})
    parse_spec(GRID | {"solver": {"stages": ["newton", "lp"]}})


#: anything a TOML file or a dict can hold
VALUES = st.recursive(
    st.none()
    | st.booleans()
    | st.integers(min_value=-(10**30), max_value=10**30)
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.text(max_size=8),
    lambda inner: (
        st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=6), inner, max_size=3)
    ),
    max_leaves=6,
)
KEYS = st.sampled_from(list(FLAT_KEYS) + list(SECTIONS))


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.dictionaries(KEYS, VALUES, max_size=6), st.sampled_from([GRID, THRESHOLD]))
def test_any_spec_is_accepted_or_refused_in_one_line(extra, base):
    _outcome(copy.deepcopy(base) | extra)


@settings(max_examples=200, deadline=None)
@given(
    st.sampled_from(sorted((s, k) for s, keys in SECTIONS.items() for k in keys)),
    VALUES,
)
def test_any_section_value_is_accepted_or_refused_in_one_line(where, value):
    section, key = where
    data = copy.deepcopy(THRESHOLD if section == "threshold" else GRID)
    data.setdefault(section, {})[key] = value
    _outcome(data)


# --------------------------------------------------------------------------- results directories


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    out = tmp_path_factory.mktemp("finished") / "run"
    run_sweep(parse_spec(GRID | {"p_r": [0.5, 0.7]}), out, executor="serial", progress=False)
    return out


SPEC_JSON_FIELDS = [
    ("spec",),
    ("spec", "grid"),
    ("spec", "grid", "n"),
    ("spec", "grid", "p_r"),
    ("spec", "grid", "phi"),
    ("spec", "samples"),
    ("spec", "lattice"),
    ("spec", "gamma"),
    ("spec", "angles"),
    ("spec", "solver"),
    ("spec", "chunk_size"),
    ("spec", "threshold"),
    ("spec", "verdict"),
    ("settings",),
    ("settings_digest",),
    ("rows_revision",),
    ("format",),
]


@pytest.mark.parametrize("where", SPEC_JSON_FIELDS)
def test_a_spec_json_with_wrong_types_is_one_line(tmp_path, finished, where):
    """`info` on a directory whose _spec.json had wrong types printed a traceback."""
    record = json.loads((finished / "_spec.json").read_text())
    for i, value in enumerate(MALFORMED[:14] + [10**30]):
        out = tmp_path / f"d{i}"
        shutil.copytree(finished, out)
        changed = copy.deepcopy(record)
        node = changed
        for key in where[:-1]:
            node = node[key]
        node[where[-1]] = value
        (out / "_spec.json").write_text(json.dumps(changed))
        for call in (describe, load_results):
            try:
                call(out)
            except InputError as exc:
                assert "\n" not in str(exc), exc


def test_info_on_a_malformed_spec_json_is_one_line(tmp_path, finished, capsys):
    out = tmp_path / "bad"
    shutil.copytree(finished, out)
    record = json.loads((out / "_spec.json").read_text())
    record["spec"]["lattice"] = ["fcc"]
    (out / "_spec.json").write_text(json.dumps(record))
    assert main(["info", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "_spec.json does not describe a sweep" in err, err


@pytest.mark.parametrize(
    "entry",
    [
        {"part": "../outside.parquet", "bytes": 1, "sha256": "0", "rows": 1},
        {"part": "OUTSIDE", "bytes": 1, "sha256": "0", "rows": 1},
        {"part": ["a"], "bytes": 1},
        {"part": "part-x.parquet", "bytes": "1"},
        [],
        "x",
    ],
)
def test_a_manifest_entry_never_names_a_file_outside_the_directory(tmp_path, finished, entry):
    """A manifest line whose "part" was a path (``../x``, ``/abs``) had that file read and,
    failing its checksum, deleted: a resumed sweep could delete files anywhere."""
    out = tmp_path / "run"
    shutil.copytree(finished, out)
    victim = tmp_path / "outside.parquet"
    victim.write_text("keep me")
    if isinstance(entry, dict) and entry.get("part") == "OUTSIDE":
        entry = dict(entry, part=str(victim))  # an absolute path
    with open(out / "_manifest.jsonl", "a") as fh:
        fh.write(json.dumps(entry) + "\n")
    describe(out)
    run_sweep(parse_spec(GRID | {"p_r": [0.5, 0.7]}), out, executor="serial", progress=False)
    assert victim.read_text() == "keep me"
    assert len(load_results(out)) == 4


def test_packing_fractions_that_seed_the_same_samples_are_refused():
    """0.8400001 and 0.8400002 drew the same packings (the seed rounds the fraction to 1e-6)."""
    spec = {"packing": {}, "n": 16, "fraction": [0.8400001, 0.8400002]}
    with pytest.raises(SpecError, match="differ in their first 6 decimals"):
        parse_spec(spec)
    parse_spec(spec | {"fraction": [0.840001, 0.840002]})


def test_a_spec_is_read_once_so_a_pipe_works_and_a_bom_is_named(tmp_path):
    """``sweep <(cat spec.toml)`` read the pipe twice and saw an empty second read."""
    from tensegrity_rigidity.ensemble.spec import load_spec_text

    text = "n = 4\np_r = [0.5]\nsamples = 1\n"
    read, write = os.pipe()
    os.write(write, text.encode())
    os.close(write)
    try:
        spec, source = load_spec_text(f"/dev/fd/{read}")
    finally:
        os.close(read)
    assert source == text and spec.samples == 1
    bom = tmp_path / "bom.toml"
    bom.write_text("\ufeff" + text, encoding="utf-8")
    with pytest.raises(SpecError, match="byte-order mark"):
        load_spec_text(bom)
