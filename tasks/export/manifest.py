"""The export root's manifest.json (contracts.export.ExportManifest): every target exported so far with its files,
and a target's calibration once `crosscheck` fitted it."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from pydantic import ValidationError

from contracts.export import ExportManifest
from tasks.publish import write_text_atomic

MANIFEST = "manifest.json"
TETMESH_DIR = "tetmesh"


def read_manifest(out_root: Path) -> ExportManifest | None:
    """The manifest an earlier export left (None when absent or unreadable: it is then rewritten)."""
    try:
        return ExportManifest.model_validate_json((out_root / MANIFEST).read_text(encoding="utf-8"))
    except (OSError, ValidationError):
        return None


def record_calibration(out_root: Path, sim: str, calibrated: dict[str, Any]) -> None:
    """manifest.json: the simulator's TargetManifest.calibrated, its files added to the target's (left alone when
    there is no manifest or it has no such target)."""
    manifest = read_manifest(out_root)
    if manifest is not None and sim in manifest.targets:
        t = manifest.targets[sim]
        files = list(dict.fromkeys([*t.files, *calibrated.get("files", [])]))
        manifest.targets[sim] = t.model_copy(update={"calibrated": calibrated, "files": files})
        write_text_atomic(out_root / MANIFEST, manifest.model_dump_json(indent=2) + "\n")
