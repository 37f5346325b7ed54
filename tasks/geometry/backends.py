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

import tempfile
from pathlib import Path
from typing import Any

import numpy as np
import trimesh
from scipy.spatial import cKDTree

from contracts.errors import InputError
from contracts.request import AssetRequest
from contracts.stage import L0Parameters, load_contract
from tasks.geometry import backend_hunyuan3d, catalogue, pipeline
from tasks.geometry.backend_io import (HUNYUAN3D_PREFIX, BackendOutput, GeometryBackendError, call_http, call_python,
                                      is_http)
from tasks.geometry.canonical import canonicalize
from tasks.geometry.checks import outside_distance
from tasks.geometry.mesh_import import repair_mesh
from tasks.geometry.sdf import program_bounds

GAUSSIAN_ON_MESH_FRACTION = 0.02  # backend Gaussians whose p95 distance outside the mesh exceeds this x its longest
#                                   extent do not belong to it and are ignored [-]
COLOR_NEIGHBOURS = 8
Y_UP_TO_Z_UP = np.array([[1.0, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]])  # +90 deg about x: +y -> +z


def call_backend(spec: str, request: AssetRequest, scratch: Path, timeout_s: float) -> BackendOutput:
    """Run the backend a spec names and load its output."""
    if spec.startswith(HUNYUAN3D_PREFIX):
        return backend_hunyuan3d.call(spec, request, scratch, timeout_s)
    if is_http(spec):
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
