"""Sweep specifications: a TOML file describing a grid of parameters and what to compute.

Flat keys (each a scalar or a list; the grid is the product of the lists)::

    n = [16, 32]            # lattice size
    delta = 0.2             # node disorder
    p_r = [0.4, 0.5, 0.6]   # rod probability
    p_t = 0.3               # one-sided element probability
    f_c = [0.0, 0.5, 1.0]   # cable fraction
    phi = ["dilation", "shear", "compression", 0.7]
    samples = 100           # eta runs per grid point; run k uses theta = 2 pi (k - 1) / eta
    seed = 1                # a list gives independent replicas
    verdict = "exact"       # "paper": decide grid samples the paper's way instead
                            # (solver.inexact: L-BFGS-B from u = 0, E > 1e-8 E(u = 0))

Optional sections (defaults shown)::

    [lattice]
    kind = "triangular"     # or "square"

    [strain]
    gamma = 1.0             # magnitude; E scales as gamma^2, verdicts do not depend on it

    [solver]                # any field of SolverOptions
    max_iter = 100

    [output]
    chunk_size = 32         # samples per result file (the unit of resumption)

    [threshold]             # threshold mode: per-sample critical point along a monotone path
    path = "p_r"            # "p_r": raise p_r at fixed p_t;  "total": raise p_r at fixed
                            # p_r + p_t = p_t (p_t then means the total occupation)

In threshold mode the grid's ``p_r`` key is not used (omit it). ``verdict = "paper"`` applies to
grid mode only (a bisection needs verdicts monotone in p_r, which the paper's are not); its rows
hold the verdict, the energy reached, the affine energy and the iteration count.

Randomness: sample k at grid point (n, delta, seed) draws its geometry and site uniforms from
``SeedSequence(seed, spawn_key=(n, bits(delta), k))``; it does not depend on ``p_r``, ``p_t``,
``f_c`` or ``phi``. Samples of the same index therefore share their disorder across those
parameters (common random numbers): each sample's rigidity is monotone in ``p_r`` and ``p_t``,
differences between grid points are far less noisy, and thresholds derive exactly the grid's P.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import tomllib
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path

from ..errors import InputError, SpecError
from ..model.strain import parse_phi
from ..solver.core import SolverOptions

GRID_KEYS = ("n", "delta", "p_r", "p_t", "f_c", "phi", "seed")
FLAT_KEYS = GRID_KEYS + ("samples", "verdict")
VERDICTS = ("exact", "paper")
SECTIONS = {
    "lattice": {"kind"},
    "strain": {"gamma"},
    "solver": {f.name for f in fields(SolverOptions)},
    "output": {"chunk_size"},
    "threshold": {"path"},
}
DEFAULTS = {"n": [16], "delta": [0.2], "p_t": [0.0], "f_c": [0.5], "phi": ["shear"], "seed": [0]}


@dataclass(frozen=True)
class GridPoint:
    """One point of the parameter grid (p_r is NaN in threshold mode)."""

    n: int
    delta: float
    p_r: float
    p_t: float
    f_c: float
    phi: float
    seed: int

    def key(self) -> str:
        """A short stable name for file names."""
        text = json.dumps(asdict(self), sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()[:16]


@dataclass(frozen=True)
class Spec:
    """A validated sweep specification (see the module docstring)."""

    grid: dict[str, list]
    samples: int
    lattice: str = "triangular"
    gamma: float = 1.0
    solver: dict = field(default_factory=dict)
    chunk_size: int = 32
    threshold: dict | None = None
    verdict: str = "exact"

    @property
    def mode(self) -> str:
        return "threshold" if self.threshold is not None else "grid"

    def points(self) -> list[GridPoint]:
        """All grid points, in a fixed order."""
        g = self.grid
        p_r = g["p_r"] if self.mode == "grid" else [math.nan]
        return [
            GridPoint(int(n), float(d), float(pr), float(pt), float(fc), float(ph), int(sd))
            for n, d, pr, pt, fc, ph, sd in itertools.product(
                g["n"], g["delta"], p_r, g["p_t"], g["f_c"], g["phi"], g["seed"]
            )
        ]

    def solver_options(self) -> SolverOptions:
        return SolverOptions(**self.solver)

    def canonical(self) -> dict:
        """A plain, sorted description; two specs are the same sweep iff these are equal."""
        out = {
            "grid": self.grid,
            "samples": self.samples,
            "lattice": self.lattice,
            "gamma": self.gamma,
            "solver": dict(sorted(self.solver.items())),
            "chunk_size": self.chunk_size,
            "threshold": self.threshold,
        }
        if self.verdict != "exact":  # absent by default: digests of existing sweeps unchanged
            out["verdict"] = self.verdict
        return out

    def digest(self) -> str:
        return hashlib.sha256(json.dumps(self.canonical(), sort_keys=True).encode()).hexdigest()

    def n_samples(self) -> int:
        return len(self.points()) * self.samples


def _as_list(key: str, value) -> list:
    items = value if isinstance(value, list) else [value]
    if not items:
        raise SpecError(f"'{key}' is an empty list")
    return items


def _number(key: str, value, integer: bool = False):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SpecError(f"'{key}' must be a number, got {value!r}")
    if not math.isfinite(value):
        raise SpecError(f"'{key}' must be finite, got {value!r}")
    if integer and value != int(value):
        raise SpecError(f"'{key}' must be an integer, got {value!r}")
    return int(value) if integer else float(value)


def parse_spec(data: dict) -> Spec:
    """Validate a spec given as a dict (the parsed TOML). Raises SpecError with one sentence."""
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
    threshold = None
    if "threshold" in data:
        path = data["threshold"].get("path", "p_r")
        if path not in ("p_r", "total"):
            raise SpecError(f"[threshold] path must be 'p_r' or 'total', got {path!r}")
        threshold = {"path": path}
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
    for n in grid["n"]:
        if n < 2:
            raise SpecError(f"'n' must be at least 2, got {n}")
    for d in grid["delta"]:
        if not 0 <= d < 0.5:
            raise SpecError(f"'delta' must lie in [0, 0.5), got {d}")
    for key in ("p_r", "p_t", "f_c"):
        for v in grid.get(key, []):
            if not 0 <= v <= 1:
                raise SpecError(f"'{key}' must lie in [0, 1], got {v}")
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
    lattice = data.get("lattice", {}).get("kind", "triangular")
    if lattice not in ("triangular", "square"):
        raise SpecError(f"[lattice] kind must be 'triangular' or 'square', got {lattice!r}")
    gamma = _number("gamma", data.get("strain", {}).get("gamma", 1.0))
    if gamma <= 0:
        raise SpecError(f"[strain] gamma must be positive, got {gamma}")
    solver = dict(data.get("solver", {}))
    try:
        SolverOptions(**solver)
    except (TypeError, InputError) as exc:
        raise SpecError(f"[solver]: {exc}") from None
    chunk = _number("chunk_size", data.get("output", {}).get("chunk_size", 32), integer=True)
    if chunk < 1:
        raise SpecError(f"[output] chunk_size must be at least 1, got {chunk}")
    verdict = data.get("verdict", "exact")
    if verdict not in VERDICTS:
        raise SpecError(f"'verdict' must be one of {', '.join(VERDICTS)}, got {verdict!r}")
    if verdict != "exact" and threshold is not None:
        raise SpecError("verdict = 'paper' needs grid mode: remove the [threshold] section")
    return Spec(grid, samples, lattice, gamma, solver, chunk, threshold, verdict)


def load_spec(path: str | Path) -> Spec:
    """Read and validate a TOML spec file."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise SpecError(f"{path}: cannot read ({exc.strerror})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(f"{path}: not valid TOML ({exc})") from None
    try:
        return parse_spec(data)
    except SpecError as exc:
        raise SpecError(f"{path}: {exc}") from None
