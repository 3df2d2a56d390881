"""What a reproduction costs, and which error bars its sample counts buy.

Work and time (:func:`estimate`)
    Every study declares its sweeps; the estimate expands them with the sweep engine's own
    chunk planner (:func:`~tensegrity_rigidity.ensemble.sweep.plan_chunks`), so it counts
    exactly the rows the sweeps will compute, per study and size. Rows stored under ``out`` (a
    resumed run) and rows an earlier study of the same run computes into the same sweep are not
    counted again. Each row is priced by the measured per-row costs; a sweep's wall time is the
    makespan of its chunks on W workers in submission order; each study's in-process work (its
    cost model: the analysis, trials, drawn samples) adds serially.

Error bars (:func:`expected_errors`)
    A headline estimator's bootstrap error falls as ``sigma_1(n) / sqrt(S)``, with ``sigma_1``
    (the error of one sample) measured at a few sizes and interpolated as a power law in n.

The measured constants are in ``data/costs.toml`` with their sources, written by
``benchmarks/calibrate_budget.py``. Sizes outside the measured ones are extrapolated with the
power law of the nearest two (grid solves: the factorisation's exponent) and the estimate says so.
"""

from __future__ import annotations

import heapq
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ..ensemble.jamming import sample_seconds
from ..ensemble.store import ResultStore
from ..ensemble.sweep import plan_chunks
from ..errors import InputError
from .claims import CLAIMS
from .claims import TARGETS as CLAIM_TARGETS
from .studies.rows import study_spec
from .study import Scale
from .template import load

#: the measured costs, written by benchmarks/calibrate_budget.py
DATA = Path(__file__).with_name("data") / "costs.toml"
WORDS = load("budget")


def _power_law(table: dict[int, float], n: int, exponent: float | None = None):
    """(value at n, extrapolated?) by piecewise power laws through ``table``: between measured
    sizes the power law through the two neighbours, outside that of the nearest two
    (``exponent`` instead when given; a single size: that exponent or none)."""
    sizes = sorted(table)
    if n in table:
        return float(table[n]), False
    if len(sizes) == 1:
        return float(table[sizes[0]] * (n / sizes[0]) ** (exponent or 0.0)), True
    outside = n < sizes[0] or n > sizes[-1]
    if outside:
        lo, hi = (sizes[0], sizes[1]) if n < sizes[0] else (sizes[-2], sizes[-1])
    else:
        lo, hi = next((a, b) for a, b in zip(sizes, sizes[1:], strict=False) if a < n < b)
    slope = math.log(table[hi] / table[lo]) / math.log(hi / lo)
    if outside and exponent is not None:
        slope = exponent
    ref = lo if n < hi else hi
    return float(table[ref] * (n / ref) ** slope), outside


