"""Count the tolerance-like float literals (0 < |x| < 1e-2) written inside function bodies.

The issue 74 metric: every numeric constant of the search should be named once (in
``solver.tolerances.Tolerances`` or as a strategy's field), not written inline. Counts float
constants in the bodies of functions and lambdas (not in class bodies or module constants) of
the files under a folder, and lists them; then the same literals written as keyword defaults in
signatures (a routine's tolerance belongs in ``Tolerances``, where it enters the digest).

Run: python benchmarks/count_tolerance_literals.py [src/tensegrity_rigidity/solver]
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path


def literals(path: Path) -> list[tuple[int, float]]:
    """(line, value) of each tolerance-like literal in the function bodies of ``path``."""
    found = {}
    for fn in ast.walk(ast.parse(path.read_text())):
        if not isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            continue
        for stmt in fn.body if isinstance(fn.body, list) else [fn.body]:
            for node in ast.walk(stmt):
                value = getattr(node, "value", None)
                if isinstance(node, ast.Constant) and isinstance(value, float):
                    if 0 < abs(value) < 1e-2:
                        found[(node.lineno, node.col_offset)] = value
    return sorted((line, value) for (line, _), value in found.items())


def signature_defaults(path: Path) -> list[tuple[int, str, float]]:
    """(line, function, value) of each tolerance-like literal among the signature defaults."""
    found = []
    for fn in ast.walk(ast.parse(path.read_text())):
        if not isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        for default in [*fn.args.defaults, *filter(None, fn.args.kw_defaults)]:
            for node in ast.walk(default):
                value = getattr(node, "value", None)
                if isinstance(node, ast.Constant) and isinstance(value, float):
                    if 0 < abs(value) < 1e-2:
                        found.append((node.lineno, fn.name, value))
    return sorted(found)


def main() -> None:
    root = Path(sys.argv[1] if len(sys.argv) > 1 else "src/tensegrity_rigidity/solver")
    total = 0
    for path in sorted(root.glob("*.py")):
        for line, value in literals(path):
            print(f"{path.name}:{line}: {value!r}")
            total += 1
    print(f"total {total}")
    defaults = 0
    for path in sorted(root.glob("*.py")):
        for line, name, value in signature_defaults(path):
            print(f"{path.name}:{line}: {name}(... = {value!r})")
            defaults += 1
    print(f"signature defaults {defaults}")


if __name__ == "__main__":
    main()
