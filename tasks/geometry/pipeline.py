"""The L0 units of work as plain functions (no Prefect): request -> mesh -> proxy, particles, Gaussians -> checks."""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
import trimesh
from pydantic import Field

from contracts.agents import RoleConfig
from contracts.asset_dir import ParticleBody
from contracts.base import Model
from contracts.concept import ConceptMatch
from contracts.errors import InputError
from contracts.evidence import Attempt
from contracts.request import AssetRequest, Quality
from contracts.shape import ShapeProgram
from contracts.stage import L0Parameters, StageContract, at_quality, load_contract
from tasks.agents.intent import match_material, own_nouns
from tasks.geometry import catalogue, concepts
from tasks.geometry.bend import MIN_ASPECT, bend_along_length, can_bend, stated_bend
from tasks.geometry.canonical import canonicalize, rest_on_ground, seat_flat
from tasks.geometry.checks import GeometryChecks, evaluate, geometry_metrics
from tasks.geometry.collision import CoacdSettings, convex_parts, union_volume
from tasks.geometry.gaussians import make_gaussians
from tasks.geometry.meshing import mesh_program, scale_to_extents
from tasks.geometry.particles import ParticleSettings, ShellUnresolved, sample_particles, sample_shell
from tasks.geometry.rest import rest_on_proxy
from tasks.geometry.shell import Surface, concept_wall_m
from tasks.geometry.silhouette import PhotoReconstruction

Arrays = dict[str, np.ndarray]


class L0Settings(Model):
    """Everything that shapes L0's output for one quality (read from the L0 stage contract)."""

    quality: Quality
    marching_cubes_resolution: int = Field(gt=8, description="voxels along the longest extent [-]")
    particles: ParticleSettings
    coacd: CoacdSettings
    gaussians_per_particle: float = Field(gt=0)
    gaussian_surface_fraction: float = Field(default=0.75, ge=0, le=1)
    max_gaussians: int = Field(default=400_000, gt=0)
    seed: int = 0
    designer: RoleConfig | None = Field(default=None, description="litellm model that writes the ShapeProgram of a "
                                        "text request (None: the offline grammar)")
    critic: RoleConfig | None = Field(default=None, description="litellm model that judges the design's renders "
                                      "(used when it has vision)")


def settings_from_contract(quality: Quality, contract: StageContract | None = None, seed: int = 0,
                           coacd_overrides: dict | None = None) -> L0Settings:
    """L0 settings for a quality preset from the contract's parameters."""
    contract = contract or load_contract("L0")
    p, typed = contract.parameters, L0Parameters.of(contract)
    coacd = {k[len("coacd_"):]: (v[quality] if isinstance(v, dict) else v) for k, v in p.items() if k.startswith("coacd_")}
    coacd.update(coacd_overrides or {})
    return L0Settings(
        quality=quality,
        marching_cubes_resolution=int(p["marching_cubes_resolution"][quality]),
        particles=ParticleSettings(
            cells_per_longest_extent=int(p["particles_per_longest_extent"][quality]),
            max_particles=int(p["max_particles"][quality]),
            min_particles=typed.min_particles,
            min_cells_through_thinnest=typed.min_cells_through_thinnest,
            hollow_particles=typed.hollow_particles,
        ),
        coacd=CoacdSettings(**coacd),
        gaussians_per_particle=float(p["gaussians_per_particle"]),
        gaussian_surface_fraction=typed.gaussian_surface_fraction,
        max_gaussians=int(at_quality(typed.max_gaussians, quality)),
        seed=seed,
    )


class BuildInfo(Model):
    """How the mesh was made: source, catalogue match, size, repairs and warnings."""

    source: Literal["text", "image", "mesh"]
    name: str
    category: str
    entry: str | None = Field(default=None, description="catalogue entry used (text / image prior)")
    program: ShapeProgram | None = None
    size: catalogue.SizeSpec | None = None
    modifiers: list[str] = Field(default_factory=list)
    concept: ConceptMatch | None = Field(default=None, description="text path: the lexicon concept understood, the "
                                         "fallback taken and the real object's typical mass")
    segmentation: str | None = Field(default=None, description="image path: alpha | grabcut+saliency[+shadow] "
                                     "(tasks/geometry/image.py); the reconstruction is in `photo`")
    thickness_m: float | None = Field(default=None, description="depth along the camera's view (image path) [m]")
    photo: PhotoReconstruction | None = Field(default=None, description="image path: how the photo became a mesh")
    reoriented: bool = Field(default=False, description="the resting pose differs from the input's orientation")
    notes: list[str] = Field(default_factory=list)
    warnings: list[str] = Field(default_factory=list)
    generator: str = Field(default="offline", description="what made the shape: offline | litellm/<model> | "
                           "backend:<spec> (a fallback to the offline grammar says so in warnings)")
    design_attempts: list[Attempt] = Field(default_factory=list, description="the LLM Designer's attempts "
                                           "(written to evidence/attempts.jsonl as stage L0)")


