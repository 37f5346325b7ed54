"""L0 geometry flow: build mesh -> convex proxy -> (a text request's) rest on the proxy -> particles, Gaussians ->
checks (each a content-cached task)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from prefect import flow

import cache
from cache import cached_task
from contracts.agents import AgentConfig
from contracts.asset_dir import ParticleBody
from contracts.request import AssetRequest, Quality
from contracts.stage import StageContract, load_contract
from tasks.agents.fallbacks import l0_designer_stand_in
from tasks.agents.records import AttemptRecorder
from tasks.geometry import pipeline, rest, sources
from tasks.geometry.checks import GeometryChecks
from tasks.geometry.collision import CoacdSettings
from tasks.geometry.outputs import publish_dir, write_outputs
from tasks.geometry.particles import ParticleSettings
from tasks.geometry.pipeline import Arrays, BuildInfo, L0Settings

TASK_VERSION = "1"  # bump when tasks/geometry changes what these tasks return
MESH_VERSION = "31"  # l0.mesh alone; 2: marching cubes no longer pinches the surface at samples on the level;
# 3: BuildInfo.generator / design_attempts (LLM Designer, reconstruction backends); 4: text -> lexicon concept and
# grammar program (BuildInfo.concept), colours and shape phrases; 5: photos keep their upright, lathe / inflation,
# size from the concept (#35); 6: standing toys seated on a flat base (canonical.seat_flat), pouches and slumps (#35);
# 7: stuffed toys weighed by their typical mass at the built size, sealed-set-6 classes (#35); 8: long and flat
# goods keep their cross-section or thickness under a stated size, bags of goods, formed sheets (sealed set 7, #35);
# 9: bagged potting soil weighs as potting mix (fills.yaml); 10: set 8's classes (a bunch of grapes, a T-rex on its
# feet and tail, a baseball cap, an owl's face, keychain toys, a rumpled t-shirt, a silk scarf, part and pose words);
# 11: set 9's (a slice across a loaf, a wrung-out cloth twisted and wet, a footbag, a solid chew bone, a knee brace);
# 12: pose adverbs after the noun ('sitting upright') are not the object; 13: set 10's classes (a hedgehog's spines,
# a pleated face mask, a slice of bread, a tied sack, a felt mouse, nested cups, a sticky hand, a 1.5 m pool noodle;
# slender objects meshed with 12 cells across); 14: set 11's (a bare small size is a sheet's thickness, a pair of a
# hand-written toy, bags holding a stated number of goods, a whole raw fish, filled doughnuts, food half eaten);
# 15: dev set 12's (bags of unknown goods as pouches, goods bulging a bag's film, compound heads, garment sizes, 'w/',
# a pair said after the goods, folded and rolled sheets' stated flat size, squid, swim rings, sleep masks, ...; and
# sealed set 12's: a pack of N sheets stacked, newborn garments, memory foam bath mats, an open C ring);
# 16: dev set 13's (a count of goods built that many side by side, a stated mass sizes the object, fractions of an
# inch before a unit, gauze rolls, rubber boots, bulb syringes, saddle and Thai pads, suction lids, crib sheets,
# underpads, radiator hoses; a grooved near-convex mesh's proxy is CoACD's root hull); 17: dev set 14's (a three-
# quarter "iso" render, a pack's printed label, a rolled sheet's stated length nearer its flat length is the sheet's,
# "for rabbits" is no object, food cues choose WordNet's food sense, car mats, nap mats, foam tiles, feeding tubes,
# O-rings, gaskets, menstrual cups, squeeze bottles, kale, foil blankets, hand warmers, pipe insulation, tentacles);
# 18: dev set 15's (one-piece garments with legs, a material's thickness is not the object's size, counted slices,
# half-empty bags, a croissant's crescent, a pillow's seam, rolled towels and socks on their plans, wedge foam, ...);
# 19: the stills in the material's finish (gloss, grain, mottle) with a scale bar (tasks.render.finish, scale_bar)
# 20: dev set 17's (pillow packs' crimped ends, a sheet draped over a bar or folded then rolled, stacked slices
# keep their outline, foam puzzle tiles, a side dent, a cinnamon roll's swirl, a powder 'dusted' over the top)
# 21: dev set 18's (a height stated of a bag lying flat is the height it stands, paper bags, reams and pads of
# sticky notes as stacked sheets, cotton wool rolls, twine balls, empty and half-used sacks)
# 22: dev sets 19 and 20's (spelling, bottles, stacked discs; a churro's ridges, a glove blown up, goods seen one by
# one through a bag, a folded sheet's stated flat size, goods in a clear bag built as the goods); 23: dev set 21's
# (a sock ball's cuff, a faceted paper wad, stitched jeans, wedge gores, a pizza slice as a wedge, half rolled, nigiri)
# 24: dev set 22's (hand-written hot dog, taco, puppets, tutu...; sheet stripes, band balls, a boa, a rope's hank)
# 25: the lexicon audit's 287 redrawn objects (session 37); 'slightly' takes a third of a shape word's change;
# 26: part colours blended over 0.6 draft cells, not 1.5 (a raised label keeps its colour); bags show their goods
# 27: session 40's (folded cloth with round creases, layer lines and towel bands; folded robes, aprons and bibs
# with their cues; a strapped sleeping bag roll; a hand-drawn entry's states by its plan; sea sponge, mozzarella, kale)
# 28: session 41's (a round cord of many turns coiled as a hank with its end and fitting; sealed set 27's redraws)
# 29: sessions 42-59's redraws and readings, a pack's goods printed on its label (tasks.geometry.prints), a bag of
# goods weighed as their retail pack, a light fabric weighing a heavy-fabric garment; 30: a print's ink contrasts
# with what lies under each letter, containers of goods (session 60); 31: a central part prints both faces, a long face
# turned up reads along its length
PROXY_VERSION = "6"  # l0.proxy alone; 2: CoACD's coarse copy keeps cells across a long or flat good's thinnest side;
# 3: a mesh that hugs its convex hull is proxied by CoACD's root hull (collision.NEAR_CONVEX_*: a yarn ball 40 s -> 0.3 s)
# 4: CoACD's pieces merged down to the budget by ours (collision.merge_hulls: a dog bed 38 -> 20 s), the coarse copy
# never finer than the mesh (a foam puzzle tile 21 -> 8 s)
# 5: the budget grows while the hulls' union is over 1.5x the mesh (collision.merged_to_cover: a beanie, a hat)
# 6: a coarse copy that lost a thin wall is redone finer or skipped (a straw hat's proxy covered 5 % of it); a good of
# at most 12 pieces over 1.5x is split at finer CoACD thresholds (a necktie: 1 piece, 2.27x -> 4, 1.24x; a coiled rope
# 7, 1.95x -> 32, 1.47x)
REST_VERSION = "1"  # l0.rest alone (tasks.geometry.rest: a text request's mesh and proxy turned together onto the
# proxy's nearest face that holds a lean when the pose built is no rest of it; session 45: a padel ball on its seam,
# a kielbasa's U)
PARTICLES_VERSION = "2"  # l0.particles alone; 2: a hollow concept's particles are its shell (build_body, with the
# ParticleBody record; session 32), opt-in: ParticleSettings.hollow_particles (the L0 contract's) keys it
GAUSSIANS_VERSION = "3"  # l0.gaussians alone; 2: surface discs dense and small for the particle spacing (#36);
# 3: on blue-noise surface samples


@dataclass(frozen=True)
class L0Result:
    """What L0 established: aligned mesh, convex proxy, particles, Gaussians, build record and gate results."""

    mesh: Arrays
    proxy: Arrays
    particles: Arrays
    gaussians: Arrays
    info: BuildInfo
    checks: GeometryChecks
    body: ParticleBody | None = None  # what the particles fill (solid, or a hollow object's shell); None: not recorded


def geometry_request(request: AssetRequest) -> AssetRequest:
    """The fields of a request that geometry depends on (material words or targets never invalidate L0)."""
    return AssetRequest(text=request.text, image_path=request.image_path, mesh_path=request.mesh_path,
                        size_hint_m=request.size_hint_m, seed=request.seed, geometry_backend=request.geometry_backend,
                        pose=request.pose)


@cached_task(version=MESH_VERSION, name="l0.mesh")
def build_mesh(request: AssetRequest, settings: L0Settings) -> tuple[Arrays, BuildInfo]:
    """Aligned, metric, watertight mesh with colours."""
    return sources.build_mesh(request, settings)


@cached_task(version=f"{TASK_VERSION}.{PROXY_VERSION}", name="l0.proxy")
def build_proxy(mesh: Arrays, coacd: CoacdSettings) -> Arrays:
    """CoACD convex collision proxy."""
    return pipeline.build_proxy(mesh, coacd)


@cached_task(version=f"{TASK_VERSION}.{REST_VERSION}", name="l0.rest")
def rest_on_proxy(mesh: Arrays, proxy: Arrays) -> tuple[Arrays, Arrays, str | None]:
    """The mesh and proxy on a rest of the proxy, and the note when they were turned (tasks.geometry.rest)."""
    return rest.rest_on_proxy(mesh, proxy)


@cached_task(version=f"{TASK_VERSION}.{PARTICLES_VERSION}", name="l0.particles")
def build_particles(mesh: Arrays, particles: ParticleSettings, wall_m: float | None = None,
                    solid_reason: str | None = None) -> tuple[Arrays, ParticleBody]:
    """MPM particles with volumes summing to the mesh volume, or to a hollow object's shell of wall_m."""
    return pipeline.build_body(mesh, particles, wall_m, solid_reason)


