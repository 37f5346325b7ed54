"""The engine reads no environment variable: its switches are SimConfig.kernel (contracts.sim.KernelOptions), so cache
keys and records name the kernel variant that made a result."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from contracts.sim import KernelOptions, SimConfig

ENGINE = Path(__file__).resolve().parents[2] / "tasks" / "mpm"


def environment_reads(source: str) -> list[int]:
    """Line numbers of `os.environ`, `os.getenv`, `os.putenv`, `environ...` or `getenv(...)` in a module's source
    (imports of them included)."""
    lines = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Attribute) and node.attr in ("environ", "environb", "getenv", "getenvb", "putenv"):
            lines.append(node.lineno)
        elif isinstance(node, ast.Name) and node.id in ("environ", "environb", "getenv", "getenvb", "putenv"):
            lines.append(node.lineno)
        elif isinstance(node, ast.ImportFrom) and node.module == "os" and any(
                a.name in ("environ", "environb", "getenv", "getenvb", "putenv") for a in node.names):
            lines.append(node.lineno)
    return lines


def test_the_scan_finds_every_form_of_environment_read() -> None:
    for src in ("import os\nx = os.environ.get('A')", "import os\nx = os.getenv('A', '1')",
                "from os import environ\nx = environ['A']", "import os\nx = os.environ['A']"):
        assert environment_reads(src), src
    assert not environment_reads("import os\nx = os.cpu_count()\nenv = {}\ny = env.get('a')")


def test_no_environment_variable_is_read_under_tasks_mpm() -> None:
    files = sorted(ENGINE.rglob("*.py"))
    assert len(files) > 10
    found = {str(p.relative_to(ENGINE)): environment_reads(p.read_text(encoding="utf-8")) for p in files}
    assert not {k: v for k, v in found.items() if v}


def test_kernel_options_enter_the_cache_key_only_when_not_the_defaults() -> None:
    """Defaults are left out of the canonical JSON (the keys of results from before the options existed); any other
    value is in it and comes back from the dump."""
    assert "kernel" not in SimConfig().canonical_json()
    assert "kernel" not in SimConfig(kernel=KernelOptions()).canonical_json()
    other = SimConfig(kernel=KernelOptions(scatter="warp", cpu_fuse=False))
    assert '"scatter":"warp"' in other.canonical_json() and other.canonical_json() != SimConfig().canonical_json()
    assert SimConfig.model_validate_json(other.model_dump_json()) == other
    assert KernelOptions.from_assignments(["scatter=warp", "cpu_fuse=false", "p2g_parts=3"]) == KernelOptions(
        scatter="warp", cpu_fuse=False, p2g_parts=3)
    with pytest.raises(ValueError):
        KernelOptions.from_assignments(["p2g_parts=4"])
    with pytest.raises(ValueError):
        KernelOptions.from_assignments(["no_such_option=1"])
