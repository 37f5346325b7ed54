"""Reconstruction backends: a Python entry point and an HTTP endpoint make the mesh; L0 sizes, aligns and gates it."""

from __future__ import annotations

import base64
import json
import os
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import numpy as np
import pytest
import trimesh
from helpers import run, settings

from contracts.request import AssetRequest
from tasks.geometry import pipeline, sources
from tasks.geometry.backends import GeometryBackendError, call_http
from tests.geometry import fake_backend

REPO = Path(__file__).resolve().parents[2]
FAKE = "tests.geometry.fake_backend"


def _mesh(arrays: dict) -> trimesh.Trimesh:
    return pipeline.arrays_to_mesh(arrays)


def test_entry_point_mesh_is_canonicalised_sized_and_passes_the_gates() -> None:
    """A normalised y-long blob from the backend comes out x-long, resting on z = 0, at the stated 10 cm length."""
    fake_backend.CALLS.clear()
    req = AssetRequest(text="a squishy ball 10 cm long", seed=7, geometry_backend=f"{FAKE}:icosphere")
    mesh, info, _, particles, gaussians, checks = run(req, settings(method="hull"))
    m = _mesh(mesh)
    assert checks.passed, checks.failed
    np.testing.assert_allclose(m.extents, [0.1, 0.05, 0.05], rtol=0.03)  # 2:1:1, longest on x
    assert m.bounds[0][2] == pytest.approx(0.0, abs=1e-9) and m.is_watertight
    assert np.abs(m.bounds.mean(axis=0)[:2]).max() < 1e-9  # centred in x, y
    assert info.generator == f"backend:{FAKE}:icosphere" and info.source == "text"
    assert particles["volumes_m3"].sum() == pytest.approx(m.volume, rel=1e-6)
    call = fake_backend.CALLS[-1]
    assert call["text"] == "a squishy ball 10 cm long" and call["seed"] == 7 and call["image_path"] is None
    assert Path(call["out_dir"]).name.startswith("deformsmith-backend-") and not Path(call["out_dir"]).exists()


def test_metric_mesh_keeps_its_size_and_gaussians_colour_an_uncoloured_mesh() -> None:
    s = settings(method="hull")
    box, info = sources.build_mesh(AssetRequest(text="a foam block", geometry_backend=f"{FAKE}:metric_box"), s)
    np.testing.assert_allclose(_mesh(box).extents, [0.12, 0.08, 0.05], rtol=0.02)
    assert any("in metres" in n for n in info.notes)

    bean, info = sources.build_mesh(AssetRequest(text="a jelly bean", size_hint_m=0.05,
                                                  geometry_backend=f"{FAKE}:red_bean_file"), s)
    m = _mesh(bean)
    np.testing.assert_allclose(m.extents, [0.05, 0.02, 0.02], rtol=0.03)  # the hint wins; capsule 1.0 x 0.4 x 0.4
    rgb = np.asarray(m.visual.vertex_colors)[:, :3].astype(float).mean(axis=0)
    assert rgb[0] > 200 and rgb[1] < 60 and rgb[2] < 60  # red from the Gaussians, the PLY itself carries no colour
    assert any("coloured from the backend's 2000 Gaussians" in n for n in info.notes)


@pytest.mark.parametrize("spec, message", [
    ("no_such_backend_module:make", "cannot import 'no_such_backend_module': ModuleNotFoundError"),
    (f"{FAKE}:missing", "has no function 'missing'"),
    (f"{FAKE}:broken", "failed: RuntimeError: checkpoint not found"),
    (f"{FAKE}:not_a_mesh", "returned no usable mesh: mesh file not found: CUDA out of memory"),
    (f"{FAKE}:two_spheres", "cannot be repaired: the mesh holds 2 separate bodies"),
    (f"{FAKE}:open_sheet", "cannot be repaired: the mesh is flat"),
])
def test_entry_point_failures_are_one_clear_line(spec: str, message: str) -> None:
    with pytest.raises(GeometryBackendError) as err:
        sources.build_mesh(AssetRequest(text="a ball", geometry_backend=spec), settings(method="hull"))
    assert message in str(err.value) and "\n" not in str(err.value)
    assert spec.split(":")[0] in str(err.value)


