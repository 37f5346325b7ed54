"""`deformsmith material` (L2 on an asset directory) and `deformsmith probe KIND` (one probe, its metrics); the
screening candidates under each schedule are `python -m benchmarks.l2_schedule`."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, cast

import typer
from pydantic import ValidationError

from cache import use_cache_root
from contracts.agents import AgentConfig
from contracts.errors import validation_message
from contracts.material import Material
from contracts.sim import SimConfig
from flows.cli.apps import RECORD_HELP, app, check_record, console, emit_json, fail, prefect_log_level, results
from flows.cli.physical_cmds import asset_path
from tasks.preflight import check_asset_dir, check_locations
from tasks.report.layers import material_line

if TYPE_CHECKING:
    from contracts.asset_dir import KeepTrials

RIGID_KINDS = ("place", "drop", "slide")  # L1 rigid probes (pybullet); `drop` is rigid unless --deformable
DEFORMABLE_KINDS = ("compress", "lift", "stability")
KINDS = ("place", "drop", "slide", "compress", "lift", "stability")


def _check_asset(asset: Path) -> None:
    """The asset directory must hold an L0 output."""
    # lazy: contracts.asset_dir's models (~0.1 s; --help imports every command module)
    from tasks.asset_dir import AssetDir

    if not AssetDir(asset).has("geometry"):
        fail(f"{asset} is not an asset directory (no geometry.json); run `deformsmith geometry ... --out {asset}`")


def _material_overrides(E: float | None, nu: float | None, damping: float | None) -> dict[str, float]:
    """The material fields given on the command line, checked (finite, within Material's own bounds)."""
    for name, v in (("--E", E), ("--nu", nu), ("--damping", damping)):
        if v is not None and not math.isfinite(v):
            fail(f"{name} must be a finite number, got {v}")
    given = {k: v for k, v in (("youngs_modulus_pa", E), ("poisson_ratio", nu), ("damping_rate_per_s", damping))
             if v is not None}
    _validated({"youngs_modulus_pa": 1e4, "poisson_ratio": 0.3, "damping_rate_per_s": 0.0, **given})
    return given


def _material(E: float | None, nu: float | None, damping: float | None, asset: Path):
    """The material to probe: the asset's adopted material (L2's, or the L3 revision it adopted; else the intent's
    priors), with the given overrides."""
    # lazy: contracts.asset_dir's models (~0.1 s; --help imports every command module)
    from tasks.asset_dir import AssetDir

    from flows.l2_material import l2_targets  # lazy: pulls prefect, warp, trimesh (--help imports every command module)
    # lazy: pulls trimesh, zarr, skimage (--help imports every command module)
    from tasks.geometry.outputs import load_l0

    given = _material_overrides(E, nu, damping)
    adir = AssetDir(asset)
    if adir.has("material"):
        base = adir.adopted_material().material.model_dump()
    else:  # the priors always hold every material field (the vocabulary's default material fills the gaps)
        pri = l2_targets(load_l0(adir.path), None).priors
        base = {k: pri[k] for k in ("youngs_modulus_pa", "poisson_ratio", "damping_rate_per_s")}
    return _validated({**base, **given})


_PARAMETER_NAMES = {"youngs_modulus_pa": "E (--E) [Pa]", "poisson_ratio": "nu (--nu)",
                    "damping_rate_per_s": "damping (--damping) [1/s]"}


def _validated(values: dict[str, float]):
    """A Material, or one clear line naming the invalid parameter and a non-zero exit."""
    try:
        return Material(**values)
    except ValidationError as exc:
        fail("invalid material: " + validation_message(exc, names=_PARAMETER_NAMES, with_input=True))


@app.command("probe")
def probe(
    kind: str = typer.Argument(..., help="place | drop | slide (L1 rigid, pybullet) | compress | lift | stability"),
    asset: Path = typer.Option(..., "--asset", help="asset directory (an L0 output, with physical.json if L1 ran)"),
    E: float = typer.Option(None, "--E", help="Young's modulus [Pa] (deformable probes)"),
    nu: float = typer.Option(None, "--nu", help="Poisson's ratio [-], 0 <= nu < 0.5 (deformable probes)"),
    damping: float = typer.Option(None, "--damping", help="damping rate [1/s] (deformable probes)"),
    rho: float = typer.Option(None, "--rho", help="density [kg/m^3] overriding the L1 model"),
    deformable: bool = typer.Option(False, "--deformable", help="drop: the MPM drop (L2) instead of the rigid one"),
    held_out: bool = typer.Option(False, "--held-out", help="compress/drop: the contract's held-out strain / height"),
    as_json: bool = typer.Option(False, "--json", help="print the probe result as JSON"),
) -> None:
    """Run one probe on an asset and print its metrics (SI units in every metric name)."""
    if kind not in KINDS:
        fail(f"unknown probe '{kind}'; choose one of {', '.join(KINDS)}")
    _material_overrides(E, nu, damping)  # reject bad material options before touching the asset
    _check_asset(asset)
    if rho is not None and not (math.isfinite(rho) and rho > 0):
        fail(f"--rho must be a positive finite density [kg/m^3], got {rho}")
    check_locations()  # the probe's result and recording go to the cache: its root usable, before the probe runs
    prefect_log_level("CRITICAL")
    if kind in RIGID_KINDS and not (kind == "drop" and deformable):
        if any(v is not None for v in (E, nu, damping)):
            fail(f"--E/--nu/--damping apply to deformable probes; '{kind}' is a rigid L1 probe")
        try:
            # lazy: pulls prefect, trimesh, zarr (--help imports every command module)
            from flows.l1_physical import run_rigid_probe
        except ImportError:
            fail(f"the rigid probe '{kind}' needs flows.l1_physical.run_rigid_probe, which is not available")
        with console.status(f"rigid probe {kind}..."):
            result = run_rigid_probe(kind, asset, rho=rho)
    else:
        # lazy: pulls prefect, warp, trimesh (--help imports every command module)
        from flows.l2_material import physical_for, run_probe
        # lazy: pulls trimesh, zarr, skimage (--help imports every command module)
        from tasks.geometry.outputs import load_l0

        material = _material(E, nu, damping, asset)
        physical = physical_for(asset, load_l0(asset), rho)
        with console.status(f"MPM probe {kind} (E={material.youngs_modulus_pa:.4g} Pa)..."):
            result = run_probe(kind, asset, material, physical=physical, held_out=held_out)
    if as_json:
        emit_json(result.model_dump(mode="json"))
    else:
        results.print(f"[bold]{kind}[/] health ok={result.health.ok} sim_calls={result.sim_calls} "
                      f"wall={result.wall_time_s:.1f} s")
        for k, v in sorted(result.metrics.items()):
            results.print(f"  {k} = {v:.6g}")
    if not result.health.ok:
        fail(f"probe '{kind}' failed its numerical health: {result.health.check} at t={result.health.sim_time_s} s "
             f"({result.health.detail})", code=1)


@app.command("material")
def material(
    asset_dir: Path = typer.Argument(None, help="asset directory holding L0 and L1 (physical.json) (or --asset)"),
    asset: Path = typer.Option(None, "--asset", help="asset directory holding L0 and L1 (physical.json)"),
    intent: str = typer.Option(None, "--intent", help="material words, e.g. 'soft plush', 'firm rubber'; default: "
                               "the request `geometry` stored (its --intent, else its text), as `generate` does"),
    llm: str = typer.Option(None, "--llm", help="litellm model playing the agent roles (default: offline rules)"),
    cpu_threads: int = typer.Option(2, "--cpu-threads", help="threads sharing each MPM rollout's particles"),
    cache_dir: Path = typer.Option(None, "--cache", help="cache root (default: $DEFORMSMITH_CACHE or the user cache)"),
    as_json: bool = typer.Option(False, "--json", help="print material.json to stdout"),
    keep: str = typer.Option("adopted", "--record", help=RECORD_HELP),
) -> None:
    """Run L2 on an asset: MPM probes, harness-selected neo-Hookean material -> material.json, evidence, recordings."""

    from tasks.asset_dir import AssetDir, document_json  # lazy: contracts.asset_dir's models (~0.1 s at --help)
    from tasks.publish import staged_update  # lazy: pulls ctypes (--help imports every command module)

    asset = asset_path(asset_dir, asset)
    _check_asset(asset)
    if intent is not None and not intent.strip():
        fail("--intent is empty")
    if not 1 <= cpu_threads <= 64:
        fail(f"--cpu-threads must be 1 to 64, got {cpu_threads}")
    check_record(keep)
    if cache_dir is not None:
        use_cache_root(cache_dir)
    check_asset_dir(asset)  # the asset directory, its parent and the cache root usable, before L2 runs
    prefect_log_level("CRITICAL")
    from flows.l2_material import run_l2  # lazy: pulls prefect, warp, trimesh (--help imports every command module)

    agents = AgentConfig.llm(llm) if llm else None
    import time

    started = time.perf_counter()
    # L2 writes into a working copy, swapped in whole when it ends: files and evidence together, or nothing
    with console.status("L2 material (MPM probes)..."), staged_update(asset) as work:
        mat, outcome = run_l2(work, intent, agents=agents, sim=SimConfig(cpu_threads=cpu_threads),
                              keep=cast("KeepTrials", keep))  # (checked by check_record)
    wall_s = time.perf_counter() - started
    adir = AssetDir(asset)
    record = adir.material()
    if as_json:
        emit_json(document_json(record))
    if mat is None:
        fail(f"L2 found no valid material: {outcome.message}", code=1)
    # the result line; beside --json output, on stderr
    (console if as_json else results).print(material_line(mat, outcome, record, wall_s, adir.file("material")))
