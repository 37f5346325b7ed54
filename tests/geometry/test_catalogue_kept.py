"""The catalogue's parse is kept beside its files under a hash of their bytes: read back whole, re-parsed when a
file changes, and never half-written."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from tasks.geometry import catalogue_programs as cp


@pytest.fixture
def shapes_copy(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """The catalogue and two shapes files in a temporary folder, the module pointed at them."""
    shapes = tmp_path / "shapes"
    shapes.mkdir()
    for name in sorted(p.name for p in cp.SHAPES_DIR.glob("*.yaml"))[:2]:
        shutil.copy(cp.SHAPES_DIR / name, shapes / name)
    shutil.copy(cp.CATALOGUE_FILE, tmp_path / "catalogue.yaml")
    monkeypatch.setattr(cp, "SHAPES_DIR", shapes)
    monkeypatch.setattr(cp, "CATALOGUE_FILE", tmp_path / "catalogue.yaml")
    cp.catalogue_yaml.cache_clear()
    yield shapes
    cp.catalogue_yaml.cache_clear()


def test_the_parse_is_kept_read_back_and_renewed_when_a_file_changes(shapes_copy: Path) -> None:
    first = cp.catalogue_yaml()
    kept = list((shapes_copy / "__pycache__").glob("catalogue-*.pickle"))
    assert len(kept) == 1 and not list((shapes_copy / "__pycache__").glob(".catalogue-*"))  # whole, no temp left
    cp.catalogue_yaml.cache_clear()
    assert cp.catalogue_yaml() == first  # read back: the same data
    some = sorted(shapes_copy.glob("*.yaml"))[0]
    text = some.read_text(encoding="utf-8")
    key = next(iter(cp.load_yaml(text)["entries"]))
    some.write_text(text.replace("entries:", "entries:\n  kept_test_entry: {category: test, parts: []}", 1),
                    encoding="utf-8")
    cp.catalogue_yaml.cache_clear()
    renewed = cp.catalogue_yaml()
    assert "kept_test_entry" in renewed["entries"] and key in renewed["entries"]
    now = list((shapes_copy / "__pycache__").glob("catalogue-*.pickle"))
    assert len(now) == 1 and now != kept  # the stale parse removed


def test_a_broken_kept_parse_is_parsed_again(shapes_copy: Path) -> None:
    first = cp.catalogue_yaml()
    kept = next((shapes_copy / "__pycache__").glob("catalogue-*.pickle"))
    kept.write_bytes(kept.read_bytes()[:100])  # cut short
    cp.catalogue_yaml.cache_clear()
    assert cp.catalogue_yaml() == first
