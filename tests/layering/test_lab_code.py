"""Lab code has one home, benchmarks/: no module of the product packages is a benchmark, profile or experiment by its
name, and none of them imports benchmarks (the CLI included: the lab's drivers run as `python -m benchmarks.<name>`).

A pure scan of file names and import statements (test_layers.imports); nothing under test is imported.
"""

from __future__ import annotations

import re

import pytest

from tests.layering.test_layers import ROOT, file_imports, sources

PRODUCT = ("contracts", "cache", "tasks", "flows")
# a module (or package) whose name says it is lab code: bench, benchmark(s), suite_bench, profile(r), profiling,
# experiment(s), gpu_profile, ... as a whole word of its snake_case name
LAB_NAME = re.compile(r"(^|_)(bench|benchmarks?|profil(e|er|es|ing)|experiments?)(_|$)")


def lab_named(path_parts: tuple[str, ...]) -> bool:
    """Whether a module path (package folders and the file's stem) names lab code anywhere along it."""
    return any(LAB_NAME.search(part) for part in path_parts)


@pytest.mark.parametrize("package", PRODUCT)
def test_no_lab_modules_in_the_product(package: str) -> None:
    """No file or folder under contracts/, cache/, tasks/, flows/ is named as a benchmark, profile or experiment."""
    found = [p.relative_to(ROOT).as_posix() for p in sources(package)
             if lab_named(p.relative_to(ROOT).with_suffix("").parts)]
    assert not found, "lab code belongs in benchmarks/:\n" + "\n".join(found)


@pytest.mark.parametrize("package", PRODUCT)
def test_the_product_does_not_import_the_lab(package: str) -> None:
    """No module under the product packages imports benchmarks, at module level or inside a function."""
    bad = [f"{p.relative_to(ROOT).as_posix()}:{line} imports {name}" for p in sources(package)
           for name, line, _ in file_imports(p) if name.split(".")[0] == "benchmarks"]
    assert not bad, "the product imports the lab:\n" + "\n".join(bad)


def test_the_name_check_sees_lab_names() -> None:
    """The pattern catches the lab names that lived in the packages and leaves product names alone."""
    for parts in (("tasks", "mpm", "bench"), ("cache", "bench"), ("tasks", "geometry", "suite_bench"),
                  ("tasks", "render", "gpu_profile"), ("flows", "experiments", "x"), ("tasks", "profiler")):
        assert lab_named(parts), parts
    for parts in (("tasks", "mpm", "scene"), ("tasks", "manipulation", "trial"), ("tasks", "record", "trials"),
                  ("contracts", "stage"), ("tasks", "geometry", "concepts"), ("tasks", "mpm", "benchmarked_scene")):
        assert not lab_named(parts), parts
