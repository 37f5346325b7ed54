"""`deformsmith generate` (the main job) and `deformsmith inspect` (an asset's validation summary)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, cast

import typer
from pydantic import ValidationError
from rich.markup import escape

from cache import runtime, use_cache_root
from contracts.errors import RequirementNotMet, validation_message
from contracts.manifest import AssetManifest  # (not flows.generate: no Prefect import to read a file)
from contracts.request import AssetRequest
from flows.cli.apps import RECORD_HELP, app, check_device, check_record, console, emit_json, fail, results
from flows.cli.evidence_cmds import print_tallies
from flows.cli.geometry_cmds import GEOMETRY_BACKEND_HELP, STRICT_CONCEPT_HELP
from flows.cli.llm_option import LLM_FALLBACK_HELP, llm_agents
from tasks.asset_cache import keep_asset, request_key, serve
from tasks.preflight import check_request, concept_line
from tasks.batch_requests import slug
from tasks.publish import check_out_dir
from tasks.record.viewer import asset_recordings, has_display, viewer_command
from tasks.report.evidence import validation_tallies
from tasks.report.layers import generate_summary, inspect_lines, wall_time_line

if TYPE_CHECKING:
    from contracts.sim import Device
    from contracts.asset_dir import KeepTrials

DEFAULT_TEXT = "a soft plush turtle toy, about 25 cm long"


def _default_out(text: str | None, image: Path | None, mesh: Path | None) -> Path:
    """out/<slug of the input>."""
    return Path("out") / slug(text or (image.stem if image else mesh.stem if mesh else "asset"))


def print_summary(manifest, asset_dir: Path) -> None:
    """The validation summary: counts from the attempt records (the same tallies `evidence` prints), key figures
    from the manifest, and why a stage did not simply pass, in full."""
    tallies, figures = validation_tallies(manifest, asset_dir)
    print_tallies(tallies, figures, title="validation summary")


def preload_layers(l3: bool) -> None:
    """Import the layer flows now: the generate flow waits for the local Prefect server before its first step, and
    these imports (~2-3 s on 2 cores: trimesh, Warp, rerun) would otherwise only start after that wait."""
    import contextlib
    import importlib

    for module in ("flows.l0_geometry", "flows.l1_physical", "flows.l2_material", "flows.renders", "tasks.mpm",
                   "tasks.record.rerun_recording", *(("flows.l3_manipulation",) if l3 else ())):
        importlib.import_module(module)
    for module in ("prefect.flow_engine", "prefect.task_engine"):  # what running the first flow imports
        with contextlib.suppress(ImportError):
            importlib.import_module(module)


@app.command("generate")
def generate(
    text: str = typer.Argument(None, help=f"what to make (default with no input: '{DEFAULT_TEXT}')"),
    image: Path = typer.Option(None, "--image", help="PNG/JPEG of the object"),
    mesh: Path = typer.Option(None, "--mesh", help="OBJ/PLY/STL/GLB/OFF mesh"),
    out: Path = typer.Option(None, "--out", help="asset directory to publish (default: out/<name>)"),
    device: str = typer.Option("cpu", "--device", help="cpu | cuda (the MPM's Warp device)"),
    cpu_threads: int = typer.Option(2, "--cpu-threads", help="CPU: threads sharing each MPM rollout (results depend "
                                    "on this number, not on the machine's cores)"),
    quality: str = typer.Option("draft", "--quality", help="draft | standard | high"),
    size_m: float = typer.Option(None, "--size-m", help="longest extent [m] (overrides sizes in the text)"),
    intent: str = typer.Option(None, "--intent", help="material words, e.g. 'firm rubber' (default: from the text)"),
    seed: int = typer.Option(0, "--seed"),
    pose: str = typer.Option("upright", "--pose", help="photo: upright (the photo's vertical is up, default) | "
                             "stable (the most stable resting pose)"),
    llm: str = typer.Option(None, "--llm", help="litellm model string for every agent role, L0's shape Designer "
                            "included (default: offline rule backend)"),
    llm_fallback: str = typer.Option("rule", "--llm-fallback", help=LLM_FALLBACK_HELP),
    geometry_backend: str = typer.Option(None, "--geometry-backend", envvar="DEFORMSMITH_GEOMETRY_BACKEND",
                                         help=GEOMETRY_BACKEND_HELP),
    cache_dir: Path = typer.Option(None, "--cache", help="cache root"),
    as_json: bool = typer.Option(False, "--json", help="print the summary as JSON"),
    l3: bool = typer.Option(True, "--l3/--no-l3", help="run L3 (robot pick-and-place validation) after L2"),
    require_l3: bool = typer.Option(False, "--require-l3", help="exit 7 when L3 does not pass (no grasp, a failed "
                                    "pick); the asset is published either way"),
    strict_concept: bool = typer.Option(False, "--strict-concept", help=STRICT_CONCEPT_HELP),
    record: str = typer.Option("adopted", "--record", help=RECORD_HELP),
) -> None:
    """Text, image or mesh -> a published asset directory: geometry, physical model, tested material, evidence."""
    check_device(device)
    check_record(record)
    if quality not in ("draft", "standard", "high"):
        fail(f"--quality must be draft, standard or high, got '{quality}'")
    if not 1 <= cpu_threads <= 64:
        fail(f"--cpu-threads must be 1 to 64, got {cpu_threads}")
    if require_l3 and not l3:
        fail("--require-l3 needs L3: drop --no-l3")
    for path, what in ((image, "image"), (mesh, "mesh")):
        if path is not None and not path.is_file():
            fail(f"{what} file not found: {path}")
    if text is None and image is None and mesh is None:
        text = DEFAULT_TEXT
    try:
        request = AssetRequest(text=text, image_path=image.absolute() if image else None,
                               mesh_path=mesh.absolute() if mesh else None, size_hint_m=size_m,
                               material_intent=intent, seed=seed, quality=quality, pose=pose,
                               geometry_backend=geometry_backend or None)
    except ValidationError as exc:
        fail("invalid request: " + validation_message(exc))
    if cache_dir is not None:
        use_cache_root(cache_dir)
    out = out or _default_out(text, image, mesh)
    check_request(request, out)  # image header, output parent and cache root usable, before any layer
    agents = llm_agents(llm, llm_fallback)
    check_out_dir(Path(out).expanduser().absolute())  # not an asset directory: refused before anything is read
    what = text if text is not None else (image or mesh).name
    # a request whose asset the cache holds for this code (tasks.asset_cache): republished, no layer loaded
    served_key = request_key(request, device=device, cpu_threads=cpu_threads, keep=record, manipulate=l3, llm=llm)
    served = serve(served_key, out, strict_concept) if served_key is not None else None
    if served is not None:
        if served.analogy is not None:
            console.print(f"[yellow]{escape(served.analogy)}[/yellow]", soft_wrap=True)
        console.log(f"[bold]generate[/bold] {escape(repr(what))} -> {escape(str(out))} ({device}, {quality})")
        for stage, message in served.warnings:  # what the run that made it warned of (its records hold them too)
            console.log(f"[bold]{escape(stage)}[/bold] [yellow]{escape(message)}[/yellow]")
        console.log("[bold]cache[/bold] the same request, options and code made this asset: republished from the "
                    "result cache (no layer ran)")
        path = Path(out) / "asset.json"
        report(AssetManifest.model_validate_json(path.read_text(encoding="utf-8")), out, {"cache": served.wall_s},
               as_json, require_l3)
        return
    runtime.prestart_local_server()  # the layers will run: Prefect's local server starts while they load
    # lazy: pulls trimesh, skimage, scipy (--help imports every command module)
    from tasks.request import checked_request

    checked = checked_request(request)  # a rigid material or '10 km long' is one line here, before the layers load
    analogy = concept_line(request, strict_concept)  # InputError under --strict-concept: before any layer
    if analogy is not None:
        console.print(f"[yellow]{escape(analogy)}[/yellow]", soft_wrap=True)  # the first line: a guess
    console.log(f"[bold]generate[/bold] {escape(repr(what))} -> {escape(str(out))} ({device}, {quality})")

    with console.status("loading the layers and the local Prefect server") as status:
        # lazy: pulls prefect, warp, pybullet (--help imports every command module)
        from flows.generate import TIMINGS, generate_asset

        preload_layers(l3)  # while Prefect's local server starts in its own process (~3 s on 2 cores)

        warnings: list[tuple[str, str]] = []  # kept with the asset: a served rerun says them again

        def on_stage(stage: str, message: str) -> None:
            status.update(f"{stage}: {message}")
            style = "yellow" if message.startswith("warning:") else "default"
            if message.startswith("warning:"):
                warnings.append((stage, message))
            console.log(f"[bold]{stage}[/bold] [{style}]{escape(message)}[/{style}]")  # a reason may hold [ ]

        manifest = generate_asset(checked, out, device=cast("Device", device), agents=agents, on_stage=on_stage,
                                  manipulate=l3, cpu_threads=cpu_threads,  # (device: checked by check_device)
                                  keep=cast("KeepTrials", record))  # (checked by check_record)
    if served_key is not None:  # a rerun of the same request and code is served from this copy
        keep_asset(served_key, Path(out), analogy, warnings)
    report(manifest, out, dict(TIMINGS), as_json, require_l3)


def report(manifest: AssetManifest, out: Path, timings: dict[str, float], as_json: bool, require_l3: bool) -> None:
    """generate's results: the summary (or --json) on stdout, L3's outcome on stderr, exit 7 under --require-l3 when L3
    did not pass."""
    if as_json:
        emit_json(generate_summary(out, manifest, timings))
    else:
        print_summary(manifest, out)
        results.print(wall_time_line(timings))
        results.print(f"asset published: {out}", markup=False, highlight=False)
    l3_line = next((s for s in manifest.validation if s.stage == "L3"), None)
    if l3_line is not None and not l3_line.passed:  # on stderr: with --json, stdout holds the JSON alone
        console.print(f"L3 did not pass: {l3_line.reason or ', '.join(l3_line.failed_gates)}; the asset is published "
                      f"with this outcome" + ("" if require_l3 else " (--require-l3 makes this exit 7)"), markup=False)
    if require_l3 and l3_line is not None and not l3_line.passed:  # (flows.generate.require_l3, without its imports)
        raise RequirementNotMet("L3", l3_line.reason or ", ".join(l3_line.failed_gates), str(out))  # exit 7


@app.command("inspect")
def inspect_asset(
    asset: Path = typer.Argument(..., help="asset directory written by `deformsmith generate`"),
    as_json: bool = typer.Option(False, "--json"),
) -> None:
    """Print an asset's validation summary, material and physical model."""
    path = asset / "asset.json"
    if not path.is_file():
        fail(f"{asset} is not an asset directory (no asset.json)")
    manifest = AssetManifest.model_validate_json(path.read_text(encoding="utf-8"))
    if as_json:
        emit_json(manifest.model_dump(mode="json"))
        return
    print_summary(manifest, asset)
    for line in inspect_lines(manifest):
        results.print(line)


@app.command("view")
def view(
    asset: Path = typer.Argument(..., help="asset directory"),
    dry_run: bool = typer.Option(False, "--dry-run", help="print the viewer command instead of starting it"),
) -> None:
    """Open the asset's recordings (recordings/*.rrd, and the probe recordings its records name in the cache) in the
    Rerun viewer."""
    import subprocess

    recordings, gone = asset_recordings(asset)
    for name in gone:
        console.print(f"{name}: not in the asset, and the cache no longer holds it", markup=False, highlight=False)
    if not recordings:
        fail(f"{asset} has no recordings/*.rrd")
    viewer, command = viewer_command(recordings)
    if dry_run:
        typer.echo(" ".join(command))
        return
    if viewer is None:
        fail("the Rerun viewer is not installed (it ships with rerun-sdk: pip install rerun-sdk); "
             "then run: " + " ".join(command))
    if not has_display():
        fail("no display to open a viewer on; copy the .rrd files to a machine with one and run: " + " ".join(command))
    subprocess.Popen(command)  # the viewer runs on after this command returns
