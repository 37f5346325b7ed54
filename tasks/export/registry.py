"""Export targets by name: the module that writes each one and the package it needs (an optional extra)."""

from __future__ import annotations

import importlib
import importlib.util
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from contracts.errors import InputError

if TYPE_CHECKING:
    from contracts.export import TargetManifest
    from tasks.export.inputs import ExportInputs

INSTALL_HINT = 'pip install -e ".[export]"'
MESHER = "igl"  # every target needs the tet mesh (isosurface stuffing on libigl's signed distance)


@dataclass(frozen=True)
class Target:
    """One export target: `module.export(inputs, out_dir) -> TargetManifest`; `package` must be importable to run."""

    name: str
    module: str
    package: str | None  # import name of the package the export needs (None: none beyond the core)


TARGETS: dict[str, Target] = {t.name: t for t in (
    Target("mujoco", "tasks.export.mujoco", "mujoco"),
    Target("genesis", "tasks.export.genesis", None),  # writes a scene file; genesis-world is needed only to load it
    Target("usd", "tasks.export.usd", "pxr"),
    Target("drake", "tasks.export.drake", None),      # SDFormat + VTK text; pydrake is needed only to load it
    Target("sofa", "tasks.export.sofa", None),        # a Python scene file; SofaPython3 is needed only to run it
)}


def target_names() -> list[str]:
    """Every registered target, in order."""
    return list(TARGETS)


def resolve_targets(to: str) -> list[str]:
    """`--to` value -> target names (`all`, one name or a comma list); InputError on an unknown name."""
    names = target_names() if to.strip() == "all" else [n.strip() for n in to.split(",") if n.strip()]
    unknown = [n for n in names if n not in TARGETS]
    if unknown or not names:
        raise InputError(f"unknown export target {', '.join(unknown) or repr(to)}; choose from "
                         f"{', '.join(target_names())} or all")
    return names


def exporter(name: str) -> Callable[[ExportInputs, Path], TargetManifest]:
    """The export function of a target (InputError naming the extra when its package is missing)."""
    target = TARGETS[name]
    for package in (MESHER, target.package):
        if package and importlib.util.find_spec(package) is None:
            raise InputError(f"export to {name} needs the {package} package: {INSTALL_HINT}")
    try:
        module = importlib.import_module(target.module)
    except ModuleNotFoundError as exc:
        if exc.name and exc.name.startswith("tasks."):
            raise InputError(f"export target {name} is not available in this version ({exc.name} missing)") from None
        raise InputError(f"export to {name} needs the {exc.name} package: {INSTALL_HINT}") from None
    return module.export
