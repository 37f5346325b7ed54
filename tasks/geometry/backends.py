"""Reconstruction backends: a user's text-/image-to-3D model makes the mesh, L0 does the rest.

A backend is named by `AssetRequest.geometry_backend` (CLI `--geometry-backend`, env `DEFORMSMITH_GEOMETRY_BACKEND`):

- ``package.module:function`` -- a Python entry point, imported and called in this process as
  ``function(request: dict) -> result``. ``request`` holds ``text`` (str | None), ``image_path`` (str | None),
  ``seed`` (int), ``size_hint_m`` (float | None) and ``out_dir`` (a scratch directory the function may write its
  files into; removed afterwards). ``result`` is a mesh file path (OBJ/PLY/STL/GLB/GLTF/OFF), a ``trimesh.Trimesh``
  (or ``Scene``), a dict ``{"vertices": (V, 3), "faces": (F, 3), "colors": (V, 3|4) uint8 (optional)}``, or a dict
  ``{"mesh": <one of those>, "gaussians_ply": <3DGS .ply path> (optional), "metric": bool (optional)}``.
- ``http(s)://host:port/path`` -- an HTTP endpoint. L0 POSTs JSON ``{"text", "image_base64", "seed",
  "size_hint_m"}`` (``image_base64``: the photo file's bytes, base64, or null) and expects status 200 with JSON
  ``{"mesh_base64": ..., "mesh_format": "glb"|"obj"|"ply"|"stl"|"off", "gaussians_ply_base64": ... (optional),
  "metric": bool (optional)}``; the wait is bounded by the L0 contract's ``geometry_backend_timeout_s``.
- ``hunyuan3d+http(s)://host:port[?options]`` -- Tencent Hunyuan3D-2's ``api_server.py`` spoken in its own API
  (image in, GLB out): ``tasks/geometry/backend_hunyuan3d.py``, the reference adapter for a real server.

``metric: true`` says the mesh is in metres (kept unless the text or a hint states a size); otherwise (the usual
normalised output of image-to-3D models) it is scaled to the stated size, else the lexicon's typical size of the
named object, else ``geometry_backend_default_size_m`` (with a warning). The mesh is then repaired, canonicalised
(most stable resting pose, z up, longest horizontal extent on x), sized and gated exactly like an imported mesh;
L0's own particles and Gaussians are built from it. Gaussians from the backend are moved by the same transform,
checked to lie on the mesh, and colour the mesh when it has no colours of its own (the asset's Gaussians stay bound
to the MPM particles). A ``#tag`` suffix (``mod:fn#v2``, ``http://h/gen#v2``) is part of the backend's identity,
which keys L0's cache: change it to rebuild after the model changed. Every failure is one line (exit code 2).
"""

from __future__ import annotations

import base64
import http.client
import importlib
import json
import os
import tempfile
import urllib.error
import urllib.request
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import trimesh
from plyfile import PlyData
from scipy.spatial import cKDTree

from contracts.errors import InputError
from contracts.request import AssetRequest
from contracts.stage import L0Parameters, load_contract
from tasks.geometry import catalogue, pipeline
from tasks.geometry.canonical import canonicalize
from tasks.geometry.checks import outside_distance
from tasks.geometry.mesh_import import SUPPORTED, _vertex_colors, load_mesh_file, repair_mesh
from tasks.geometry.sdf import program_bounds

ENV_VAR = "DEFORMSMITH_GEOMETRY_BACKEND"
HUNYUAN3D_PREFIX = "hunyuan3d+"  # 'hunyuan3d+http://host:port': Hunyuan3D-2's own API server (backend_hunyuan3d.py)
GAUSSIAN_ON_MESH_FRACTION = 0.02  # backend Gaussians whose p95 distance outside the mesh exceeds this x its longest
#                                   extent do not belong to it and are ignored [-]
COLOR_NEIGHBOURS = 8
Y_UP_TO_Z_UP = np.array([[1.0, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]])  # +90 deg about x: +y -> +z


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


def _is_http(spec: str) -> bool:
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
        from tasks.geometry.gaussians import SH_C0

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


def call_backend(spec: str, request: AssetRequest, scratch: Path, timeout_s: float) -> BackendOutput:
    """Run the backend a spec names and load its output."""
    if spec.startswith(HUNYUAN3D_PREFIX):
        from tasks.geometry import backend_hunyuan3d

        return backend_hunyuan3d.call(spec, request, scratch, timeout_s)
    if _is_http(spec):
        return call_http(spec, request, scratch, timeout_s)
    return call_python(spec, request, scratch)


def _target_size(request: AssetRequest, out: BackendOutput, default_m: float,
                  warnings: list[str], notes: list[str]) -> tuple[catalogue.SizeSpec | None, Any]:
    """The size to scale to (None: keep a metric mesh's) and the text's offline design (None without text)."""
    design = None
    if request.text and request.text.strip():
        design = catalogue.design_from_text(request.text, request.size_hint_m)
    if request.size_hint_m is not None:
        size = catalogue.SizeSpec(longest_m=request.size_hint_m, stated=f"size hint {request.size_hint_m:g} m")
        catalogue.check_size(size)
        return size, design
    if design is not None and design.size.explicit:
        return design.size.model_copy(update={"axis_scale": (1.0, 1.0, 1.0)}), design
    if out.metric:
        notes.append("the backend says its mesh is in metres: its size is kept")
        return None, design
    if design is not None:
        b = program_bounds(design.program)
        longest = float((b[1] - b[0]).max())
        notes.append(f"no size stated: scaled to the typical size of '{design.entry}', {longest:.3g} m")
        return catalogue.SizeSpec(longest_m=longest, stated=f"typical size of {design.entry}"), design
    warnings.append(f"no size stated and nothing named: assuming a {default_m:g} m longest extent")
    return catalogue.SizeSpec(longest_m=default_m, stated="default size"), None


