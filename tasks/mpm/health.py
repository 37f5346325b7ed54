"""Numerical health of a rollout: which check failed, when (step, sim time), where (scene, particle)."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Literal

HealthCheck = Literal["nonfinite", "left_domain", "j_out_of_bounds", "energy_blowup", "out_of_grid"]
FLAG_NAMES: tuple[HealthCheck, ...] = ("nonfinite", "left_domain", "j_out_of_bounds", "out_of_grid")
FATAL: frozenset[str] = frozenset({"nonfinite", "left_domain", "j_out_of_bounds", "energy_blowup"})


@dataclass(frozen=True)
class HealthIssue:
    """One failed (or, for out_of_grid, recovered) check."""

    check: HealthCheck
    scene: int
    step: int  # 1-based global step during which it was first seen
    sim_time_s: float  # simulation time at the end of that step [s]
    particle: int | None  # scene-local index of the lowest-numbered offending particle (None: scene-wide check)
    detail: str = ""


@dataclass
class HealthStatus:
    """Status of a rollout: ok unless a fatal check failed; issues in order of discovery."""

    ok: bool = True
    steps: int = 0
    sim_time_s: float = 0.0
    issues: list[HealthIssue] = field(default_factory=list)
    warnings: list[HealthIssue] = field(default_factory=list)

    def first(self, scene: int | None = None) -> HealthIssue | None:
        """The first fatal issue (of one scene, if given), or None."""
        for i in self.issues:
            if scene is None or i.scene == scene:
                return i
        return None

    def scene_ok(self, scene: int) -> bool:
        """True when no fatal issue concerns the scene."""
        return self.first(scene) is None

    def as_dict(self) -> dict:
        """JSON-ready representation."""
        return asdict(self)
