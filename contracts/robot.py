"""L3 manipulation: grasps, the action plan and what happened (SI units)."""

from __future__ import annotations

from pathlib import Path

from pydantic import Field, model_validator

from contracts.base import Model
from contracts.errors import InputError
from contracts.yaml_io import load_yaml
from contracts.stage import packaged_parameters

Vec3 = tuple[float, float, float]
GRIPPERS_DIR = Path(__file__).parent / "grippers"
DEFAULT_GRIPPER = "franka_hand"


class PadSpec(Model):
    """A finger's flat gripping face: its size and how far the fingertip reaches past the face's centre."""

    width_m: float = Field(gt=0, le=0.1, description="face width, across the closing and approach axes [m]")
    height_m: float = Field(gt=0, le=0.1, description="face height, along the approach axis [m]")
    tip_beyond_center_m: float = Field(ge=0, le=0.1,
                                       description="fingertip past the face centre, along the approach [m]")


class BoxSpec(Model):
    """An axis-aligned box (lo, hi corners) in the gripper's TCP frame: z = approach, y = towards finger 0 [m]."""

    lo_m: Vec3
    hi_m: Vec3

    @model_validator(mode="after")
    def _ordered(self) -> BoxSpec:
        if any(lo >= hi for lo, hi in zip(self.lo_m, self.hi_m)):
            raise ValueError("a box needs lo_m < hi_m on every axis")
        return self


class GripperSpec(Model):
    """A parallel two-finger gripper mounted on the Panda's flange: what L3 needs of it, in SI units.

    The TCP frame is the midpoint of the two pad faces: z along the approach (out of the flange), y towards finger 0
    (the left finger), x = y cross z. ``urdf_hand``: the Franka Hand of the pybullet_data URDF, whose pads and
    collision boxes are measured from its meshes (pad and boxes may be left out); any other gripper is the Panda arm to
    its flange (panda_link8) plus ``tcp_offset_m`` / ``tcp_yaw_deg``, with the pads and boxes of this record.
    """

    name: str = Field(pattern=r"^[a-z0-9_]+$")
    title: str
    source: str = Field(description="where the figures come from")
    urdf_hand: bool = False
    stroke_m: float = Field(gt=0, le=0.3, description="largest opening between the pad faces [m]")
    max_grip_force_n: float = Field(gt=0, description="largest force each finger presses with [N]")
    max_closing_speed_m_per_s: float = Field(gt=0, description="fastest closing speed of each finger [m/s]")
    mass_kg: float = Field(gt=0, description="gripper mass, coupling included [kg]")
    tcp_offset_m: float = Field(gt=0, le=0.4, description="flange -> pad-face midpoint along the flange z [m]")
    tcp_yaw_deg: float = Field(default=0.0, description="turn of the TCP frame about the flange z [deg]")
    pad: PadSpec | None = None
    palm_box: BoxSpec | None = Field(default=None, description="gripper body, fixed in the TCP frame")
    finger_half_width_m: float | None = Field(default=None, gt=0, description="finger half width along x [m]")
    finger_thickness_m: float | None = Field(default=None, gt=0, description="finger, outward from its pad face [m]")
    finger_top_m: float | None = Field(default=None, lt=0, description="TCP-frame z where a finger meets the body [m]")

    @model_validator(mode="after")
    def _geometry(self) -> GripperSpec:
        missing = [k for k in ("pad", "palm_box", "finger_half_width_m", "finger_thickness_m", "finger_top_m")
                   if getattr(self, k) is None]
        if missing and not self.urdf_hand:
            raise ValueError(f"gripper '{self.name}' without a URDF hand needs {', '.join(missing)}")
        return self


def gripper_names() -> list[str]:
    """Names of the packaged grippers (contracts/grippers/*.yaml)."""
    return sorted(p.stem for p in GRIPPERS_DIR.glob("*.yaml"))


def load_gripper(name: str = DEFAULT_GRIPPER) -> GripperSpec:
    """A packaged gripper by name (InputError naming the known ones when there is no such gripper)."""
    path = GRIPPERS_DIR / f"{name}.yaml"
    if not path.is_file():
        raise InputError(f"no gripper '{name}': known grippers are {', '.join(gripper_names())}")
    spec = GripperSpec.model_validate(load_yaml(path.read_text(encoding="utf-8")))
    if spec.name != name:
        raise InputError(f"{path}: name '{spec.name}' does not match the file name")
    return spec


class GraspCandidate(Model):
    """An antipodal two-finger grasp on the asset, in the asset frame."""

    center_m: Vec3 = Field(description="grasp centre (between the pads) [m]")
    closing_axis: Vec3 = Field(description="unit vector from finger 1 to finger 2 [-]")
    approach_axis: Vec3 = Field(description="unit vector along which the hand approaches (down = (0,0,-1)) [-]")
    width_m: float = Field(gt=0, le=0.3, description="object width between the contact points [m] (the gripper's "
                           "stroke bounds it)")
    friction_cone_ok: bool = Field(description="both contact normals inside the friction cone [-]")
    score: float = Field(description="ranking score, higher is better [-]")
    rank: int = Field(ge=0, description="0 = best")


class ActionPlan(Model):
    """Approach -> closure -> lift -> transport -> release -> retreat; the fields L3 may revise."""

    grasp: GraspCandidate
    gripper: str = Field(default=DEFAULT_GRIPPER, description="the gripper on the flange (contracts/grippers/*.yaml)")
    gripper_reason: str = Field(default="", description="why the Planner chose that gripper")
    grasp_reason: str = Field(default="", description="the part the grasp holds and why (a soft toy or animal is "
                              "held by its body), '' when no part preference applies")
    squeeze_depth_m: float = Field(ge=0, le=0.15, description="closure past the contact width, per finger [m]; "
                                   "with a force target, the deepest the fingers may close")
    closing_speed_m_per_s: float = Field(default=0.02, gt=0, description="finger closing speed, per finger [m/s]")
    grip_force_limit_n: float | None = Field(
        default=None, gt=0, description="force-controlled closure: the fingers close until their mean normal force is "
        "about to reach this force target, per finger [N], and hold that opening until release (however deep, up to "
        "squeeze_depth_m); None: position control to the full squeeze")
    lift_height_m: float = Field(default_factory=lambda: float(packaged_parameters("L3")["lift_height_m"]), gt=0,
                                 description="height the object is lifted [m] (default: the L3 contract's)")
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
