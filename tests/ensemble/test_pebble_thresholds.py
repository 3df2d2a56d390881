"""find_threshold(method="pebble") equals the certified bisection on rods-only paths."""

from __future__ import annotations

import numpy as np
import pytest

from tensegrity_rigidity import InputError, find_threshold, rigid_clusters
from tensegrity_rigidity.ensemble.thresholds import EventPath
from tensegrity_rigidity.model.lattice import DEFAULT_DELTA
from tensegrity_rigidity.model.sampling import lattice_geometry
from tensegrity_rigidity.model.strain import strain_tensor

#: (samples, smallest n, largest n) of the default run and of the slow run
DEFAULT = (30, 4, 12)
SLOW = (120, 4, 32)


def _agreement(count: int, n_lo: int, n_hi: int, seed: int):
    rng = np.random.default_rng(seed)
    decided, disagreements = 0, []
    for k in range(count):
        n = int(rng.integers(n_lo, n_hi + 1))
        net, u, v = lattice_geometry(n, DEFAULT_DELTA, rng)
        eps = strain_tensor(float(rng.uniform(0, 2 * np.pi)), float(rng.uniform(0, 2 * np.pi)))
        lp = find_threshold(net, u, v, eps, 0.0, 0.5)
        pb = find_threshold(net, u, v, eps, 0.0, 0.5, method="pebble")
        assert pb.decided and pb.solves == 0 and pb.undecided == 0
        if lp.decided:
            decided += 1
            if not (lp.s == pb.s or (np.isnan(lp.s) and np.isnan(pb.s))):
                disagreements.append((k, n, lp.s, pb.s))
        else:  # an interval must still hold the exact threshold
            assert lp.s_low <= pb.s <= lp.s_high
    return decided, disagreements


def test_pebble_thresholds_equal_the_certified_bisection():
    decided, disagreements = _agreement(*DEFAULT, seed=770)
    assert disagreements == []
    assert decided >= 0.9 * DEFAULT[0]


@pytest.mark.slow
def test_pebble_thresholds_equal_the_certified_bisection_up_to_n_32():
    decided, disagreements = _agreement(*SLOW, seed=771)
    assert disagreements == []
    assert decided >= 100


def test_the_threshold_is_where_the_network_starts_to_wrap():
    rng = np.random.default_rng(772)
    net, u, v = lattice_geometry(8, DEFAULT_DELTA, rng)
    th = find_threshold(net, u, v, np.eye(2), 0.0, 0.5, method="pebble")
    assert 0.5 < th.s < 0.85 and th.p_t == 0.0 and th.s_low == th.s == th.s_high
    ev = EventPath(u, v, "p_r", 0.0, 0.5)
    at = int(np.searchsorted(ev.positions, th.s))  # the event that made it rigid
    assert not rigid_clusters(net.with_kinds(ev.kinds(at))).wraps
    assert rigid_clusters(net.with_kinds(ev.kinds(at + 1))).wraps


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"p_t": 0.1}, "rods-only"),
        ({"path": "total"}, "rods-only"),
        ({"method": "simplex"}, "unknown threshold method"),
    ],
)
def test_bad_pebble_requests_are_refused(kwargs, match):
    rng = np.random.default_rng(773)
    net, u, v = lattice_geometry(4, DEFAULT_DELTA, rng)
    args = {"p_t": 0.0, "path": "p_r", "method": "pebble"} | kwargs
    with pytest.raises(InputError, match=match):
        find_threshold(net, u, v, np.eye(2), args["p_t"], 0.5, args["path"], None, args["method"])


SWEEP_SPEC = """
n = 6
p_t = 0.0
phi = ["shear", "dilation"]
samples = 8
seed = 4
[threshold]
path = "p_r"
"""


def test_a_threshold_sweep_can_use_the_pebble_game(tmp_path):
    import tomllib

    from tensegrity_rigidity import load_results, parse_spec, run_sweep

    lp = parse_spec(tomllib.loads(SWEEP_SPEC))
    pb = parse_spec(tomllib.loads(SWEEP_SPEC + 'method = "pebble"\n'))
    assert pb.threshold == {"path": "p_r", "method": "pebble"}
    assert lp.threshold == {"path": "p_r"} and "threshold_method" not in lp.settings()
    assert pb.settings()["threshold_method"] == "pebble"
    run_sweep(lp, tmp_path / "lp", executor="serial", progress=False)
    run_sweep(pb, tmp_path / "pb", executor="serial", progress=False)
    a = load_results(tmp_path / "lp").sort_values(["phi", "sample"])
    b = load_results(tmp_path / "pb").sort_values(["phi", "sample"])
    assert (b.solves == 0).all() and b.decided.all()
    ok = a.decided.values
    np.testing.assert_array_equal(a.threshold_p_r.values[ok], b.threshold_p_r.values[ok])
    # the rods at the threshold: the pebble game's m*, the same by both methods
    np.testing.assert_array_equal(a.threshold_rods.values[ok], b.threshold_rods.values[ok])
    assert (b.threshold_one_sided == 0).all() and (b.sites == 3 * 36).all()
    assert (b.backbone_sites <= b.stressed_sites).all() and (b.backbone_sites > 0).all()
    assert (b.backbone_nodes <= b.stressed_nodes).all()


