"""L0's mesh from its source: a text (the offline grammar, or an LLM Designer), a photo, a mesh file, or a
reconstruction backend; each aligned, sized and metric (tasks/geometry/pipeline.py builds the rest from it)."""

from __future__ import annotations

import re

import numpy as np

from contracts.errors import InputError
from contracts.request import AssetRequest
from tasks.agents.intent import check_request_object
from tasks.geometry import catalogue, image as image_mod, silhouette
from tasks.geometry.backends import from_backend
from tasks.geometry.canonical import canonicalize
from tasks.geometry.mesh_import import import_mesh
from tasks.geometry.pipeline import Arrays, BuildInfo, L0Settings, final_size, mesh_from_text, mesh_to_arrays, sized_concept
from tasks.geometry.sdf import program_bounds


def build_mesh(request: AssetRequest, settings: L0Settings) -> tuple[Arrays, BuildInfo]:
    """The aligned, metric, watertight mesh for a request (text, image or mesh path)."""
    kind = request.input_kind
    if request.geometry_backend is not None:
        return from_backend(request, settings)
    if kind == "text" and settings.designer is not None:
        from tasks.geometry.shape_designer import from_text_llm  # lazy: pulls litellm (~10 s), only with an LLM Designer

        return from_text_llm(request, settings)
    if kind == "text":
        return mesh_from_text(request, settings)
    if kind == "image":
        return _from_image(request, settings)
    return _from_mesh(request, settings)


def _is_named(design: catalogue.Design) -> bool:
    """True when the Designer found the object itself (no fallback to a body plan, category or material)."""
    concept = getattr(design, "concept", None)
    if concept is not None and getattr(concept, "fallback_level", None) is not None:
        return concept.fallback_level in ("exact", "synonym")
    return getattr(design, "match_score", 0.0) > 0.0


DEFAULT_PHOTO_SIZE_M = 0.2  # longest extent of a photographed object when neither a size nor any concept is known [m]
_CAMERA_STEM = re.compile(r"^(?:img|dsc|dscn|dscf|pxl|photo|image|pic|picture|screenshot|scan|frame|p)?[\s\d]*$")


def _stem_words(request: AssetRequest) -> str | None:
    """The photo's file name as words ('soda_can-2.jpg' -> 'soda can 2'); None for a camera's own names (IMG_0042)."""
    if request.image_path is None:
        return None
    stem = re.sub(r"[_\-.]+", " ", request.image_path.stem).strip()
    return None if not stem or _CAMERA_STEM.match(stem.lower()) else stem


def _photo_concept(request: AssetRequest) -> tuple[catalogue.Design | None, catalogue.Design | None, list[str]]:
    """(the design of a named object, the best design by analogy, notes): the text first, then the material intent,
    then the file name; a named object is one the lexicon knows by name (exact or synonym)."""
    notes: list[str] = []
    best: catalogue.Design | None = None
    rank = {"exact": 0, "synonym": 1, "body_plan": 2, "category": 3, "material": 4, "generic": 5}
    for source, words in (("text", request.text), ("intent", request.material_intent),
                          ("file name", _stem_words(request))):
        if not words or not words.strip():
            continue
        try:
            design = catalogue.design_from_text(words, request.size_hint_m)
        except InputError:
            if source == "text":
                raise
            continue
        level = design.concept.fallback_level if design.concept is not None else ("exact" if _is_named(design)
                                                                                   else "generic")
        if source != "text" and _is_named(design):
            notes.append(f"object '{design.entry}' named by the {source} '{words}'")
        if _is_named(design):
            return design, design, notes
        cur = best.concept.fallback_level if best is not None and best.concept is not None else "generic"
        if best is None or rank.get(level, 5) < rank.get(cur, 5):
            best = design
    return None, best, notes


