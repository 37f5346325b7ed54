"""The layers import downwards only: contracts <- cache <- tasks <- flows <- benchmarks (deployments above flows); the
subpackages of tasks/ import downwards in TASKS_ORDER; the MPM engine has no Prefect; imports of our own modules are
at module level, the few function-level ones (at most LAZY_LIMIT) each saying why on its line or the line above.

A pure AST scan of the source files (every import statement, also those inside functions and under TYPE_CHECKING,
relative ones resolved); nothing under test is imported.
"""

from __future__ import annotations

import ast
import functools
import io
import re
import tokenize
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
ORDER = ("contracts", "cache", "tasks", "flows", "benchmarks")  # each may import those before it, never those after
PRODUCT = ("contracts", "cache", "tasks", "flows")  # none of them imports deployments/ either
OWN = (*ORDER, "deployments")  # our own top-level packages (and the deployment scripts)
# tasks/ in layers, lowest first: a subpackage (or top-level module) of tasks/ may import those before it and itself,
# never those after. Derived from what the code needs: the engine, the records and the child processes know no layer;
# render (one camera model for every image and video) draws arrays and knows records (the card); the harness (agents)
# knows records; geometry builds with the harness's LLM roles (the shape Designer) and draws its reference views; the
# robot measures geometry's meshes; probes run the engine on geometry; manipulation, export, evaluation, the request
# check, the commands' pre-flight checks, the batch's requests and its throughput figures sit on top; report (what the
# command line shows of results) reads them all; the real-world figures and the calibration from video (which fits
# with the export calibration's searches and the real-world impact probe) come last.
TASKS_ORDER = ("native_output", "quiet_pybullet", "processes", "publish", "asset_dir", "mpm", "record", "render",
               "agents", "geometry", "physical", "robot", "probes", "manipulation", "manifest_summary", "export",
               "evaluation", "asset_cache", "request", "preflight", "batch_requests", "throughput", "report", "realworld",
               "calibrate")
LAZY_LIMIT = 62  # function-level imports of our own modules, in all of OWN's sources together (62: `calibrate`)
BAD_REASON = re.compile(r"\b(cycle|cyclic|circular)\b", re.I)  # a circle is fixed by moving code, not by a lazy import


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
    above = set(ORDER[ORDER.index(layer) + 1:]) | ({"deployments"} if layer in PRODUCT else set())
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


@dataclass(frozen=True)
class ImportSite:
    """One import statement of our own modules: the modules it names, where, and the comment that says why."""

    targets: tuple[str, ...]  # absolute module names (`from tasks import geometry` -> tasks.geometry)
    line: int
    in_function: bool
    reason: str  # the comment on its lines or on the line just above ('' when none)
    text: str


_LINE = re.compile(r"[^\r\n]*(?:\r\n|\r|\n)|[^\r\n]+\Z")  # a line as the parser splits them (ast's _splitlines_no_ff)


def source_segment(parser_lines: list[str], node: ast.stmt) -> str:
    """ast.get_source_segment(source, node) from the source's lines as the parser splits them (_LINE), split once per
    file: get_source_segment splits the whole source again for every statement (~15 s over tasks/ on CI's CPU)."""
    end = node.end_lineno if node.end_lineno is not None else node.lineno
    part = "".join(parser_lines[node.lineno - 1:end])
    here = ast.Pass(lineno=1, col_offset=node.col_offset, end_lineno=end - node.lineno + 1,
                    end_col_offset=node.end_col_offset)
    return ast.get_source_segment(part, here) or ""


@functools.cache  # (both tasks/ checks below read every tasks/ file: each is tokenized and parsed once)
def own_imports(source: str, module: str, is_package: bool = False) -> tuple[ImportSite, ...]:
    """The import statements of `source` that name our own packages (relative ones made absolute)."""
    package = module.split(".") if is_package else module.split(".")[:-1]
    lines = source.splitlines()
    parser_lines = _LINE.findall(source)
    comments: dict[int, str] = {}
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type == tokenize.COMMENT:
            comments[tok.start[0]] = tok.string.lstrip("#").strip()
    found: list[ImportSite] = []

    def site(node: ast.Import | ast.ImportFrom, targets: list[str], in_function: bool) -> None:
        own = tuple(t for t in targets if t.split(".")[0] in OWN)
        if not own:
            return
        above = node.lineno - 1
        reason = " ".join(comments[n] for n in range(node.lineno, (node.end_lineno or node.lineno) + 1)
                          if n in comments)
        if not reason and above in comments and lines[above - 1].lstrip().startswith("#"):
            reason = comments[above]
        found.append(ImportSite(own, node.lineno, in_function, reason, source_segment(parser_lines, node)))

    def visit(node: ast.AST, in_function: bool) -> None:
        if isinstance(node, ast.Import):
            site(node, [alias.name for alias in node.names], in_function)
        elif isinstance(node, ast.ImportFrom):
            base = package[: len(package) - node.level + 1] if node.level else []
            name = ".".join(base + ([node.module] if node.module else []))
            site(node, [f"{name}.{alias.name}" for alias in node.names] if name in OWN else [name], in_function)
        inner = in_function or isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
        for child in ast.iter_child_nodes(node):
            visit(child, inner)

    visit(ast.parse(source), False)
    return tuple(found)


