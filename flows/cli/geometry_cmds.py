"""`deformsmith geometry` (L0 alone) and `deformsmith bench geometry`."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import typer
from pydantic import ValidationError
from rich.markup import escape

from contracts.errors import validation_message
from flows.cli.apps import app, bench_app, console, emit_json, fail, prefect_log_level, results
from flows.cli.llm_option import LLM_FALLBACK_HELP, llm_agents
from flows.cli.preflight import STRICT_CONCEPT_HELP, check_request, concept_line

QUALITIES = ("draft", "standard", "high")
GEOMETRY_BACKEND_HELP = ("reconstruction backend that makes the mesh: a Python entry point 'module:function' or an "
                         "HTTP endpoint 'http://host:port/path' (interface: tasks/geometry/backends.py)")


def _agents(llm: str | None, fallback: str = "rule"):
    """Every role played by one litellm model (L0: the shape Designer and Critic), or None for the offline code."""
    return llm_agents(llm, fallback)


@app.command("geometry")
def geometry(
    text: str = typer.Argument(None, help="description, e.g. 'a soft plush turtle toy, about 25 cm long'"),
    image: Path = typer.Option(None, "--image", help="PNG/JPEG of the object (text, if given, describes it)"),
    mesh: Path = typer.Option(None, "--mesh", help="OBJ/PLY/STL/GLB/OFF mesh (units: metres unless --size-m)"),
    out: Path = typer.Option(..., "--out", help="output directory (written atomically)"),
    quality: str = typer.Option("draft", "--quality", help="draft | standard | high"),
    size_m: float = typer.Option(None, "--size-m", help="longest extent of the object [m]"),
    seed: int = typer.Option(0, "--seed", help="seed of every random choice"),
    pose: str = typer.Option("upright", "--pose", help="photo: upright (the photo's vertical is up, default) | "
                             "stable (the most stable resting pose)"),
    intent: str = typer.Option(None, "--intent", help="material words, e.g. 'firm rubber' (default: from the text); "
                               "stored with the request for `physical` and `material`, never changes the geometry"),
    no_cache: bool = typer.Option(False, "--no-cache", help="run the plain functions, without Prefect or the cache"),
    as_json: bool = typer.Option(False, "--json", help="print geometry.json to stdout"),
    llm: str = typer.Option(None, "--llm", help="litellm model string: the model writes the shape program of a text "
                            "request (a vision model also judges its renders); default: the offline grammar"),
    llm_fallback: str = typer.Option("rule", "--llm-fallback", help=LLM_FALLBACK_HELP),
    geometry_backend: str = typer.Option(None, "--geometry-backend", envvar="DEFORMSMITH_GEOMETRY_BACKEND",
                                         help=GEOMETRY_BACKEND_HELP),
    strict_concept: bool = typer.Option(False, "--strict-concept", help=STRICT_CONCEPT_HELP),
) -> None:
    """Run L0 alone: text, image or mesh -> mesh.glb, collision/, particles.zarr, gaussians.ply, renders/, geometry.json."""
    if quality not in QUALITIES:
        fail(f"--quality must be one of {', '.join(QUALITIES)}, not '{quality}'")
    if size_m is not None and not (0.01 <= size_m <= 2.0):
        fail(f"--size-m {size_m:g} m is outside the supported range [0.01, 2] m")
    from contracts.request import AssetRequest

    try:
        request = AssetRequest(text=text, image_path=image.absolute() if image else None,
                               mesh_path=mesh.absolute() if mesh else None, size_hint_m=size_m,
                               material_intent=intent, seed=seed, quality=quality, pose=pose,
                               geometry_backend=geometry_backend or None)
    except ValidationError as exc:
        fail("invalid request: " + validation_message(exc))
    if intent is not None and not intent.strip():
        fail("--intent is empty")
    _preflight(request)
    analogy = concept_line(request, strict_concept)  # InputError under --strict-concept: nothing written
    if analogy is not None:
        console.print(f"[yellow]{escape(analogy)}[/yellow]", soft_wrap=True)  # the first line: a guess
    check_request(request, out, cache=not no_cache)  # image header, output parent and cache root usable
    prefect_log_level("CRITICAL")  # user errors surface as one line, not task tracebacks
    from flows.l0_geometry import run_l0, write_l0

    with console.status(f"L0 geometry ({quality})..."):
        result = run_l0(request, use_cache=not no_cache, agents=_agents(llm, llm_fallback))
        write_l0(result, out, request=request)
    if as_json:
        from tasks.asset_dir import AssetDir, document_json

        emit_json(document_json(AssetDir(out).geometry()))
    m = result.checks.metrics
    (console if as_json else results).print(  # the result line; beside --json output, on stderr
        f"[bold]{result.info.name}[/] ({result.info.source}): {m['extent_x_m']:.3f} x {m['extent_y_m']:.3f} x "
        f"{m['extent_z_m']:.3f} m, {m['volume_m3'] * 1e6:.1f} cm^3, {int(m['particle_count'])} particles, "
        f"{int(m['gaussian_count'])} Gaussians, {int(m['proxy_parts'])} convex parts -> {out}"
    )
    for w in result.info.warnings:
        console.print(f"[yellow]warning:[/] {w}")
    if not result.checks.passed:
        fail(f"L0 hard gates failed: {', '.join(result.checks.failed)} (outputs kept in {out} as evidence)", code=1)


def _preflight(request) -> None:
    """Cheap input checks before any flow starts (missing files, unsupported formats, absurd stated sizes)."""
    from tasks.geometry import catalogue
    from tasks.geometry.mesh_import import SUPPORTED

    if request.mesh_path is not None:
        if not request.mesh_path.is_file():
            fail(f"mesh file not found: {request.mesh_path}")
        if request.mesh_path.suffix.lower() not in SUPPORTED:
            fail(f"unsupported mesh format '{request.mesh_path.suffix}'; use one of {', '.join(SUPPORTED)}")
    if request.image_path is not None and not request.image_path.is_file():
        fail(f"image file not found: {request.image_path}")
    if request.text and request.text.strip():
        catalogue.check_size(catalogue.parse_size(request.text))


_BENCH_CASE = r"""
import json, resource, sys, time
from contracts.request import AssetRequest
from tasks.geometry import pipeline
req = AssetRequest(**json.loads(sys.argv[1]))
s = pipeline.settings_from_contract(sys.argv[2], seed=0)
t = {}
t0 = time.perf_counter(); mesh, info = pipeline.build_mesh(req, s); t["mesh_s"] = time.perf_counter() - t0
t0 = time.perf_counter(); proxy = pipeline.build_proxy(mesh, s.coacd); t["coacd_s"] = time.perf_counter() - t0
t0 = time.perf_counter(); parts = pipeline.build_particles(mesh, s.particles); t["particles_s"] = time.perf_counter() - t0
t0 = time.perf_counter(); g = pipeline.build_gaussians(mesh, parts, s); t["gaussians_s"] = time.perf_counter() - t0
t0 = time.perf_counter(); ch = pipeline.check_geometry(mesh, proxy, parts, g); t["checks_s"] = time.perf_counter() - t0
import tempfile, pathlib
from tasks.geometry.outputs import write_outputs
with tempfile.TemporaryDirectory() as d:
    t0 = time.perf_counter(); write_outputs(pathlib.Path(d), mesh, proxy, parts, g, info, ch); t["write_s"] = time.perf_counter() - t0