def _affine(src: np.ndarray, dst: np.ndarray) -> np.ndarray:
    """4x3 affine map with dst = [src 1] @ A (the similarity the canonical frame and sizing applied)."""
    a, *_ = np.linalg.lstsq(np.c_[src, np.ones(len(src))], dst, rcond=None)
    return a


def _apply_gaussians(out: BackendOutput, repaired: trimesh.Trimesh, final: trimesh.Trimesh, seed: int,
                     notes: list[str], warnings: list[str]) -> None:
    """Move the backend's Gaussians into the asset frame, check they lie on the mesh; colour an uncoloured mesh."""
    if out.gaussian_positions is None:
        return
    pos = np.c_[out.gaussian_positions, np.ones(len(out.gaussian_positions))] @ _affine(repaired.vertices,
                                                                                          final.vertices)
    rng = np.random.default_rng(seed)
    probe = pos if len(pos) <= 20_000 else pos[rng.choice(len(pos), 20_000, replace=False)]
    p95 = float(np.percentile(outside_distance(final, probe, seed), 95))
    limit = GAUSSIAN_ON_MESH_FRACTION * float(final.extents.max())
    if p95 > limit:
        warnings.append(f"the backend's {len(pos)} Gaussians do not lie on its mesh (95th percentile "
                        f"{p95 * 1000:.3g} mm outside > {limit * 1000:.3g} mm): ignored")
        return
    vc = np.asarray(final.visual.vertex_colors)
    if len(np.unique(vc[:, :3], axis=0)) > 1:
        notes.append(f"backend Gaussians ({len(pos)}) aligned with the mesh (95th percentile {p95 * 1000:.3g} mm "
                     "outside); the mesh's own colours kept")
        return
    k = min(COLOR_NEIGHBOURS, len(pos))
    d, idx = cKDTree(pos).query(final.vertices, k=k)
    d, idx = d.reshape(len(final.vertices), k), idx.reshape(len(final.vertices), k)
    w = out.gaussian_opacities[idx] / np.maximum(d, 1e-6)  # type: ignore[index]
    rgb = np.einsum("vk,vkc->vc", w, out.gaussian_colors[idx]) / w.sum(axis=1, keepdims=True)  # type: ignore[index]
    colors = np.c_[np.round(np.clip(rgb, 0, 1) * 255).astype(np.uint8), np.full(len(rgb), 255, np.uint8)]
    final.visual = trimesh.visual.ColorVisuals(final, vertex_colors=colors)
    notes.append(f"mesh coloured from the backend's {len(pos)} Gaussians (95th percentile {p95 * 1000:.3g} mm "
                 "outside the mesh)")


def concept_fields(design: Any, mesh: trimesh.Trimesh) -> dict[str, Any]:
    """BuildInfo's `concept` for the lexicon's reading of the text, at the size the mesh was built (empty when there
    is no design or BuildInfo has no concept)."""
    if design is None or "concept" not in pipeline.BuildInfo.model_fields:
        return {}
    concept = getattr(design, "concept", None)
    sized = getattr(pipeline, "sized_concept", None)
    return {"concept": sized(concept, mesh) if concept is not None and sized is not None else concept}


def from_backend(request: AssetRequest, settings: Any) -> tuple[dict[str, np.ndarray], Any]:
    """sources.build_mesh through a reconstruction backend: call it, then repair, canonicalise, size like a mesh."""
    spec = str(request.geometry_backend).strip()
    params = L0Parameters.of(load_contract("L0"))
    timeout_s = params.geometry_backend_timeout_s
    with tempfile.TemporaryDirectory(prefix="deformsmith-backend-") as tmp:
        out = call_backend(spec, request, Path(tmp), timeout_s)
    try:
        repaired, notes = repair_mesh(out.mesh)
    except InputError as exc:
        raise GeometryBackendError(f"geometry backend '{spec}' returned a mesh that cannot be repaired: {exc}") \
            from exc
    warnings: list[str] = []
    size, design = _target_size(request, out, params.geometry_backend_default_size_m,
                                warnings, notes)
    if out.up_axis == "y" and request.pose == "upright":  # the model's vertical stays up, as for L0's own photos
        mesh, rotated = canonicalize(repaired.copy().apply_transform(Y_UP_TO_Z_UP), "keep", align_xy=True)
        notes.append("the model's vertical (glTF +y) kept up (pose 'stable' for the most stable resting pose)")
    else:
        mesh, rotated = canonicalize(repaired, "most_stable", align_xy=True)
    try:
        mesh = pipeline.final_size(mesh, size)
    except InputError as exc:
        raise GeometryBackendError(f"geometry backend '{spec}': {exc}") from exc
    _apply_gaussians(out, repaired, mesh, request.seed, notes, warnings)
    name = (design.program.name if design is not None else
            request.image_path.stem if request.image_path is not None else "backend object")
    entry = design.entry if design is not None else None
    extra = concept_fields(design, mesh)
    info = pipeline.BuildInfo(
        source=request.input_kind, name=name,
        category=design.program.category if design is not None else "unknown", entry=entry, size=size,
        modifiers=design.modifiers if design is not None else [], reoriented=rotated,
        notes=[f"mesh made by the geometry backend '{spec}'", *out.notes, *notes],
        warnings=[*(design.warnings if design is not None else []), *warnings], generator=f"backend:{spec}", **extra)
    return pipeline.mesh_to_arrays(mesh), info
