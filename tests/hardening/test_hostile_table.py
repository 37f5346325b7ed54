"""Hostile inputs, table-driven: texts, images, meshes, numbers, paths, locations and signals. Each ends in a clear
`error:` line (or the CLI's usage error), a non-zero exit, no traceback, nothing published and nothing cached.

Each row runs the real command in its own process. The default run takes one input of each kind (FAST, each refused
before any layer starts); the whole table and the signal rows are slow-marked:
`pytest -m slow tests/hardening/test_hostile_table.py`.
"""

from __future__ import annotations

import os
import signal
import struct
import subprocess
import sys
import time
import zlib
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest


REPO = Path(__file__).resolve().parents[2]


def _png(path: Path, width: int, height: int, rgb: np.ndarray | None = None) -> Path:
    """A PNG written by hand: a header that says width x height, and (optionally) real pixels."""
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    if rgb is None:
        rgb = np.zeros((1, width, 3), np.uint8)  # a header that lies: one row of pixels for width x height
    raw = b"".join(b"\x00" + row.tobytes() for row in rgb)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
                     + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
    return path


def _file(name: str, data: bytes | str) -> Callable[[Path], str]:
    def make(tmp: Path) -> str:
        p = tmp / name
        p.write_bytes(data if isinstance(data, bytes) else data.encode())
        return str(p)
    return make


def _two_cubes(tmp: Path) -> str:
    import trimesh

    a = trimesh.creation.box((0.05, 0.05, 0.05))
    b = trimesh.creation.box((0.05, 0.05, 0.05))
    b.apply_translation((0.5, 0, 0))
    p = tmp / "two.obj"
    trimesh.util.concatenate([a, b]).export(p)
    return str(p)


def _nan_mesh(tmp: Path) -> str:
    p = tmp / "nan.obj"
    p.write_text("v nan 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n")
    return str(p)


def _flat_mesh(tmp: Path) -> str:
    p = tmp / "flat.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n")
    return str(p)


def _blank(tmp: Path) -> str:
    return str(_png(tmp / "blank.png", 64, 64, np.full((64, 64, 3), 255, np.uint8)))


def _dir(tmp: Path) -> str:
    (tmp / "a_dir.png").mkdir()
    return str(tmp / "a_dir.png")


def _plain_file(tmp: Path) -> str:
    (tmp / "plain").write_text("x")
    return str(tmp / "plain")


def _not_asset_dir(tmp: Path) -> str:
    (tmp / "notes").mkdir()
    (tmp / "notes" / "todo.txt").write_text("mine")
    return str(tmp / "notes")