t["total_s"] = sum(t.values())
t["coacd_fraction"] = t["coacd_s"] / t["total_s"]
t["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
t.update(particles=len(parts["positions_m"]), gaussians=len(g["positions_m"]), faces=len(mesh["faces"]),
         convex_parts=len(proxy["part_face_count"]), gates_passed=ch.passed)
print(json.dumps(t))
"""

_BENCH_CACHE = r"""
import json, sys, time
from contracts.request import AssetRequest
from flows.l0_geometry import run_l0
req = AssetRequest(**json.loads(sys.argv[1]))
t0 = time.perf_counter(); run_l0(req, "draft"); first = time.perf_counter() - t0
t0 = time.perf_counter(); run_l0(req, "draft"); second = time.perf_counter() - t0
print(json.dumps({"first_run_s": first, "cache_hit_rerun_s": second}))
"""


def _run_case(code: str, *args: str, env: dict[str, str] | None = None) -> dict:
    proc = subprocess.run([sys.executable, "-P", "-c", code, *args], capture_output=True, text=True,
                          env={**os.environ, **(env or {})})
    if proc.returncode != 0:
        fail(f"benchmark case failed: {proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else proc.returncode}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _bench_suite(suite: Path, quality: str, sheet: Path | None, as_json: bool) -> None:
    """`bench geometry --suite`: every prompt through L0, one row each (see tasks/geometry/suite_bench.py)."""
    from contracts.errors import InputError
    from tasks.geometry.suite_bench import run_suite

    quality = quality.split(",")[0]
    if quality not in QUALITIES:
        fail(f"--qualities must name one of {', '.join(QUALITIES)}, not '{quality}'")
    try:
        result = run_suite(suite, quality, sheet, progress=lambda m: console.print(m))
    except InputError as exc:
        fail(str(exc))
    if as_json:
        emit_json(result)
        return
    for r in result["rows"]:
        mass = f"{r['mass_estimate_kg'] * 1e3:8.1f} g" if r["mass_estimate_kg"] is not None else "       -  "
        ext = " x ".join(f"{v:.3f}" for v in r["extents_m"])
        results.print(f"{r['text'][:44]:44s} {r['concept']:20s} {r['fallback_level']:9s} {ext} m {mass} "
                      f"{r['seconds']:5.1f} s")
    results.print(result["summary"])


@bench_app.command("geometry")
def bench_geometry(
    as_json: bool = typer.Option(False, "--json", help="print the figures as JSON"),
    skip_cache: bool = typer.Option(False, "--skip-cache", help="skip the cache-hit measurement (Prefect start-up)"),
    qualities: str = typer.Option(",".join(QUALITIES), "--qualities", help="comma-separated qualities"),
    suite: Path = typer.Option(None, "--suite", help="YAML/JSON prompt suite (e.g. tests/geometry/heldout_prompts.yaml "
                               "or contracts/suites/default.yaml): per prompt the concept, fallback level, size, "
                               "mass estimate and seconds of L0 (at the first of --qualities, default draft)"),
    contact_sheet: Path = typer.Option(None, "--contact-sheet", help="with --suite: PNG of every prompt's render"),
) -> None:
    """L0 wall time, peak memory and CoACD share for the plush turtle per quality and the largest pybullet_data mesh;
    with --suite, the text path on every prompt of a suite."""
    if suite is not None:
        _bench_suite(suite, qualities if qualities != ",".join(QUALITIES) else "draft", contact_sheet, as_json)
        return
    import pybullet_data

    turtle = json.dumps({"text": "a soft plush turtle toy, about 25 cm long"})
    data = Path(pybullet_data.getDataPath())
    candidates = [data / n for n in ("duck.obj", "teddy2_VHACD_CHs.obj", "bunny.obj", "torus/torus_textured.obj",
                                     "soccerball.obj")]
    largest = max(candidates, key=lambda p: p.stat().st_size)
    mesh_req = json.dumps({"mesh_path": str(largest), "size_hint_m": 0.2})
    figures: dict = {"turtle": {}, "largest_pybullet_mesh": {"file": largest.name}}
    for q in qualities.split(","):
        console.print(f"turtle, {q} ...")
        figures["turtle"][q] = _run_case(_BENCH_CASE, turtle, q)
        console.print(f"{largest.name}, {q} ...")
        figures["largest_pybullet_mesh"][q] = _run_case(_BENCH_CASE, mesh_req, q)
    if not skip_cache:
        console.print("cache-hit rerun (Prefect flow, fresh cache) ...")
        with tempfile.TemporaryDirectory() as d:
            figures["turtle"]["cache"] = _run_case(_BENCH_CACHE, turtle, env={"DEFORMSMITH_CACHE": d,
                                                                                "PREFECT_LOGGING_LEVEL": "WARNING"})
    figures["cpu_count"] = os.cpu_count()
    if as_json:
        emit_json(figures)
        return
    for name in ("turtle", "largest_pybullet_mesh"):
        for q, f in figures[name].items():
            if isinstance(f, dict) and "total_s" in f:
                results.print(f"{name:24s} {q:9s} total {f['total_s']:6.2f} s  coacd {f['coacd_s']:6.2f} s "
                              f"({100 * f['coacd_fraction']:.0f}%)  peak {f['peak_rss_mb']:.0f} MB  "
                              f"{f['particles']} particles")
    if "cache" in figures["turtle"]:
        c = figures["turtle"]["cache"]
        results.print(f"flow first run {c['first_run_s']:.2f} s, cache-hit rerun {c['cache_hit_rerun_s']:.2f} s")