def _photo_size(request: AssetRequest, text_design: catalogue.Design | None, named: catalogue.Design | None,
                analogy: catalogue.Design | None) -> tuple[catalogue.SizeSpec, str, list[str]]:
    """The size to build a photographed object at and where it comes from: the text or --size-m, else the named
    object's typical size (the lexicon), else the typical size of the concept found by analogy, else a default with a
    warning. Never a silent default."""
    if request.size_hint_m is not None:
        size = catalogue.SizeSpec(longest_m=request.size_hint_m, stated=f"size hint {request.size_hint_m:g} m")
        catalogue.check_size(size)
        return size, f"stated: {request.size_hint_m:g} m", []
    axis_scale = text_design.size.axis_scale if text_design is not None else (1.0, 1.0, 1.0)
    if text_design is not None and text_design.size.explicit:
        return text_design.size, f"stated: '{text_design.size.stated}'", []
    for design, how in ((named, "typical size of a"), (analogy, "typical size of the concept built by analogy,")):
        if design is None:
            continue
        concept = design.concept
        if design is analogy and (concept is None or concept.fallback_level == "generic"):
            continue
        typical = concept.typical_size_m if concept is not None else None
        if typical is None:
            b = program_bounds(design.program)
            typical = float((b[1] - b[0]).max())
        size = catalogue.SizeSpec(longest_m=typical, axis_scale=axis_scale)
        warn = [] if design is named else [f"no size given and no known object named: {how} '{design.entry}', "
                                           f"{typical:.3g} m longest extent (state it with --size-m or in the text)"]
        return size, f"{how} '{design.entry}' ({typical:.3g} m)", warn
    size = catalogue.SizeSpec(longest_m=DEFAULT_PHOTO_SIZE_M, axis_scale=axis_scale)
    return size, f"default ({DEFAULT_PHOTO_SIZE_M:g} m)", [
        f"no size given and no object named: assuming {DEFAULT_PHOTO_SIZE_M:g} m longest extent, a guess (state the "
        "size with --size-m or in the text, or name the object)"]


def _from_image(request: AssetRequest, settings: L0Settings) -> tuple[Arrays, BuildInfo]:
    check_request_object(request)  # 'a teacup', or teacup.jpg, is refused as in the text path (unless soft words)
    img = image_mod.load_image(request.image_path)  # type: ignore[arg-type]
    mask, method = image_mod.segment(img, seed=request.seed)
    text_design = None
    if request.text and request.text.strip():
        text_design = catalogue.design_from_text(request.text, request.size_hint_m)
    named, analogy, notes = _photo_concept(request)
    warnings: list[str] = []
    size, size_from, size_warnings = _photo_size(request, text_design, named, analogy)
    warnings += size_warnings
    if named is None and text_design is not None:
        warnings += text_design.warnings
    notes.append(f"size: {size_from}")
    entry = named.entry if named is not None else None
    longest = size.longest_m or max((v for v in size.extents_m if v is not None), default=DEFAULT_PHOTO_SIZE_M)
    mesh, photo = silhouette.reconstruct(mask, img, longest, settings.marching_cubes_resolution,
                                         named.program if named is not None else None, entry)
    warnings += photo.notes
    before = mesh.vertices.copy()
    if request.pose == "stable":
        mesh, rotated = canonicalize(mesh, "most_stable", align_xy=True)
    else:  # the photo's vertical is up: the table it stands on is the ground
        mesh, rotated = canonicalize(mesh, "keep", align_xy=False)
    mesh = final_size(mesh, size)
    photo = silhouette.follow_camera(photo, before, mesh.vertices)
    name = request.image_path.stem if request.image_path else "image object"
    depth = float(np.ptp(mesh.vertices @ np.asarray(photo.camera_forward)))
    mods = text_design.modifiers if text_design is not None else []
    concept = getattr(named or analogy, "concept", None)
    info = BuildInfo(source="image", name=name, category=catalogue.entry_category(entry) if entry else
                     (concept.category if concept is not None else "unknown"),
                     entry=entry, program=named.program if named is not None and photo.method == "program fit" else None,
                     size=size, modifiers=mods,
                     segmentation=method, thickness_m=depth, reoriented=rotated, notes=notes,
                     warnings=warnings, photo=photo, concept=sized_concept(concept, mesh))
    return mesh_to_arrays(mesh), info


def _from_mesh(request: AssetRequest, settings: L0Settings) -> tuple[Arrays, BuildInfo]:
    mesh, notes = import_mesh(request.mesh_path)  # type: ignore[arg-type]
    mesh, rotated = canonicalize(mesh, "most_stable", align_xy=True)
    size = None
    entry = None
    warnings: list[str] = []
    if request.size_hint_m is not None:
        size = catalogue.SizeSpec(longest_m=request.size_hint_m, stated=f"size hint {request.size_hint_m:g} m")
        catalogue.check_size(size)
    if request.text and request.text.strip():
        design = catalogue.design_from_text(request.text, request.size_hint_m)
        entry = design.entry
        warnings += design.warnings
        if design.size.explicit:
            size = design.size
    mesh = final_size(mesh, size)
    info = BuildInfo(source="mesh", name=request.mesh_path.stem, category=catalogue.entry_category(entry) if entry else "unknown",  # type: ignore[union-attr]
                     entry=entry, size=size, reoriented=rotated, notes=notes, warnings=warnings)
    return mesh_to_arrays(mesh), info
