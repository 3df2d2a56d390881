"""Write ``release_claims.json``: every measurement of the tiny scale, by the release at 5454841.

Run once, with the release's sources first on the path, from the repository's root::

    git archive 5454841 src | tar -x -C /tmp/old
    PYTHONPATH=/tmp/old/src python tests/paper/data/make_release_claims.py /tmp/tiny-old

It runs ``reproduce --scale tiny`` into the given directory (serially, so that nothing depends
on the workers), reads every study back from the stored rows and writes each measurement's
claim, factor, label, value and standard errors. ``tests/paper/test_same_numbers.py`` computes
the same from its own tiny run and compares.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

import tensegrity_rigidity
from tensegrity_rigidity.cli.main import main
from tensegrity_rigidity.paper.registry import STUDIES

RELEASE = "5454841"


def measurements(results: dict) -> list[dict]:
    """Plain records of every measurement of ``results`` (study name -> result)."""
    out = []
    for study, result in sorted(results.items()):
        for m in result.measured:
            out.append(
                {
                    "study": study,
                    "claim": m.claim,
                    "factor": m.factor,
                    "label": m.label,
                    "value": [float(v) for v in np.asarray(m.value, float)],
                    "err": [float(e) for e in m.err],
                }
            )
    return out


if __name__ == "__main__":
    out = Path(sys.argv[1])
    print("using", tensegrity_rigidity.__file__, file=sys.stderr)
    args = ["reproduce", "--scale", "tiny", "--out", str(out), "--workers", "1"]
    assert main([*args, "--no-progress"]) == 0
    from tensegrity_rigidity.paper.studies import SCALES, STORED

    tiny = SCALES["tiny"]
    stored = dict(workers=STORED, scheduler=None, progress=False)
    results = {name: STUDIES[name](out, tiny, **stored) for name in tiny.studies}
    commit = subprocess.run(
        ["git", "rev-parse", "--short", RELEASE], capture_output=True, text=True
    ).stdout.strip()
    record = {
        "generated_by": "tests/paper/data/make_release_claims.py (see its docstring)",
        "release": commit or RELEASE,
        "scale": "tiny",
        "measurements": measurements(results),
    }
    here = Path(__file__).with_name("release_claims.json")
    ms = ",\n".join("  " + json.dumps(m) for m in record.pop("measurements"))
    head = json.dumps(record, indent=1)[:-2]
    here.write_text(head + f',\n "measurements": [\n{ms}\n ]\n}}\n')
    print(f"wrote {len(record['measurements'])} measurements to {here}", file=sys.stderr)
