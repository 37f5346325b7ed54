"""Calling a reconstruction backend and loading what it returns (tasks/geometry/backends.py says what a backend is
and takes its mesh through L0): a Python entry point or an HTTP endpoint, its mesh and optional 3DGS Gaussians."""


from __future__ import annotations

import base64
import http.client
import importlib
import json
import os
import urllib.error
import urllib.request
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import trimesh
from plyfile import PlyData

from contracts.errors import InputError
from contracts.request import AssetRequest
from tasks.geometry.gaussians import SH_C0
from tasks.geometry.mesh_import import SUPPORTED, _vertex_colors, load_mesh_file

ENV_VAR = "DEFORMSMITH_GEOMETRY_BACKEND"
HUNYUAN3D_PREFIX = "hunyuan3d+"  # 'hunyuan3d+http://host:port': Hunyuan3D-2's own API server (backend_hunyuan3d.py)


class GeometryBackendError(InputError):
    """The configured reconstruction backend could not be loaded, failed, or returned no usable mesh."""


@dataclass
class BackendOutput:
    """What a backend returned, loaded: one mesh (vertex colours), optional Gaussians, and whether it is metric."""

    mesh: trimesh.Trimesh
    gaussian_positions: np.ndarray | None = None   # (G, 3) in the mesh's frame
    gaussian_colors: np.ndarray | None = None      # (G, 3) RGB in [0, 1]
    gaussian_opacities: np.ndarray | None = None   # (G,)
    metric: bool = False
    notes: list[str] = field(default_factory=list)
    up_axis: str | None = None                     # 'y': the model's frame is y-up (glTF), kept under pose 'upright'


def backend_from_env() -> str | None:
    """The backend named by $DEFORMSMITH_GEOMETRY_BACKEND (None when unset or empty)."""
    value = os.environ.get(ENV_VAR, "").strip()
    return value or None


def is_http(spec: str) -> bool:
    return spec.startswith(("http://", "https://"))


def load_entry_point(spec: str) -> Callable[[dict[str, Any]], Any]:
    """The function a 'module:function[#tag]' spec names (GeometryBackendError when it cannot be imported)."""
    target = spec.split("#", 1)[0]
    module_name, _, func_name = target.partition(":")
    try:
        module = importlib.import_module(module_name)
    except Exception as exc:  # ImportError, or the module's own import-time errors
        raise GeometryBackendError(f"geometry backend '{spec}': cannot import '{module_name}': "
                                   f"{type(exc).__name__}: {exc}".split("\n")[0]) from exc
    func = getattr(module, func_name, None)
    if not callable(func):
        raise GeometryBackendError(f"geometry backend '{spec}': module '{module_name}' has no function '{func_name}'")
    return func


def _backend_request(request: AssetRequest) -> dict[str, Any]:
    return {"text": request.text, "image_path": str(request.image_path) if request.image_path else None,
            "seed": request.seed, "size_hint_m": request.size_hint_m}


def call_python(spec: str, request: AssetRequest, scratch: Path) -> BackendOutput:
    """Call a Python entry point and load what it returned."""
    func = load_entry_point(spec)
    try:
        result = func({**_backend_request(request), "out_dir": str(scratch)})
    except GeometryBackendError:
        raise
    except Exception as exc:  # the user's model code
        raise GeometryBackendError(f"geometry backend '{spec}' failed: {type(exc).__name__}: {exc}".split("\n")[0]) \
            from exc
    return load_result(spec, result)


