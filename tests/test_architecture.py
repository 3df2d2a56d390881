"""The layering of ARCHITECTURE.md: each subpackage imports only the stages before it."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import tensegrity_rigidity

ROOT = Path(tensegrity_rigidity.__file__).parent
ORDER = ["model", "combinatorics", "solver", "analysis", "ensemble", "paper", "cli"]


def _imported_subpackages(path: Path) -> set[str]:
    """Subpackages of tensegrity_rigidity imported by a module (relative or absolute)."""
    pkg = path.parent.relative_to(ROOT).parts
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = list(pkg[: len(pkg) - node.level + 1])
                target = base + (node.module.split(".") if node.module else [])
                if not node.module:  # from .. import x
                    target = base + [a.name for a in node.names][:1]
            elif node.module and node.module.startswith("tensegrity_rigidity."):
                target = node.module.split(".")[1:]
            else:
                continue
            if target:
                found.add(target[0])
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.startswith("tensegrity_rigidity."):
                    found.add(a.name.split(".")[1])
    return found


@pytest.mark.parametrize("sub", ORDER)
def test_each_stage_imports_only_earlier_stages(sub):
    allowed = set(ORDER[: ORDER.index(sub) + 1]) | {"errors", "interrupts"}
    for path in (ROOT / sub).glob("*.py"):
        bad = _imported_subpackages(path) - allowed
        assert not bad, f"{path.relative_to(ROOT)} imports {sorted(bad)}"


def test_the_checker_sees_a_forbidden_import(tmp_path):
    fake = ROOT / "model" / "_probe_forbidden.py"
    fake.write_text("from ..solver.core import solve\n")
    try:
        assert _imported_subpackages(fake) == {"solver"}
    finally:
        fake.unlink()


def _imported_modules(path: Path) -> set[str]:
    """Top-level names of the modules a file imports absolutely (``scipy``, ``numpy``, ...)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and not node.level and node.module:
            found.add(node.module.split(".")[0])
        elif isinstance(node, ast.Import):
            found |= {a.name.split(".")[0] for a in node.names}
    return found


#: the paper layer's modules that render: they fill templates with the studies' numbers
RENDERERS = ("report.py", "render.py", "template.py", "figures.py", "style.py")


@pytest.mark.parametrize("name", RENDERERS)
def test_the_report_renders_and_computes_nothing(name):
    """Computation lives in the studies and analysis/: the report's modules import neither."""
    path = ROOT / "paper" / name
    assert "analysis" not in _imported_subpackages(path), name
    assert "scipy" not in _imported_modules(path), name


def test_the_renderer_checker_sees_a_forbidden_import(tmp_path):
    probe = tmp_path / "probe.py"
    probe.write_text("from scipy import stats\nimport numpy as np\n")
    assert _imported_modules(probe) == {"scipy", "numpy"}


def _study_modules() -> dict[str, str]:
    """Module name (``studies/<stem>.py``) of every registered study -> the study's name."""
    from tensegrity_rigidity.paper import registry

    out = {}
    for path in (ROOT / "paper" / "studies").glob("*.py"):
        module = __import__(f"tensegrity_rigidity.paper.studies.{path.stem}", fromlist=["_"])
        study = getattr(module, "STUDY", None)
        if study is not None and study in registry.REGISTRY:
            out[path.stem] = study.name
    return out


def _study_imports(path: Path, stems: set[str]) -> set[str]:
    """The study modules (of ``stems``) that a file imports, however it spells the import."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            parts = (node.module or "").split(".")
            if parts[-1] in stems and "studies" in parts[:-1]:
                found.add(parts[-1])
            if node.level == 1 and path.parent.name == "studies" and parts[0] in stems:
                found.add(parts[0])
            if parts[-1] == "studies" or (not node.module and path.parent.name == "studies"):
                found |= {a.name for a in node.names} & stems
        elif isinstance(node, ast.Import):
            for a in node.names:
                parts = a.name.split(".")
                if "studies" in parts and parts[-1] in stems:
                    found.add(parts[-1])
    return found


def test_studies_are_plug_ins_that_only_the_registry_imports():
    """A study is one module and its template: no other module of the package imports it (the
    report, figures, budget and comparison loop over the registry), and its module loads no
    other study's template."""
    stems = _study_modules()
    assert len(stems) >= 10 and "jamming_onset" in stems
    for path in ROOT.rglob("*.py"):
        if path.name == "registry.py" and path.parent.name == "paper":
            continue
        bad = _study_imports(path, set(stems)) - {path.stem}
        assert not bad, f"{path.relative_to(ROOT)} imports the study module(s) {sorted(bad)}"
    for stem, name in stems.items():
        text = (ROOT / "paper" / "studies" / f"{stem}.py").read_text()
        others = {n for n in stems.values() if n != name}
        assert not any(f'load("{n}")' in text for n in others), stem


def test_the_study_checker_sees_an_import_of_a_study(tmp_path):
    sibling = tmp_path / "studies" / "probe.py"
    sibling.parent.mkdir()
    sibling.write_text("from .three_d import SEED_3D\nfrom .rows import Rows\n")
    assert _study_imports(sibling, {"three_d", "fss"}) == {"three_d"}
    probe = tmp_path / "probe.py"
    probe.write_text(
        "from ..paper.studies import jamming_onset\n"
        "import tensegrity_rigidity.paper.studies.three_d\n"
        "from .studies.fss import sweeps\n"
    )
    assert _study_imports(probe, {"jamming_onset", "three_d", "fss", "fig2"}) == {
        "jamming_onset",
        "three_d",
        "fss",
    }
