"""A verdict is a function of the instance and the options: the same in a fresh process,
after other solves in the same process, and under a parallel load."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np

from tensegrity_rigidity import lattice_instance, solve

CASES = [
    (16, 0.55, 0.2, 0.0, "compression", 1),
    (16, 0.45, 0.3, 1.0, "dilation", 2),
    (16, 0.5, 0.3, 0.5, "shear", 3),
]

SCRIPT = """
import json, sys
from tensegrity_rigidity import lattice_instance, solve
out = []
for n, p_r, p_t, f_c, phi, seed in json.loads(sys.argv[1]):
    r = solve(lattice_instance(n, p_r, p_t, f_c, phi=phi, theta=0.3, seed=seed))
    s = r.summary(); s.pop("seconds"); out.append(s)
print(json.dumps(out))
"""


def _here():
    out = []
    for n, p_r, p_t, f_c, phi, seed in CASES:
        r = solve(lattice_instance(n, p_r, p_t, f_c, phi=phi, theta=0.3, seed=seed))
        s = r.summary()
        s.pop("seconds")
        out.append(s)
    return out


def _fresh():
    res = subprocess.run(
        [sys.executable, "-c", SCRIPT, json.dumps(CASES)], capture_output=True, text=True
    )
    assert res.returncode == 0, res.stderr
    return json.loads(res.stdout)


def test_same_result_fresh_after_other_solves_and_under_load():
    first = _fresh()
    # after other solves in this process
    rng = np.random.default_rng(0)
    for _ in range(5):
        solve(lattice_instance(12, rng.uniform(0.3, 0.8), 0.2, 0.5, seed=int(rng.integers(99))))
    assert _here() == first
    # under a parallel load: two more processes solving at the same time
    loads = [
        subprocess.Popen(
            [sys.executable, "-c", SCRIPT, json.dumps(CASES * 3)],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        for _ in range(2)
    ]
    try:
        assert _fresh() == first
        assert _here() == first
    finally:
        for proc in loads:
            proc.wait()
