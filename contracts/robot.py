"""L3 manipulation: grasps, the action plan and what happened (SI units)."""

from __future__ import annotations

from pydantic import Field

from contracts.base import Model

Vec3 = tuple[float, float, float]


class GraspCandidate(Model):
    """An antipodal two-finger grasp on the asset, in the asset frame."""

    center_m: Vec3 = Field(description="grasp centre (between the pads) [m]")
    closing_axis: Vec3 = Field(description="unit vector from finger 1 to finger 2 [-]")
    approach_axis: Vec3 = Field(description="unit vector along which the hand approaches (down = (0,0,-1)) [-]")
    width_m: float = Field(gt=0, le=0.08, description="object width between the contact points [m]")
    friction_cone_ok: bool = Field(description="both contact normals inside the friction cone [-]")
    score: float = Field(description="ranking score, higher is better [-]")
    rank: int = Field(ge=0, description="0 = best")


class ActionPlan(Model):
    """Approach -> closure -> lift -> transport -> release -> retreat; the fields L3 may revise."""

    grasp: GraspCandidate
    squeeze_depth_m: float = Field(ge=0, le=0.04, description="closure past the contact width, per finger [m]")
    closing_speed_m_per_s: float = Field(default=0.02, gt=0, description="finger closing speed, per finger [m/s]")
    grip_force_limit_n: float | None = Field(
        default=None, gt=0, description="force-guarded closure: the fingers stop closing (and hold that opening until "
        "release) when their mean normal force is about to reach this, per finger [N]; None: position control "
        "to the full squeeze")
    lift_height_m: float = Field(default=0.10, gt=0, description="height the object is lifted [m]")
    place_height_m: float = Field(default=0.01, ge=0,
                                  description="grasp height above its pick height when the fingers open [m]")
    target_xy_m: tuple[float, float] = Field(description="place target in the table frame [m]")
    initial_yaw_deg: float = Field(default=0.0, description="object yaw on the table [deg]")
    approach_duration_s: float = Field(default=1.0, gt=0)
    closure_duration_s: float = Field(default=1.0, gt=0)
    lift_duration_s: float = Field(default=1.0, gt=0)
    transport_duration_s: float = Field(default=1.5, gt=0)
    release_duration_s: float = Field(default=0.5, gt=0)
    retreat_duration_s: float = Field(default=0.5, gt=0)
    settle_duration_s: float = Field(default=0.5, gt=0)


class ManipulationOutcome(Model):
    """Labels of one pick-and-place attempt; failures are kept and labelled."""

    lifted: bool = Field(description="object rose >= the set lift height [-]")
    transported: bool = Field(description="object reached the target with the hand [-]")
    released_in_target: bool = Field(description="object rests within tolerance of the target [-]")
    settled: bool = Field(description="object at rest at the end [-]")
    slipped: bool = Field(description="object moved relative to the fingers beyond tolerance [-]")
    force_budget_violated: bool = Field(description="a finger's mean reaction force exceeded the budget [-]")
    numerically_healthy: bool = Field(description="no health check failed [-]")
    max_strain: float = Field(description="largest principal strain of any particle [-]")
    strain_p99: float | None = Field(default=None, description="principal strain exceeded by at most 1 % of the "
                                     "body's volume, largest over the recorded frames (the deformation bound) [-]")
    max_finger_force_n: tuple[float, float] = Field(description="max mean reaction force per finger [N]")
    slip_distance_m: float = Field(description="object displacement relative to the fingers while held [m]")
    place_error_m: float = Field(description="distance of the rest position from the target [m]")

    @property
    def success(self) -> bool:
        """Task success: every label good."""
        return (self.lifted and self.transported and self.released_in_target and self.settled
                and not self.force_budget_violated and self.numerically_healthy)