@dataclass(frozen=True)
class Costs:
    """The measured costs (``data/costs.toml``) and the models that read them."""

    data: dict

    @classmethod
    def load(cls, path: Path = DATA) -> Costs:
        return cls(tomllib.loads(Path(path).read_text()))

    def table(self, name: str, within: str = "") -> dict[int, float]:
        """Size -> value of one entry (``within``: a group such as ``sigma_1``)."""
        entry = self.data[within][name] if within else self.data[name]
        return {int(n): float(v) for n, v in entry["by_n"].items()}

    def factor(self, name: str, p_t: float) -> float:
        """An entry's factor at p_t (linear between its p_t, constant beyond)."""
        points = sorted((float(k), float(v)) for k, v in self.data[name]["by_p_t"].items())
        xs, ys = zip(*points, strict=True)
        return float(np.interp(p_t, xs, ys))

    def seconds(self, name: str) -> float:
        return float(self.data[name]["seconds"])

    def analysis(self, study: str) -> float:
        """In-process seconds of a study's analysis per 100 bootstrap replicas."""
        per = self.data["analysis"]["per_100_replicas"]
        if study not in per:
            raise InputError(f"study {study!r} has no work model: its run time cannot be estimated")
        return float(per[study])

    def row_seconds(self, mode: str, n: int, p_t: float) -> tuple[float, bool]:
        """(mean seconds of one row, extrapolated?) for a sweep of ``mode`` at size n and p_t:
        "threshold" (a search), "pebble" (a rods-only threshold by the pebble game), "grid" (an
        exact grid sample with its minimum-norm displacements), "energy" (without them) or
        "paper" (the paper's verdict)."""
        if mode == "pebble":
            return _power_law(self.table("pebble"), n)
        if mode == "threshold" and p_t == 0.0:
            return _power_law(self.table("rods_threshold"), n)
        if mode == "threshold":
            t, ext = _power_law(self.table("threshold"), n)
            return t * self.factor("threshold_pt_factor", p_t), ext
        if mode in ("grid", "energy"):
            t, ext = _power_law(self.table("grid"), n, self.data["grid"]["exponent"])
            t *= self.data["grid_without_displacements"]["factor"] if mode == "energy" else 1.0
            return t * self.factor("grid_pt_factor", p_t), ext
        if mode == "paper":
            return _power_law(self.table("paper_verdict"), n)
        raise InputError(
            f"unknown sweep mode {mode!r}; use 'threshold', 'pebble', 'grid', 'energy' or 'paper'"
        )

    def row_seconds_3d(self, mode: str, n: int, p_t: float) -> tuple[float, bool]:
        """The same on the FCC lattice, where only threshold sweeps are priced."""
        if mode != "threshold":
            raise InputError(f"no 3D cost model for {mode!r} sweeps; only 'threshold' is priced")
        if p_t == 0.0:
            return _power_law(self.table("rods_threshold_3d"), n)
        t, ext = _power_law(self.table("threshold_3d"), n)
        return t * self.factor("threshold_pt_factor", p_t), ext

    def sigma_1(self, estimator: str, n: int) -> tuple[float, bool]:
        """(error of one sample of ``estimator`` at size n, extrapolated?)."""
        group = self.data["sigma_1"]
        if estimator not in group or estimator == "what":
            known = ", ".join(k for k in group if k != "what")
            raise InputError(f"no error model for {estimator!r}; known: {known}")
        table, like = self.table(estimator, "sigma_1"), group[estimator].get("scales_like")
        if like is not None and n not in table:
            ((k, v),) = table.items()
            other = self.table(like, "sigma_1")
            return v * _power_law(other, n)[0] / _power_law(other, k)[0], True
        return _power_law(table, n)

    @property
    def targets(self) -> dict[str, float]:
        """Target errors: the claims' families and the method's shifts."""
        shifts = {k: v for k, v in self.data["shift_targets"].items() if k != "what"}
        return dict(CLAIM_TARGETS) | shifts


COSTS = Costs.load()
row_seconds, row_seconds_3d, sigma_1 = COSTS.row_seconds, COSTS.row_seconds_3d, COSTS.sigma_1


def samples_for(estimator: str, n: int, target: float) -> int:
    """Samples per point for a bootstrap error of at most ``target`` at size n."""
    return math.ceil((sigma_1(estimator, n)[0] / target) ** 2)


def expected_error(estimator: str, n: int, samples: int) -> float:
    """The error ``estimator`` is expected to have with ``samples`` samples per point at n."""
    return sigma_1(estimator, n)[0] / math.sqrt(samples) if samples > 0 else math.inf


@dataclass(frozen=True)
class SweepCost:
    """The work of one sweep of a study: the rows its spec asks for, those still to compute
    (``new_rows``), their summed CPU seconds and the makespan of their chunks."""

    study: str
    name: str
    mode: str
    n: int
    rows: int
    new_rows: int
    cpu_seconds: float
    wall_seconds: float
    extrapolated: bool


@dataclass(frozen=True)
class Estimate:
    """Work counts and estimated wall time of a scale: its sweeps in the order the studies run
    them, each study's in-process seconds (``serial``), what is extrapolated (``notes``) and
    the scale's budget (wall minutes on 2 workers, None if it states none)."""

    scale: str
    workers: int
    studies: tuple[str, ...]
    sweeps: tuple[SweepCost, ...]
    serial: dict[str, float] = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    budget_minutes: float | None = None

    @property
    def wall_seconds(self) -> float:
        return sum(s.wall_seconds for s in self.sweeps) + sum(self.serial.values())

    @property
    def cpu_seconds(self) -> float:
        return sum(s.cpu_seconds for s in self.sweeps) + sum(self.serial.values())

    @property
    def over_budget(self) -> bool:
        """Whether the wall time exceeds the scale's budget (meant for 2 workers)."""
        return self.budget_minutes is not None and self.wall_seconds > 60 * self.budget_minutes

    def table(self) -> pd.DataFrame:
        """Per study and size: threshold searches (pebble-game passes included), grid solves,
        paper verdicts, packings (rows still to compute), CPU and wall minutes (in-process work
        on the study's first row)."""
        rows = []
        for study in self.studies:
            mine = [s for s in self.sweeps if s.study == study]
            for i, n in enumerate(sorted({s.n for s in mine}) or [None]):
                here = [s for s in mine if s.n == n]
                serial = self.serial.get(study, 0.0) if i == 0 else 0.0
                count = {m: sum(s.new_rows for s in here if s.mode in ms) for m, ms in (
                    ("thresholds", ("threshold", "pebble")), ("grid", ("grid", "energy")),
                    ("paper", ("paper",)), ("packings", ("packing",)))}  # fmt: skip
                rows.append({"study": study, "n": n, **count,
                             "cpu_min": (sum(s.cpu_seconds for s in here) + serial) / 60,
                             "wall_min": (sum(s.wall_seconds for s in here) + serial) / 60,
                             "extrapolated": any(s.extrapolated for s in here)})  # fmt: skip
        return pd.DataFrame(rows)