def call_http(spec: str, request: AssetRequest, scratch: Path, timeout_s: float) -> BackendOutput:
    """POST the request to an HTTP endpoint and load its JSON answer."""
    url = spec.split("#", 1)[0]
    body = _backend_request(request)
    image = body.pop("image_path")
    body["image_base64"] = base64.b64encode(Path(image).read_bytes()).decode() if image else None
    raw = http_exchange(url, body, timeout_s)
    try:
        answer = json.loads(raw)
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise GeometryBackendError(f"geometry backend {url} answered with something that is not JSON "
                                   f"({len(raw)} bytes)") from exc
    if not isinstance(answer, dict) or not isinstance(answer.get("mesh_base64"), str):
        keys = sorted(answer) if isinstance(answer, dict) else type(answer).__name__
        raise GeometryBackendError(f"geometry backend {url} answered without 'mesh_base64' (got {keys})")
    fmt = str(answer.get("mesh_format", "glb")).lower().lstrip(".")
    if f".{fmt}" not in SUPPORTED:
        raise GeometryBackendError(f"geometry backend {url}: mesh_format '{fmt}' is not one of "
                                   f"{', '.join(s[1:] for s in SUPPORTED)}")
    mesh_path = scratch / f"backend_mesh.{fmt}"
    mesh_path.write_bytes(_b64(url, answer["mesh_base64"], "mesh_base64"))
    result: dict[str, Any] = {"mesh": mesh_path, "metric": bool(answer.get("metric", False))}
    if answer.get("gaussians_ply_base64"):
        ply = scratch / "backend_gaussians.ply"
        ply.write_bytes(_b64(url, answer["gaussians_ply_base64"], "gaussians_ply_base64"))
        result["gaussians_ply"] = ply
    return load_result(url, result)


def http_exchange(url: str, body: dict[str, Any] | None, timeout_s: float, accept: str = "application/json",
                  label: str | None = None) -> bytes:
    """POST `body` as JSON (GET when None) and return the answer's bytes; every failure is one GeometryBackendError
    line naming `label` (default: the URL): HTTP status with the start of the answer, unreachable, or no answer
    within `timeout_s`."""
    who = label or url
    data = None if body is None else json.dumps(body).encode()
    req = urllib.request.Request(url, data=data, method="GET" if body is None else "POST",
                                 headers={"Content-Type": "application/json", "Accept": accept})
    try:
        with urllib.request.urlopen(req, timeout=timeout_s) as resp:  # noqa: S310 - the user's own endpoint
            return bytes(resp.read())
    except urllib.error.HTTPError as exc:
        detail = exc.read()[:200].decode(errors="replace").strip().replace("\n", " ")
        raise GeometryBackendError(f"geometry backend {who} answered HTTP {exc.code}: {detail or exc.reason}") from exc
    except (TimeoutError, urllib.error.URLError) as exc:
        reason = getattr(exc, "reason", exc)
        if isinstance(reason, TimeoutError) or isinstance(exc, TimeoutError) or "timed out" in str(reason):
            raise GeometryBackendError(f"geometry backend {who} did not answer within {timeout_s:g} s") from exc
        raise GeometryBackendError(f"geometry backend {who} is unreachable: {reason}") from exc
    except (OSError, http.client.HTTPException) as exc:  # a connection reset or closed mid-answer
        raise GeometryBackendError(f"geometry backend {who}: connection failed: {type(exc).__name__}: {exc}"
                                   .split("\n")[0]) from exc


def _b64(url: str, text: str, key: str) -> bytes:
    try:
        return base64.b64decode(text, validate=True)
    except ValueError as exc:
        raise GeometryBackendError(f"geometry backend {url}: '{key}' is not valid base64") from exc


def load_result(spec: str, result: Any) -> BackendOutput:
    """A backend's return value -> BackendOutput (GeometryBackendError for anything that is not a mesh)."""
    gaussians, metric = None, False
    if isinstance(result, dict) and "mesh" in result:
        gaussians, metric = result.get("gaussians_ply"), bool(result.get("metric", False))
        result = result["mesh"]
    try:
        mesh = _as_mesh(result)
    except InputError as exc:
        raise GeometryBackendError(f"geometry backend '{spec}' returned no usable mesh: {exc}") from exc
    out = BackendOutput(mesh=mesh, metric=metric)
    if gaussians is not None:
        try:
            out.gaussian_positions, out.gaussian_colors, out.gaussian_opacities = read_gaussian_ply(Path(gaussians))
        except (OSError, ValueError, KeyError) as exc:
            raise GeometryBackendError(f"geometry backend '{spec}': Gaussians {gaussians} unreadable: "
                                       f"{type(exc).__name__}: {exc}".split("\n")[0]) from exc
    return out


