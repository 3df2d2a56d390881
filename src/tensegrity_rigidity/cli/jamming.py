"""The ``jamming`` command: the certified jamming test of a packing (registered by :mod:`~.cli`)."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

#: largest gap of a contact read from a GSD frame, in mean diameters: single precision's
#: resolution with room for a few roundings
GSD_TOLERANCE = 1e-5


def add_parser(sub) -> None:
    p = sub.add_parser(
        "jamming",
        help="test whether a packing is jammed (locally, collectively, strictly)",
        description="Read a packing (a GSD frame, or an instance file whose struts are contacts) "
        "and print its certified jamming verdict: rattlers, contacts, isostatic excess, and the "
        "certificate's numbers.",
    )
    p.add_argument("file", help="a .gsd file (HOOMD-blue) or an instance file (.npz)")
    p.add_argument(
        "--kind",
        default="all",
        choices=["local", "collective", "strict", "all"],
        help="which test (default all three)",
    )
    p.add_argument(
        "--tolerance",
        type=float,
        default=None,
        help=f"GSD only: largest gap of a contact in mean diameters (default {GSD_TOLERANCE:g}: "
        "GSD stores positions in single precision)",
    )
    p.add_argument("--frame", type=int, default=None, help="GSD only: frame (default the last)")
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    p.set_defaults(handler=_run)


def _summary(r) -> dict:
    out = {
        "kind": r.kind,
        "status": r.status,
        "particles": r.n_particles,
        "rattlers": r.n_rattlers,
        "contacts": r.n_contacts,
        "backbone_contacts": r.backbone_contacts,
        "isostatic_contacts": r.isostatic_contacts,
        "isostatic_excess": None if math.isnan(r.isostatic_excess) else r.isostatic_excess,
        "reason": r.reason,
        "message": r.message,
    }
    c = r.certificate
    if r.status == "jammed":
        out |= {"margin": c.margin, "sigma": c.sigma, "strictness": c.strictness}
    elif r.status == "unjammed" and c is not None:
        out |= {"motion": "flex" if c.flex else "opens contacts", "opened": c.opened,
                "violation": c.violation}  # fmt: skip
    return {
        k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in out.items()
    }


def _run(args) -> int:
    from ..errors import InputError
    from ..solver.jamming import jamming

    path = Path(args.file)
    if path.suffix.lower() == ".gsd":
        from ..model.interop import read_gsd

        tolerance = GSD_TOLERANCE if args.tolerance is None else args.tolerance
        frame = -1 if args.frame is None else args.frame
        network = read_gsd(path, frame).contact_network(tolerance=tolerance)
    elif path.suffix.lower() == ".npz":
        from ..model.io import load_instance

        if args.tolerance is not None or args.frame is not None:
            raise InputError(
                f"{path}: --tolerance and --frame read a GSD file; an instance file's contacts "
                "are its struts"
            )
        network = load_instance(path).network
    else:
        raise InputError(f"{path}: expected a .gsd or an instance .npz file")
    kinds = ["local", "collective", "strict"] if args.kind == "all" else [args.kind]
    results = [_summary(jamming(network, kind)) for kind in kinds]
    if args.json:
        print(json.dumps(results if len(results) > 1 else results[0], indent=2))
        return 0
    first = results[0]
    print(f"{path}: {first['particles']} particles, {first['contacts']} contacts, "
          f"{first['rattlers']} rattlers")  # fmt: skip
    for r in results:
        detail = r["message"] or ""
        if r["status"] == "jammed":
            margin = "inf" if r["margin"] is None else f"{r['margin']:.3g}"  # JSON has no inf
            detail = f"margin {margin}, excess contacts " + str(
                r["backbone_contacts"] - r["isostatic_contacts"]
            )
        elif r["status"] == "unjammed" and "motion" in r:
            detail = r["motion"] + (
                f" ({r['opened']} open by more than tau)" if r["opened"] else ""
            )
        print(f"  {r['kind']:<10}  {r['status']:<9}  {detail}")
    sys.stdout.flush()
    return 0