def mesh_to_arrays(mesh: trimesh.Trimesh) -> Arrays:
    """vertices (V, 3) float64 [m], faces (F, 3) int64, colors (V, 4) uint8."""
    vc = np.asarray(mesh.visual.vertex_colors, dtype=np.uint8) if mesh.visual.kind == "vertex" else \
        np.tile(np.array([190, 190, 190, 255], np.uint8), (len(mesh.vertices), 1))
    return {"vertices": np.asarray(mesh.vertices, np.float64), "faces": np.asarray(mesh.faces, np.int64), "colors": vc}


def arrays_to_mesh(a: Arrays) -> trimesh.Trimesh:
    """Inverse of mesh_to_arrays."""
    m = trimesh.Trimesh(a["vertices"], a["faces"], process=False)
    m.visual = trimesh.visual.ColorVisuals(m, vertex_colors=a["colors"])
    return m


def final_size(mesh: trimesh.Trimesh, size: catalogue.SizeSpec | None) -> trimesh.Trimesh:
    if size is not None:
        scale_to_extents(mesh, size.resolve(mesh.extents))
    rest_on_ground(mesh)
    ext = mesh.extents
    if ext.max() > catalogue.MAX_SIZE_M or ext.max() < catalogue.MIN_SIZE_M:
        raise InputError(
            f"the object would be {ext.max():.4g} m long, outside [{catalogue.MIN_SIZE_M:g}, {catalogue.MAX_SIZE_M:g}] m "
            "(mesh units are taken as metres: give a size, e.g. --size-m 0.2)"
        )
    return mesh


SEATED_CATEGORIES = frozenset({"plush_animal", "rubber_toy", "silicone_toy"})  # standing toys get a flat base


def mesh_from_text(request: AssetRequest, settings: L0Settings) -> tuple[Arrays, BuildInfo]:
    design = catalogue.design_from_text(request.text or "", request.size_hint_m)
    mesh = mesh_program(design.program, settings.marching_cubes_resolution)
    mesh, rotated = canonicalize(mesh, "keep_if_stable", align_xy=False)
    if rotated:
        mesh, _ = canonicalize(mesh, "keep_if_stable", align_xy=True)
    elif design.program.category in SEATED_CATEGORIES:
        mesh, _ = seat_flat(mesh)
    mesh = final_size(mesh, design.size)
    concept = design.concept
    if concept is not None and concept.category in concepts.STUFFED_CATEGORIES:
        _final, stretch = catalogue.final_scale(design.size, design.program, concept.typical_size_m or 0.0)
        concept = concepts.stuffed_as_built(concept, float(mesh.extents.max()), float(mesh.volume), stretch,
                                           request.text or "")
    sized = sized_concept(concept, mesh)  # (the straight object's size: a bend keeps its length and volume)
    mesh, notes, bent = _bent_as_said(mesh, request.text or "")
    warnings = [w for w in design.warnings if not (bent and w.startswith("state 'bent' is not drawn"))]
    program = design.program.model_copy(update={"target_extent_m": tuple(float(v) for v in mesh.extents)})
    info = BuildInfo(source="text", name=design.program.name, category=design.program.category, entry=design.entry,
                     program=program, size=design.size, modifiers=design.modifiers, reoriented=rotated or bent,
                     warnings=warnings, concept=sized, notes=notes)
    return mesh_to_arrays(mesh), info


