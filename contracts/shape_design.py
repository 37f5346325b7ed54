"""Role I/O of L0's LLM shape Designer and vision Critic, and the L0 contract's bounds on a proposed ShapeProgram."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from contracts.base import Model
from contracts.shape import ShapeProgram
from contracts.stage import L0Parameters, StageContract

FRAME = ("metres; z up; the object rests on the ground with its lowest point at z = 0 after meshing; put its "
         "longest horizontal extent on x; parts are combined in order as signed distances (union / subtract / "
         "intersect, smooth by blend_m), so every union part must touch or overlap the body built before it")


class ShapeBounds(Model):
    """What the L0 contract allows in one proposed ShapeProgram (contracts/stages/L0_geometry.yaml, shape_*)."""

    max_parts: int = Field(ge=1, description="parts of one program [-]")
    part_size_m: tuple[float, float] = Field(description="range of every primitive dimension [m]")
    extent_m: tuple[float, float] = Field(description="range of the program's longest bounding-box side [m]")
    max_blend_m: float = Field(ge=0, description="largest blend radius [m]")
    part_scale: tuple[float, float] = Field(description="range of each per-axis transform scale [-]")
    check_resolution: int = Field(default=40, ge=8, description="cells along the longest extent of the one-body "
                                  "check [-]")
    max_detached_share: float = Field(default=0.01, ge=0, lt=1, description="volume share allowed outside the "
                                      "largest body [-]")

    @classmethod
    def from_contract(cls, contract: StageContract) -> ShapeBounds:
        """The bounds in the L0 contract's parameters."""
        p = L0Parameters.of(contract)
        return cls(max_parts=p.shape_max_parts, part_size_m=p.shape_part_size_m, extent_m=p.shape_extent_m,
                   max_blend_m=p.shape_max_blend_m, part_scale=p.shape_part_scale,
                   check_resolution=p.shape_check_resolution, max_detached_share=p.shape_max_detached_share)


class ShapeDesignRequest(Model):
    """What the L0 Designer sees: the user's words, the size they stated, the bounds, and feedback on a draft."""

    text: str = Field(description="the user's description of the object")
    stated_size: str | None = Field(default=None, description="the size stated in the text or as a hint; the mesh "
                                    "is scaled to it after meshing, so proportions matter more than absolute size")
    frame: str = FRAME
    bounds: ShapeBounds
    previous: ShapeProgram | None = Field(default=None, description="the draft the Critic asked to revise")
    critique: str | None = Field(default=None, description="what the Critic saw wrong in the previous draft")
    budget_left: int = Field(ge=0, description="answers left, this one included; each invalid answer costs one")


class ShapeCriticRequest(Model):
    """What the L0 Critic sees, besides the rendered views: the request and the program that was meshed."""

    text: str = Field(description="the user's description of the object")
    program: ShapeProgram
    views: list[str] = Field(description="the images attached, in order: orthographic front (+x), side (-y), top")
    extents_m: tuple[float, float, float] = Field(description="the meshed object's bounding box x, y, z [m]")


class ShapeCritique(Model):
    """Accept the rendered object as what was asked for, or ask for one revision with the problems seen."""

    verdict: Literal["accept", "revise"]
    problems: list[str] = Field(default_factory=list, description="what differs from the request, per part")
    rationale: str = ""

    def feedback(self) -> str:
        """One line for the Designer."""
        return "; ".join([*self.problems, self.rationale] if self.rationale else self.problems) or "revise the shape"
