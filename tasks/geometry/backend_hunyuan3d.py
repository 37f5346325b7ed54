"""Reference adapter for a real image-to-3D server: Tencent Hunyuan3D-2's API server (image in, GLB out).

Spec: ``hunyuan3d+http(s)://host:port[/prefix][?option=value&...][#tag]`` (CLI ``--geometry-backend``), dispatched
by ``backends.call_backend``; the GLB then goes through L0 exactly like any backend's mesh (repair, canonical pose,
size from the text / hint / lexicon, gates). Everything is written to the backend's scratch directory, which L0
removes; every failure is one ``GeometryBackendError`` line (exit code 2), so nothing is half-written.

The API followed is the server's own, read from https://github.com/Tencent/Hunyuan3D-2 at commit
2ee477019f15cabc4a9546b1ed9bb21862136bdf (2025-05-14): ``api_server.py`` (last changed in 54b7eab9), its README
section "API Server" and ``blender_addon.py`` (the project's own client):

- ``POST /generate`` with JSON ``{"image": <the image file, base64>, "seed": int (1234), "octree_resolution": int
  (128), "num_inference_steps": int (5), "guidance_scale": float (5.0), "texture": bool (false), "face_count": int
  (40000), "type": "glb"}`` (server defaults in brackets; without ``image``, ``text`` is turned into an image by the
  server's text-to-image pipeline, which the stock ``api_server.py`` leaves commented out, so a text-only request
  fails there). Success: HTTP 200 whose body is the GLB file itself; failure: HTTP 404 with JSON
  ``{"text": <a generic message>, "error_code": 1}`` (the reason is only in the server's log).
- ``POST /send`` with the same body -> ``{"uid": str}``, generation runs in a server thread; ``GET /status/{uid}`` ->
  ``{"status": "processing"}`` or ``{"status": "completed", "model_base64": <the GLB, base64>}``. A job that fails on
  the server stays "processing": only the timeout ends it.

Options in the spec's query string: ``mode=sync`` (``/generate``, the default) or ``mode=async`` (``/send`` then
``/status`` every ``poll_s`` seconds, default 2), and the server's own ``octree_resolution``, ``num_inference_steps``,
``guidance_scale``, ``face_count`` and ``texture`` (default false: an untextured, grey mesh, as the server's
default; true needs a server started with ``--enable_tex`` and its colours are kept). Options not named are left to the server. The request's seed is always sent; the
wait (both modes together) is bounded by the L0 contract's ``geometry_backend_timeout_s``. The mesh is normalised
(not metric), so L0 sizes it from the request; it is y-up (glTF), and that vertical is kept under the request's
pose 'upright' (the default, as for L0's own photos), while pose 'stable' lays it in its most stable pose.
"""

from __future__ import annotations

import base64
import json
import time
import urllib.parse
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from contracts.request import AssetRequest
from tasks.geometry.backend_io import (
    HUNYUAN3D_PREFIX,
    BackendOutput,
    GeometryBackendError,
    _b64,
    http_exchange,
    load_result,
)

SOURCE = "github.com/Tencent/Hunyuan3D-2 api_server.py @ 2ee477019f15cabc4a9546b1ed9bb21862136bdf"
GLB_MAGIC = b"glTF"
OPTIONS: dict[str, type] = {"octree_resolution": int, "num_inference_steps": int, "guidance_scale": float,
                            "face_count": int, "texture": bool}
CLIENT_OPTIONS: dict[str, type] = {"mode": str, "poll_s": float}
DEFAULT_POLL_S = 2.0
TEXT_ONLY_HINT = ("a text-only request needs the server's text-to-image pipeline, which the stock api_server.py does "
                  "not load: give a photo (--image)")


@dataclass
class Hunyuan3DSpec:
    """A parsed 'hunyuan3d+http://host:port[/prefix][?options][#tag]' spec."""

    base: str                                           # http(s)://host:port[/prefix], no trailing slash
    options: dict[str, Any] = field(default_factory=dict)   # sent to the server
    mode: str = "sync"
    poll_s: float = DEFAULT_POLL_S


def parse_spec(spec: str) -> Hunyuan3DSpec:
    """The server's base URL and options (GeometryBackendError for an unknown or malformed option)."""
    url = spec.strip().split("#", 1)[0][len(HUNYUAN3D_PREFIX):]
    parts = urllib.parse.urlsplit(url)
    if parts.scheme not in ("http", "https") or not parts.netloc:
        raise GeometryBackendError(f"geometry backend '{spec}': expected hunyuan3d+http(s)://host:port")
    out = Hunyuan3DSpec(base=f"{parts.scheme}://{parts.netloc}{parts.path.rstrip('/')}")
    for key, value in urllib.parse.parse_qsl(parts.query, keep_blank_values=True):
        kind = OPTIONS.get(key) or CLIENT_OPTIONS.get(key)
        if kind is None:
            raise GeometryBackendError(f"geometry backend '{spec}': unknown option '{key}' (known: "
                                       f"{', '.join([*CLIENT_OPTIONS, *OPTIONS])})")
        try:
            parsed = _convert(kind, value)
        except ValueError as exc:
            raise GeometryBackendError(f"geometry backend '{spec}': option {key}={value!r} is not a "
                                       f"{kind.__name__}") from exc
        if key == "mode":
            if parsed not in ("sync", "async"):
                raise GeometryBackendError(f"geometry backend '{spec}': mode must be sync or async, not {value!r}")
            out.mode = parsed
        elif key == "poll_s":
            out.poll_s = max(float(parsed), 0.01)
        else:
            out.options[key] = parsed
    return out


