"""Sweep specifications: a TOML file describing a grid of parameters and what to compute.

Flat keys (each a scalar or a list of distinct values; the grid is the product of the lists)::

    n = [16, 32]            # lattice size
    delta = 0.2             # node disorder
    p_r = [0.4, 0.5, 0.6]   # rod probability
    p_t = 0.3               # one-sided element probability
    f_c = [0.0, 0.5, 1.0]   # cable fraction
    phi = ["dilation", "shear", "compression", 0.7]
    samples = 100           # samples k = 1 .. samples per grid point
    seed = 1                # a list gives independent replicas (non-negative integers)
    verdict = "exact"       # "paper": decide grid samples the paper's way instead
                            # (ensemble.inexact: L-BFGS-B from u = 0, E > 1e-8 E(u = 0))

Optional sections (defaults shown, but for ``[solver]``, whose line is an example)::

    [lattice]
    kind = "triangular"     # or "square", or "fcc" (3D: principal axes by sequence_rotation(k))

    [strain]
    gamma = 1.0             # magnitude; E scales as gamma^2, verdicts do not depend on it
    angles = "golden"       # principal-axis angle of sample k: "golden" or "uniform" (below)

    [solver]                # any field of SolverOptions (finite values); none by default
    max_iter = 100          # e.g. Newton's iterations (SolverOptions' default is 40)

    [output]
    chunk_size = 32         # samples per result file (the unit of resumption)

    [threshold]             # threshold mode: per-sample critical point along a monotone path
    path = "p_r"            # "p_r": raise p_r at fixed p_t;  "total": raise p_r at fixed
                            # p_r + p_t = p_t (p_t then means the total occupation)
    method = "lp"           # "lp": certified bisection; "pebble": one pebble-game pass,
                            # rods-only paths only (path "p_r", p_t = 0)

    [packing]               # packing mode: random bidisperse soft packings, each tested
    dim = 2                 # for collective and strict jamming (ensemble.jamming); 2 or 3
    ratio = 1.4             # diameter ratio of the large to the small particles

In threshold mode the grid's ``p_r`` key is not used (omit it). In packing mode the grid is
``n`` (particles), ``fraction`` (packing fractions, required) and ``seed``; the lattice's keys
and sections (``delta``, ``p_r``, ``p_t``, ``f_c``, ``phi``, ``verdict``, ``[lattice]``,
``[strain]``, ``[solver]``, ``[threshold]``) do not apply and are refused. Sample ``k`` at
``(n, fraction, seed)`` is drawn from ``default_rng([seed, n, round(fraction 1e6), k])``
(:func:`~tensegrity_rigidity.ensemble.jamming.sample_rng`); its strain angle is 0.

``verdict = "paper"`` applies to grid mode only (a bisection needs verdicts monotone in p_r,
which the paper's are not); its rows hold the verdict, the energy reached, the affine energy and
the iteration count.

Strain angles. Sample ``k`` is strained along principal axes at angle ``theta_k``:

* ``"golden"`` (the default): ``theta_k = 2 pi frac((k - 1) phi_g)`` with the golden ratio
  ``phi_g = (1 + sqrt 5) / 2``. It does not depend on the number of samples, so a sweep can grow
  (``samples = 100`` -> ``200``) and keep every finished sample. Any ``K`` consecutive angles are
  spread almost evenly over the circle (at most three distinct gaps, the three-distance
  theorem; discrepancy O(log K / K)), far below the ``1 / sqrt K`` statistical error of ``K``
  samples, so the sequence adds no visible error to an average over theta. Since
  ``eps(theta + pi) = eps(theta)``, what matters is ``2 theta`` modulo ``2 pi``, again an
  irrational rotation: no two samples share a strain tensor. This is the default because
  sweeps should be extendable; the reproduction of the paper uses it.
* ``"uniform"``: the paper's ``theta_k = 2 pi (k - 1) / samples``. Every angle depends on the
  total count, so changing ``samples`` changes every sample (nothing is reused); with an even
  count the samples come in pairs ``theta``, ``theta + pi`` of identical strain tensors.

Randomness: sample k at grid point (n, delta, seed) draws its geometry and site uniforms from
``SeedSequence(seed, spawn_key=(n, bits(delta), k))``; it does not depend on ``p_r``, ``p_t``,
``f_c`` or ``phi``. Samples of the same index therefore share their disorder across those
parameters (common random numbers): each sample's rigidity is monotone in ``p_r`` and ``p_t``,
differences between grid points are far less noisy, and thresholds derive exactly the grid's P.

Identity of results. Everything that changes a sample's result and is not a grid value is a
*setting* (:meth:`Spec.settings`: mode and threshold path, lattice, gamma, angle sequence, every
field of the effective :class:`~tensegrity_rigidity.solver.core.SolverOptions`). Each row is
keyed by its :meth:`Spec.point_key` (a digest of the settings and the grid point), its sample
index and its angle, so a results directory can grow by samples or grid values, or be resumed
with another chunk size or worker count, and reuse every finished row; a spec with other
settings is refused there (it would compute different rows).
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import os
import sys
import tomllib
import warnings
from dataclasses import dataclass, field, fields, is_dataclass, replace
from functools import cached_property
from pathlib import Path
from typing import Any

from ..errors import InputError, SpecError
from ..model.lattice import CROSSING_DELTA
from ..model.limits import check_gamma
from ..model.network import show
from ..model.sampling import LATTICE_DIMENSIONS, LATTICES
from ..model.softdisks import DIAMETER_RATIO, FIRE, GRADIENT_TOL, MAX_STEPS
from ..model.strain import parse_phi
from ..solver.core import SolverOptions
from ..solver.jamming import JammingOptions

GRID_KEYS = ("n", "delta", "p_r", "p_t", "f_c", "phi", "seed")
#: the grid of packing mode: particles, packing fraction, seed
PACKING_KEYS = ("n", "fraction", "seed")

#: Packing fractions enter the seed rounded to this many decimals: two fractions closer than
#: that would draw the same packings, so a spec must keep them apart.
FRACTION_DECIMALS = 6


def fraction_key(phi: float) -> int:
    """A packing fraction as the integer that seeds its samples: ``round(phi 10^6)``.

    Parameters
    ----------
    phi : float
        Packing fraction.

    Returns
    -------
    int
    """
    return int(round(phi * 10**FRACTION_DECIMALS))


FLAT_KEYS = GRID_KEYS + ("samples", "verdict", "fraction")
VERDICTS = ("exact", "paper")
#: how threshold mode finds a sample's threshold (:func:`~.thresholds.find_threshold`)
THRESHOLD_METHODS = ("lp", "pebble")
THRESHOLD_PATHS = ("p_r", "total")
SECTIONS = {
    "lattice": {"kind"},
    "strain": {"gamma", "angles"},
    # the scalar fields of SolverOptions, and ``stages`` as names
    "solver": {f.name for f in fields(SolverOptions)} - {"refiner", "tolerances"},
    "output": {"chunk_size"},
    "threshold": {"path", "method"},
    "packing": {"dim", "ratio"},
}
#: the keys and sections of lattice sweeps, which a packing sweep refuses
LATTICE_ONLY = ("delta", "p_r", "p_t", "f_c", "phi", "verdict", "lattice", "strain", "solver",
                "threshold")  # fmt: skip
DEFAULTS: dict[str, list] = {
    "n": [16],
    "delta": [0.2],
    "p_t": [0.0],
    "f_c": [0.5],
    "phi": ["shear"],
    "seed": [0],
}
ANGLE_SEQUENCES = ("golden", "uniform")
#: the golden ratio of the "golden" angle sequence
GOLDEN = (1.0 + math.sqrt(5.0)) / 2.0


def strain_angle(k: int, samples: int, sequence: str = "golden") -> float:
    """Principal-axis angle theta of sample ``k`` (1-based) of ``samples``, in [0, 2 pi).

    Parameters
    ----------
    k : int
        Sample index, ``1 <= k <= samples``.
    samples : int
        Samples per grid point (used by ``"uniform"`` only).
    sequence : {"golden", "uniform"}
        ``2 pi frac((k - 1) phi_g)`` or the paper's ``2 pi (k - 1) / samples`` (module docstring).

    Returns
    -------
    float
        theta_k, radians.

    Raises
    ------
    InputError
        On an unknown sequence.

    Examples
    --------
    >>> from tensegrity_rigidity.ensemble.spec import strain_angle
    >>> [round(strain_angle(k, 100), 4) for k in (1, 2, 3)]
    [0.0, 3.8832, 1.4833]
    """
    if sequence == "golden":
        return 2.0 * math.pi * math.fmod((k - 1) * GOLDEN, 1.0)
    if sequence == "uniform":
        return 2.0 * math.pi * (k - 1) / samples
    raise InputError(f"unknown angle sequence {sequence!r}; use 'golden' or 'uniform'")


@dataclass(frozen=True)
class GridPoint:
    """One point of the parameter grid.

    Attributes
    ----------
    n : int
        Lattice size.
    delta : float
        Node disorder.
    p_r : float
        Rod probability (NaN in threshold mode).
    p_t : float
        One-sided probability (the total ``p_r + p_t`` on the threshold path "total").
    f_c : float
        Cable fraction.
    phi : float
        Strain type.
    seed : int
        Seed of the samples' randomness.
    fraction : float
        Packing fraction (packing mode; NaN otherwise, where it is not part of the point's key).
    """

    n: int
    delta: float
    p_r: float
    p_t: float
    f_c: float
    phi: float
    seed: int
    fraction: float = math.nan


#: the fields of a lattice point's key (a packing point's are :data:`PACKING_KEYS`)
_POINT_FIELDS = GRID_KEYS
#: the largest finite double: an integer beyond it is not a number a float key can hold
_LARGEST_FLOAT = sys.float_info.max
#: the largest integer a row stores (int64 columns)
_LARGEST_INT = 2**63 - 1


def _plain(obj: Any) -> Any:
    """``obj`` as JSON reads it back: a dataclass as its class name and fields (recursively),
    tuples as lists; other objects (a strategy that is not a dataclass) by their type name."""
    if is_dataclass(obj) and not isinstance(obj, type):
        return {"class": type(obj).__name__} | {
            f.name: _plain(getattr(obj, f.name)) for f in fields(obj)
        }
    if isinstance(obj, (list, tuple)):
        return [_plain(x) for x in obj]
    if obj is None or isinstance(obj, (bool, int, float, str)):
        return obj
    return {"class": type(obj).__name__}


def solver_settings(options: SolverOptions) -> dict:
    """The solver options as the settings record them: the whole frozen object, recursively.

    Parameters
    ----------
    options : SolverOptions
        The effective options.

    Returns
    -------
    dict
        JSON-ready: each dataclass as its class name and fields, tuples as lists.
    """
    return _plain(options)


def packing_settings(packing: dict) -> dict:
    """The settings of a packing sweep: what changes its rows besides the grid.

    Parameters
    ----------
    packing : dict
        The spec's ``[packing]`` section as parsed (``dim``, ``ratio``).

    Returns
    -------
    dict
        JSON-ready: ``mode`` ("packing"), ``packing``, ``minimiser`` (FIRE's constants, the
        force tolerance and the step limit of :mod:`~tensegrity_rigidity.model.softdisks`)
        and ``jamming`` (the test's :class:`~tensegrity_rigidity.solver.jamming.JammingOptions`,
        whole).
    """
    minimiser = {"fire": dict(sorted(FIRE.items())), "gradient_tol": GRADIENT_TOL,
                 "max_steps": MAX_STEPS}  # fmt: skip
    return {"mode": "packing", "packing": dict(sorted(packing.items())), "minimiser": minimiser,
            "jamming": _plain(JammingOptions())}  # fmt: skip


def _digest(obj) -> str:
    return hashlib.sha256(json.dumps(obj, sort_keys=True).encode()).hexdigest()


@dataclass(frozen=True)
class Spec:
    """A validated sweep specification (see the module docstring); built by :func:`parse_spec`.

    Attributes
    ----------
    grid : dict
        Grid key ("n", "delta", "p_r", "p_t", "f_c", "phi", "seed") -> list of values (no
        "p_r" in threshold mode); phi as floats.
    samples : int
        Samples per grid point.
    lattice : str
        "triangular" or "square".
    gamma : float
        Strain magnitude.
    solver : dict
        Fields of :class:`~tensegrity_rigidity.SolverOptions` given in ``[solver]``.
    chunk_size : int
        Samples per result file (the unit of resumption).
    threshold : dict or None
        ``{"path": "p_r" | "total"}`` in threshold mode (with ``"method": "pebble"`` when so
        chosen), None in grid mode.
    angles : str
        Strain-angle sequence, "golden" or "uniform".
    verdict : str
        "exact" or "paper".
    packing : dict or None
        ``{"dim": d, "ratio": r}`` in packing mode (its grid: :data:`PACKING_KEYS`), None
        otherwise.
    """

    grid: dict[str, list]
    samples: int
    lattice: str = "triangular"
    gamma: float = 1.0
    solver: dict = field(default_factory=dict)
    chunk_size: int = 32
    threshold: dict | None = None
    angles: str = "golden"
    verdict: str = "exact"
    packing: dict | None = None

    @property
    def mode(self) -> str:
        """ "packing" (a ``[packing]`` section), "threshold" (a ``[threshold]`` section) or
        "grid"."""
        if self.packing is not None:
            return "packing"
        return "threshold" if self.threshold is not None else "grid"

    def _keys(self) -> tuple[str, ...]:
        """The grid's keys, in the order of :meth:`points`."""
        if self.mode == "packing":
            return PACKING_KEYS
        return tuple(k for k in GRID_KEYS if k != "p_r" or self.mode == "grid")

    def n_points(self) -> int:
        """Number of grid points, without building them.

        Returns
        -------
        int
            The product of the lengths of the grid's lists.
        """
        return math.prod(len(self.grid[k]) for k in self._keys())

    def points(self) -> list[GridPoint]:
        """All grid points, in a fixed order.

        Returns
        -------
        list of GridPoint
            The product of the grid's lists in the order n, delta, p_r, p_t, f_c, phi, seed
            (packing mode: n, fraction, seed; the lattice's fields NaN).
        """
        g = self.grid
        if self.mode == "packing":
            nan = math.nan
            return [
                GridPoint(int(n), nan, nan, nan, nan, nan, int(sd), float(fr))
                for n, fr, sd in itertools.product(g["n"], g["fraction"], g["seed"])
            ]
        p_r = g["p_r"] if self.mode == "grid" else [math.nan]
        return [
            GridPoint(int(n), float(d), float(pr), float(pt), float(fc), float(ph), int(sd))
            for n, d, pr, pt, fc, ph, sd in itertools.product(
                g["n"], g["delta"], p_r, g["p_t"], g["f_c"], g["phi"], g["seed"]
            )
        ]

    def solver_options(self) -> SolverOptions:
        """The options every solve of this sweep uses.

        Returns
        -------
        SolverOptions
            The ``[solver]`` section over the defaults; threshold mode does not compute the
            minimum-norm displacements unless asked.
        """
        base = {"min_norm": False} if self.mode == "threshold" else {}
        return SolverOptions(**(base | self.solver))

    def angle(self, k: int) -> float:
        """The principal-axis angle of sample k.

        Parameters
        ----------
        k : int
            Sample index, 1-based.

        Returns
        -------
        float
            theta_k of the spec's angle sequence (:func:`strain_angle`); 0 in packing mode,
            which strains nothing.
        """
        if self.mode == "packing":
            return 0.0
        return strain_angle(k, self.samples, self.angles)

    def settings(self) -> dict:
        """Everything but the grid that changes a sample's result (JSON-ready).

        The effective :class:`SolverOptions` are listed as a whole, recursively (the
        strategies in order with their knobs, the refiner, every tolerance), defaults
        included, so a changed default anywhere in the search is a changed setting.

        Returns
        -------
        dict
            ``mode``, ``threshold_path``, ``lattice``, ``gamma``, ``angles``, ``verdict``,
            ``solver`` (and ``threshold_method`` when it is not ``"lp"``). A
            pebble-game sweep records ``solver`` as ``None``: no solver option can change its
            rows, so a change to the solver leaves them current. A packing sweep records
            ``mode``, ``packing`` (dimension and diameter ratio), ``minimiser`` (FIRE's
            constants, its force tolerance and step limit) and ``jamming`` (the test's options).
        """
        if self.mode == "packing":
            return packing_settings(self.packing or {})
        pebble = self.threshold is not None and self.threshold.get("method") == "pebble"
        return {
            "mode": self.mode,
            "threshold_path": None if self.threshold is None else self.threshold["path"],
            **(
                {"threshold_method": self.threshold["method"]}
                if self.threshold is not None and "method" in self.threshold
                else {}
            ),
            "lattice": self.lattice,
            "gamma": self.gamma,
            "angles": self.angles,
            "verdict": self.verdict,
            # the options as a whole: any field, however deep, is part of the digest
            "solver": None if pebble else solver_settings(self.solver_options()),
        }

    def settings_digest(self) -> str:
        """SHA-256 of :meth:`settings`: a results directory holds rows of one digest.

        Returns
        -------
        str
            64 hexadecimal digits.
        """
        return _digest(self.settings())

    def point_key(self, point: GridPoint) -> str:
        """Digest of the settings and the grid point: with (sample, theta) a row's identity.

        Parameters
        ----------
        point : GridPoint
            A point of this spec's grid.

        Returns
        -------
        str
            24 hexadecimal digits, stored in every row as ``point_key``.
        """
        keys = PACKING_KEYS if self.mode == "packing" else _POINT_FIELDS
        p = {name: getattr(point, name) for name in keys}
        if self.mode == "threshold":
            p["p_r"] = None  # NaN is not JSON
        # the digest of {"settings": ..., "point": p} exactly as json.dumps(..., sort_keys=True)
        # writes it, with the settings encoded once per spec instead of once per point (a grid
        # of 200,000 points spent 50 s here)
        text = '{"point": ' + json.dumps(p, sort_keys=True) + ', "settings": '
        return hashlib.sha256((text + self._settings_json + "}").encode()).hexdigest()[:24]

    @cached_property
    def _settings_json(self) -> str:
        """:meth:`settings` as JSON with sorted keys (computed once: the spec is frozen)."""
        return json.dumps(self.settings(), sort_keys=True)

    def at(self, point: GridPoint) -> Spec:
        """This spec with a grid of one point: what a task needs to compute a chunk there.

        Parameters
        ----------
        point : GridPoint
            A point of this spec's grid.

        Returns
        -------
        Spec
            The same settings, samples and options (so the same rows and point keys), its
            grid lists of one value each: a task carries its chunk, not the whole grid (which
            took 1.8 MB per task at 200,000 values of ``p_r``).
        """
        grid = {key: [getattr(point, key)] for key in self.grid}
        return replace(self, grid=grid)

    def canonical(self) -> dict:
        """A plain, sorted description of the whole spec (JSON-ready).

        Returns
        -------
        dict
            What a results directory records as its spec (``_spec.json``).
        """
        if self.mode == "packing":
            return {"grid": self.grid, "samples": self.samples, "packing": self.packing,
                    "chunk_size": self.chunk_size}  # fmt: skip
        out = {
            "grid": self.grid,
            "samples": self.samples,
            "lattice": self.lattice,
            "gamma": self.gamma,
            "angles": self.angles,
            "solver": dict(sorted(self.solver.items())),
            "chunk_size": self.chunk_size,
            "threshold": self.threshold,
        }
        if self.verdict != "exact":  # absent by default: digests of existing sweeps unchanged
            out["verdict"] = self.verdict
        return out

    def n_samples(self) -> int:
        """Rows the spec asks for.

        Returns
        -------
        int
            Grid points times samples.
        """
        return self.n_points() * self.samples


def _as_list(key: str, value) -> list:
    items = value if isinstance(value, list) else [value]
    if not items:
        raise SpecError(f"'{key}' is an empty list")
    return items


def _number(key: str, value, integer: bool = False):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SpecError(f"'{key}' must be a number, got {show(value)}")
    if isinstance(value, int):  # exact (TOML's are 64-bit, a dict's may be larger)
        if integer:
            if abs(value) > _LARGEST_INT:
                raise SpecError(f"'{key}' must lie within 64-bit integers, got {show(value)}")
            return value
        if abs(value) > _LARGEST_FLOAT:
            raise SpecError(f"'{key}' must be finite, got {show(value)}")
        return float(value)
    if not math.isfinite(value):
        raise SpecError(f"'{key}' must be finite, got {show(value)}")
    if integer and value != int(value):
        raise SpecError(f"'{key}' must be an integer, got {show(value)}")
    if integer and abs(value) > _LARGEST_INT:
        raise SpecError(f"'{key}' must lie within 64-bit integers, got {show(value)}")
    return int(value) if integer else float(value)


def _choice(what: str, value, allowed) -> str:
    """``value`` if it is one of the strings ``allowed``, else one line naming them."""
    if not isinstance(value, str) or value not in allowed:
        names = ", ".join(repr(a) for a in allowed)
        raise SpecError(f"{what} must be one of {names}, got {show(value)}")
    return value


def parse_spec(data: dict) -> Spec:
    """Validate a spec given as a dict (the parsed TOML).

    Parameters
    ----------
    data : dict
        Flat keys and sections as in the module docstring (what ``tomllib.loads`` returns).

    Returns
    -------
    Spec
        The validated spec.

    Raises
    ------
    SpecError
        One sentence naming the key and what is wrong with it.

    Warns
    -----
    UserWarning
        When ``delta`` is large enough for bonds to cross.

    Examples
    --------
    >>> from tensegrity_rigidity import parse_spec
    >>> spec = parse_spec({"n": 8, "p_r": [0.6, 0.7], "phi": "shear", "samples": 10})
    >>> spec.mode, spec.n_points(), spec.n_samples()
    ('grid', 2, 20)
    """
    if not isinstance(data, dict):
        raise SpecError("a spec must be a table of keys")
    unknown = sorted(k for k in data if k not in FLAT_KEYS and k not in SECTIONS)
    if unknown:
        raise SpecError(
            f"unknown key(s) {', '.join(map(repr, unknown))}; known: "
            f"{', '.join(FLAT_KEYS + tuple(SECTIONS))}"
        )
    for sec, allowed in SECTIONS.items():
        if sec in data:
            if not isinstance(data[sec], dict):
                raise SpecError(f"[{sec}] must be a section")
            bad = sorted(set(data[sec]) - allowed)
            if bad:
                raise SpecError(
                    f"unknown key(s) {', '.join(map(repr, bad))} in [{sec}]; "
                    f"known: {', '.join(sorted(allowed))}"
                )
    if "packing" in data:
        return _packing_spec(data)
    if "fraction" in data:
        raise SpecError("'fraction' (packing fractions) needs a [packing] section")
    threshold = None
    if "threshold" in data:
        path = _choice("[threshold] path", data["threshold"].get("path", "p_r"), THRESHOLD_PATHS)
        threshold = {"path": path}
        method = data["threshold"].get("method", "lp")
        method = _choice("[threshold] method", method, THRESHOLD_METHODS)
        if method != "lp":  # recorded only when not the default: older specs keep their settings
            threshold["method"] = method
        if "p_r" in data:
            raise SpecError("threshold mode finds p_r itself: remove the 'p_r' key")
    elif "p_r" not in data:
        raise SpecError("'p_r' is required (or add a [threshold] section)")
    grid: dict[str, list] = {}
    for key in GRID_KEYS:
        if key == "p_r" and threshold is not None:
            continue
        raw = _as_list(key, data[key]) if key in data else list(DEFAULTS[key])
        if key == "phi":
            try:
                grid[key] = [parse_phi(v) if isinstance(v, str) else _number(key, v) for v in raw]
            except Exception as exc:  # InputError from parse_phi
                raise SpecError(str(exc)) from None
        elif key in ("n", "seed"):
            grid[key] = [_number(key, v, integer=True) for v in raw]
        else:
            grid[key] = [_number(key, v) for v in raw]
        _check_distinct(key, grid[key])
    for n in grid["n"]:
        if n < 2:
            raise SpecError(f"'n' must be at least 2, got {n}")
    for sd in grid["seed"]:
        if sd < 0:
            raise SpecError(f"'seed' must be a non-negative integer, got {sd}")
    lattice = _choice("[lattice] kind", data.get("lattice", {}).get("kind", "triangular"), LATTICES)
    for d in grid["delta"]:
        if not 0 <= d < 0.5:
            raise SpecError(f"'delta' must lie in [0, 0.5), got {d}")
    for key in ("p_r", "p_t", "f_c"):
        for v in grid.get(key, []):
            if not 0 <= v <= 1:
                raise SpecError(f"'{key}' must lie in [0, 1], got {v}")
    if threshold is not None and threshold.get("method") == "pebble":
        if lattice == "fcc":
            raise SpecError("[threshold] method 'pebble' decides 2D lattices, not 'fcc'")
        if threshold["path"] != "p_r" or any(v != 0 for v in grid["p_t"]):
            raise SpecError(
                "[threshold] method 'pebble' follows rods-only paths: path 'p_r' with p_t = 0"
            )
        if any(d == 0 for d in grid["delta"]):
            raise SpecError(
                "[threshold] method 'pebble' decides generic positions, and delta = 0 leaves the "
                "lattice's collinear bonds (its thresholds differ): use delta > 0 or method 'lp'"
            )
    if threshold is None:
        worst = max(grid["p_r"]) + max(grid["p_t"])
        if worst > 1 + 1e-12:
            raise SpecError(
                f"p_r + p_t exceeds 1 at a grid point ({max(grid['p_r'])} + "
                f"{max(grid['p_t'])} = {worst})"
            )
    samples = _number("samples", data.get("samples", 1), integer=True)
    if samples < 1:
        raise SpecError(f"'samples' must be at least 1, got {samples}")
    gamma = _number("gamma", data.get("strain", {}).get("gamma", 1.0))
    try:
        check_gamma(gamma, "[strain] gamma")
    except InputError as exc:
        raise SpecError(str(exc)) from None
    angles = data.get("strain", {}).get("angles", "golden")
    angles = _choice("[strain] angles", angles, ANGLE_SEQUENCES)
    if angles != "golden" and LATTICE_DIMENSIONS[lattice] == 3:
        raise SpecError(
            f"[strain] angles = {angles!r} sets 2D principal axes; on the {lattice} lattice "
            "sample k's axes are sequence_rotation(k) (remove the key)"
        )
    solver = dict(data.get("solver", {}))
    for key, value in solver.items():
        if isinstance(value, float) and not math.isfinite(value):
            raise SpecError(f"[solver] {key} must be finite, got {show(value)}")
    try:
        SolverOptions(**solver)
    except (TypeError, InputError) as exc:
        raise SpecError(f"[solver]: {exc}") from None
    chunk = _number("chunk_size", data.get("output", {}).get("chunk_size", 32), integer=True)
    if chunk < 1:
        raise SpecError(f"[output] chunk_size must be at least 1, got {chunk}")
    worst_delta = max(grid["delta"])
    if worst_delta >= CROSSING_DELTA[lattice]:
        warnings.warn(
            f"delta = {worst_delta} lets bonds of the {lattice} lattice cross (from delta = "
            f"{CROSSING_DELTA[lattice]:.4f} a node can be kicked across the opposite side of "
            "one of its triangles)",
            UserWarning,
            stacklevel=2,
        )
    verdict = _choice("'verdict'", data.get("verdict", "exact"), VERDICTS)
    if verdict != "exact" and threshold is not None:
        raise SpecError("verdict = 'paper' needs grid mode: remove the [threshold] section")
    return Spec(grid, samples, lattice, gamma, solver, chunk, threshold, angles, verdict)


def _packing_spec(data: dict) -> Spec:
    """A packing sweep's spec (``data`` has a ``[packing]`` section; keys already known)."""
    other = [k for k in LATTICE_ONLY if k in data]
    if other:
        raise SpecError(
            f"a [packing] sweep has no lattice: remove {', '.join(map(repr, other))} (its grid "
            "is n, fraction and seed)"
        )
    if "fraction" not in data:
        raise SpecError("'fraction' (packing fractions) is required in a [packing] sweep")
    grid = {
        "n": [_number("n", v, integer=True) for v in _as_list("n", data.get("n", 64))],
        "fraction": [_number("fraction", v) for v in _as_list("fraction", data["fraction"])],
        "seed": [_number("seed", v, integer=True) for v in _as_list("seed", data.get("seed", 0))],
    }
    for key, values in grid.items():
        _check_distinct(key, values)
    if min(grid["n"]) < 4 or min(grid["seed"]) < 0:
        raise SpecError("'n' must be at least 4 particles and 'seed' non-negative")
    if not all(0 < f < 1 for f in grid["fraction"]):
        raise SpecError(f"'fraction' must lie in (0, 1), got {show(grid['fraction'])}")
    keys = [fraction_key(f) for f in grid["fraction"]]
    if len(set(keys)) < len(keys):
        raise SpecError(
            f"'fraction' values must differ in their first {FRACTION_DECIMALS} decimals (they "
            f"seed the samples rounded so), got {show(grid['fraction'])}"
        )
    section = data["packing"]
    dim = _number("[packing] dim", section.get("dim", 2), integer=True)
    ratio = _number("[packing] ratio", section.get("ratio", DIAMETER_RATIO))
    if dim not in (2, 3) or not 1 <= ratio <= 10:
        raise SpecError(f"[packing] needs dim 2 or 3 and a ratio in [1, 10], got {dim}, {ratio}")
    samples = _number("samples", data.get("samples", 1), integer=True)
    chunk = _number("chunk_size", data.get("output", {}).get("chunk_size", 32), integer=True)
    if samples < 1 or chunk < 1:
        raise SpecError(f"'samples' and [output] chunk_size must be at least 1: {samples}, {chunk}")
    return Spec(grid, samples, chunk_size=chunk, packing={"dim": dim, "ratio": ratio})


def _check_distinct(key: str, values: list) -> None:
    """A repeated grid value would claim samples twice and store them once: refuse it."""
    seen = set()
    for v in values:
        if v in seen:
            raise SpecError(f"'{key}' lists the value {show(v)} twice; give each value once")
        seen.add(v)


def load_spec(path: str | os.PathLike) -> Spec:
    """Read and validate a TOML spec file.

    Parameters
    ----------
    path : str or path-like
        A UTF-8 TOML file (keys in the module docstring).

    Returns
    -------
    Spec
        The validated spec.

    Raises
    ------
    SpecError
        If the file cannot be read, is not UTF-8 or TOML, or is not a valid spec (one
        sentence, prefixed with the path).
    """
    return load_spec_text(path)[0]


def load_spec_text(path: str | os.PathLike) -> tuple[Spec, str]:
    """:func:`load_spec`, with the file's text: read once (a pipe, ``<(...)``, reads only once).

    Parameters
    ----------
    path : str or path-like
        The TOML file.

    Returns
    -------
    spec : Spec
        The validated spec.
    text : str
        The file's text (kept beside the results as ``_spec.toml``).

    Raises
    ------
    SpecError
        As :func:`load_spec`.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise SpecError(f"a spec file's path must be a str or path, got {show(path)}")
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise SpecError(f"{path}: cannot read ({exc.strerror})") from None
    except UnicodeDecodeError as exc:
        raise SpecError(
            f"{path}: not UTF-8 text (byte {exc.object[exc.start]:#04x} at offset {exc.start}); "
            "TOML files are UTF-8"
        ) from None
    if text.startswith("\ufeff"):
        raise SpecError(
            f"{path}: starts with a byte-order mark (U+FEFF), which TOML does not allow; save it "
            "as UTF-8 without BOM"
        )
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(f"{path}: not valid TOML ({exc})") from None
    try:
        return parse_spec(data), text
    except SpecError as exc:
        raise SpecError(f"{path}: {exc}") from None
