"""The builders of the API with every malformed argument: one-line InputError, never a traceback
and never a silently different object."""

from __future__ import annotations

import numpy as np
import pytest

from tensegrity_rigidity import (
    InputError,
    SolverOptions,
    lattice_instance,
    random_periodic_network,
    square_lattice,
    strain_tensor,
    triangular_lattice,
)
from tensegrity_rigidity.model.lattice import fcc_lattice
from tensegrity_rigidity.model.strain import sequence_rotation

#: values of every wrong type and range
MALFORMED = [
    None,
    "x",
    "",
    [1, 2],
    {},
    (),
    1j,
    True,
    -1,
    -0.1,
    float("nan"),
    float("inf"),
    10**30,
    10**400,
    np.array([1.0, 2.0]),
    np.eye(2),
    object(),
]


def _rng():
    return np.random.default_rng(0)


#: (builder, its valid arguments): each argument in turn is replaced by each malformed value
BUILDERS = {
    "lattice_instance": (
        lattice_instance,
        dict(n=4, p_r=0.6, p_t=0.2, f_c=0.5, phi="shear", theta=0.0, gamma=1.0, delta=0.2),
    ),
    "lattice_instance fcc": (
        lattice_instance,
        dict(n=3, p_r=0.6, p_t=0.2, phi="shear", theta=0.0, delta=0.2, lattice="fcc"),
    ),
    "lattice_instance seed and lattice": (
        lattice_instance,
        dict(n=4, p_r=0.6, seed=1, lattice="triangular", rotation_matrix=None),
    ),
    "triangular_lattice": (triangular_lattice, dict(n=4, delta=0.2, rng=_rng)),
    "square_lattice": (square_lattice, dict(n=4, delta=0.2, rng=_rng, diagonals=False)),
    "fcc_lattice": (fcc_lattice, dict(n=3, delta=0.2, rng=_rng)),
    "random_periodic_network": (
        random_periodic_network,
        dict(n_nodes=5, n_bonds=8, rng=_rng, box=None, max_shift=1, dim=2),
    ),
    "strain_tensor": (
        strain_tensor,
        dict(phi="shear", theta=0.0, gamma=1.0, rotation_matrix=None, dim=None),
    ),
    "sequence_rotation": (sequence_rotation, dict(k=3)),
}


def _acceptable(builder: str, key: str, value) -> bool:
    """Whether ``value`` is a valid ``key`` of ``builder`` after all (the table is shared)."""
    real = isinstance(value, (int, float)) and not isinstance(value, bool)
    finite = real and abs(value) < 1e308
    if key in ("phi", "theta") and finite:  # any angle; a nonzero theta is 2D only
        return key == "phi" or "fcc" not in builder
    if key == "gamma" and finite:
        return 1e-140 <= value <= 1e140
    if value is None:
        return key in ("seed", "rotation_matrix", "box", "dim")  # (rng: delta > 0 here)
    if key == "seed" and isinstance(value, int) and not isinstance(value, bool):
        return value >= 0  # any non-negative integer seeds a SeedSequence
    if key == "rotation_matrix" and isinstance(value, np.ndarray):
        return value.shape == (2, 2) and "fcc" not in builder
    if key == "box" and isinstance(value, np.ndarray):
        return value.shape == (2, 2)
    if key == "diagonals":
        return value is True
    return False


def _cases():
    for name, (fn, base) in BUILDERS.items():
        for key in base:
            for value in MALFORMED:
                yield pytest.param(name, fn, base, key, value, id=f"{name}-{key}-{value!r:.12}")


@pytest.mark.parametrize("name, fn, base, key, value", list(_cases()))
def test_every_malformed_argument_is_one_line(name, fn, base, key, value):
    """delta=None, rng=42, a phi, theta or gamma of the wrong type, a lattice that is a list:
    tracebacks before (TypeError, AttributeError, ValueError, OverflowError)."""
    kw = {k: (v() if callable(v) else v) for k, v in base.items()}
    kw[key] = value
    if _acceptable(name, key, value):
        fn(**kw)
        return
    with pytest.raises(InputError) as info:
        fn(**kw)
    assert "\n" not in str(info.value) and len(str(info.value)) < 300, info.value


@pytest.mark.parametrize(
    "call, needle",
    [
        (lambda: lattice_instance(4, 0.5, delta=None), "delta must be a number"),
        (lambda: triangular_lattice(4, 0.2, rng=42), "rng must be a numpy.random.Generator"),
        (lambda: triangular_lattice(4, 0.0, rng=42), "rng must be a numpy.random.Generator"),
        (lambda: random_periodic_network(4, 6, _rng(), box=np.eye(2), dim=3), "dim = 3"),
        (lambda: random_periodic_network(4, 6, 42), "rng must be"),
        (lambda: random_periodic_network(4.5, 6, _rng()), "n_nodes must be an integer"),
        (lambda: square_lattice(4, 0.2, _rng(), diagonals="yes"), "diagonals must be True"),
        (lambda: lattice_instance(4, 0.5, p_t=2), "p_t must lie in"),
        (lambda: lattice_instance(4, 0.5, f_c=5), "f_c must lie in"),
        (lambda: lattice_instance(4, 0.5, f_c=True), "f_c must be a number"),
        (lambda: lattice_instance(4, 0.5, lattice=["fcc"]), "unknown lattice"),
        (lambda: strain_tensor("shear", dim=np.array([2, 3])), "dim must be 2 or 3"),
    ],
)
def test_the_reported_builder_mistakes_are_refused(call, needle):
    with pytest.raises(InputError, match=needle.replace("(", r"\(")):
        call()


