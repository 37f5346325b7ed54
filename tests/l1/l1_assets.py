"""Light L0 assets for L1's priors and mass band: a request's built mesh and its geometry record."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from contracts.concept import ConceptMatch
from contracts.request import AssetRequest
from tasks.geometry import pipeline, sources
from tasks.geometry.outputs import L0Asset


FAST_COACD = dict(preprocess_resolution=20, max_convex_hull=8, threshold=0.15, mcts_iterations=30, mcts_nodes=8,
                  mcts_max_depth=2, resolution=500, max_input_faces=3000)
BUILT = "built"  # asset_of(concept=BUILT): keep the concept L0 recorded (if any)


def asset_of(request: AssetRequest, concept: ConceptMatch | None | str = BUILT, stored: bool = True) -> L0Asset:
    """An L0 asset of a request's built mesh (one particle per mesh: L1's priors and mass band need only the record,
    the mesh and the volume), its record as `write_l0(..., request=request)` writes it. concept: BUILT keeps L0's
    own info.concept, None removes it (no concept known), a ConceptMatch replaces it (a fixture)."""
    mesh, info = sources.build_mesh(request, pipeline.settings_from_contract("draft"))
    m = pipeline.arrays_to_mesh(mesh)
    record: dict = {"info": info.model_dump(mode="json", exclude={"design_attempts"})}
    if concept is None:
        record["info"].pop("concept", None)
    elif isinstance(concept, ConceptMatch):
        record["info"]["concept"] = concept.model_dump(mode="json")
    if stored:
        record["request"] = request.model_dump(mode="json")
    return L0Asset(mesh=m, particles_m=np.zeros((1, 3)), volumes_m3=np.array([float(m.volume)]),
                   particle_colors=np.zeros((1, 3), np.uint8), spacing_m=0.01, urdf=Path("none.urdf"),
                   proxy_parts=[], gaussians={}, record=record)


def write_l0_dir(request: AssetRequest, out: Path, stored: bool = True) -> Path:
    """A whole L0 directory of a request at draft (fast CoACD) in out; stored: geometry.json keeps the request."""
    from flows.l0_geometry import L0Result, write_l0

    s = pipeline.settings_from_contract("draft", coacd_overrides=FAST_COACD)
    mesh, info = sources.build_mesh(request, s)
    proxy = pipeline.build_proxy(mesh, s.coacd)
    particles = pipeline.build_particles(mesh, s.particles)
    gaussians = pipeline.build_gaussians(mesh, particles, s)
    checks = pipeline.check_geometry(mesh, proxy, particles, gaussians)
    write_l0(L0Result(mesh, proxy, particles, gaussians, info, checks), out, request=request if stored else None)
    return out
