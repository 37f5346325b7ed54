"""Cross-simulator check: L2's object drop and compression probes re-run in another simulator (definitions, numpy).

The measurements are L2's (tasks.probes.deformable), with the tet-mesh nodes playing the particles (node masses from
the simulator) and the tetrahedra giving the deformation gradients (F = Ds Dm^-1 per tet):
  effective_modulus_pa  compression to L2's strain between frictionless plates; (F / A) / e with F the mean plate force
                        over the hold, A L2's cross-section of the object, e = 1 - h / h0 in L2's equivalent heights
  recovery_ratio        (h_r - h_l) / (h0 - h_l) after the plate is withdrawn, capped at 1
  rebound_ratio, max_impact_strain, settle_time_s
                        the drop from height_fraction x H (L2's _drop_metrics on the simulator's COM, kinetic energy,
                        ground force and 95th-percentile tet compressive strain)
DeformSmith's values are the object probes L2 measured on the asset's adopted material (AssetDir.adopted_material:
material.json's metrics, or an adopted L3 revision's L2 revalidation; object_<metric>, the probes' selection settings:
compression strain and drop height fraction of the L2 contract).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from contracts.errors import InputError
from contracts.stage import L2Parameters, load_contract
from tasks.asset_dir import AssetDir
from tasks.probes.deformable import _drop_metrics
from tasks.probes.metrics import compressive_strain

# crosscheck metric -> (probe, material.json key of DeformSmith's MPM value)
METRICS: dict[str, tuple[str, str]] = {
    "effective_modulus_pa": ("compress", "object_effective_modulus_pa"),
    "recovery_ratio": ("compress", "object_recovery_ratio"),
    "rebound_ratio": ("drop", "object_rebound_ratio"),
    "max_impact_strain": ("drop", "object_max_impact_strain"),
    "settle_time_s": ("drop", "object_settle_time_s"),
}
CALIBRATED_METRICS = ("effective_modulus_pa", "rebound_ratio")  # what calibration fits; the 15 % agreement target
AGREEMENT_TOLERANCE = 0.15
G = 9.81


@dataclass(frozen=True)
class ProbeTargets:
    """L2's probe settings and the object's measured values (material.json), the reference of the crosscheck."""

    strain: float
    height_fraction: float
    area_m2: float | None          # L2's cross-section of the object (None: computed from the tet mesh)
    spacing_m: float               # L2 particle spacing (its layer thickness for the bottom layer)
    ours: dict[str, float]         # metric -> DeformSmith MPM value


def probe_targets(asset_dir: Path) -> ProbeTargets:
    """The reference values and probe settings from the asset's material.json and the L2 contract."""
    adir = AssetDir(Path(asset_dir))
    path = Path(asset_dir) / "material.json"
    if not path.is_file():
        raise InputError(f"{path} not found: crosscheck needs an asset that went through L2")
    record = adir.material()
    if not record.passed:
        raise InputError(f"{path}: L2 did not validate a material; nothing to check against")
    p = L2Parameters.of(load_contract("L2"))
    metrics = dict(adir.adopted_material().metrics)  # measured on the material the export carries
    ours = {name: float(metrics[key]) for name, (_, key) in METRICS.items() if key in metrics}
    if "effective_modulus_pa" not in ours or "rebound_ratio" not in ours:
        raise InputError(f"{path} has no object compression/drop metrics (object_effective_modulus_pa, "
                         "object_rebound_ratio): re-run L2")
    area = None
    for probe in record.held_out.probes:  # the object's cross-section is L2's for either strain
        spec = probe.get("spec", {}) if isinstance(probe, dict) else {}
        if spec.get("kind") == "compress" and "area_m2" in spec.get("params", {}):
            area = float(spec["params"]["area_m2"])
    spacing = float(adir.physical_model().particle_spacing_m)
    return ProbeTargets(strain=p.compression_strain, height_fraction=p.drop_height_fraction_of_height, area_m2=area,
                        spacing_m=spacing, ours=ours)


# -- measurements on a tet body ------------------------------------------------------------------------------------
class TetKinematics:
    """Per-tet deformation gradients and the COM / layer measures of a tet body (rest nodes x0, masses m)."""

    def __init__(self, rest_nodes_m: np.ndarray, tets: np.ndarray, masses_kg: np.ndarray):
        self.x0 = np.asarray(rest_nodes_m, np.float64)
        self.tets = np.asarray(tets, np.int64)
        self.m = np.asarray(masses_kg, np.float64)
        self.dm_inv = np.linalg.inv(self._edges(self.x0))

    def _edges(self, x: np.ndarray) -> np.ndarray:
        p = x[self.tets]
        return np.stack([p[:, 1] - p[:, 0], p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]], axis=2)

    def deformation_gradients(self, x: np.ndarray) -> np.ndarray:
        """F = Ds Dm^-1 per tet (M, 3, 3)."""
        return self._edges(np.asarray(x, np.float64)) @ self.dm_inv

    def strain_p95(self, x: np.ndarray) -> float:
        """95th percentile over the tets of the largest compressive principal strain 1 - sigma_min(F)."""
        return float(np.percentile(compressive_strain(self.deformation_gradients(x)), 95))

    def com(self, x: np.ndarray, mask: np.ndarray | None = None) -> np.ndarray:
        """Mass-weighted mean position [m] (of the masked nodes)."""
        w = self.m if mask is None else self.m[mask]
        xs = x if mask is None else x[mask]
        return (xs * w[:, None]).sum(axis=0) / w.sum()

    def kinetic_energy(self, v: np.ndarray) -> float:
        """1/2 sum m |v|^2 [J]."""
        return float(0.5 * np.sum(self.m * np.einsum("ij,ij->i", v, v)))


