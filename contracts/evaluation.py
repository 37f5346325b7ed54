"""Evaluation boundary models: a suite of cases (the documented file format) and per-arm result records."""

from __future__ import annotations

import re
from typing import Any, Literal

from pydantic import Field, model_validator

from contracts.base import Model

CaseKind = Literal["text", "image", "mesh"]
Ablation = Literal["hierarchy", "harness", "manipulation"]
Arm = Literal["flat", "hierarchical", "one_shot", "harness", "no_feedback", "full"]
ARMS: dict[str, tuple[str, str]] = {"hierarchy": ("flat", "hierarchical"), "harness": ("one_shot", "harness"),
                                    "manipulation": ("no_feedback", "full")}  # (baseline, ours)
CASE_ID = re.compile(r"^[a-z0-9][a-z0-9_-]{0,63}$")


class Drawing(Model):
    """A shape drawn into a PNG for an image case (fractions of the image; RGB 0-255 on a light background)."""

    shape: Literal["ellipse", "rounded_rect", "polygon"]
    color: tuple[int, int, int] = Field(description="fill colour, RGB 0-255")
    aspect: float = Field(default=1.0, gt=0.1, le=1.0, description="height / width of ellipse or rectangle [-]")
    corner: float = Field(default=0.15, ge=0, le=0.5, description="corner radius / shorter side [-]")
    points: list[tuple[float, float]] = Field(default_factory=list, description="polygon vertices in [0, 1]^2")
    size_px: int = Field(default=256, ge=64, le=1024)

    @model_validator(mode="after")
    def _polygon(self) -> Drawing:
        if self.shape == "polygon" and len(self.points) < 3:
            raise ValueError("a polygon needs >= 3 points")
        return self


class Condition(Model):
    """A held-out manipulation condition: place target and initial yaw."""

    target_xy_m: tuple[float, float]
    initial_yaw_deg: float = 0.0


class SuiteCase(Model):
    """One evaluation case: an input (text, drawn image or mesh), the expected material intent, an optional size."""

    id: str = Field(description="unique slug [a-z0-9_-]")
    kind: CaseKind
    text: str | None = Field(default=None, description="text prompt (kind text), or a description for others")
    drawing: Drawing | None = Field(default=None, description="kind image: the shape drawn on first use")
    image: str | None = Field(default=None, description="kind image: a PNG/JPEG path (relative to the suite file)")
    mesh: str | None = Field(default=None, description="kind mesh: 'pybullet_data:<path>' or a path")
    size_m: float | None = Field(default=None, gt=0, description="longest extent [m]")
    intent: str = Field(min_length=1, description="expected material intent words, e.g. 'soft plush'")
    expected_material: str | None = Field(default=None, description="vocabulary material the intent must match")
    manipulation: bool = Field(default=False, description="one of the assets of ablation C")
    tags: list[str] = Field(default_factory=list)

    @model_validator(mode="after")
    def _inputs(self) -> SuiteCase:
        if not CASE_ID.match(self.id):
            raise ValueError(f"case id '{self.id}' must match {CASE_ID.pattern}")
        if self.kind == "text" and not (self.text and self.text.strip()):
            raise ValueError(f"{self.id}: a text case needs text")
        if self.kind == "image" and (self.drawing is None) == (self.image is None):
            raise ValueError(f"{self.id}: an image case needs exactly one of drawing or image")
        if self.kind == "mesh" and not self.mesh:
            raise ValueError(f"{self.id}: a mesh case needs mesh")
        return self


class Suite(Model):
    """A named list of cases plus the held-out manipulation conditions of ablation C."""

    name: str
    version: int = 1
    description: str = ""
    manipulation_conditions: list[Condition] = Field(default_factory=list)
    cases: list[SuiteCase] = Field(min_length=1)

    @model_validator(mode="after")
    def _unique(self) -> Suite:
        ids = [c.id for c in self.cases]
        dup = sorted({i for i in ids if ids.count(i) > 1})
        if dup:
            raise ValueError(f"case ids repeat: {dup}")
        return self


class ConditionResult(Model):
    """One manipulation trial under a held-out condition (ablation C)."""

    condition: Condition
    task_success: bool
    material_pass: bool
    labels: dict[str, float] = Field(default_factory=dict)
    cache_key: str | None = None
    attempt: str | None = Field(default=None, description="interaction attempt (Zarr group) of the trial")


class ArmResult(Model):
    """What one arm of one ablation did on one case; every figure of the report is aggregated from these."""

    ablation: Ablation
    arm: Arm
    case_id: str
    case_kind: CaseKind
    delivered: bool = Field(description="an asset (or material) came out; missing = failure")
    physics_pass: bool | None = Field(default=None, description="independent physics tests on the delivered asset")
    target_satisfied: bool | None = Field(default=None, description="held-out deformation/recovery targets met")
    hard_failure: bool | None = Field(default=None, description="instability, implausible deformation or no output")
    failure_kinds: list[str] = Field(default_factory=list)
    sim_calls: int = Field(default=0, description="construction simulation calls")
    eval_sim_calls: int = Field(default=0, description="simulation calls of the independent tests")
    conditions: list[ConditionResult] = Field(default_factory=list, description="ablation C trials")
    metrics: dict[str, float] = Field(default_factory=dict)
    evidence: dict[str, Any] = Field(default_factory=dict, description="cache keys, records and files behind it")
    asset_dir: str | None = None
    wall_s: float = 0.0
    error: str | None = None
