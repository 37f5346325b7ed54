"""The pick-and-place video is made once per content: a warm rerun copies it from the cache (cache.files)."""

from __future__ import annotations

from pathlib import Path

from cache import content_key
from cache.files import cached_file, source_digest


def test_a_file_is_made_once_then_copied_and_a_code_edit_makes_a_new_key(tmp_path: Path) -> None:
    code = tmp_path / "renderer.py"
    code.write_text("FPS = 30\n")
    data = tmp_path / "attempt_000"
    data.mkdir()
    (data / "x").write_bytes(b"\x00" * 64)
    made: list[Path] = []

    def make(path: Path) -> None:
        made.append(path)
        path.write_bytes(b"video bytes")

    key = content_key("video", source_digest([code], ("numpy",)), data)
    assert cached_file(key, tmp_path / "a" / "v.mp4", make) is False
    assert cached_file(key, tmp_path / "b" / "v.mp4", make) is True
    assert made == [tmp_path / "a" / "v.mp4"] and (tmp_path / "b" / "v.mp4").read_bytes() == b"video bytes"
    code.write_text("FPS = 60\n")
    assert content_key("video", source_digest([code], ("numpy",)), data) != key
    (data / "x").write_bytes(b"\x01" * 64)
    assert content_key("video", source_digest([tmp_path / "renderer.py"], ("numpy",)), data) != key
