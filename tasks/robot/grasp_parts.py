"""Which part of a soft toy or animal a grasp holds, and the Planner's preference for the body over end parts.

A person picks a plush toy up by its body (torso, shell), not by its head, an ear or a leg: an end part is thin or
hangs off a narrow neck, so the toy swings and bends about it, and a toy carried by the head looks wrong. For an
object built from a shape program (the text path, ``geometry.json``'s ``info.program``) each grasp's centre is mapped
back into the program's frame and named by the part it lies deepest inside. Without a program (a photo inflated from
its silhouette, an imported mesh) the body is told by depth: the grasp centre's distance to the surface against the
object's largest inscribed depth (the torso is the thickest region of a plush toy; limbs, ears and a head on a neck
are thinner). Body grasps keep their sampler order and go first; end-part grasps stay as fall-backs, and the
preference says why in words for the action plan.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
import trimesh
from scipy.spatial import cKDTree

from contracts.robot import GraspCandidate
from contracts.shape import ShapeProgram
from tasks.geometry.grammar.parts import part_group
from tasks.geometry.meshing import sample_program
from tasks.geometry.sdf import part_sdf
from tasks.robot.grasp import GraspSettings

# part groups (tasks.geometry.grammar.parts.part_group) that are the body a person holds a toy or an animal by
BODY_PARTS = frozenset({"body", "torso", "belly", "tummy", "chest", "shell", "carapace", "hull", "trunk body",
                        "back", "breast", "abdomen", "thorax", "cushion", "pillow body"})
# categories whose objects a person holds by the body (plush toys and animal-shaped things)
BODY_FIRST_CATEGORIES = frozenset({"plush_animal", "animal", "toy_animal", "rubber_toy", "pet_toy"})
SIDE_TURNS_DEG = (0.0, -45.0, 45.0, -90.0, 90.0)  # approaches tried about each closing line when the body needs a side
DEPTH_SHARE = 0.6  # without a program: a grasp centre at least this share of the deepest interior is on the body


@dataclass(frozen=True)
class PartPreference:
    """The candidates reordered (body first), each one's part, and the sentence the action plan records."""

    candidates: list[GraspCandidate]
    parts: list[str]
    reason: str


def _program_frame(points_m: np.ndarray, program: ShapeProgram, bounds_m: np.ndarray) -> np.ndarray:
    """Asset-frame points [m] -> the program's frame, for a mesh that was only scaled per axis and moved (not turned)
    after meshing: the program's meshed bounding box maps onto the asset's (``bounds_m``, (2, 3))."""
    field, origin, spacing = sample_program(program.model_copy(update={"target_extent_m": None}), 40)
    inside = np.argwhere(field <= 0.0)
    lo = origin + spacing * inside.min(axis=0)
    hi = origin + spacing * (inside.max(axis=0) + 1)
    scale = (hi - lo) / np.maximum(bounds_m[1] - bounds_m[0], 1e-9)
    return (points_m - bounds_m[0]) * scale + lo


def program_parts(points_m: np.ndarray, program: ShapeProgram, bounds_m: np.ndarray) -> list[str]:
    """The part each asset-frame point lies deepest inside (its group: 'left ear' -> 'ear'); unions only."""
    p = _program_frame(np.asarray(points_m, dtype=np.float64), program, np.asarray(bounds_m, dtype=np.float64))
    unions = [part for part in program.parts if part.operation == "union"]
    d = np.stack([part_sdf(p, part) for part in unions], axis=1)
    return [part_group(unions[i].name) for i in np.argmin(d, axis=1)]


def depth_parts(points_m: np.ndarray, mesh: trimesh.Trimesh, interior_m: np.ndarray | None = None,
                samples: int = 4000) -> list[str]:
    """'body' where a point's depth below the surface is at least DEPTH_SHARE of the object's deepest, else 'end'.
    ``interior_m``: points inside the object (the MPM particles) to find the deepest; default a filled voxel grid."""
    surface, _ = trimesh.sample.sample_surface_even(mesh, samples, seed=0)
    tree = cKDTree(np.asarray(surface))
    if interior_m is None or len(interior_m) == 0:
        interior_m = np.asarray(mesh.voxelized(float(mesh.extents.max()) / 24.0).fill().points)
    deepest = float(tree.query(np.asarray(interior_m, dtype=np.float64))[0].max())
    depth = tree.query(np.asarray(points_m, dtype=np.float64))[0]
    return ["body" if d >= DEPTH_SHARE * deepest else "end" for d in depth]