def slice_area_m2(nodes_m: np.ndarray, tets: np.ndarray, z_m: float) -> float:
    """Area [m^2] of the horizontal section of a tet mesh at height z (sum over the cut tets of their cut polygons)."""
    x = np.asarray(nodes_m, np.float64)[np.asarray(tets)]
    total = 0.0
    for t in x:
        d = t[:, 2] - z_m
        pts = []
        for a, b in ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)):
            if (d[a] < 0) != (d[b] < 0):
                s = d[a] / (d[a] - d[b])
                pts.append(t[a, :2] + s * (t[b, :2] - t[a, :2]))
        if len(pts) >= 3:
            p = np.array(pts)
            c = p.mean(axis=0)
            order = np.argsort(np.arctan2(p[:, 1] - c[1], p[:, 0] - c[0]))
            q = p[order]
            total += 0.5 * abs(float(np.sum(q[:, 0] * np.roll(q[:, 1], -1) - np.roll(q[:, 0], -1) * q[:, 1])))
    return total


def drop_metrics(t: np.ndarray, z: np.ndarray, vz: np.ndarray, ke: np.ndarray, fg: np.ndarray, s95: np.ndarray,
                 mass_kg: float, height_m: float, dt_s: float) -> dict[str, float]:
    """L2's drop metrics (tasks.probes.deformable._drop_metrics) of the sampled series."""
    return _drop_metrics(np.asarray(t), np.asarray(z), np.asarray(vz), np.asarray(ke), np.asarray(fg),
                         np.asarray(s95), mass_kg, height_m, dt_s)


def compression_metrics(forces_n: list[float], h0_m: float, hold_heights_m: list[float],
                        recovered_heights_m: list[float], area_m2: float) -> dict[str, float]:
    """L2's compression metrics from the plate forces and equivalent heights sampled over the hold and the recovery:
    effective_modulus_pa = (F / A) / e, e = 1 - h_l / h0; recovery_ratio = (h_r - h_l) / (h0 - h_l), capped at 1."""
    F = float(np.mean(forces_n))
    h_l = float(np.mean(hold_heights_m))
    e_h = 1.0 - h_l / h0_m
    applied = h0_m - h_l
    return {
        "effective_modulus_pa": (max(F, 0.0) / area_m2) / e_h if e_h > 0 and area_m2 > 0 else math.nan,
        "compression_strain": e_h, "compression_force_n": F, "cross_section_m2": area_m2,
        "recovery_ratio": min(1.0, (float(np.mean(recovered_heights_m)) - h_l) / applied) if applied > 0 else math.nan,
    }


def sample_interval_s(period_s: float, longest_s: float = 5e-3) -> float:
    """L2's sampling interval: a sixth of the fundamental period within [1 ms, longest_s]."""
    return float(min(longest_s, max(1e-3, period_s / 6.0)))


# -- reports -------------------------------------------------------------------------------------------------------
class MetricRow(BaseModel):
    """One metric: DeformSmith's MPM value, the target simulator's before and after calibration."""

    model_config = ConfigDict(extra="forbid")

    ours: float | None = None
    theirs: float | None = None
    theirs_calibrated: float | None = None
    rel_error: float | None = Field(default=None, description="|theirs - ours| / |ours| before calibration")
    rel_error_calibrated: float | None = None


class CrosscheckReport(BaseModel):
    """The crosscheck of one asset in one simulator (SI units; metric names as in L2)."""

    model_config = ConfigDict(extra="forbid")

    asset: str
    sim: str
    probes: dict[str, float] = Field(description="probe settings: strain, height_fraction, area_m2")
    metrics: dict[str, MetricRow]
    parameters: dict[str, float] = Field(description="the target's own parameters as exported")
    calibration: dict | None = None
    agree_within: float = AGREEMENT_TOLERANCE
    agrees: bool | None = Field(default=None, description="calibrated modulus and rebound within agree_within")
    sim_calls: int = 0
    wall_time_s: float = 0.0
    notes: list[str] = Field(default_factory=list)


def rel_error(theirs: float | None, ours: float | None) -> float | None:
    """|theirs - ours| / |ours| (None when either is missing or ours is 0)."""
    if theirs is None or ours is None or not math.isfinite(theirs) or ours == 0:
        return None
    return abs(theirs - ours) / abs(ours)


def metric_rows(ours: dict[str, float], before: dict[str, float],
                after: dict[str, float] | None = None) -> dict[str, MetricRow]:
    """The report's rows, one per crosscheck metric."""
    rows = {}
    for name in METRICS:
        o, b = ours.get(name), before.get(name)
        a = after.get(name) if after else None
        rows[name] = MetricRow(ours=o, theirs=b, theirs_calibrated=a, rel_error=rel_error(b, o),
                               rel_error_calibrated=rel_error(a, o))
    return rows


__all__ = ["AGREEMENT_TOLERANCE", "CALIBRATED_METRICS", "CrosscheckReport", "METRICS", "MetricRow", "ProbeTargets",
           "TetKinematics", "compression_metrics", "drop_metrics", "metric_rows", "probe_targets", "rel_error",
           "sample_interval_s", "slice_area_m2"]