def _bent_as_said(mesh: trimesh.Trimesh, text: str) -> tuple[trimesh.Trimesh, list[str], bool]:
    """(mesh, notes, bent): the mesh bent as the request says ('bent into a U') when it is long enough to bend, with
    the note saying so; else the mesh and a note when a bend was said but the object is too short to show one."""
    bend = stated_bend(text)
    if bend is None:
        return mesh, [], False
    if not can_bend(mesh.extents):
        return mesh, [f"'{bend.words}': not drawn, the object is not long enough to bend "
                      f"(longest side under {MIN_ASPECT:g}x the others)"], False
    length = float(max(mesh.extents[:2]))
    return bend_along_length(mesh, bend.angle_rad), [
        f"'{bend.words}': drawn bent by {math.degrees(bend.angle_rad):.0f} deg along its {length:.3g} m length (its "
        "length and volume kept)"], True


def sized_concept(concept: ConceptMatch | None, mesh: trimesh.Trimesh) -> ConceptMatch | None:
    """The concept with the plausible mass range at the built size: typical mass x (built / typical longest
    extent)^3, within a factor of 2 either way [kg]."""
    if concept is None or concept.typical_mass_kg is None or concept.typical_size_m is None:
        return concept
    m = concept.typical_mass_kg * (float(mesh.extents.max()) / concept.typical_size_m) ** 3
    return concept.model_copy(update={"typical_mass_range_kg": (m / 2.0, m * 2.0)})


def build_proxy(mesh: Arrays, settings: CoacdSettings) -> Arrays:
    """Convex parts as concatenated arrays: vertices, faces (part-local indices), part_vertex_count, part_face_count."""
    parts = convex_parts(arrays_to_mesh(mesh), settings)
    return {
        "vertices": np.concatenate([p.vertices for p in parts]).astype(np.float64),
        "faces": np.concatenate([p.faces for p in parts]).astype(np.int64),
        "part_vertex_count": np.array([len(p.vertices) for p in parts], np.int64),
        "part_face_count": np.array([len(p.faces) for p in parts], np.int64),
        "union_volume_m3": np.array(union_volume(parts)),
    }


def proxy_parts(proxy: Arrays) -> list[trimesh.Trimesh]:
    """Split concatenated proxy arrays back into convex meshes."""
    out = []
    v0 = f0 = 0
    for nv, nf in zip(proxy["part_vertex_count"], proxy["part_face_count"]):
        out.append(trimesh.Trimesh(proxy["vertices"][v0 : v0 + nv], proxy["faces"][f0 : f0 + nf], process=False))
        v0, f0 = v0 + int(nv), f0 + int(nf)
    return out


def build_particles(mesh: Arrays, settings: ParticleSettings) -> Arrays:
    """positions_m (N, 3), volumes_m3 (N,) summing to the mesh volume, colors (N, 3) uint8, spacing_m, lattice_fill_ratio,
    body_volume_m3 (what the volumes sum to: the mesh volume)."""
    return build_body(mesh, settings)[0]


SHELL_OPT_IN = ("built solid: a shell is opt-in (L0 parameter hollow_particles: shell) until a gas-pressure model "
                "keeps a pressurised ball's bounce (a rubber shell alone: tennis-ball rule rebound 0.12, rule 0.53-0.58)")


def build_body(mesh: Arrays, settings: ParticleSettings, wall_m: float | None = None,
               solid_reason: str | None = None) -> tuple[Arrays, ParticleBody]:
    """The MPM particles and what they fill: a hollow object's shell of wall_m (tasks.geometry.particles.sample_shell)
    when given, settings.hollow_particles is 'shell' (opt-in: SHELL_OPT_IN says why) and the lattice resolves the wall
    within the budget, else the solid (build_particles' arrays; the reason a hollow object stayed solid in the record:
    solid_reason, SHELL_OPT_IN, or why its wall could not be resolved)."""
    m = arrays_to_mesh(mesh)
    volume = float(m.volume)
    if wall_m is not None and settings.hollow_particles != "shell":
        solid_reason = SHELL_OPT_IN
    elif wall_m is not None:
        try:
            pos, vol, col, dx, fill, shell_m3 = sample_shell(m, settings, wall_m)
        except ShellUnresolved as exc:
            solid_reason = f"built solid: {exc}"
        else:
            arrays = {"positions_m": pos, "volumes_m3": vol, "colors": col, "spacing_m": np.array(dx),
                      "lattice_fill_ratio": np.array(fill), "body_volume_m3": np.array(shell_m3)}
            return arrays, ParticleBody(kind="shell", wall_m=wall_m, requested_wall_m=wall_m, spacing_m=dx,
                                        volume_m3=shell_m3, enclosed_volume_m3=volume)
    pos, vol, col, dx, fill = sample_particles(m, settings)
    arrays = {"positions_m": pos, "volumes_m3": vol, "colors": col, "spacing_m": np.array(dx),
              "lattice_fill_ratio": np.array(fill), "body_volume_m3": np.array(volume)}
    return arrays, ParticleBody(kind="solid", requested_wall_m=wall_m, spacing_m=dx, volume_m3=volume,
                                enclosed_volume_m3=volume, reason=solid_reason)


