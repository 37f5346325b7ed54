"""Decompression bombs: an image whose header declares too many pixels is refused before it is decoded."""

from __future__ import annotations

import json
import struct
import subprocess
import sys
import zlib
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from contracts.errors import InputError
from tasks.geometry import image, image_guard

REPO = Path(__file__).resolve().parents[2]


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def write_bomb(path: Path, width: int = 20000, height: int = 20000) -> Path:
    """A valid 1-bit greyscale PNG of width x height px, all black, a few tens of kB on disk (400 MP decoded)."""
    row = b"\x00" * (1 + (width + 7) // 8)  # filter byte + packed bits
    comp = zlib.compressobj(9)
    idat = b"".join(comp.compress(row) for _ in range(height)) + comp.flush()
    ihdr = struct.pack(">IIBBBBB", width, height, 1, 0, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + _chunk(b"IHDR", ihdr) + _chunk(b"IDAT", idat) + _chunk(b"IEND", b""))
    return path


_PROBE = """
import json, resource, sys, time
from pathlib import Path
from contracts.errors import InputError
from tasks.geometry import image
import PIL.Image  # imported by the first check anyway; not part of the check's time
t, cpu = time.perf_counter(), time.process_time()
try:
    image.load_image(Path(sys.argv[1]))
    err = None
except InputError as exc:
    err = str(exc)
# VmHWM: this process image's peak (getrusage's ru_maxrss keeps the forking parent's peak across exec: 1.4 GB
# when pytest's process had grown that large in the full suite)
hwm_kb = next(int(ln.split()[1]) for ln in Path("/proc/self/status").read_text().splitlines() if ln.startswith("VmHWM"))
print(json.dumps({"s": time.perf_counter() - t, "cpu_s": time.process_time() - cpu, "err": err,
                  "rss_mb": hwm_kb / 1024}))
"""


def test_bomb_is_refused_from_its_header_fast_and_small(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    bomb = write_bomb(tmp_path / "bomb.png")
    assert bomb.stat().st_size < 200_000
    monkeypatch.setattr(Image, "MAX_IMAGE_PIXELS", None)
    with Image.open(bomb) as im:  # a real PNG: another tool reads its header (and could decode it)
        assert im.size == (20000, 20000) and im.mode == "1"
    out = subprocess.run([sys.executable, "-c", _PROBE, str(bomb)], cwd=REPO, capture_output=True, text=True,
                         timeout=120, check=True)
    res = json.loads(out.stdout.strip().splitlines()[-1])
    assert res["err"] is not None and "20000 x 20000 px" in res["err"] and "40 MP allowed" in res["err"]
    assert "\n" not in res["err"]
    assert res["cpu_s"] < 1.0 and res["s"] < 5.0, res  # ~0.01 s on an idle machine; wall time spread for busy CI
    assert res["rss_mb"] < 300, res  # peak of the whole process (numpy, OpenCV, SciPy imported); decoding = 1.2 GB+


def test_limit_is_configurable_and_normal_images_pass(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "small.png"
    Image.fromarray(np.full((300, 400, 3), 90, np.uint8)).save(path)
    assert image.load_image(path).shape == (300, 400, 3)
    monkeypatch.setenv(image_guard.ENV_VAR, "100000")
    with pytest.raises(InputError, match=r"400 x 300 px .* more than the 0\.1 MP allowed"):
        image.load_image(path)
    assert Image.MAX_IMAGE_PIXELS == 100000  # Pillow's own guard agrees
    monkeypatch.setenv(image_guard.ENV_VAR, "lots")
    with pytest.raises(InputError, match="not a number of pixels"):
        image.load_image(path)
    monkeypatch.delenv(image_guard.ENV_VAR)
    assert image_guard.check_image_size(path) == (400, 300)
    assert Image.MAX_IMAGE_PIXELS == image_guard.MAX_IMAGE_PIXELS_DEFAULT


def test_bomb_through_the_cli_is_one_error_line(tmp_path: Path, cli_env: dict[str, str]) -> None:
    bomb = write_bomb(tmp_path / "bomb.png")
    out_dir = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "flows.cli.main", "geometry", "--image", str(bomb),
                           "--out", str(out_dir)], cwd=REPO, capture_output=True, text=True, timeout=300,
                          env=cli_env)  # the session's Prefect server: the command starts none of its own
    assert proc.returncode == 2, proc.stderr[-2000:]
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert lines == [ln for ln in lines if ln.startswith("error:")] and len(lines) == 1, proc.stderr[-2000:]
    assert "MP allowed" in lines[0]
    assert not out_dir.exists()


def test_a_file_without_an_image_header_is_refused_before_any_decoder(tmp_path: Path) -> None:
    fake = tmp_path / "photo.png"
    fake.write_bytes(b"\x00" * 4096)
    with pytest.raises(InputError, match="cannot read image photo.png: not a valid PNG/JPEG"):
        image_guard.check_image_size(fake)
    jpeg = tmp_path / "photo.jpg"
    Image.fromarray(np.full((64, 48, 3), 200, np.uint8)).save(jpeg, quality=90)
    assert image_guard.check_image_size(jpeg) == (48, 64)