# (id, command line; a callable makes a path in the test's folder and returns it, "{out}" is the output path)
ROWS: list[tuple[str, list]] = [
    # texts
    ("text_empty", ["generate", ""]),
    ("text_blank", ["generate", "   "]),
    ("text_rigid_steel", ["generate", "a steel wrench"]),
    ("text_rigid_glass", ["generate", "a glass vase"]),
    ("text_too_long", ["generate", "a soft plush turtle " * 2000]),
    ("text_control_chars", ["generate", "a sponge\x07\x1b[2J"]),  # a NUL cannot reach argv at all
    ("text_10_km", ["generate", "a plush turtle, 10 km long"]),
    ("text_5_m", ["generate", "a sponge 5 m long"]),
    ("text_1_mm", ["generate", "a foam cube, 1 mm"]),
    ("text_and_image", ["generate", "a sponge", "--image", _file("x.png", b"")]),
    ("text_and_mesh", ["generate", "a sponge", "--mesh", _file("x.obj", "")]),
    # images
    ("image_missing", ["generate", "--image", "/nonexistent/photo.png"]),
    ("image_is_dir", ["generate", "--image", _dir]),
    ("image_empty_file", ["generate", "--image", _file("empty.png", b"")]),
    ("image_text_file", ["generate", "--image", _file("notes.png", "hello, not a picture")]),
    ("image_truncated", ["generate", "--image", _file("cut.png", b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\x00")]),
    ("image_bomb_header", ["generate", "--image", lambda t: str(_png(t / "bomb.png", 20000, 20000))]),
    ("image_one_pixel", ["generate", "--image", lambda t: str(_png(t / "px.png", 1, 1, np.zeros((1, 1, 3), np.uint8)))]),
    ("image_blank_white", ["generate", "--image", _blank]),
    ("image_wrong_extension", ["generate", "--image", _file("photo.tiffx", b"II*\x00")]),
    # meshes
    ("mesh_missing", ["generate", "--mesh", "/nonexistent/m.obj"]),
    ("mesh_is_dir", ["generate", "--mesh", lambda t: (t / "m.obj").mkdir() or str(t / "m.obj")]),
    ("mesh_unsupported_ext", ["generate", "--mesh", _file("m.xyz", "1 2 3\n")]),
    ("mesh_garbage_stl", ["generate", "--mesh", _file("m.stl", os.urandom(200))]),
    ("mesh_nan_vertex", ["generate", "--mesh", _nan_mesh]),
    ("mesh_flat_sheet", ["generate", "--mesh", _flat_mesh]),
    ("mesh_two_bodies", ["generate", "--mesh", _two_cubes]),
    # numbers
    ("quality_unknown", ["generate", "a sponge", "--quality", "ultra"]),
    ("device_unknown", ["generate", "a sponge", "--device", "tpu"]),
    ("threads_zero", ["generate", "a sponge", "--cpu-threads", "0"]),
    ("threads_huge", ["generate", "a sponge", "--cpu-threads", "100000"]),
    ("size_negative", ["generate", "a sponge", "--size-m", "-1"]),
    ("size_zero", ["generate", "a sponge", "--size-m", "0"]),
    ("size_nan", ["generate", "a sponge", "--size-m", "nan"]),
    ("size_inf", ["generate", "a sponge", "--size-m", "inf"]),
    ("size_huge", ["generate", "a sponge", "--size-m", "100"]),
    ("seed_not_a_number", ["generate", "a sponge", "--seed", "abc"]),
    ("require_l3_without_l3", ["generate", "a sponge", "--require-l3", "--no-l3"]),
    ("llm_fallback_unknown", ["generate", "a sponge", "--llm-fallback", "maybe"]),
    ("material_bad_E", ["material", "{out}", "--E", "-5"]),
    # paths and locations
    ("out_under_proc", ["generate", "a sponge", "--out", "/proc/deformsmith-hostile/x"]),
    ("out_parent_is_file", ["generate", "a sponge", "--out", lambda t: _plain_file(t) + "/x"]),
    ("out_is_file", ["generate", "a sponge", "--out", _plain_file]),
    ("out_not_an_asset", ["generate", "a sponge", "--out", _not_asset_dir]),
    ("cache_under_proc", ["generate", "a sponge", "--cache", "/proc/deformsmith-hostile/cache"]),
    ("cache_is_file", ["generate", "a sponge", "--cache", _plain_file]),
    ("inspect_missing", ["inspect", "/nonexistent/asset"]),
    ("evidence_not_asset", ["evidence", _not_asset_dir]),
    ("physical_not_asset", ["physical", _not_asset_dir]),
    ("manipulate_not_asset", ["manipulate", _not_asset_dir]),
]


def _argv(row: list, tmp: Path) -> list[str]:
    out = []
    for a in row:
        a = a(tmp) if callable(a) else a
        out.append(a.replace("{out}", str(tmp / "asset")) if isinstance(a, str) else a)
    if "--out" not in out and out[0] == "generate":
        out += ["--out", str(tmp / "asset")]
    if "--cache" not in out:
        out += ["--cache", str(tmp / "cache")]
    return out


def test_the_table_holds_at_least_forty_inputs_of_every_kind() -> None:
    ids = [r[0] for r in ROWS]
    assert len(ids) == len(set(ids)) >= 40
    for kind in ("text", "image", "mesh", "size", "out", "cache"):
        assert any(i.startswith(kind) for i in ids), kind


# one input of each kind, each refused before any layer starts (about 1-2 s each): the default run's sample
FAST = ("text_blank", "text_rigid_steel", "text_too_long", "text_10_km", "image_missing", "image_bomb_header",
        "mesh_unsupported_ext", "size_inf", "threads_zero", "seed_not_a_number", "out_under_proc", "cache_is_file")


def _check_refused(row: list, tmp_path: Path) -> None:
    argv = _argv(row, tmp_path)
    before = sorted(p.name for p in tmp_path.iterdir())
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "flows.cli.main", *argv], cwd=REPO, capture_output=True, text=True,
                          timeout=600, env={**os.environ, "PYTHONPATH": str(REPO)})
    took_s = time.perf_counter() - t0
    err = proc.stderr
    assert proc.returncode != 0, err[-2000:]
    assert "Traceback" not in err, err[-3000:]
    lines = [ln for ln in err.splitlines() if ln.strip()]
    usage = "Usage:" in err and ("Invalid value" in err or "No such option" in err or "Error" in err)
    assert (lines and lines[-1].startswith("error: ")) or usage, err[-2000:]
    assert not (tmp_path / "asset").exists(), "an asset was published"
    assert not list((tmp_path / "cache").glob("entries/*")), "a cache entry was written"
    left = sorted(p.name for p in tmp_path.iterdir())
    assert not [n for n in left if n not in before and n != "cache"], left
    assert took_s < 120.0, f"refusing took {took_s:.1f} s"


@pytest.mark.parametrize("row", [r[1] for r in ROWS if r[0] in FAST], ids=[r[0] for r in ROWS if r[0] in FAST])
def test_hostile_input_sample_is_refused_at_once(row: list, tmp_path: Path) -> None:
    _check_refused(row, tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("row", [r[1] for r in ROWS if r[0] not in FAST],
                         ids=[r[0] for r in ROWS if r[0] not in FAST])
def test_hostile_input_is_a_clear_error_and_leaves_nothing(row: list, tmp_path: Path) -> None:
    _check_refused(row, tmp_path)


def _run_and_signal(tmp: Path, sig: int, after_s: float) -> tuple[subprocess.CompletedProcess[str], Path]:
    out, cache = tmp / "asset", tmp / "cache"
    cmd = [sys.executable, "-m", "flows.cli.main", "generate", "a kitchen sponge 10 x 7 x 3 cm", "--no-l3", "--out",
           str(out), "--cache", str(cache)]
    proc = subprocess.Popen(cmd, cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env={**os.environ, "PYTHONPATH": str(REPO)})
    time.sleep(after_s)
    proc.send_signal(sig)
    stdout, stderr = proc.communicate(timeout=300)
    return subprocess.CompletedProcess(cmd, proc.returncode, stdout, stderr), out


@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_a_signal_mid_run_publishes_nothing_and_keeps_the_cache_sound(sig: int, tmp_path: Path) -> None:
    from cache import CacheStore

    done, out = _run_and_signal(tmp_path, sig, after_s=25.0)
    assert done.returncode != 0, done.stderr[-2000:]
    assert "Traceback" not in done.stderr, done.stderr[-3000:]
    assert not out.exists()
    assert not [p.name for p in tmp_path.iterdir() if ".partial-" in p.name]
    if (tmp_path / "cache").exists():
        assert CacheStore(tmp_path / "cache").verify() == []


# -- the layer commands on an existing asset directory: unusable locations refused before the layer runs -------------
def _stub_asset(tmp: Path) -> Path:
    """An asset directory as the layer commands first look at it (geometry.json, physical.json), not a valid one: a
    refusal must come from the location check, before any layer reads it."""
    asset = tmp / "asset"
    asset.mkdir()
    for name in ("geometry.json", "physical.json"):
        (asset / name).write_text("{}\n")
    (asset / "evidence").mkdir()
    (asset / "evidence" / "attempts.jsonl").write_text("")
    (asset / "interaction").mkdir()
    return asset


def _read_only(asset: Path) -> None:
    """Make the folder holding the asset a read-only file system (a tmpfs remounted read-only; skipped without root)."""
    holder = asset.parent / "ro"
    holder.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(holder)], capture_output=True).returncode:
        pytest.skip("cannot mount a tmpfs here")
    import shutil

    shutil.copytree(asset, holder / "asset")
    subprocess.run(["mount", "-o", "remount,ro", str(holder)], check=True)


