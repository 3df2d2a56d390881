"""The LP strategy's verdicts do not depend on which HiGHS plugins happen to be installed.

HiGHS's ``solver = "ipm"`` runs IPX, or HiPO whenever the plugin ``highspy-extras`` is installed,
and their crossovers end at different vertices. The strategy names its interior point
(``LinearProgram.interior``), so the same instance and options give the same certificates,
to the last bit, with the plugin importable and with it blocked. The test extra installs the
plugin, so both sides run here.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from tensegrity_rigidity.errors import InputError
from tensegrity_rigidity.solver import stages
from tensegrity_rigidity.solver.stages import LinearProgram

#: near-threshold probes that the LP strategy alone decides: (n, seed, strain, p_t, f_c, event)
#: (benchmarks/near_threshold_set.py's configurations 0 and 2 on both sides of their thresholds;
#: HiGHS's "ipm" with the plugin installed ends at other vertices on every one of them)
PROBES = [
    (12, [12, 0, 0], "compression", 0.3, 1.0, 421),
    (12, [12, 0, 0], "compression", 0.3, 1.0, 422),
    (16, [16, 2, 0], "shear", 0.3, 0.5, 758),
    (16, [16, 2, 0], "shear", 0.3, 0.5, 759),
]

SCRIPT = """
import hashlib, json, sys
if sys.argv[1] == "blocked":
    sys.modules["highspy_extras"] = None  # as if the plugin were not installed
sys.path.insert(0, sys.argv[3])
import numpy as np
from tests.instances import near_threshold_instance
from tensegrity_rigidity.solver.core import SolverOptions, decide
from tensegrity_rigidity.solver.stages import LinearProgram, hipo_available
opts = SolverOptions(min_norm=False, stages=(LinearProgram(),))
out = {"hipo": hipo_available(), "verdicts": []}
for n, seed, phi, p_t, f_c, event in json.loads(sys.argv[2]):
    v = decide(near_threshold_instance(n, seed, phi, p_t, f_c, event), opts)
    cert = v.rigid if v.status == "rigid" else v.floppy
    x = np.asarray(cert.t if v.status == "rigid" else cert.u)
    # a long double's padding bytes are not part of its value: hash it as two doubles
    head = x.astype(float)
    bits = hashlib.sha256(head.tobytes() + (x - head).astype(float).tobytes()).hexdigest()
    out["verdicts"].append([v.status, v.stage, v.reason, bits])
print(json.dumps(out))
"""


def _run(mode: str) -> dict:
    from pathlib import Path

    root = str(Path(__file__).resolve().parents[2])
    res = subprocess.run(
        [sys.executable, "-c", SCRIPT, mode, json.dumps(PROBES), root],
        capture_output=True,
        text=True,
    )
    assert res.returncode == 0, res.stderr
    return json.loads(res.stdout)


def test_lp_verdicts_are_the_same_with_the_hipo_plugin_and_without():
    with_plugin, without = _run("importable"), _run("blocked")
    assert with_plugin["hipo"], "the test extra installs highspy-extras: both sides must run"
    assert not without["hipo"]
    assert with_plugin["verdicts"] == without["verdicts"]
    assert {v[0] for v in with_plugin["verdicts"]} <= {"rigid", "floppy"}


def test_an_unknown_interior_point_is_refused_in_one_line():
    with pytest.raises(InputError, match="LinearProgram.interior must be one of ipx, hipo"):
        LinearProgram(interior="ipm")


def test_hipo_without_its_plugin_is_refused_in_one_line(monkeypatch):
    monkeypatch.setattr(stages, "hipo_available", lambda: False)
    with pytest.raises(InputError, match="pip install highspy-extras"):
        LinearProgram(interior="hipo")


def test_a_highs_call_that_leaves_the_algorithm_to_highs_is_refused():
    import numpy as np
    import scipy.sparse as sp

    from tensegrity_rigidity.solver.highs import run_lp

    A = sp.csc_matrix(np.ones((1, 2)))
    with pytest.raises(ValueError, match="must name its algorithm"):
        run_lp(A, [1.0, 1.0], [0.0, 0.0], [1.0, 1.0], [1.0], [2.0], solver="ipm")
    h = run_lp(A, [1.0, 2.0], [0.0, 0.0], [1.0, 1.0], [1.0], [2.0], solver="simplex")
    assert list(h.getSolution().col_value) == [1.0, 0.0]