def test_threshold_rows_count_the_elements_just_after_the_threshold(tmp_path):
    import tomllib

    from tensegrity_rigidity import load_results, parse_spec, run_sweep
    from tensegrity_rigidity.ensemble.runner import sample_geometry
    from tensegrity_rigidity.model.network import Element

    text = SWEEP_SPEC.replace("p_t = 0.0", "p_t = 0.3\nf_c = 1.0").replace("= 8", "= 3")
    spec = parse_spec(tomllib.loads(text))
    run_sweep(spec, tmp_path / "os", executor="serial", progress=False)
    rows = load_results(tmp_path / "os")
    point = spec.points()[0]
    for r in rows.itertuples():
        _, u, v, _ = sample_geometry(spec, point, r.sample)
        ev = EventPath(u, v, "p_r", 0.3, 1.0)
        c = int(np.searchsorted(ev.positions, r.threshold_p_r)) + 1  # after the threshold event
        assert ev.positions[c - 1] == r.threshold_p_r
        at = ev.kinds(c)
        assert np.sum(at != ev.kinds(c - 1)) == 1  # one event: a rod, or a cable entering
        assert r.threshold_rods == np.sum(at == Element.ROD)
        assert r.threshold_one_sided == np.sum(at == Element.CABLE)


@pytest.mark.parametrize(
    "extra, needle",
    [
        ('method = "simplex"\n', "method must be"),
        ('method = "pebble"\np_t = 0.2\n', "rods-only"),
    ],
)
def test_bad_pebble_specs_are_refused(extra, needle):
    import tomllib

    from tensegrity_rigidity import SpecError, parse_spec

    text = SWEEP_SPEC.replace("p_t = 0.0\n", "") if "p_t" in extra else SWEEP_SPEC
    if "p_t" in extra:
        text = text.replace("n = 6\n", "n = 6\np_t = 0.2\n")
        extra = extra.replace("p_t = 0.2\n", "")
    with pytest.raises(SpecError, match=needle):
        parse_spec(tomllib.loads(text + extra))


def _bad_uniforms():
    """(name, u, v) of uniforms no sample of the network has: each must be refused."""
    rng = np.random.default_rng(774)
    net, u, v = lattice_geometry(4, DEFAULT_DELTA, rng)
    m = net.n_sites
    cases = {
        "more": (np.r_[u, rng.random(5000)], np.r_[v, rng.random(5000)]),
        "fewer": (u[: m // 2], v[: m // 2]),
        "v longer": (u, np.r_[v, 0.5]),
        "2d": (u[None, :], v),
        "nan": (np.r_[np.nan, u[1:]], v),
        "nan in v": (u, np.r_[v[:-1], np.nan]),
        "inf": (np.r_[np.inf, u[1:]], v),
        "1.5": (np.r_[1.5, u[1:]], v),
        "1.0": (np.r_[1.0, u[1:]], v),
        "negative": (np.r_[-0.1, u[1:]], v),
        "complex": (u + 0j, v),
        "strings": (np.array(["a"] * m), v),
        "none": (None, v),
    }
    return net, cases


@pytest.mark.parametrize("method", ["pebble", "lp"])
@pytest.mark.parametrize("case", list(_bad_uniforms()[1]))
def test_uniforms_that_do_not_fit_the_network_are_refused_before_any_kernel(method, case):
    """More uniforms than sites made the pebble kernel index sites that do not exist (a
    segmentation fault); fewer gave a subset's threshold; NaN or 1.5 were taken by both
    methods. Each is one InputError now."""
    net, cases = _bad_uniforms()
    u, v = cases[case]
    with pytest.raises(InputError, match=r"^[^\n]*$"):
        find_threshold(net, u, v, np.eye(2), 0.0, 0.5, method=method)


@pytest.mark.parametrize(
    "p_t, f_c", [(2.0, 0.5), (-0.1, 0.5), (0.0, 5.0), (0.0, np.nan), ("x", 0.5)]
)
def test_probabilities_of_a_threshold_path_are_checked(p_t, f_c):
    rng = np.random.default_rng(775)
    net, u, v = lattice_geometry(4, DEFAULT_DELTA, rng)
    for method in ("lp", "pebble"):
        with pytest.raises(InputError, match="p_t|f_c"):
            find_threshold(net, u, v, np.eye(2), p_t, f_c, method=method)


def test_more_uniforms_than_sites_does_not_kill_the_interpreter(tmp_path):
    """The crash itself, in a child process (exit 139 before the fix)."""
    import subprocess
    import sys

    script = (
        "import numpy as np\n"
        "from tensegrity_rigidity import InputError, find_threshold\n"
        "from tensegrity_rigidity.model.sampling import lattice_geometry\n"
        "net, u, v = lattice_geometry(6, 0.1, np.random.default_rng(0))\n"
        "r = np.random.default_rng(1)\n"
        "try:\n"
        "    find_threshold(net, r.random(200000), r.random(200000), np.eye(2), 0, 0.5,\n"
        "                   method='pebble')\n"
        "except InputError as exc:\n"
        "    print('refused:', exc)\n"
    )
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr[-500:]
    assert out.stdout.startswith("refused: u must have shape")
