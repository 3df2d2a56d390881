"""Every example of the README and the guides runs as printed, and every sample output shown
is what the commands print.

Each page runs top to bottom in a fresh directory holding a copy of ``examples/`` (as a user
in the repository's root has it): its shell commands through bash with this environment's
``tensegrity-rigidity`` first on the PATH, its Python blocks in one namespace per page. A
``text`` block is the output of the commands run since the previous one and is compared with
it, ``...`` standing for any text (doctest's ELLIPSIS); a block that shows something else is
preceded by ``<!-- not output -->``. A ``toml`` block that starts with ``# examples/NAME``
is that file, character for character; every other ``toml`` block must parse.
"""

from __future__ import annotations

import doctest
import os
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from tensegrity_rigidity.cli.main import build_parser

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
PAGES = [
    "README.md",
    "docs/getting-started.md",
    *sorted(str(p.relative_to(ROOT)) for p in (ROOT / "docs" / "guide").glob("*.md")),
]
#: shell commands not run, each with the reason (a regular expression on the command)
NOT_RUN = {
    r"python3 -m venv|pip install": "installs packages: CI runs the README's two commands on a "
    "clean checkout",
    r"sphinx-build": "tests/test_docs.py builds the documentation",
    r"--scheduler|^dask ": "needs a running Dask scheduler",
}
#: commands only parsed, not run: a reproduction takes minutes to hours (tests/paper runs
#: --scale tiny end to end, the CLI tests --estimate)
PARSED_ONLY = r"^tensegrity-rigidity reproduce\b"
#: Python blocks not run, with the reason
PYTHON_NOT_RUN = {
    r"dask_jobqueue": "needs dask-jobqueue and a SLURM cluster",
    r"^from \.\.study import": "a module of the package (relative imports, a template beside "
    "it): tests/paper/test_adding_a_study.py runs it in its place",
}
NOT_OUTPUT = "<!-- not output -->"
FENCE = re.compile(r"^```(\w+)\n(.*?)^```\n", flags=re.S | re.M)


def blocks(page: str) -> list[tuple[str, str, bool]]:
    """(language, text, marked as not output) of every fenced block of a page, in order."""
    text = (ROOT / page).read_text()
    out = []
    for m in FENCE.finditer(text):
        before = text[: m.start()].rstrip().splitlines()[-1:] or [""]
        out.append((m.group(1), m.group(2), before[0].strip() == NOT_OUTPUT))
    return out


def commands(script: str) -> list[str]:
    """One command per line, continuation lines joined; blank and comment lines dropped."""
    joined = script.replace("\\\n", " ")
    return [line.strip() for line in joined.splitlines() if line.strip() and line[0] != "#"]


def why_not_run(command: str) -> str | None:
    for pattern, reason in NOT_RUN.items():
        if re.search(pattern, command):
            return reason
    return None


@pytest.fixture
def fresh(tmp_path, monkeypatch):
    """A fresh directory with a copy of examples/, the working directory of the page."""
    shutil.copytree(EXAMPLES, tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    return tmp_path


def run_page(page: str, where: Path) -> dict:
    """Run a page's examples in ``where``; returns counts of what ran and what was checked."""
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    namespace: dict = {"__name__": "__example__"}
    done = {"commands": 0, "parsed": 0, "skipped": 0, "python": 0, "outputs": 0, "toml": 0}
    printed = ""
    for lang, text, not_output in blocks(page):
        if lang == "bash":
            for command in commands(text):
                if why_not_run(command):
                    done["skipped"] += 1
                elif re.search(PARSED_ONLY, command):
                    argv = command.split("#")[0].split()[1:]
                    build_parser().parse_args(argv)  # SystemExit on a wrong option or scale
                    done["parsed"] += 1
                else:
                    proc = subprocess.run(
                        ["bash", "-c", command], cwd=where, env=env, capture_output=True, text=True
                    )
                    assert proc.returncode == 0, f"{page}: {command}\n{proc.stderr}"
                    printed += proc.stdout
                    done["commands"] += 1
        elif lang == "python":
            if any(re.search(p, text, flags=re.M) for p in PYTHON_NOT_RUN):
                done["skipped"] += 1
                continue
            exec(compile(text, page, "exec"), namespace)
            done["python"] += 1
        elif lang == "text" and not not_output:
            checker = doctest.OutputChecker()
            assert checker.check_output(text, printed, doctest.ELLIPSIS), (
                f"{page}: the output shown is not what the commands print:\n{text}\n"
                f"--- printed ---\n{printed}"
            )
            printed = ""
            done["outputs"] += 1
        elif lang == "toml":
            first = text.splitlines()[0]
            if first.startswith("# examples/"):
                name = first.split()[1].rstrip(":")
                assert text == (ROOT / name).read_text(), f"{page} shows {name} otherwise"
            tomllib.loads(text)
            done["toml"] += 1
    return done


#: at least this much of each page runs and is checked: a change that makes the runner skip
#: them (a renamed marker, another fence style) fails here
EXPECTED = {
    "README.md": {"commands": 6, "python": 1},
    "docs/getting-started.md": {"commands": 3, "outputs": 1, "python": 2},
    "docs/guide/sweeps.md": {"commands": 3, "outputs": 1, "python": 1, "toml": 2},
    "docs/guide/thresholds.md": {"commands": 1, "outputs": 1, "python": 1, "toml": 1},
    "docs/guide/three-dimensions.md": {"commands": 1, "outputs": 1, "python": 1, "toml": 1},
    "docs/guide/reproduction.md": {"parsed": 3},
}


@pytest.mark.parametrize("page", PAGES)
def test_examples_run_as_printed(page, fresh):
    done = run_page(page, fresh)
    assert sum(done.values()) > 0, f"{page} has no example"
    for what, least in EXPECTED.get(page, {}).items():
        assert done[what] >= least, (page, what, done)


def test_every_example_file_is_shown_and_run_somewhere():
    text = "".join((ROOT / page).read_text() for page in PAGES)
    for path in EXAMPLES.glob("*.toml"):
        name = f"examples/{path.name}"
        assert f"sweep {name}" in text, f"no page runs {name}"
        assert path.read_text().startswith(f"# {name}: "), f"{name} should say what it is"


def test_the_output_check_sees_a_drifted_output(tmp_path):
    """The comparison fails where the numbers differ and passes over ``...``."""
    checker = doctest.OutputChecker()
    assert checker.check_output(
        "status  rigid\nwork ... s\n", "status  rigid\nwork 1 s\n", doctest.ELLIPSIS
    )
    assert not checker.check_output("energy  10.1\n", "energy  10.2\n", doctest.ELLIPSIS)