def prefer_body(candidates: list[GraspCandidate], parts: list[str], how: str) -> PartPreference:
    """Body grasps first (sampler order kept within each group); ``how`` says how parts were told ('shape program'
    or 'depth')."""
    body = [i for i, p in enumerate(parts) if p in BODY_PARTS]
    if not candidates:
        return PartPreference([], [], "no grasp to choose from")
    order = body + [i for i in range(len(candidates)) if i not in set(body)]
    ranked = [candidates[i].model_copy(update={"rank": r}) for r, i in enumerate(order)]
    first = parts[order[0]]
    others = sorted({p for p in parts if p not in BODY_PARTS})
    if not body:
        reason = (f"held by the {first}: no feasible grasp lies on the body (parts told by {how}; the feasible "
                  f"grasps are on: {', '.join(others)})")
    elif order[0] != 0:
        reason = (f"held by the {first}, not the {parts[0]} the sampler ranked first: a soft toy or animal is "
                  f"picked up by its body, which does not swing or bend about a thin or end part (parts told by "
                  f"{how}; {len(body)} of {len(candidates)} feasible grasps on the body)")
    else:
        what = "the body" if first == "body" else f"the {first}, the body"
        reason = f"held by {what} (parts told by {how}; {len(body)} of {len(candidates)} feasible grasps on the body)"
    return PartPreference(ranked, [parts[i] for i in order], reason)


def body_first(candidates: list[GraspCandidate], category: str, program: ShapeProgram | None,
               reoriented: bool, mesh: trimesh.Trimesh, interior_m: np.ndarray | None = None
               ) -> PartPreference | None:
    """The Planner's part preference for a soft toy or animal (None for other categories): parts from the shape
    program when the asset kept the program's orientation, else from depth."""
    if category not in BODY_FIRST_CATEGORIES or not candidates:
        return None
    centres = np.asarray([c.center_m for c in candidates], dtype=np.float64)
    if program is not None and not reoriented:
        parts = program_parts(centres, program, np.asarray(mesh.bounds))
        return prefer_body(candidates, parts, "the shape program's parts")
    parts = depth_parts(centres, mesh, interior_m)
    return prefer_body(candidates, parts, "depth below the surface")


def _reachable_first(pref: PartPreference, reachable: Callable[[GraspCandidate], bool]) -> PartPreference:
    """Body grasps the arm can execute ahead of those it cannot (order kept otherwise); stops at the first one."""
    for i, (c, p) in enumerate(zip(pref.candidates, pref.parts)):
        if p in BODY_PARTS and reachable(c):
            order = [i] + [j for j in range(len(pref.candidates)) if j != i]
            return PartPreference([pref.candidates[j].model_copy(update={"rank": r}) for r, j in enumerate(order)],
                                  [pref.parts[j] for j in order], pref.reason)
    return pref


def body_first_grasps(select: Callable[[GraspSettings], list[GraspCandidate]], settings: GraspSettings,
                      category: str, program: ShapeProgram | None, reoriented: bool, mesh: trimesh.Trimesh,
                      reachable: Callable[[GraspCandidate], bool] = lambda c: True,
                      interior_m: np.ndarray | None = None) -> tuple[list[GraspCandidate], str]:
    """The Planner's grasps for an object, body first for a soft toy or animal: the sampler's top-down grasps, and
    when none of them is on the body (a sitting teddy's head is over its torso), side approaches as well (the open
    hand comes in level with the body); side grasps the arm can execute (``reachable``) first. Returns the
    candidates and the sentence for the action plan ('' when the preference does not apply)."""
    grasps = select(settings)
    pref = body_first(grasps, category, program, reoriented, mesh, interior_m)
    if pref is None:
        return grasps, ""
    if pref.parts and pref.parts[0] in BODY_PARTS:
        return pref.candidates, pref.reason
    side = select(replace(settings, max_tilt_deg=90.0, approach_turns_deg=SIDE_TURNS_DEG))
    side_pref = body_first(side, category, program, reoriented, mesh, interior_m)
    side_pref = _reachable_first(side_pref, reachable) if side_pref is not None else None
    if side_pref is not None and side_pref.parts and side_pref.parts[0] in BODY_PARTS:
        return side_pref.candidates, side_pref.reason + "; approached from the side: from above the hand cannot reach it"
    return pref.candidates, pref.reason + "; no side approach reaches the body either"


__all__ = ["body_first_grasps", "BODY_FIRST_CATEGORIES", "BODY_PARTS", "PartPreference", "body_first", "depth_parts", "prefer_body",
           "program_parts"]