def _convert(kind: type, value: str) -> Any:
    if kind is bool:
        if value.lower() not in ("true", "false", "1", "0", "yes", "no"):
            raise ValueError(value)
        return value.lower() in ("true", "1", "yes")
    return kind(value)


def request_body(request: AssetRequest, parsed: Hunyuan3DSpec) -> dict[str, Any]:
    """The JSON body api_server.py reads: the photo as base64 (else the text), the seed, the named options."""
    body: dict[str, Any] = {}
    if request.image_path is not None:
        body["image"] = base64.b64encode(Path(request.image_path).read_bytes()).decode()
    elif request.text and request.text.strip():
        body["text"] = request.text.strip()
    else:
        raise GeometryBackendError("geometry backend hunyuan3d: the request has neither a photo nor text")
    body.update({"seed": int(request.seed), "texture": False, "type": "glb"})
    body.update(parsed.options)
    return body


def call(spec: str, request: AssetRequest, scratch: Path, timeout_s: float) -> BackendOutput:
    """Generate the mesh on a Hunyuan3D-2 API server (synchronously or by send/status polling) and load it."""
    parsed = parse_spec(spec)
    body = request_body(request, parsed)
    try:
        glb = _generate(parsed, body, timeout_s) if parsed.mode == "sync" else _send_and_poll(parsed, body, timeout_s)
    except GeometryBackendError as exc:
        if "image" not in body and "unreachable" not in str(exc):
            raise GeometryBackendError(f"{exc}; {TEXT_ONLY_HINT}") from exc
        raise
    if not glb.startswith(GLB_MAGIC):
        start = glb[:60].decode(errors="replace").replace("\n", " ")
        raise GeometryBackendError(f"geometry backend {HUNYUAN3D_PREFIX}{parsed.base} answered with something that "
                                   f"is not a GLB ({len(glb)} bytes: {start!r})")
    path = scratch / "hunyuan3d.glb"
    path.write_bytes(glb)
    out = load_result(f"{HUNYUAN3D_PREFIX}{parsed.base}", {"mesh": path, "metric": False})
    out.up_axis = "y"  # glTF's up, which Hunyuan3D-2's meshes follow
    out.notes.append(f"Hunyuan3D-2 API server {parsed.base} ({parsed.mode}; seed {body['seed']}"
                     + "".join(f", {k} {v}" for k, v in parsed.options.items()) + ")")
    return out


def _exchange(parsed: Hunyuan3DSpec, path: str, body: dict[str, Any] | None, timeout_s: float,
              accept: str = "application/json") -> bytes:
    """One request to the server (backend_io.http_exchange: every failure one line, named by the spec)."""
    return http_exchange(parsed.base + path, body, timeout_s, accept, label=f"{HUNYUAN3D_PREFIX}{parsed.base}{path}")


def _generate(parsed: Hunyuan3DSpec, body: dict[str, Any], timeout_s: float) -> bytes:
    """POST /generate: the answer's body is the GLB (a failure is HTTP 404 with a generic JSON text)."""
    try:
        return _exchange(parsed, "/generate", body, timeout_s, "model/gltf-binary, application/octet-stream, */*")
    except GeometryBackendError as exc:
        if "HTTP 404" in str(exc) and '"error_code"' in str(exc):  # api_server.py's answer to every failure
            raise GeometryBackendError(f"geometry backend {HUNYUAN3D_PREFIX}{parsed.base}/generate: generation "
                                       "failed on the server (HTTP 404 with its generic error_code answer: the "
                                       "server's log says why)") from exc
        raise


def _send_and_poll(parsed: Hunyuan3DSpec, body: dict[str, Any], timeout_s: float) -> bytes:
    """POST /send, then GET /status/{uid} until 'completed', within timeout_s in all."""
    deadline = time.monotonic() + timeout_s
    label = f"{HUNYUAN3D_PREFIX}{parsed.base}"
    sent = _json(label + "/send", _exchange(parsed, "/send", body, timeout_s))
    uid = sent.get("uid")
    if not isinstance(uid, str) or not uid:
        raise GeometryBackendError(f"geometry backend {label}/send answered without a 'uid' (got {sorted(sent)})")
    status_path = f"/status/{urllib.parse.quote(uid, safe='')}"
    while (left := deadline - time.monotonic()) > 0:
        try:
            raw = _exchange(parsed, status_path, None, left)
        except GeometryBackendError as exc:
            if "did not answer within" in str(exc) and deadline - time.monotonic() <= 0.05:
                break  # the last poll ran into the overall deadline: the job is what did not finish in time
            raise
        answer = _json(label + status_path, raw)
        status = answer.get("status")
        if status == "completed":
            if not isinstance(answer.get("model_base64"), str):
                raise GeometryBackendError(f"geometry backend {label}{status_path}: 'completed' without "
                                           "'model_base64'")
            return _b64(label + status_path, answer["model_base64"], "model_base64")
        if status != "processing":
            raise GeometryBackendError(f"geometry backend {label}{status_path} answered status {status!r} (expected "
                                       "'processing' or 'completed')")
        time.sleep(max(0.0, min(parsed.poll_s, deadline - time.monotonic())))
    raise GeometryBackendError(f"geometry backend {label}: job {uid} not completed within {timeout_s:g} s (a job that "
                               "fails on the server stays 'processing': see the server's log)")


def _json(label: str, raw: bytes) -> dict[str, Any]:
    try:
        answer = json.loads(raw)
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise GeometryBackendError(f"geometry backend {label} answered with something that is not JSON "
                                   f"({len(raw)} bytes)") from exc
    if not isinstance(answer, dict):
        raise GeometryBackendError(f"geometry backend {label} answered a JSON {type(answer).__name__}, not an object")
    return answer