def _wall(request: AssetRequest, info: BuildInfo, mesh: Arrays) -> tuple[float | None, str | None]:
    """The wall the particles are a shell of (pipeline.hollow_wall), from the concept and the whole request's
    material words (its material intent too: L1 weighs the object by them), fitted on the built mesh to the
    concept's typical mass (the wall L1 weighs)."""
    return pipeline.hollow_wall(info.concept, request.material_intent or request.text, mesh)


@cached_task(version=GAUSSIANS_VERSION, name="l0.gaussians")
def build_gaussians(mesh: Arrays, particles: Arrays, per_particle: float, surface_fraction: float,
                    max_gaussians: int, seed: int) -> Arrays:
    """Gaussians bound to the particles."""
    s = L0Settings(quality="draft", marching_cubes_resolution=64,
                   particles=ParticleSettings(cells_per_longest_extent=2, max_particles=1), coacd=CoacdSettings(),
                   gaussians_per_particle=per_particle, gaussian_surface_fraction=surface_fraction,
                   max_gaussians=max_gaussians, seed=seed)
    return pipeline.build_gaussians(mesh, particles, s)


@cached_task(version=TASK_VERSION, name="l0.checks")
def check_geometry(mesh: Arrays, proxy: Arrays, particles: Arrays, gaussians: Arrays,
                   contract: StageContract) -> GeometryChecks:
    """Hard-gate metrics against the L0 contract."""
    return pipeline.check_geometry(mesh, proxy, particles, gaussians, contract)