# (id, argv with "{asset}", the `error:` line must contain; "{asset}" and "{cache}" filled in), env
LAYER_ROWS: list[tuple[str, list[str], str, dict[str, str]]] = [
    ("physical_cache_under_proc", ["physical", "{asset}", "--cache", "/proc/deformsmith-hostile/cache"],
     "cache root: cannot use /proc/deformsmith-hostile/cache", {}),
    ("material_asset_read_only", ["material", "{ro}"], "asset directory: cannot use {ro}: read-only file system", {}),
    ("manipulate_cache_is_file", ["manipulate", "{asset}", "--cache", "{asset}/geometry.json"],
     "cache root: cannot use {asset}/geometry.json", {}),
    ("physical_disk_too_full", ["physical", "{asset}"], "MB needed", {"DEFORMSMITH_MIN_FREE_MB": "1e12"}),
    ("physical_asset_read_only", ["physical", "{ro}"], "asset directory: cannot use {ro}: read-only file system", {}),
    ("manipulate_asset_read_only", ["manipulate", "{ro}"], "asset directory: cannot use {ro}: read-only file system",
     {}),
    ("material_cache_under_proc", ["material", "{asset}", "--cache", "/proc/deformsmith-hostile/cache"],
     "cache root: cannot use /proc/deformsmith-hostile/cache", {}),
    ("material_disk_too_full", ["material", "{asset}"], "MB needed", {"DEFORMSMITH_MIN_FREE_MB": "1e12"}),
    ("manipulate_cache_under_proc", ["manipulate", "{asset}", "--cache", "/proc/deformsmith-hostile/cache"],
     "cache root: cannot use /proc/deformsmith-hostile/cache", {}),
    ("probe_cache_under_proc", ["probe", "compress", "--asset", "{asset}"],
     "cache root: cannot use /proc/deformsmith-hostile/cache", {"DEFORMSMITH_CACHE": "/proc/deformsmith-hostile/cache"}),
    ("replay_video_under_proc", ["replay", "{asset}", "--video", "/proc/deformsmith-hostile/replay.mp4"],
     "output: cannot use /proc/deformsmith-hostile", {}),
    ("replay_frames_is_file", ["replay", "{asset}", "--frames", "{asset}/geometry.json"],
     "output: {asset}/geometry.json is a file, not a directory", {}),
]
LAYER_FAST = ("physical_cache_under_proc", "material_asset_read_only", "manipulate_cache_is_file",
              "physical_disk_too_full")


