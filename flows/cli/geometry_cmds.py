"""`deformsmith geometry`: L0 alone (its benchmark is `python -m benchmarks.geometry_bench`)."""

from __future__ import annotations

from pathlib import Path

import typer
from pydantic import ValidationError
from rich.markup import escape

from contracts.errors import validation_message
from contracts.request import AssetRequest
from flows.cli.apps import app, console, emit_json, fail, prefect_log_level, results
from flows.cli.llm_option import LLM_FALLBACK_HELP, llm_agents
from tasks.preflight import check_request, concept_line
from tasks.report.layers import geometry_line

QUALITIES = ("draft", "standard", "high")
GEOMETRY_BACKEND_HELP = ("reconstruction backend that makes the mesh: a Python entry point 'module:function' or an "
                         "HTTP endpoint 'http://host:port/path' (interface: tasks/geometry/backends.py)")
HOLLOW_SHELL_HELP = ("build a hollow object's (a tennis ball's) MPM particles as its wall alone (the L0 contract's "
                     "hollow_particles: shell); default solid: a rubber shell alone is a dead ball (tennis-ball rule "
                     "rebound 0.12 against 0.53-0.58), with its gas as a wall modulus (a pressurised ball's) still "
                     "just under (0.524). `physical` and `material` on the directory follow geometry.json's record")
STRICT_CONCEPT_HELP = ("refuse an object the lexicon does not name (exit 2, nothing written) instead of building it by "
                       "analogy")


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
    hollow_shell: bool = typer.Option(False, "--hollow-shell", help=HOLLOW_SHELL_HELP),
) -> None:
    """Run L0 alone: text, image or mesh -> mesh.glb, collision/, particles.zarr, gaussians.ply, renders/, geometry.json."""
    # lazy: contracts.asset_dir's models (~0.1 s; --help imports every command module)
    from tasks.asset_dir import AssetDir, document_json

    if quality not in QUALITIES:
        fail(f"--quality must be one of {', '.join(QUALITIES)}, not '{quality}'")
    if size_m is not None and not (0.01 <= size_m <= 2.0):
        fail(f"--size-m {size_m:g} m is outside the supported range [0.01, 2] m")

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
    # lazy: pulls prefect, trimesh, zarr (--help imports every command module)
    from flows.l0_geometry import run_l0, with_hollow_particles, write_l0

    contract = with_hollow_particles("shell") if hollow_shell else None
    with console.status(f"L0 geometry ({quality})..."):
        result = run_l0(request, contract=contract, use_cache=not no_cache, agents=_agents(llm, llm_fallback))
        write_l0(result, out, request=request)
    if as_json:
        emit_json(document_json(AssetDir(out).geometry()))
    # the result line; beside --json output, on stderr
    (console if as_json else results).print(geometry_line(result.info, result.checks, out))
    for w in result.info.warnings:
        console.print(f"[yellow]warning:[/] {w}")
    if not result.checks.passed:
        fail(f"L0 hard gates failed: {', '.join(result.checks.failed)} (outputs kept in {out} as evidence)", code=1)


def _preflight(request) -> None:
    """Cheap input checks before any flow starts (missing files, unsupported formats, absurd stated sizes)."""
    from tasks.geometry import catalogue  # lazy: pulls trimesh, skimage, scipy (--help imports every command module)
    # lazy: pulls trimesh, skimage, scipy (--help imports every command module)
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