@flow(name="l0-geometry", log_prints=False)
def l0_geometry(request: AssetRequest, settings: L0Settings, contract: StageContract) -> L0Result:
    """Build and check the geometry of one request."""
    mesh, info = build_mesh(geometry_request(request), settings)
    proxy = build_proxy(mesh, settings.coacd)
    if pipeline.pose_is_ours(request):
        mesh, proxy, note = rest_on_proxy(mesh, proxy)
        info = pipeline.with_rest_note(info, note)
    particles, body = build_particles(mesh, settings.particles, *_wall(request, info, mesh))
    body = pipeline.with_gas(body, info.concept)  # a pressurised ball's shell records its gas (outside the cache key)
    gaussians = build_gaussians(mesh, particles, settings.gaussians_per_particle, settings.gaussian_surface_fraction,
                                settings.max_gaussians, settings.seed)
    checks = check_geometry(mesh, proxy, particles, gaussians, contract)
    return L0Result(mesh, proxy, particles, gaussians, info, checks, body)


def with_hollow_particles(kind: str, contract: StageContract | None = None) -> StageContract:
    """The L0 contract (the packaged one by default) with its hollow_particles parameter set: 'shell' builds a hollow
    concept's particles as its wall (opt-in, `deformsmith geometry --hollow-shell`), 'solid' as the whole volume."""
    contract = contract or load_contract("L0")
    return contract.model_copy(update={"parameters": {**contract.parameters, "hollow_particles": kind}})