def _check_layer_refused(row: tuple[str, list[str], str, dict[str, str]], tmp_path: Path) -> None:
    from test_layer_publish import tree_digest

    _, argv, want, env = row
    asset = _stub_asset(tmp_path)
    ro = tmp_path / "ro" / "asset"
    if any("{ro}" in a for a in argv):
        _read_only(asset)
    try:
        fill = {"{asset}": str(asset), "{ro}": str(ro), "{cache}": str(tmp_path / "cache")}

        def filled(text: str) -> str:
            for k, v in fill.items():
                text = text.replace(k, v)
            return text

        argv = [filled(a) for a in argv]
        target = ro if any(str(ro) in a for a in argv) else asset
        before = tree_digest(target)
        run_env = {**os.environ, "PYTHONPATH": str(REPO), "DEFORMSMITH_CACHE": str(tmp_path / "cache"), **env}
        proc = subprocess.run([sys.executable, "-m", "flows.cli.main", *argv], cwd=REPO, capture_output=True,
                              text=True, timeout=300, env=run_env)
        assert proc.returncode == 2, proc.stderr[-3000:]
        assert "Traceback" not in proc.stderr, proc.stderr[-3000:]
        lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
        assert len(lines) == 1 and lines[0].startswith("error: ") and filled(want) in lines[0], proc.stderr[-3000:]
        assert tree_digest(target) == before
        assert not [p.name for p in target.parent.iterdir() if ".partial-" in p.name]
        assert not list((tmp_path / "cache").glob("entries/*")), "a cache entry was written"
    finally:
        if ro.exists():
            subprocess.run(["umount", "-l", str(ro.parent)], capture_output=True)


@pytest.mark.parametrize("row", [r for r in LAYER_ROWS if r[0] in LAYER_FAST],
                         ids=[r[0] for r in LAYER_ROWS if r[0] in LAYER_FAST])
def test_a_layer_command_refuses_an_unusable_location_at_once(row: tuple[str, list[str], str, dict[str, str]],
                                                              tmp_path: Path) -> None:
    _check_layer_refused(row, tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("row", [r for r in LAYER_ROWS if r[0] not in LAYER_FAST],
                         ids=[r[0] for r in LAYER_ROWS if r[0] not in LAYER_FAST])
def test_a_layer_command_refuses_every_unusable_location(row: tuple[str, list[str], str, dict[str, str]],
                                                         tmp_path: Path) -> None:
    _check_layer_refused(row, tmp_path)
