"""What the layer commands show of an asset: the result line of `geometry` and `material`, L1's table and mass check
(`physical`), L3's table and JSON summary (`manipulate`), the lines `inspect` prints under the validation summary and
the summary `generate --json` prints. Built from the typed records; printing is the command's."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from rich.table import Table

from contracts.agents import StageOutcome
from contracts.manifest import AssetManifest
from contracts.material import Material
from contracts.physical import PhysicalModel

if TYPE_CHECKING:
    from contracts.asset_dir import MaterialRecord
    from contracts.manipulation import ManipulationRecord
    from tasks.geometry.pipeline import BuildInfo
    from tasks.geometry.checks import GeometryChecks

L3_SUMMARY_FIELDS = {"passed", "status", "message", "reason", "outcome", "forces", "held_out", "attempt", "values",
                     "numerics", "material_source", "recordings"}  # what `manipulate --json` prints of the record


def geometry_line(info: BuildInfo, checks: GeometryChecks, out: Path) -> str:
    """L0's result line: the object, its extents, volume and counts, where it was written."""
    m = checks.metrics
    return (f"[bold]{info.name}[/] ({info.source}): {m['extent_x_m']:.3f} x {m['extent_y_m']:.3f} x "
            f"{m['extent_z_m']:.3f} m, {m['volume_m3'] * 1e6:.1f} cm^3, {int(m['particle_count'])} particles, "
            f"{int(m['gaussian_count'])} Gaussians, {int(m['proxy_parts'])} convex parts -> {out}")


def physical_table(outcome: StageOutcome, phys: PhysicalModel | None) -> Table:
    """L1's result: the physical model's density, mass and friction, then every metric."""
    table = Table(title=f"L1 physical model: {outcome.status}")
    table.add_column("metric")
    table.add_column("value", justify="right")
    if phys:
        table.add_row("density [kg/m^3]", f"{phys.density_kg_per_m3:.4g}")
        table.add_row("mass [kg]", f"{phys.mass_kg:.4g}")
        table.add_row("ground / gripper friction [-]", f"{phys.ground_friction:.3g} / {phys.gripper_friction:.3g}")
    for k, v in sorted(outcome.metrics.items()):
        table.add_row(k, f"{v:.4g}")
    return table


def mass_check_lines(mass: dict[str, Any]) -> list[str]:
    """L1's mass check as written in physical.json: the band and where it came from, then its notes (indented)."""
    lo, hi = mass["band_kg"]
    return [f"mass check: {lo * 1e3:.3g}-{hi * 1e3:.3g} g from {mass['source']}", *(f"  {n}" for n in mass["notes"])]


def material_line(mat: Material, outcome: StageOutcome, record: MaterialRecord, wall_s: float, path: Path) -> str:
    """L2's result line: the material, how the harness ended, its simulations and time, where it was written."""
    return (f"[bold]material[/]: E={mat.youngs_modulus_pa:.4g} Pa, nu={mat.poisson_ratio:.3g}, "
            f"damping={mat.damping_rate_per_s:.3g} 1/s ({outcome.status}, {record.sim_calls} simulation "
            f"calls, {wall_s:.1f} s) -> {path}")


def manipulation_summary(record: ManipulationRecord, wall_time_s: float) -> dict[str, Any]:
    """`manipulate --json`: manipulation.json's summary fields and the wall time."""
    return {**record.model_dump(mode="json", include=L3_SUMMARY_FIELDS), "wall_time_s": wall_time_s}


def manipulation_table(record: ManipulationRecord) -> Table:
    """L3's labels and figures, by name."""
    table = Table(title=f"L3 manipulation: {record.status}")
    table.add_column("label / figure")
    table.add_column("value", justify="right")
    for k, v in sorted(record.labels.items()):
        table.add_row(k, f"{v:.4g}")
    return table


def inspect_lines(manifest: AssetManifest) -> list[str]:
    """Below `inspect`'s validation summary: the material, the physical model, each stage's failed gates and the
    pick-and-place outcome (those the manifest has)."""
    lines = []
    if manifest.material:
        m = manifest.material
        lines.append(f"material: E = {m.youngs_modulus_pa:.4g} Pa, nu = {m.poisson_ratio:.3g}, "
                     f"damping = {m.damping_rate_per_s:.3g} 1/s")
    if manifest.physical_model:
        p = manifest.physical_model
        lines.append(f"physical: rho = {p.density_kg_per_m3:.4g} kg/m^3, mass = {p.mass_kg:.4g} kg, "
                     f"{p.particle_count} particles")
    for s in manifest.validation:
        if s.failed_gates:
            lines.append(f"{s.stage} failed gates: {', '.join(s.failed_gates)}")
    if manifest.manipulation:
        o = manifest.manipulation
        lines.append(f"pick-and-place: lifted {o.lifted}, transported {o.transported}, released in target "
                     f"{o.released_in_target}, slipped {o.slipped}, max finger force "
                     f"{max(o.max_finger_force_n):.3g} N, strain (1 % of volume) "
                     f"{o.strain_p99 if o.strain_p99 is not None else float('nan'):.3g}, peak particle strain "
                     f"{o.max_strain:.3g}")
    return lines


def generate_summary(out: Path, manifest: AssetManifest, timings: dict[str, float]) -> dict[str, Any]:
    """`generate --json`: the asset directory, validation, material, physical model, pick-and-place outcome, files
    and the wall time per layer [s]."""
    return {"asset_dir": str(out), "validation": [s.model_dump(mode="json") for s in manifest.validation],
            "material": manifest.material.model_dump(mode="json") if manifest.material else None,
            "physical_model": manifest.physical_model.model_dump(mode="json") if manifest.physical_model else None,
            "manipulation": manifest.manipulation.model_dump(mode="json") if manifest.manipulation else None,
            "files": manifest.files, "wall_time_s": dict(timings)}


def wall_time_line(timings: dict[str, float]) -> str:
    """'wall time: L0 1.2 s, L1 3.4 s, ...'."""
    return "wall time: " + ", ".join(f"{k} {v:.1f} s" for k, v in timings.items())
