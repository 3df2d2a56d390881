"""The command line starts at once: building the parser, ``--help`` of every command and
``--version`` import no numerical library, and ``solve`` imports only the solver's.

Speed itself is measured in benchmarks/bench_cli_start.py; these tests check the cause.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from tensegrity_rigidity import __version__

#: libraries that take a second or more to import between them; none is needed to parse
HEAVY = ("matplotlib", "scipy.stats", "numba", "pandas", "pyarrow", "dask", "scipy")

PROBE = """
import json, sys
from tensegrity_rigidity.cli.main import build_parser, main
{body}
print(json.dumps(sorted(m for m in {heavy!r} if m in sys.modules)))
"""


def _loaded(body: str, heavy=HEAVY, cwd=None) -> list[str]:
    """Which of ``heavy`` a fresh interpreter has imported after running ``body``."""
    code = PROBE.format(body=body, heavy=tuple(heavy))
    proc = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=cwd, check=False
    )
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_building_the_parser_imports_no_numerical_library():
    assert _loaded("build_parser()") == []


@pytest.mark.parametrize("command", [[], ["sample"], ["solve"], ["sweep"], ["info"], ["reproduce"]])
def test_help_imports_no_numerical_library(command):
    body = f"""
try:
    main({[*command, "--help"]!r})
except SystemExit:
    pass
"""
    assert _loaded(body) == []


def test_version_is_the_package_version():
    proc = subprocess.run(
        [sys.executable, "-m", "tensegrity_rigidity", "--version"], capture_output=True, text=True
    )
    assert proc.returncode == 0 and proc.stdout.strip() == f"tensegrity-rigidity {__version__}"


def test_solve_imports_neither_pandas_nor_matplotlib_nor_numba(tmp_path):
    body = """
assert main(["sample", "s.npz", "--n", "4", "--p-r", "0.7"]) == 0
assert main(["solve", "s.npz"]) == 0
"""
    heavy = ("matplotlib", "scipy.stats", "numba", "pandas", "pyarrow", "dask")
    assert _loaded(body, heavy, cwd=tmp_path) == []
