"""Held-out prompts (tests/geometry/heldout_prompts.yaml, written before the lexicon grew past ~100 entries):
>= 90 % become the concept they name, and >= 90 % weigh within 2x of the real object's sourced mass."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from contracts.request import AssetRequest
from helpers import settings
from tasks.geometry import pipeline, sources
from tasks.geometry.concepts import read_text
from tests.geometry.test_mass_classes import planned_mass

PROMPTS = yaml.safe_load((Path(__file__).parent / "heldout_prompts.yaml").read_text(encoding="utf-8"))["prompts"]


def test_heldout_prompts_are_many_and_sourced() -> None:
    assert len(PROMPTS) >= 40 and all(p["mass_kg"] > 0 and len(p["source"]) > 15 for p in PROMPTS)


def test_heldout_prompts_give_their_concept() -> None:
    got = {p["text"]: read_text(p["text"]).entry.key for p in PROMPTS}  # parsing only (fast)
    misses = [(p["text"], got[p["text"]], p["concept"]) for p in PROMPTS if got[p["text"]] != p["concept"]]
    assert len(misses) <= 0.1 * len(PROMPTS), misses


@pytest.mark.slow
def test_heldout_prompts_weigh_within_2x() -> None:
    """Through L0 (draft mesh) and the concept's mass estimate (volume or shell x density)."""
    s = settings("draft")
    off = []
    for p in PROMPTS:
        mesh, info = sources.build_mesh(AssetRequest(text=p["text"]), s)
        m = pipeline.arrays_to_mesh(mesh)
        kg = info.concept.mass_estimate_kg(m.volume, m.area)
        if kg is None:  # a shape word's own form ('a heart-shaped pillow'): L1 weighs it by its material's prior
            kg = planned_mass(p["text"])
        ratio = kg / p["mass_kg"]
        if not 0.5 <= ratio <= 2.0:
            off.append((p["text"], round(ratio, 2)))
    assert len(off) <= 0.1 * len(PROMPTS), off


def test_suite_files_are_read_and_bad_ones_refused(tmp_path: Path) -> None:
    """`python -m benchmarks.geometry_bench --suite` reads the held-out file and an evaluation suite's text cases; bad files fail clearly."""
    from contracts.errors import InputError
    from benchmarks.geometry_bench import contact_sheet, load_prompts, summary

    assert len(load_prompts(Path(__file__).parent / "heldout_prompts.yaml")) == len(PROMPTS)
    suite = Path(__file__).parents[2] / "contracts" / "suites" / "default.yaml"
    assert len(load_prompts(suite)) == 30
    (tmp_path / "bad.yaml").write_text("prompts: [{text: ''}]", encoding="utf-8")
    with pytest.raises(InputError, match="have no text"):
        load_prompts(tmp_path / "bad.yaml")
    with pytest.raises(InputError, match="not found"):
        load_prompts(tmp_path / "missing.yaml")
    rows = [{"concept_ok": True, "mass_ratio": 1.5, "gates_passed": True, "seconds": 3.0, "cpu_seconds": 2.0},
            {"concept_ok": False, "mass_ratio": 2.5, "gates_passed": True, "seconds": 5.0, "cpu_seconds": 4.0}]
    s = summary(rows)
    assert s["concept_ok_fraction"] == 0.5 and s["mass_within_2x_fraction"] == 0.5 and s["max_cpu_seconds"] == 4.0
    import numpy as np

    sheet = contact_sheet([np.zeros((10, 12, 3), np.uint8)] * 7, ["a"] * 7, columns=3)
    assert sheet.shape == (3 * (10 + 34), 36, 3)