def run_l0(request: AssetRequest, quality: Quality | None = None, contract: StageContract | None = None,
           use_cache: bool = True, coacd_overrides: dict | None = None,
           agents: AgentConfig | None = None) -> L0Result:
    """Run L0 for a request (the Prefect flow with cached tasks, or the plain functions with use_cache=False).
    agents: a litellm Designer writes the shape program of a text request (its Critic judges the renders when it
    has vision); the model strings key the cache."""
    contract = contract or load_contract("L0")
    settings = pipeline.settings_from_contract(quality or request.quality, contract, request.seed, coacd_overrides)
    stood_in: str | None = None
    if agents is not None and agents.designer.backend == "litellm" and request.input_kind == "text" \
            and request.geometry_backend is None:
        stood_in = l0_designer_stand_in(agents)
        if stood_in is None:
            critic = agents.critic if agents.critic.backend == "litellm" else None
            settings = settings.model_copy(update={"designer": agents.designer, "critic": critic})
    result = _run_l0(request, settings, contract, use_cache)
    if stood_in is not None:  # the offline build is cached under the offline key, so a later run with a key asks
        info = result.info.model_copy(update={"warnings": [*result.info.warnings, stood_in]})
        result = L0Result(result.mesh, result.proxy, result.particles, result.gaussians, info, result.checks,
                          result.body)
    return result


def _run_l0(request: AssetRequest, settings: pipeline.L0Settings, contract: StageContract,
            use_cache: bool) -> L0Result:
    """L0 with resolved settings: the plain functions (use_cache=False) or the Prefect flow with cached tasks."""
    if not use_cache:
        mesh, info = sources.build_mesh(geometry_request(request), settings)
        proxy = pipeline.build_proxy(mesh, settings.coacd)
        if pipeline.pose_is_ours(request):
            mesh, proxy, info = pipeline.rested(mesh, proxy, info)
        particles, body = pipeline.build_body(mesh, settings.particles, *_wall(request, info, mesh))
        body = pipeline.with_gas(body, info.concept)
        gaussians = pipeline.build_gaussians(mesh, particles, settings)
        return L0Result(mesh, proxy, particles, gaussians, info,
                        pipeline.check_geometry(mesh, proxy, particles, gaussians, contract), body)
    with cache.local_runtime():
        return l0_geometry(request, settings, contract)


def write_l0(result: L0Result, out_dir: Path, extra: dict | None = None,
             request: AssetRequest | None = None) -> dict[str, str]:
    """Publish an L0 result into out_dir atomically (nothing is left behind on error). `request`, the whole request
    (material intent and target overrides too, which never key L0's cache), is stored as geometry.json's `request`,
    so that `physical` and `material` run on the directory derive the material as `generate` does."""
    if request is not None:
        extra = {**(extra or {}), "request": request.model_dump(mode="json")}
    files: dict[str, str] = {}

    def build(tmp: Path) -> None:
        body = {"particles": result.body.model_dump(mode="json")} if result.body is not None else {}
        files.update(write_outputs(tmp, result.mesh, result.proxy, result.particles, result.gaussians, result.info,
                                   result.checks, {**body, **(extra or {})}))
        if result.info.design_attempts:  # the LLM Designer's attempts, as the other stages record theirs

            recorder = AttemptRecorder(tmp, "L0")
            for attempt in result.info.design_attempts:
                recorder.record(attempt)
            recorder.close()

    publish_dir(build, out_dir)
    return files


__all__ = ["L0Result", "run_l0", "write_l0", "with_hollow_particles", "l0_geometry", "geometry_request", "np"]