def test_a_random_network_takes_its_dimension_from_its_box():
    """dim=3 with a 2D box returned a 2D network; without dim the box decides."""
    assert random_periodic_network(4, 6, _rng(), box=np.eye(3) * 2).dim == 3
    assert random_periodic_network(4, 6, _rng(), dim=3).dim == 3
    assert random_periodic_network(4, 6, _rng()).dim == 2


@pytest.mark.parametrize("theta", [0.3, -1.0, 1e-9])
def test_a_nonzero_theta_is_refused_where_a_rotation_sets_the_axes(theta):
    """`lattice_instance(..., lattice="fcc", theta=...)` and `strain_tensor(..., dim=3,
    theta=...)` ignored theta silently (3D axes are a rotation matrix)."""
    with pytest.raises(InputError, match="ignored in 3D"):
        lattice_instance(3, 0.6, lattice="fcc", theta=theta)
    with pytest.raises(InputError, match="ignored in 3D"):
        strain_tensor("shear", theta, dim=3)
    with pytest.raises(InputError, match="both set the principal axes"):
        strain_tensor("shear", theta, rotation_matrix=sequence_rotation(2))
    with pytest.raises(InputError, match="both set the principal axes"):
        strain_tensor("shear", theta, rotation_matrix=np.eye(2))
    # theta = 0 (the default) and 2D angles keep working, bit for bit
    assert np.array_equal(
        lattice_instance(3, 0.6, lattice="fcc", theta=0.0).strain,
        lattice_instance(3, 0.6, lattice="fcc").strain,
    )
    assert strain_tensor("shear", theta).shape == (2, 2)


def test_solver_options_of_the_wrong_type_are_refused():
    for kw, needle in (
        ({"stages": {"lp": 1}}, "stages must be a list"),
        ({"stages": "lp"}, "stages must be a list"),
        ({"refiner": 3}, "refiner must be a Refiner"),
        ({"tolerances": None}, "tolerances must be a Tolerances"),
        ({"max_iter": np.eye(2)}, "max_iter must be int"),
    ):
        with pytest.raises(InputError, match=needle) as info:
            SolverOptions(**kw)
        assert "\n" not in str(info.value)


def _api_misuses():
    """(name, call, needle) of wrong-typed API calls found beyond the issue's list."""
    from tensegrity_rigidity import (
        decide,
        find_threshold,
        load_instance,
        nonaffinity,
        run_sweep,
        solve,
    )

    inst = lattice_instance(4, 0.6, 0.2, seed=1)
    other = lattice_instance(5, 0.6, seed=1)
    net = inst.network
    rng = np.random.default_rng(0)
    u, v = rng.random(net.n_sites), rng.random(net.n_sites)
    return [
        ("options dict", lambda: decide(inst, {"max_iter": 3}), "options must be a SolverOptions"),
        ("options str", lambda: solve(inst, "fast"), "options must be a SolverOptions"),
        (
            "start shape",
            lambda: decide(inst, initial_displacements=np.zeros(3)),
            "initial_displacements must have shape",
        ),
        (
            "start NaN",
            lambda: decide(inst, initial_displacements=np.full((16, 2), np.nan)),
            "initial_displacements contains NaN",
        ),
        (
            "tensions shape",
            lambda: decide(inst, initial_tensions=np.zeros(5)),
            "initial_tensions must have shape",
        ),
        ("tensions text", lambda: decide(inst, initial_tensions="x"), "must be a numeric"),
        (
            "another instance's result",
            lambda: nonaffinity(inst, solve(other)),
            "pass the result of solve",
        ),
        ("nonaffinity gamma", lambda: nonaffinity(inst, solve(inst), gamma="x"), "gamma"),
        (
            "threshold options",
            lambda: find_threshold(net, u, v, np.eye(2), 0.0, 0.5, options={"a": 1}),
            "options must be a SolverOptions",
        ),
        ("sweep of a number", lambda: run_sweep(5, "never"), "spec must be a Spec"),
        ("sweep of a dict", lambda: run_sweep({"n": 4}, "never"), "spec must be a Spec"),
        ("instance path", lambda: load_instance(5), "must be a str or path"),
    ]


@pytest.mark.parametrize("name, call, needle", _api_misuses(), ids=lambda x: str(x)[:20])
def test_wrong_types_beyond_the_builders_are_one_line(name, call, needle):
    """Found by trying every public function with wrong types: AttributeError, ValueError,
    IndexError and TypeError tracebacks before, and one silent wrong number (the nonaffinity
    of another instance's result)."""
    with pytest.raises(InputError, match=needle) as info:
        call()
    assert "\n" not in str(info.value)
