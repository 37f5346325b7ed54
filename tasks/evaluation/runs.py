"""An evaluation on disk: its options, where each arm's record of each case lives (``records/<ablation>/<arm>/
<case>.json``, written atomically), which arms a case takes part in and whether a case is done (resume)."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

from contracts.evaluation import ARMS, ArmResult, Condition, SuiteCase

ALL = ("hierarchy", "harness", "manipulation")


@dataclass(frozen=True)
class EvalOptions:
    """How an evaluation runs."""

    suite: str = "default"
    ablations: tuple[str, ...] = ALL
    limit: int | None = None
    case_ids: tuple[str, ...] = ()
    quality: str = "draft"
    device: str = "cpu"
    workers: int = 1
    out: Path = Path("out/eval")
    llm: str | None = None
    videos: bool = True
    vision_llm: str | None = None  # rates our assets' drop videos; None: the --llm model, if any
    conditions: tuple[Condition, ...] = field(default_factory=tuple)


def record_path(out: Path, ablation: str, arm: str, case_id: str) -> Path:
    """Where one arm's record of one case lives."""
    return Path(out) / "records" / ablation / arm / f"{case_id}.json"


def write_record(out: Path, r: ArmResult) -> Path:
    """Atomic write of a record."""
    path = record_path(out, r.ablation, r.arm, r.case_id)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(r.model_dump_json(indent=2) + "\n", encoding="utf-8")
    tmp.replace(path)
    return path


def load_records(out: Path) -> list[ArmResult]:
    """Every record under OUT/records."""
    root = Path(out) / "records"
    return [ArmResult.model_validate_json(p.read_text(encoding="utf-8")) for p in sorted(root.rglob("*.json"))]


def needed_arms(case: SuiteCase, ablations: tuple[str, ...]) -> list[tuple[str, str]]:
    """(ablation, arm) pairs this case takes part in."""
    return [(a, arm) for a in ablations for arm in ARMS[a] if a != "manipulation" or case.manipulation]


def case_done(out: Path, case: SuiteCase, ablations: tuple[str, ...]) -> bool:
    """Every record the case needs exists (a resumed evaluation skips it)."""
    return all(record_path(out, a, arm, case.id).is_file() for a, arm in needed_arms(case, ablations))


def not_built(case: SuiteCase, needed: list[tuple[str, str]], why: str, wall_s: float) -> list[ArmResult]:
    """Every needed arm's record of a case whose asset could not be built (L0's gates failed): a hard failure."""
    return [ArmResult(ablation=ablation, arm=arm, case_id=case.id, case_kind=case.kind, delivered=False,
                      hard_failure=True, failure_kinds=[why], error=why, wall_s=wall_s) for ablation, arm in needed]