def _as_mesh(result: Any) -> trimesh.Trimesh:
    """A mesh file path, Trimesh, Scene or arrays dict -> one vertex-coloured Trimesh."""
    if isinstance(result, (str, os.PathLike)):
        return load_mesh_file(Path(result))
    if isinstance(result, trimesh.Scene):
        result = result.to_geometry() if hasattr(result, "to_geometry") else result.dump(concatenate=True)
    c: np.ndarray | None
    if isinstance(result, trimesh.Trimesh):
        v, f, c = result.vertices, result.faces, _vertex_colors(result)
    elif isinstance(result, dict) and {"vertices", "faces"} <= set(result):
        v, f = np.asarray(result["vertices"], np.float64), np.asarray(result["faces"])
        c = result.get("colors")
    else:
        raise InputError(f"a {type(result).__name__} is not a mesh (return a mesh file path, a trimesh.Trimesh, or "
                         "{'vertices', 'faces'[, 'colors']})")
    v = np.asarray(v, np.float64)
    if v.ndim != 2 or v.shape[1] != 3 or np.asarray(f).ndim != 2 or np.asarray(f).shape[1] != 3 or len(f) == 0:
        raise InputError(f"vertices must be (V, 3) and faces (F, 3) with F > 0, got {v.shape} and {np.shape(f)}")
    if not np.all(np.isfinite(v)):
        raise InputError("non-finite vertex coordinates")
    f = np.asarray(f, np.int64)
    if f.min() < 0 or f.max() >= len(v):
        raise InputError(f"face indices outside [0, {len(v) - 1}]")
    mesh = trimesh.Trimesh(v, f, process=False)
    if c is None:
        c = np.tile(np.array([190, 190, 190, 255], np.uint8), (len(v), 1))
    c = np.asarray(c)
    if c.dtype.kind == "f":
        c = np.round(np.clip(c, 0, 1) * 255)
    if c.shape[:1] != (len(v),) or c.shape[1] not in (3, 4):
        raise InputError(f"colors must be (V, 3|4), got {c.shape}")
    c = c.astype(np.uint8) if c.shape[1] == 4 else np.c_[c.astype(np.uint8), np.full(len(v), 255, np.uint8)]
    mesh.visual = trimesh.visual.ColorVisuals(mesh, vertex_colors=c)
    return mesh


def read_gaussian_ply(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Centres (G, 3), RGB in [0, 1] (from the SH DC terms, or red/green/blue) and opacities of a 3DGS .ply."""
    v = PlyData.read(str(path))["vertex"].data
    names = set(v.dtype.names or ())
    pos = np.stack([np.asarray(v[k], np.float64) for k in ("x", "y", "z")], axis=1)
    if {"f_dc_0", "f_dc_1", "f_dc_2"} <= names:
        rgb = np.stack([np.asarray(v[f"f_dc_{i}"], np.float64) for i in range(3)], axis=1) * SH_C0 + 0.5
    elif {"red", "green", "blue"} <= names:
        rgb = np.stack([np.asarray(v[k], np.float64) for k in ("red", "green", "blue")], axis=1) / 255.0
    else:
        rgb = np.full((len(pos), 3), 0.75)
    alpha = 1.0 / (1.0 + np.exp(-np.asarray(v["opacity"], np.float64))) if "opacity" in names else np.ones(len(pos))
    keep = np.all(np.isfinite(pos), axis=1)
    if not keep.any():
        raise ValueError("no finite Gaussian centres")
    return pos[keep], np.clip(rgb[keep], 0, 1), alpha[keep]
