"""Reading the attempt records back: evidence/attempts.jsonl (written by tasks.agents.records.AttemptRecorder) into
the models, and finding those files under an asset or run directory."""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

from contracts.errors import InputError
from contracts.evidence import Attempt

ATTEMPTS_FILE = "evidence/attempts.jsonl"


def _nan_metrics(record: dict) -> dict:
    """JSON writes a NaN metric (e.g. a hold force never measured because the object slipped) as null: read it back
    as NaN, so a resumed harness can reload every attempt it wrote."""
    ev = record.get("evidence") if isinstance(record, dict) else None
    if isinstance(ev, dict) and isinstance(ev.get("metrics"), dict):
        ev["metrics"] = {k: (math.nan if v is None else v) for k, v in ev["metrics"].items()}
    return record


def read_attempts(path: str | os.PathLike[str]) -> list[Attempt]:
    """Reload attempts from a JSONL file into the models (InputError names the bad line)."""
    out = []
    p = Path(path)
    for n, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1):
        if not line.strip():
            continue
        try:
            out.append(Attempt.model_validate(_nan_metrics(json.loads(line))))
        except (ValueError, TypeError) as exc:
            raise InputError(f"{p}:{n}: not a valid attempt record: {str(exc).splitlines()[0]}") from exc
    return out


def find_attempt_files(path: str | os.PathLike[str]) -> list[Path]:
    """attempts.jsonl files for an asset dir, a run dir (searched recursively) or the file itself."""
    p = Path(path)
    if p.is_file():
        return [p]
    if not p.is_dir():
        raise InputError(f"{p}: no such file or directory")
    direct = p / ATTEMPTS_FILE
    if direct.is_file():
        return [direct]
    return sorted(p.rglob("attempts.jsonl"))