def test_backend_spec_is_validated_and_needs_text_or_image() -> None:
    with pytest.raises(ValueError, match="neither 'module:function' nor an http"):
        AssetRequest(text="a ball", geometry_backend="sam 3d please")
    with pytest.raises(ValueError, match="builds the mesh from text or an image"):
        AssetRequest(mesh_path=Path("x.obj"), geometry_backend=f"{FAKE}:icosphere")


class _Handler(BaseHTTPRequestHandler):
    """The documented HTTP interface, plus the ways a server can fail."""

    bodies: list[dict] = []

    def do_POST(self) -> None:  # noqa: N802 - http.server's name
        body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
        _Handler.bodies.append(body)
        if self.path == "/ok":
            mesh = trimesh.creation.icosphere(subdivisions=3, radius=0.5)
            mesh.apply_scale([1.0, 0.6, 0.4])
            pts, _ = trimesh.sample.sample_surface(mesh, 1500, seed=0)
            ply = Path(self.server.tmp) / "g.ply"  # type: ignore[attr-defined]
            fake_backend.write_gaussians(ply, pts, np.tile([0.1, 0.3, 0.9], (len(pts), 1)))
            self._send(200, json.dumps({"mesh_base64": base64.b64encode(mesh.export(file_type="glb")).decode(),
                                        "mesh_format": "glb",
                                        "gaussians_ply_base64": base64.b64encode(ply.read_bytes()).decode()}))
        elif self.path == "/crash":
            self._send(500, "CUDA error: out of memory")
        elif self.path == "/html":
            self._send(200, "<html>model is loading</html>")
        elif self.path == "/queued":
            self._send(200, json.dumps({"status": "queued"}))
        elif self.path == "/slow":
            time.sleep(2.0)
            self._send(200, "{}")

    def _send(self, code: int, text: str) -> None:
        data = text.encode()
        self.send_response(code)
        self.send_header("Content-Length", str(len(data)))
        self.end_headers()
        self.wfile.write(data)

    def log_message(self, *args: object) -> None:
        """Silent."""