def _makespan(costs: list[float], workers: int) -> float:
    """Finish time of ``costs`` run in order, each on the first free of ``workers``."""
    free = [0.0] * max(1, workers)
    for c in costs:
        heapq.heapreplace(free, free[0] + c)
    return max(free)


def _stored_keys(path: Path) -> set:
    """(point_key, sample, theta) of the rows stored in a sweep directory (empty if none)."""
    df = ResultStore(path).read() if path.is_dir() else pd.DataFrame()
    return set() if df.empty else set(zip(df.point_key, df["sample"], df.theta, strict=True))


def _sweep(study: str, name: str, raw: dict, done: set, workers: int, notes: list) -> SweepCost:
    """One sweep's rows to compute, priced; ``done`` (its rows stored or planned) grows."""
    spec = study_spec(raw)
    chunks = plan_chunks(spec, done)
    mode = "threshold" if spec.mode == "threshold" else spec.verdict
    mode = "pebble" if spec.settings().get("threshold_method") == "pebble" else mode
    mode = "grid" if mode == "exact" else mode
    mode = "energy" if mode == "grid" and not spec.solver_options().min_norm else mode
    price = COSTS.row_seconds_3d if spec.lattice == "fcc" else COSTS.row_seconds
    if spec.packing is not None:  # a packing and its tests, by the jamming benchmark's costs
        mode, dim = "packing", spec.packing["dim"]

        def price(mode, n, p_t):  # noqa: ARG001 (the lattice models' signature)
            return sample_seconds(n, dim), False

    costs, ext = [], False
    for point, ks in chunks:
        sec, e = price(mode, point.n, point.p_t)
        ext |= e
        costs.append(sec * len(ks))
        done.update((spec.point_key(point), k, spec.angle(k)) for k in ks)
    n = int(max(spec.grid["n"]))
    note = WORDS.label("extrapolated", mode=mode, n=n)
    if ext and note not in notes:
        notes.append(note)
    overhead = COSTS.seconds("sweep_overhead") if chunks else 0.0
    return SweepCost(study, name, mode, n, spec.n_samples(), sum(len(ks) for _, ks in chunks),
                     float(sum(costs)), _makespan(costs, workers) + overhead, ext)  # fmt: skip


def estimate(scale: Scale | str, workers: int = 2, studies: list[str] | None = None,
             out: str | Path | None = None) -> Estimate:  # fmt: skip
    """Count the work of a scale's studies (or of ``studies``) and estimate its wall time on
    ``workers``; with ``out``, the rows stored there are not counted.

    Raises
    ------
    InputError
        An unknown scale or study, or a study without a work model (nothing is left out
        silently).
    """
    from .registry import SCALES, STUDIES

    if isinstance(scale, str):
        if scale not in SCALES:
            raise InputError(f"unknown scale {scale!r}; choose from {', '.join(SCALES)}")
        scale = SCALES[scale]
    if workers < 1:
        raise InputError(f"workers must be at least 1, got {workers}")
    names = list(studies or scale.studies)
    for name in names:
        if name not in STUDIES:
            raise InputError(f"unknown study {name!r}; choose from {', '.join(STUDIES)}")
    planned: dict[str, set] = {}
    sweeps, serial = [], {}
    notes: list[str] = []
    for study in names:
        for name, raw in STUDIES[study].sweeps(scale).items():
            if name not in planned:
                planned[name] = _stored_keys(Path(out) / "studies" / name) if out else set()
            sweeps.append(_sweep(study, name, raw, planned[name], workers, notes))
        serial[study] = STUDIES[study].cost(scale, COSTS)
    return Estimate(scale.name, workers, tuple(names), tuple(sweeps), serial, tuple(notes),
                    scale.budget_minutes)  # fmt: skip


