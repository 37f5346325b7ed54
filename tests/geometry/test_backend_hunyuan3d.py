"""The Hunyuan3D-2 reference adapter against a local fake of its api_server.py (loopback only, no model)."""

from __future__ import annotations

import base64
import socket
from pathlib import Path

import numpy as np
import pytest
from helpers import run, settings

from contracts.request import AssetRequest
from tasks.geometry import pipeline, sources
from tasks.geometry.backend_hunyuan3d import parse_spec
from tasks.geometry.backends import GeometryBackendError, call_backend
from tests.geometry.fake_hunyuan3d import FakeHunyuan3D


@pytest.fixture
def photo(tmp_path: Path) -> Path:
    import cv2

    path = tmp_path / "toy.png"
    img = np.full((64, 48, 3), 255, np.uint8)
    cv2.ellipse(img, (24, 32), (14, 24), 0, 0, 360, (40, 120, 200), -1)
    cv2.imwrite(str(path), img)
    return path


def _scratch(tmp_path: Path) -> Path:
    scratch = tmp_path / "scratch"
    scratch.mkdir()
    return scratch


def test_photo_through_hunyuan3d_is_a_sized_l0_mesh_and_the_server_got_its_api(photo: Path) -> None:
    """/generate gets the photo as base64, the seed and the named options; the y-up GLB becomes an upright L0 mesh
    at 30 cm that passes the gates."""
    with FakeHunyuan3D() as srv:
        spec = f"hunyuan3d+{srv.url}?octree_resolution=256&num_inference_steps=20#v1"
        req = AssetRequest(text="a plush cushion 30 cm tall", image_path=photo, seed=5, geometry_backend=spec)
        mesh, info, _, _, _, checks = run(req, settings(method="hull"))
    assert checks.passed, checks.failed
    m = pipeline.arrays_to_mesh(mesh)
    np.testing.assert_allclose(m.extents, [0.18, 0.12, 0.3], rtol=0.03)  # 0.6 : 0.4 : 1.0, the model's y up
    assert m.is_watertight and m.bounds[0][2] == pytest.approx(0.0, abs=1e-9) and not info.reoriented
    assert any("the model's vertical (glTF +y) kept up" in n for n in info.notes)
    assert any(n.startswith(f"Hunyuan3D-2 API server {srv.url} (sync; seed 5") for n in info.notes)
    assert info.source == "image" and info.generator == f"backend:{spec}"
    [body] = srv.bodies
    assert base64.b64decode(body["image"]) == photo.read_bytes() and "text" not in body
    assert body["seed"] == 5 and body["texture"] is False and body["type"] == "glb"
    assert body["octree_resolution"] == 256 and body["num_inference_steps"] == 20


def test_pose_stable_lays_the_mesh_in_its_most_stable_pose(photo: Path) -> None:
    with FakeHunyuan3D() as srv:
        req = AssetRequest(image_path=photo, size_hint_m=0.2, pose="stable", geometry_backend=f"hunyuan3d+{srv.url}")
        mesh, info = sources.build_mesh(req, settings(method="hull"))
    np.testing.assert_allclose(pipeline.arrays_to_mesh(mesh).extents, [0.2, 0.12, 0.08], rtol=0.03)
    assert info.reoriented


def test_async_send_and_status_polling(photo: Path, tmp_path: Path) -> None:
    with FakeHunyuan3D(delay_s=0.3) as srv:
        out = call_backend(f"hunyuan3d+{srv.url}/?mode=async&poll_s=0.05&texture=false",
                           AssetRequest(image_path=photo, seed=9), _scratch(tmp_path), 10.0)
    np.testing.assert_allclose(out.mesh.extents, [0.6, 1.0, 0.4], atol=0.01)  # the raw GLB, y up
    assert srv.polls >= 3 and srv.bodies[0]["seed"] == 9 and srv.bodies[0]["texture"] is False
    assert base64.b64decode(srv.bodies[0]["image"]) == photo.read_bytes()
    assert not out.metric  # normalised: L0 sizes it from the request