def with_gas(body: ParticleBody, concept: ConceptMatch | None) -> ParticleBody:
    """A shell's record with the gas it encloses (the concept's inflation pressure and source: a pressurised ball);
    a solid's, or an unpressurised shell's, as it is."""
    if not body.shell or concept is None or concept.inflation_gauge_pa is None:
        return body
    return body.model_copy(update={"gauge_pressure_pa": concept.inflation_gauge_pa,
                                   "gauge_pressure_source": concept.inflation_source})


def pose_is_ours(request: AssetRequest) -> bool:
    """True when L0 chose the resting pose (a text request built by the grammar or an LLM Designer), so it may turn the
    body onto its proxy's resting face (tasks.geometry.rest); a photo's upright, an imported mesh's pose and a
    reconstruction backend's are the caller's."""
    return request.input_kind == "text" and request.geometry_backend is None


def rested(mesh: Arrays, proxy: Arrays, info: BuildInfo) -> tuple[Arrays, Arrays, BuildInfo]:
    """The mesh, proxy and build record on a rest of the proxy (tasks.geometry.rest.rest_on_proxy); the record says
    when they were turned."""
    mesh, proxy, note = rest_on_proxy(mesh, proxy)
    return mesh, proxy, with_rest_note(info, note)


def with_rest_note(info: BuildInfo, note: str | None) -> BuildInfo:
    """The build record of a body rest_on_proxy turned (reoriented, with its note); as it is when kept (None)."""
    if note is None:
        return info
    return info.model_copy(update={"reoriented": True, "notes": [*info.notes, note]})


def hollow_wall(concept: ConceptMatch | None, words: str | None,
                mesh: Arrays | None = None) -> tuple[float | None, str | None]:
    """The wall a hollow concept's particles are a shell of [m], else None with the reason a hollow object is built
    solid (None for a solid concept): a one-layer sheet (its built solid is that layer already), no wall in the lexicon
    (an effective density instead), or a material the words name that is not the concept's ('a foam tennis ball').
    mesh: the built surface, on which the wall is fitted to the concept's typical mass (tasks.geometry.shell.
    concept_wall_m: the shell's true volume, as L1 weighs it); without it, the lexicon's wall."""
    if concept is None or not concept.hollow:
        return None, None
    if concept.sheet:
        return None, "built solid: a one-layer sheet drawn as a thin solid (its particles are that layer)"
    if concept.wall_thickness_m is None:
        return None, "built solid: the lexicon gives no wall thickness (an effective density instead)"
    if words and concept.default_material is not None:
        named = match_material(words, None, concept.default_material, own_nouns(concept), True)
        if named != concept.default_material:
            return None, f"built solid: the words name {named}, not the {concept.default_material} of its wall"
    if mesh is not None:
        return concept_wall_m(concept, Surface.of(arrays_to_mesh(mesh))), None
    return concept.wall_thickness_m, None


def build_gaussians(mesh: Arrays, particles: Arrays, settings: L0Settings) -> Arrays:
    """Gaussians bound to particles (see tasks.geometry.gaussians)."""
    n = int(min(settings.max_gaussians, round(settings.gaussians_per_particle * len(particles["positions_m"]))))
    g = make_gaussians(arrays_to_mesh(mesh), particles["positions_m"], float(particles["spacing_m"]), max(n, 16),
                       settings.seed, settings.gaussian_surface_fraction, settings.max_gaussians)
    return dict(g)


def check_geometry(mesh: Arrays, proxy: Arrays, particles: Arrays, gaussians: Arrays,
                   contract: StageContract | None = None) -> GeometryChecks:
    """Hard-gate metrics of one L0 candidate against the L0 contract."""
    m = arrays_to_mesh(mesh)
    metrics = geometry_metrics(m, particles, gaussians, float(proxy["union_volume_m3"]), len(proxy["part_face_count"]))
    return evaluate(metrics, contract or load_contract("L0"))