@pytest.fixture
def server(tmp_path: Path) -> Iterator[str]:
    srv = ThreadingHTTPServer(("127.0.0.1", 0), _Handler)
    srv.tmp = str(tmp_path)  # type: ignore[attr-defined]
    thread = threading.Thread(target=srv.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{srv.server_address[1]}"
    finally:
        srv.shutdown()
        srv.server_close()


def test_http_backend_gets_text_image_and_seed_and_its_mesh_passes_the_gates(server: str, tmp_path: Path) -> None:
    import cv2

    photo = tmp_path / "blob.png"
    img = np.full((64, 64, 3), 255, np.uint8)
    cv2.circle(img, (32, 32), 20, (200, 80, 30), -1)
    cv2.imwrite(str(photo), img)
    _Handler.bodies.clear()
    req = AssetRequest(text="a blue cushion 30 cm long", image_path=photo, seed=3, geometry_backend=f"{server}/ok#v1")
    mesh, info, _, _, _, checks = run(req, settings(method="hull"))
    assert checks.passed, checks.failed
    m = _mesh(mesh)
    np.testing.assert_allclose(m.extents, [0.3, 0.18, 0.12], rtol=0.03)
    rgb = np.asarray(m.visual.vertex_colors)[:, :3].astype(float).mean(axis=0)
    assert rgb[2] > 180 and rgb[0] < 80  # blue, from the Gaussians moved into the asset frame with the mesh
    body = _Handler.bodies[-1]
    assert body["text"] == "a blue cushion 30 cm long" and body["seed"] == 3
    assert base64.b64decode(body["image_base64"]) == photo.read_bytes()
    assert info.source == "image" and info.generator == f"backend:{server}/ok#v1"


@pytest.mark.parametrize("path, timeout_s, message", [
    ("/crash", 10.0, "answered HTTP 500: CUDA error: out of memory"),
    ("/html", 10.0, "answered with something that is not JSON"),
    ("/queued", 10.0, "answered without 'mesh_base64' (got ['status'])"),
    ("/slow", 0.5, "did not answer within 0.5 s"),
])
def test_http_failures_are_one_clear_line(server: str, tmp_path: Path, path: str, timeout_s: float,
                                          message: str) -> None:
    with pytest.raises(GeometryBackendError, match="geometry backend http://127.0.0.1") as err:
        call_http(server + path, AssetRequest(text="a ball"), tmp_path, timeout_s)
    assert message in str(err.value) and "\n" not in str(err.value)


def test_unreachable_http_backend(tmp_path: Path) -> None:
    import socket

    with socket.socket() as s:  # a port nobody listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    with pytest.raises(GeometryBackendError, match=f"http://127.0.0.1:{port}/gen is unreachable"):
        call_http(f"http://127.0.0.1:{port}/gen", AssetRequest(text="a ball"), tmp_path, 5.0)


def test_backend_identity_keys_the_mesh_cache(prefect_api: str) -> None:
    """The same backend is a cache hit (the model is not called again); a new '#tag' rebuilds."""
    from cache import CacheStore, cache_root
    from flows.l0_geometry import build_mesh, geometry_request

    s = settings()
    fake_backend.CALLS.clear()
    spec = f"{FAKE}:icosphere"
    req = AssetRequest(text="a ball 10 cm long", material_intent="soft foam", geometry_backend=spec)
    build_mesh(geometry_request(req), s)
    build_mesh(geometry_request(req.model_copy(update={"material_intent": "firm rubber"})), s)
    build_mesh(geometry_request(req.model_copy(update={"geometry_backend": spec + "#v2"})), s)
    assert [e["outcome"] for e in CacheStore(cache_root()).events()] == ["miss", "hit", "miss"]
    assert len(fake_backend.CALLS) == 2


def _cli(*args: str, backend_env: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    """The command with the backend in the environment; `env` (conftest's cli_env) runs it against the session's
    Prefect server."""
    env = {**(env or os.environ), "PYTHONPATH": str(REPO), "DEFORMSMITH_GEOMETRY_BACKEND": backend_env}
    return subprocess.run([sys.executable, "-m", "flows.cli.main", *args], cwd=REPO, capture_output=True, text=True,
                          env=env, timeout=300)


def test_cli_backend_errors_are_one_line_from_the_environment_or_the_option(tmp_path: Path,
                                                                          cli_env: dict[str, str]) -> None:
    """The environment names the backend; --geometry-backend overrides it; a failure is one line, exit 2, no output."""
    from typer.testing import CliRunner

    from flows.cli.main import app  # every command registered

    out = tmp_path / "x"
    from_env = _cli("geometry", "a ball", "--out", str(out), "--no-cache", backend_env=f"{FAKE}:broken", env=cli_env)
    assert from_env.returncode == 2 and "Traceback" not in from_env.stderr
    assert from_env.stderr.strip().splitlines()[-1] == (f"error: geometry backend '{FAKE}:broken' failed: "
                                                        "RuntimeError: checkpoint not found: /models/sam3d.ckpt")
    option = CliRunner().invoke(app, ["geometry", "a ball", "--out", str(out), "--no-cache", "--geometry-backend",
                                      f"{FAKE}:not_a_mesh"], env={"DEFORMSMITH_GEOMETRY_BACKEND": f"{FAKE}:broken"})
    assert isinstance(option.exception, GeometryBackendError)
    assert f"'{FAKE}:not_a_mesh' returned no usable mesh" in str(option.exception)
    assert not out.exists()


@pytest.mark.slow
def test_cli_builds_with_the_backend_and_records_it(tmp_path: Path) -> None:
    out = tmp_path / "ball"
    proc = _cli("geometry", "a ball 12 cm long", "--out", str(out), "--no-cache", "--json",
                backend_env=f"{FAKE}:icosphere")
    assert proc.returncode == 0, proc.stderr
    record = json.loads(proc.stdout)
    assert record["info"]["generator"] == f"backend:{FAKE}:icosphere" and record["passed"]
    assert record["metrics"]["extent_x_m"] == pytest.approx(0.12, rel=0.03)
