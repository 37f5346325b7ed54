"""The suite format: the packaged suite validates, drawings are deterministic, bad suites fail clearly."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from contracts.errors import InputError
from tasks.evaluation.suite import draw, image_file, load_suite, select, to_request


def test_default_suite_counts_and_intents() -> None:
    suite, path = load_suite("default")
    kinds = [c.kind for c in suite.cases]
    assert kinds.count("text") == 30 and kinds.count("image") == 9 and kinds.count("mesh") >= 5
    assert sum(c.manipulation for c in suite.cases) == 6
    assert len(suite.manipulation_conditions) == 5
    assert all(c.intent and c.expected_material for c in suite.cases)


def test_manipulation_suite_is_the_plush_set_and_two_rubber_objects() -> None:
    """Ablation C of issue 36: every toy of the developers' plush set and at least two stiff rubber objects."""
    from tests.l3.test_plush_set import PLUSH_SET

    suite, _ = load_suite("manipulation")
    assert all(c.manipulation and c.kind == "text" for c in suite.cases)
    assert {c.text for c in suite.cases if c.expected_material == "plush"} == set(PLUSH_SET)
    assert sum(c.expected_material == "rubber" for c in suite.cases) >= 2
    assert len(suite.manipulation_conditions) == 5


def test_text_cases_build_from_the_catalogue() -> None:
    from tasks.geometry.catalogue import design_from_text

    suite, _ = load_suite("default")
    for c in suite.cases:
        if c.kind == "text":
            assert design_from_text(c.text).match_score > 0, c.id  # a catalogue keyword, no fuzzy fallback


def test_drawings_are_deterministic(tmp_path: Path) -> None:
    suite, path = load_suite("default")
    case = next(c for c in suite.cases if c.kind == "image")
    a, b = draw(case.drawing), draw(case.drawing)
    assert a.shape == (256, 256, 3) and np.array_equal(a, b)
    p1 = image_file(case, path.parent, tmp_path)
    assert p1.read_bytes() == image_file(case, path.parent, tmp_path / "again").read_bytes()
    req = to_request(case, path.parent, tmp_path)
    assert req.input_kind == "image" and req.material_intent == case.intent and req.size_hint_m == case.size_m


def test_mesh_cases_resolve_in_pybullet_data(tmp_path: Path) -> None:
    suite, path = load_suite("default")
    for c in suite.cases:
        if c.kind == "mesh":
            assert to_request(c, path.parent, tmp_path).mesh_path.is_file()


def test_select_limit_ids_and_manipulation() -> None:
    suite, _ = load_suite("default")
    assert [c.id for c in select(suite, 2)] == [c.id for c in suite.cases[:2]]
    assert all(c.manipulation for c in select(suite, manipulation=True))
    with pytest.raises(InputError, match="unknown case ids"):
        select(suite, ids=["nope"])


def _write(tmp_path: Path, data: dict) -> str:
    p = tmp_path / "s.json"
    p.write_text(json.dumps(data))
    return str(p)


def test_bad_suites_fail_with_the_field(tmp_path: Path) -> None:
    case = {"id": "a", "kind": "text", "text": "a foam cube 5 cm", "intent": "foam"}
    with pytest.raises(InputError, match="case ids repeat"):
        load_suite(_write(tmp_path, {"name": "x", "cases": [case, case]}))
    with pytest.raises(InputError, match="names 'pu_foam', not 'rubber'"):
        load_suite(_write(tmp_path, {"name": "x", "cases": [{**case, "expected_material": "rubber"}]}))
    with pytest.raises(InputError, match="cases.0.intent"):
        load_suite(_write(tmp_path, {"name": "x", "cases": [{**case, "intent": ""}]}))
    with pytest.raises(InputError, match="file not found"):
        load_suite(_write(tmp_path, {"name": "x", "cases": [{"id": "m", "kind": "mesh", "mesh": "no.obj",
                                                              "intent": "foam"}]}))
    with pytest.raises(InputError, match="not found"):
        load_suite(str(tmp_path / "missing-suite"))


def test_jsonl_suite(tmp_path: Path) -> None:
    p = tmp_path / "mine.jsonl"
    p.write_text('{"id": "c1", "kind": "text", "text": "a sponge 10 cm", "intent": "sponge"}\n')
    suite, _ = load_suite(str(p))
    assert suite.name == "mine" and suite.cases[0].id == "c1"
