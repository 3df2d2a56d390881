"""Designs of the verdict search side by side on the near-threshold thresholds (issue 13).

A design is an order of stages (``SolverOptions.stages``); a stage may carry parameters,
``name:param=value[:param=value]`` (``ipm:max_iter=100``, ``lp:max_iter=200``),
registered as a stage of its own for the run, and a token ``option=value`` sets a numeric or
boolean field of ``SolverOptions`` for the design (``polish=0``, ``displacement_bound=1e8``).
Every design searches the same thresholds of the near-threshold set (six configurations of
issue 13, cycled; ``near_threshold_set``) in the same run, one after the other, and records per
design: seconds per threshold (median, max, total), probes, undecided probes (and of them the
ones not resolved, the others within resolution), thresholds left
as an interval and the widest interval in events, brackets ``[s_low, s_high]`` that differ from
the first design's and brackets disjoint from it (certified verdicts that contradict each
other: must be 0), and the stages that decided the probes.

Run: python benchmarks/bench_stages.py [--sizes 32 64] [--samples 12 6]
     [--designs affine,newton,ipm,lp affine,newton,refine,ipm,support,lp ...]
     [--configs 1 0 2] [--save-undecided FOLDER]

``--save-undecided`` writes every undecided probe (its kinds and hints) for
``resolve_probes.py``; the raw results list each with its reason and best candidates.

``--configs`` keeps only the samples of the given configurations (the first ``--samples`` of
the set, cycled, filtered): at n = 128, where one threshold takes minutes to most of an hour,
``--sizes 128 --samples 3 --configs 1`` searches configuration 1 alone.
"""

from __future__ import annotations

import argparse
import time
from collections import Counter
from dataclasses import replace
from pathlib import Path

import numpy as np
from _record import machine, probe, record, table
from near_threshold_set import CONFIGS, RODS_ONLY, interval_events, samples

from tensegrity_rigidity.ensemble import thresholds
from tensegrity_rigidity.ensemble.thresholds import find_threshold
from tensegrity_rigidity.errors import InputError
from tensegrity_rigidity.model.network import Element
from tensegrity_rigidity.solver.certificates import NOT_RESOLVED
from tensegrity_rigidity.solver.core import SolverOptions
from tensegrity_rigidity.solver.options import strategy_named
from tensegrity_rigidity.solver.stages import DEFAULT_STRATEGIES

#: the default design, and the same without the refine strategy
DEFAULT_DESIGNS = [
    ",".join(x.name for x in DEFAULT_STRATEGIES),
    ",".join(x.name for x in DEFAULT_STRATEGIES if x.name != "refine"),
]

HEADER = ["n", "stages", "samples", "median s", "max s", "total s", "probes", "undecided probes",
          "not resolved", "intervals", "widest (events)", "differ", "disjoint",
          "decided by"]  # fmt: skip
DETAIL = ["n", "stages", "config", "k", "s", "interval", "events", "probes", "undecided",
          "wall s"]  # fmt: skip


def stage_name(token: str):
    """The strategy ``name:param=value:...`` (named ``token`` when it has parameters);
    parameters must be numbers."""
    base, *settings = token.split(":")
    try:
        stage = strategy_named(base)
    except InputError as exc:
        raise SystemExit(str(exc)) from None
    if not settings:
        return stage
    changes: dict = {"name": token}
    for item in settings:
        key, value = item.split("=")
        kind = type(getattr(stage, key))
        if kind not in (int, float, bool, str):
            raise SystemExit(f"{base}.{key} cannot be set here; only numbers, flags and names")
        changes[key] = bool(float(value)) if kind is bool else kind(value)
    return replace(stage, **changes)


def design(text: str) -> tuple[tuple, dict]:
    """(strategies, SolverOptions fields) of a design ``text`` (tokens separated by commas)."""
    stages, options = [], {}
    for token in text.split(","):
        if "=" in token and ":" not in token:
            key, value = token.split("=")
            default = getattr(SolverOptions(), key, None)
            if not isinstance(default, (bool, int, float)):
                raise SystemExit(f"SolverOptions.{key} is not a numeric or boolean option")
            options[key] = (
                bool(float(value)) if isinstance(default, bool) else type(default)(float(value))
            )
        else:
            stages.append(stage_name(token))
    return tuple(stages), options


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--sizes", type=int, nargs="+", default=[32, 64])
    ap.add_argument("--samples", type=int, nargs="+", default=[12, 6])
    ap.add_argument("--designs", nargs="+", default=DEFAULT_DESIGNS)
    ap.add_argument(
        "--configs",
        type=int,
        nargs="+",
        default=None,
        help="only the samples of these configurations (indices into the set)",
    )
    ap.add_argument(
        "--save-undecided",
        type=Path,
        default=None,
        help="write each undecided probe (kinds and hints, .npz) into this folder",
    )
    ap.add_argument(
        "--rods-only",
        action="store_true",
        help="the rods-only thresholds of the p_c extrapolation instead of the issue-13 set",
    )
    args = ap.parse_args()
    if args.configs is not None:
        count = len(RODS_ONLY if args.rods_only else CONFIGS)
        bad = [c for c in args.configs if not 0 <= c < count]
        if bad:
            ap.error(f"--configs {bad[0]}: the set has configurations 0 to {count - 1}")
        if any(not set(args.configs) & set(range(min(k, count))) for k in args.samples):
            ap.error("--configs selects no sample: raise --samples to reach those configurations")
    designs = [design(d) for d in args.designs]
    decided_by: Counter = Counter()
    original_decide = thresholds.decide

    def counting_decide(inst, opts, **kw):
        verdict = original_decide(inst, opts, **kw)
        decided_by[verdict.stage or "undecided"] += 1
        if not verdict.decided:
            UNDECIDED.append(_undecided_row(inst, verdict))
            if args.save_undecided is not None:
                _save_probe(args.save_undecided, inst, kw)
        return verdict

    thresholds.decide = counting_decide  # count the deciding stage of every probe
    try:
        run(args, designs, decided_by)
    finally:
        thresholds.decide = original_decide