def tasks_unit(name: str) -> str | None:
    """The unit of tasks/ a module belongs to (its subpackage or top-level module); None outside tasks/."""
    parts = name.split(".")
    return parts[1] if parts[0] == "tasks" and len(parts) > 1 else None


def tasks_order_violations(rel: str, source: str) -> list[str]:
    """'file:line imports X (unit a imports unit b, which is above it)' for each import up the tasks/ order."""
    path = ROOT / rel
    module = module_name(path)
    unit = tasks_unit(module)
    if unit is None:
        return []
    assert unit in TASKS_ORDER, f"{rel}: tasks/{unit} has no place in TASKS_ORDER"
    bad = []
    for s in own_imports(source, module, path.name == "__init__.py"):
        for target in s.targets:
            other = tasks_unit(target)
            if other is None or other == unit:
                continue
            assert other in TASKS_ORDER, f"{rel}:{s.line}: tasks/{other} has no place in TASKS_ORDER"
            if TASKS_ORDER.index(other) > TASKS_ORDER.index(unit):
                bad.append(f"{rel}:{s.line} imports {target} (tasks/{unit} is below tasks/{other}): {s.text}")
    return bad


def lazy_imports(rel: str, source: str) -> tuple[list[ImportSite], list[str]]:
    """The function-level imports of our own modules in one file, and those that do not say why (or say 'cycle')."""
    path = ROOT / rel
    lazy = [s for s in own_imports(source, module_name(path), path.name == "__init__.py") if s.in_function]
    bad = [f"{rel}:{s.line}: {s.text}" + (f"  # {s.reason}" if s.reason else "") for s in lazy
           if not s.reason or BAD_REASON.search(s.reason)]
    return lazy, bad


def all_sources() -> list[Path]:
    """The Python files of every package of OWN."""
    return [p for layer in OWN if (ROOT / layer).is_dir() for p in sources(layer)]


def test_tasks_subpackages_import_downwards() -> None:
    """No module of a tasks/ subpackage imports one above it in TASKS_ORDER (inside functions too), so the subpackages
    form no circle."""
    bad = [v for p in sources("tasks") for v in tasks_order_violations(p.relative_to(ROOT).as_posix(),
                                                                        p.read_text(encoding="utf-8"))]
    assert not bad, "imports up the order of tasks/ (TASKS_ORDER):\n" + "\n".join(bad)


def test_function_level_imports_are_few_and_say_why() -> None:
    """Imports of our own modules are at module level; a function-level one is for start-up time or an optional
    dependency and says so in a comment (never a circle: that is fixed by moving the shared piece down); at most
    LAZY_LIMIT in all."""
    lazy, bad = [], []
    for p in all_sources():
        found, unexplained = lazy_imports(p.relative_to(ROOT).as_posix(), p.read_text(encoding="utf-8"))
        lazy += found
        bad += unexplained
    assert not bad, ("function-level imports of our own modules without a reason (a comment on the line or the line "
                     "above, not a circle):\n" + "\n".join(bad))
    assert len(lazy) <= LAZY_LIMIT, f"{len(lazy)} function-level imports of our own modules (at most {LAZY_LIMIT})"


def test_the_checks_fail_on_bad_source() -> None:
    """The checks above can fail: an import up the tasks/ order, a lazy import with no reason or a circle for one, and
    a count over the limit are each caught, naming the file and line."""
    up = "import numpy\n\ndef f():\n    from tasks.geometry import pipeline  # lazy: pulls trimesh\n"
    assert tasks_order_violations("tasks/mpm/x.py", up) == [
        "tasks/mpm/x.py:4 imports tasks.geometry (tasks/mpm is below tasks/geometry): "
        "from tasks.geometry import pipeline"]
    assert tasks_order_violations("tasks/probes/x.py", "from ..geometry import outputs\n") == []  # downwards: fine
    assert tasks_order_violations("tasks/agents/x.py", "from tasks import probes\n") == [
        "tasks/agents/x.py:1 imports tasks.probes (tasks/agents is below tasks/probes): from tasks import probes"]
    src = ("def f():\n    from cache import store\n\n"
           "def g():\n    # cycle: tasks.x imports this module\n    from tasks.x import y\n\n"
           "def h():\n    import warp\n    from flows.l2_material import run_l2  # lazy: pulls warp\n"
           "    # lazy: pulls rerun\n    from tasks.record import ProbeRecording\n")
    lazy, bad = lazy_imports("flows/x.py", src)
    assert [s.line for s in lazy] == [2, 6, 10, 12]
    assert bad == ["flows/x.py:2: from cache import store",
                   "flows/x.py:6: from tasks.x import y  # cycle: tasks.x imports this module"]
    many = "".join(f"def f{i}():\n    from contracts import base  # lazy: test\n" for i in range(LAZY_LIMIT + 1))
    assert len(lazy_imports("flows/x.py", many)[0]) > LAZY_LIMIT
    assert own_imports("from . import store\n", "cache.files")[0].targets == ("cache.store",)