def expected_errors(scale: Scale | str) -> pd.DataFrame:
    """The error bar each headline claim can expect at a scale, beside its target and the
    paper's: one row per claim a study of the scale measures with a calibrated estimator
    (``claim``, ``study``, ``estimator``, ``n``, ``samples``, ``expected``, ``target``,
    ``paper``, ``meets``, ``extrapolated``). Claims whose error is not set by the sample count
    (the energy exponents, the nonaffinity peak) are not listed."""
    from .registry import SCALES, STUDIES

    scale = SCALES[scale] if isinstance(scale, str) else scale
    targets, rows = COSTS.targets, []
    for name in scale.studies:
        for claim, where, est, n, samples, *pool in STUDIES[name].errors(scale):
            s, ext = sigma_1(est, n)
            err = s / math.sqrt(samples * (pool or [1])[0]) if samples > 0 else math.inf
            c = CLAIMS.get(claim)
            rows.append({"claim": claim, "study": where, "estimator": est, "n": n,
                         "samples": samples, "expected": err, "target": targets[est],
                         "paper": c.error if c is not None else math.nan,
                         "meets": err <= targets[est], "extrapolated": ext})  # fmt: skip
    return pd.DataFrame(rows)


def describe(est: Estimate, errors: pd.DataFrame | None = None) -> str:
    """The estimate as printed by ``reproduce --estimate``: counts, times, error bars."""
    lines = [WORDS.label("head", scale=est.scale, workers=est.workers,
                         wall=est.wall_seconds / 60, cpu=est.cpu_seconds / 60)]  # fmt: skip
    if est.budget_minutes is not None and est.workers == 2:
        verdict = WORDS.label("over" if est.over_budget else "within")
        lines.append(WORDS.label("budget", minutes=est.budget_minutes, verdict=verdict))
    t = est.table()
    packings = bool(t.packings.sum())  # a column only for the scales that run packings
    w = max([8, *(len(name) for name in est.studies)])  # the longest study name
    lines += ["", f"{'study':<{w}} {'n':>4} {'thresholds':>11} {'grid':>8} {'paper':>7} "
              + (f"{'packings':>9} " if packings else "")
              + f"{'CPU min':>8} {'wall min':>9}"]  # fmt: skip
    for r in t.itertuples():
        n = "-" if r.n is None or (isinstance(r.n, float) and math.isnan(r.n)) else int(r.n)
        mark = f"  ({WORDS.label('mark')})" if r.extrapolated else ""
        lines.append(f"{r.study:<{w}} {n!s:>4} {r.thresholds:>11,} {r.grid:>8,} {r.paper:>7,} "
                     + (f"{r.packings:>9,} " if packings else "")
                     + f"{r.cpu_min:>8.1f} {r.wall_min:>9.1f}{mark}")  # fmt: skip
    lines.append(f"{'total':<{w}} {'':>4} {int(t.thresholds.sum()):>11,} {int(t.grid.sum()):>8,} "
                 f"{int(t.paper.sum()):>7,} "
                 + (f"{int(t.packings.sum()):>9,} " if packings else "")
                 + f"{est.cpu_seconds / 60:>8.1f} {est.wall_seconds / 60:>9.1f}")  # fmt: skip
    lines += [f"note: {note}" for note in est.notes]
    if errors is not None and len(errors):
        lines += ["", WORDS.label("errors"), f"{'claim':<28} {'study':<10} {'n':>4} "
                  f"{'samples':>8} {'expected':>9} {'target':>7} {'paper':>7}"]  # fmt: skip
        for r in errors.itertuples():
            flag = "" if r.meets else f"  {WORDS.label('exceeds')}"
            flag += f"  ({WORDS.label('mark_n')})" if r.extrapolated else ""
            lines.append(f"{r.claim:<28} {r.study:<10} {r.n:>4} {r.samples:>8} "
                         f"{r.expected:>9.4f} {r.target:>7.3f} {r.paper:>7.4f}{flag}")  # fmt: skip
    return "\n".join(lines)