#: The undecided probes of the run so far, one dict each (the run loop sets ``CURRENT``).
UNDECIDED: list[dict] = []
CURRENT: dict = {}


def _undecided_row(inst, verdict) -> dict:
    """One undecided probe: where it is, why it is undecided and its best candidates."""
    r, f = verdict.rigid, verdict.floppy
    return {
        **CURRENT,
        "rods": int((inst.network.kinds == Element.ROD).sum()),
        "reason": verdict.reason,
        "work": None if r is None else float(r.work),
        "residual": None if r is None else float(r.residual),
        "violation": None if f is None else float(f.violation),
        "size": None if f is None else float(f.size),
    }


def _save_probe(folder: Path, inst, hints: dict) -> None:
    """Write the probe's kinds and starting hints, so that it can be solved again alone."""
    folder.mkdir(parents=True, exist_ok=True)
    row = UNDECIDED[-1]
    name = f"n{row['n']}_c{row['config']}_k{row['k']}_{len(UNDECIDED):04d}.npz"
    arrays = {k: v for k, v in hints.items() if v is not None}
    np.savez(folder / name, kinds=inst.network.kinds, **arrays)


def run(args, designs, decided_by: Counter) -> None:
    """Search every threshold once per design, recording after each design."""
    rows, detail = [], []
    for n, count in zip(args.sizes, args.samples, strict=True):
        insts = list(samples(n, count, RODS_ONLY if args.rods_only else CONFIGS))
        if args.configs is not None:
            insts = [x for x in insts if x[0] in args.configs]
        first: dict[tuple[int, int], tuple[float, float]] = {}
        for stages, options in designs:
            opts = SolverOptions(min_norm=False, stages=stages, **options)
            label = " ".join(x.name for x in stages) + "".join(
                f" {k}={v:g}" for k, v in options.items()
            )
            decided_by.clear()
            secs, probes, undecided, widths, differ, disjoint = [], 0, 0, [], 0, 0
            for c, k, (net, u, v, eps, p_t, f_c) in insts:
                CURRENT.update(n=n, stages=label, config=c, k=k)
                probe()
                t0 = time.perf_counter()
                th = find_threshold(net, u, v, eps, p_t, f_c, options=opts)
                dt = time.perf_counter() - t0
                bracket = (th.s_low, th.s_high)
                ref = first.setdefault((c, k), bracket)
                differ += not np.allclose(ref, bracket, equal_nan=True, rtol=0, atol=0)
                disjoint += bracket[0] > ref[1] or ref[0] > bracket[1]
                width = interval_events(u, v, p_t, f_c, th)
                secs.append(dt)
                probes += th.solves
                undecided += th.undecided
                widths.append(width)
                detail.append(
                    [n, label, c, k, f"{th.s:.6f}",
                     f"[{th.s_low:.6f}, {th.s_high:.6f}]", width, th.solves, th.undecided,
                     f"{dt:.2f}"]
                )  # fmt: skip
                print(*detail[-1], flush=True)
            s = np.asarray(secs)
            here = [x for x in UNDECIDED if x["n"] == n and x["stages"] == label]
            not_resolved = sum(x["reason"] == NOT_RESOLVED for x in here)
            rows.append(
                [n, label, len(s), f"{np.median(s):.2f}", f"{s.max():.2f}",
                 f"{s.sum():.1f}", probes, undecided, not_resolved,
                 sum(w > 0 for w in widths), max(widths), differ, disjoint,
                 ", ".join(f"{k} {v}" for k, v in sorted(decided_by.items()))]
            )  # fmt: skip
            _write(rows, detail, args.rods_only)


def _write(rows, detail, rods_only: bool) -> None:
    """Record the table so far (after every design: a long run keeps what it measured)."""
    which = "rods-only thresholds (p_t = 0)" if rods_only else "near-threshold set"
    body = (
        f"Machine: {machine()}. Each threshold of the {which} searched once per "
        "design of the verdict search (`SolverOptions.stages`, and the options named after "
        "them; every other option default), "
        "in the same run, on the same samples. 'intervals': thresholds left as an interval by "
        "undecided probes, with the widest in events; 'differ': brackets [s_low, s_high] that "
        "differ from the first design's; 'disjoint': brackets that do not overlap it (certified "
        "verdicts contradicting each other: must be 0); 'decided by': the stage whose "
        "certificate decided each probe (hint: a neighbouring probe's certificate).\n\n"
        + table(HEADER, rows)
        + "\n\nPer threshold:\n\n"
        + table(DETAIL, detail)
    )
    raw = {"designs": [dict(zip(HEADER, r, strict=True)) for r in rows]}
    raw["undecided"] = UNDECIDED
    raw["thresholds"] = [dict(zip(DETAIL, d, strict=True)) for d in detail]
    if rods_only:
        record(
            "stages-rods",
            "Designs of the verdict search, rods only (bench_stages.py --rods-only)",
            body,
            raw=raw,
        )
    else:
        title = "Designs of the verdict search (benchmarks/bench_stages.py)"
        record("stages", title, body, raw=raw)


if __name__ == "__main__":
    main()