def test_text_goes_to_the_servers_text_field_when_it_has_text_to_image(tmp_path: Path) -> None:
    with FakeHunyuan3D(text_to_image=True) as srv:
        call_backend(f"hunyuan3d+{srv.url}", AssetRequest(text="a plush rabbit", seed=2), _scratch(tmp_path), 10.0)
    assert srv.bodies == [{"text": "a plush rabbit", "seed": 2, "texture": False, "type": "glb"}]


def _free_port() -> int:
    with socket.socket() as s:  # a port nobody listens on
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.mark.parametrize("behaviour, query, kind, timeout_s, message", [
    ("down", "", "photo", 5.0, "/generate is unreachable"),
    ("crash", "", "photo", 5.0, "/generate answered HTTP 500: Internal Server Error"),
    ("garbage", "", "photo", 5.0, "answered with something that is not a GLB (29 bytes: '<html>model is loading"),
    ("slow", "", "photo", 0.5, "/generate did not answer within 0.5 s"),
    ("ok", "", "not_an_image", 5.0, "/generate: generation failed on the server (HTTP 404 with its generic"),
    ("ok", "", "text", 5.0, "failed on the server (HTTP 404 with its generic error_code answer: the server's log says "
                            "why); a text-only request needs the server's text-to-image pipeline"),
    ("garbage", "?mode=async", "photo", 5.0, "/status/"),
    ("ok", "?mode=async&poll_s=0.05", "not_an_image", 0.5, "not completed within 0.5 s (a job that fails"),
    ("ok", "?steps=20", "photo", 5.0, "unknown option 'steps' (known: mode, poll_s, octree_resolution"),
    ("ok", "?texture=maybe", "photo", 5.0, "option texture='maybe' is not a bool"),
])
def test_failures_are_one_clear_line_with_nothing_written(photo: Path, tmp_path: Path, behaviour: str, query: str,
                                                          kind: str, timeout_s: float, message: str) -> None:
    junk = tmp_path / "junk.png"
    junk.write_bytes(b"not a picture")
    req = {"photo": AssetRequest(image_path=photo), "not_an_image": AssetRequest(image_path=junk),
           "text": AssetRequest(text="a plush rabbit")}[kind]
    scratch = _scratch(tmp_path)
    with FakeHunyuan3D(behaviour="ok" if behaviour == "down" else behaviour) as srv:
        url = f"http://127.0.0.1:{_free_port()}" if behaviour == "down" else srv.url
        with pytest.raises(GeometryBackendError) as err:
            call_backend(f"hunyuan3d+{url}{query}", req, scratch, timeout_s)
    text = str(err.value)
    assert message in text and "\n" not in text and "hunyuan3d+http://127.0.0.1:" in text, text
    assert list(scratch.iterdir()) == []


def test_spec_is_accepted_by_the_request_and_parsed() -> None:
    AssetRequest(text="a ball", geometry_backend="hunyuan3d+https://gpu.example:8080/h3d?mode=async#v2")
    with pytest.raises(ValueError, match="neither 'module:function' nor an http"):
        AssetRequest(text="a ball", geometry_backend="hunyuan3d+ftp://gpu.example")
    parsed = parse_spec("hunyuan3d+http://h:8081/api/?octree_resolution=380&guidance_scale=5.5&mode=async#tag")
    assert parsed.base == "http://h:8081/api" and parsed.mode == "async"
    assert parsed.options == {"octree_resolution": 380, "guidance_scale": 5.5}


def test_cli_with_the_server_down_exits_2_and_writes_nothing(photo: Path, tmp_path: Path) -> None:
    from typer.testing import CliRunner

    from flows.cli.main import app

    out = tmp_path / "x"
    spec = f"hunyuan3d+http://127.0.0.1:{_free_port()}"
    result = CliRunner().invoke(app, ["geometry", "--image", str(photo), "--size-m", "0.3", "--out", str(out),
                                      "--no-cache", "--geometry-backend", spec])
    assert isinstance(result.exception, GeometryBackendError), result.output
    assert f"{spec}/generate is unreachable" in str(result.exception)
    assert not out.exists()
