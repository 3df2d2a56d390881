"""The paper layer's size targets, measured: lines, long functions, English literals, study names.

Counts, for ``src/tensegrity_rigidity/paper`` (or ``--root``):

* **lines**: physical lines of its Python files (templates and data files listed apart);
* **long functions**: functions whose code lines (the body without its docstring, blank lines
  and comment-only lines) exceed ``--max-function`` (60);
* **English literal lines**: physical lines of string literals (f-strings included) holding
  a phrase (two words of two letters or more in a row) outside docstrings and outside error
  messages (a ``raise`` statement, a call of a name ending in ``Error`` or ``warn``);
* **study names outside their module and the registry**: string constants equal to a
  registered study's name, and imports of a study module, in any file but that study's module
  and ``registry.py``. The keys of a study's ``PARAMS`` table are scale names (the scale
  ``fss`` shares its name with the study) and are not counted.

Run: python benchmarks/paper_targets.py [--root DIR] [--studies a,b,...] [--json]
"""

from __future__ import annotations

import argparse
import ast
import io
import json
import re
import tokenize
from pathlib import Path

ROOT = Path(__file__).parents[1] / "src" / "tensegrity_rigidity" / "paper"
PHRASE = re.compile(r"[A-Za-z]{2,}[ ]+[A-Za-z]{2,}")


def _docstring_lines(tree: ast.AST) -> set[int]:
    out: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                if isinstance(body[0].value.value, str):
                    out |= set(range(body[0].lineno, body[0].end_lineno + 1))
    return out


def _error_lines(tree: ast.AST) -> set[int]:
    out: set[int] = set()
    for node in ast.walk(tree):
        name = ""
        if isinstance(node, ast.Call):
            f = node.func
            name = getattr(f, "id", "") or getattr(f, "attr", "")
        if isinstance(node, ast.Raise) or name.endswith(("Error", "warn")):
            out |= set(range(node.lineno, node.end_lineno + 1))
    return out


def english_lines(source: str) -> int:
    """Physical lines of phrase-holding string literals outside docstrings and errors."""
    tree = ast.parse(source)
    skip = _docstring_lines(tree) | _error_lines(tree)
    lines: set[int] = set()
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type not in (tokenize.STRING, getattr(tokenize, "FSTRING_MIDDLE", -1)):
            continue
        span = set(range(tok.start[0], tok.end[0] + 1))
        if span & skip:
            continue
        text = re.sub(r"\{[^{}]*\}", " ", tok.string)  # an f-string's fields are not words
        if PHRASE.search(text):
            lines |= span
    return len(lines)


def code_lines(node: ast.AST, source_lines: list[str]) -> int:
    """Lines of a function's body without its docstring, blank and comment-only lines."""
    body = node.body
    start = body[0].lineno
    if isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
        start = body[0].end_lineno + 1 if len(body) > 1 else body[0].end_lineno + 1
    count = 0
    for line in source_lines[start - 1 : node.end_lineno]:
        s = line.strip()
        if s and not s.startswith("#"):
            count += 1
    return count


def long_functions(path: Path, source: str, limit: int) -> list[tuple[str, int]]:
    tree = ast.parse(source)
    lines = source.splitlines()
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            n = code_lines(node, lines)
            if n > limit:
                out.append((f"{path.stem}.{node.name}", n))
    return out


def _params_keys(tree: ast.AST) -> set[int]:
    """ids of the key constants of module-level ``PARAMS`` dict literals (scale names)."""
    out: set[int] = set()
    for node in tree.body:  # type: ignore[attr-defined]
        targets = node.targets if isinstance(node, ast.Assign) else [getattr(node, "target", None)]
        if any(isinstance(t, ast.Name) and t.id == "PARAMS" for t in targets):
            if isinstance(node.value, ast.Dict):
                out |= {id(k) for k in node.value.keys if k is not None}
    return out


def study_names(path: Path, source: str, studies: tuple[str, ...], root: Path) -> list[str]:
    """References to a study outside its module and the registry, as 'file:line name'."""
    rel = path.relative_to(root)
    if rel.name == "registry.py":
        return []
    own = path.stem if rel.parts[0] == "studies" else None
    tree = ast.parse(source)
    params = _params_keys(tree)
    found = []
    for node in ast.walk(tree):
        names: list[str] = []
        if isinstance(node, ast.Constant) and isinstance(node.value, str):
            names = [] if id(node) in params else [node.value]
        elif isinstance(node, ast.ImportFrom):
            mod = (node.module or "").split(".")
            names = [mod[-1]] + [a.name for a in node.names]
            names = [n for n in names if n in studies and ("studies" in mod or node.level == 1)]
        for name in names:
            if name in studies and name != own:
                found.append(f"{rel}:{node.lineno} {name}")
    return found


def registered(root: Path) -> tuple[str, ...]:
    """The study modules ``root/registry.py`` imports (each study is named as its module)."""
    tree = ast.parse((root / "registry.py").read_text())
    return tuple(
        a.name
        for node in ast.walk(tree)
        if isinstance(node, ast.ImportFrom) and node.level == 1 and node.module == "studies"
        for a in node.names
    )


def measure(root: Path, studies: tuple[str, ...], limit: int) -> dict:
    files = sorted(root.rglob("*.py"))
    per_file, long, english, names = {}, [], {}, []
    for path in files:
        src = path.read_text()
        rel = str(path.relative_to(root))
        per_file[rel] = len(src.splitlines())
        long += long_functions(path, src, limit)
        english[rel] = english_lines(src)
        names += study_names(path, src, studies, root)
    other = {
        str(p.relative_to(root)): len(p.read_text().splitlines())
        for p in sorted(root.rglob("*"))
        if p.is_file() and p.suffix in (".md", ".toml", ".csv", ".json")
    }
    return {
        "python_lines": sum(per_file.values()),
        "python_files": len(files),
        "per_file": per_file,
        "data_and_template_lines": other,
        "long_functions": sorted(long, key=lambda x: -x[1]),
        "english_literal_lines": sum(english.values()),
        "english_per_file": {k: v for k, v in english.items() if v},
        "study_names_outside": names,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--root", type=Path, default=ROOT)
    ap.add_argument("--studies", help="comma-separated (default: what the registry imports)")
    ap.add_argument("--max-function", type=int, default=60)
    ap.add_argument("--json", action="store_true", help="print every count as JSON")
    args = ap.parse_args()
    studies = tuple(args.studies.split(",")) if args.studies else registered(args.root)
    m = measure(args.root, studies, args.max_function)
    if args.json:
        print(json.dumps(m, indent=1))
        return
    data = m["data_and_template_lines"]
    print(f"paper/ Python lines: {m['python_lines']} in {m['python_files']} files (target <= 5000)")
    print(f"templates and data files: {sum(data.values())} lines in {len(data)} files")
    print(f"functions over {args.max_function} code lines: {len(m['long_functions'])} (target 0)")
    for name, n in m["long_functions"]:
        print(f"  {name}: {n}")
    print(f"English string-literal lines: {m['english_literal_lines']} (target <= 60)")
    for name, n in sorted(m["english_per_file"].items(), key=lambda x: -x[1]):
        print(f"  {name}: {n}")
    print(f"study names outside their module and the registry: {len(m['study_names_outside'])}")
    for where in m["study_names_outside"]:
        print(f"  {where}")


if __name__ == "__main__":
    main()
