"""The layers import downwards only: contracts <- cache <- tasks <- flows <- benchmarks; the MPM engine has no Prefect.

A pure AST scan of the source files (every import statement, also those inside functions and under TYPE_CHECKING,
relative ones resolved); nothing under test is imported.
"""

from __future__ import annotations

import ast
import functools
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
ORDER = ("contracts", "cache", "tasks", "flows", "benchmarks")  # each may import those before it, never those after


def module_name(path: Path) -> str:
    """The dotted module name of a source file under ROOT."""
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imports(source: str, module: str, is_package: bool = False) -> list[tuple[str, int, bool]]:
    """(imported module, line, inside a function) for every import in `source`; relative imports made absolute."""
    package = module.split(".") if is_package else module.split(".")[:-1]
    found: list[tuple[str, int, bool]] = []

    def visit(node: ast.AST, in_function: bool) -> None:
        if isinstance(node, ast.Import):
            found.extend((alias.name, node.lineno, in_function) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = package[: len(package) - node.level + 1] if node.level else []
            found.append((".".join(base + ([node.module] if node.module else [])), node.lineno, in_function))
        inner = in_function or isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
        for child in ast.iter_child_nodes(node):
            visit(child, inner)

    visit(ast.parse(source), False)
    return found


def sources(layer: str) -> list[Path]:
    """The Python files of a top-level package."""
    return sorted(p for p in (ROOT / layer).rglob("*.py") if "__pycache__" not in p.parts)


@functools.cache
def file_imports(path: Path) -> list[tuple[str, int, bool]]:
    """The imports of one source file."""
    return imports(path.read_text(encoding="utf-8"), module_name(path), path.name == "__init__.py")


@pytest.mark.parametrize("layer", ORDER[:-1])
def test_no_import_runs_up(layer: str) -> None:
    """No module of a layer imports a layer above it, not even inside a function."""
    above = set(ORDER[ORDER.index(layer) + 1:])
    files = sources(layer)
    assert files, f"no sources under {layer}/"
    bad = []
    for path in files:
        rel = path.relative_to(ROOT).as_posix()
        for name, line, _ in file_imports(path):
            if name.split(".")[0] not in above:
                continue
            bad.append(f"{rel}:{line} imports {name}")
    assert not bad, "imports that run up the layers:\n" + "\n".join(bad)


def test_mpm_engine_has_no_prefect() -> None:
    """tasks/mpm (the Warp engine) imports no Prefect, directly or through cache's Prefect modules."""
    bad = [f"{p.relative_to(ROOT)}:{line} imports {name}" for p in sources("tasks/mpm")
           for name, line, _ in file_imports(p) if name.split(".")[0] in ("prefect", "flows")
           or name in ("cache.prefect_task", "cache.runtime")]
    assert not bad, "\n".join(bad)


def test_scan_sees_nested_and_relative_imports() -> None:
    """The scanner finds imports inside functions and resolves relative ones (the checks above rely on it)."""
    src = ("import os\nfrom . import store\nif X:\n    import flows\n"
           "def f():\n    from ..flows import cli\n    import benchmarks.x\n")
    assert imports(src, "cache.sub.mod") == [("os", 1, False), ("cache.sub", 2, False), ("flows", 4, False),
                                              ("cache.flows", 6, True), ("benchmarks.x", 7, True)]
    assert imports("from .. import x\n", "tasks.geometry", is_package=True) == [("tasks", 1, False)]
