"""`generate`: L0 -> L1 -> L2 (-> L3) on one working directory, then an atomic publish of the asset directory.

Resume is the cache's job: every expensive unit is a content-cached task, so a rerun after a crash rebuilds the
working directory from hits and re-executes only what never finished. The working directory is private
(`.<name>.partial-<pid>` next to the output) and is renamed into place only when every layer passed.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
import threading
from collections.abc import Callable
from pathlib import Path
from typing import TypedDict

import cache  # (sets the local Prefect environment before prefect is imported)
from cache import content_key
from cache.files import cached_file, source_digest
from cache.prefect_flow import lean_flow
from cache.tempfiles import dead_partials, owner_tag, remove_paths
from contracts.agents import AgentConfig
from contracts.asset_dir import (ASSET_JSON, DEFAULT_KEEP, KeepTrials)
from contracts.errors import RequirementNotMet, StageFailure
from contracts.manifest import AssetManifest
from contracts.manipulation import ManipulationRecord
from contracts.request import AssetRequest
from contracts.sim import Device, SimConfig
from flows import l0_geometry, l1_physical, l2_material, l3_manipulation, renders
from tasks.agents.fallbacks import fallback_notes, reset as reset_fallbacks
from tasks.asset_dir import AssetDir
from tasks.manifest_summary import (
    cache_keys, l3_summary, manipulation_outcome, provenance, reported_plan, shown_attempt,
    stage_summary,
)
from tasks.manipulation.replay import replay
from tasks.publish import check_out_dir, replace_directory
from tasks.record import recording_digest
from tasks.request import CheckedRequest, checked_request

StageCallback = Callable[[str, str], None]  # (stage, message)
TIMINGS: dict[str, float] = {}  # wall time per layer of the last generate_asset call in this process [s]


class _StageClock(TypedDict):
    """The stage being timed and when it started (time.perf_counter() [s])."""

    stage: str
    t: float


def require_l3(manifest: AssetManifest, out_dir: Path) -> None:
    """`--require-l3`: RequirementNotMet (exit 7) when L3 ran and did not pass; the asset is already published."""
    l3 = next((s for s in manifest.validation if s.stage == "L3"), None)
    if l3 is not None and not l3.passed:
        raise RequirementNotMet("L3", l3.reason or ", ".join(l3.failed_gates), str(out_dir))


def run_manipulation(work: Path, device: Device, quality: str, agents: AgentConfig | None,
                     cpu_threads: int = 1, progress: Callable[[str], None] | None = None,
                     keep: KeepTrials = DEFAULT_KEEP, on_video: Callable[[], None] | None = None) -> ManipulationRecord:
    """L3 on the working directory and the pick-and-place video of the shown attempt; the manipulation record.
    keep: which trials' states and recordings the asset keeps (tasks.manipulation.keep; the rest stay cached).
    on_video: called as the video starts (generate times it apart)."""
    options = (l3_manipulation.L3Options(device=device, cpu_threads=cpu_threads) if quality == "draft"
               else l3_manipulation.L3Options.standard(device, cpu_threads))
    record, _ = l3_manipulation.run_l3(work, options, agents, progress=progress, keep=keep)
    if on_video is not None:
        on_video()
    write_pick_and_place_video(work, record)
    return record


def write_pick_and_place_video(work: Path, record: ManipulationRecord) -> Path | None:
    """renders/pick_and_place.mp4 of the attempt the record shows (cached by the attempt's bytes); None, and an earlier
    L3's video removed, when the record shows no recorded trial (no grasp, or its interaction data is absent)."""
    n = shown_attempt(record)
    video = work / "renders" / "pick_and_place.mp4"
    if n is None or not (work / "interaction" / f"attempt_{n:03d}").is_dir():
        video.unlink(missing_ok=True)
        return None
    video.parent.mkdir(parents=True, exist_ok=True)
    cached_file(pick_and_place_video_key(work, n), video, lambda path: replay(work, n, video=path))
    return video


def pick_and_place_video_key(work: Path, attempt: int) -> str:
    """The video's cache key: the recorded attempt's bytes and the code and libraries that render and encode it
    (rendering it takes ~10 s on the CPU; a warm rerun copies it)."""
    root = Path(__file__).resolve().parent.parent
    renderer = [root / "tasks" / "manipulation" / f"{m}.py" for m in
                ("replay", "scene", "data", "particle_frames", "video")]
    renderer += sorted(p for p in (root / "tasks" / "render").glob("*.py") if not p.name.startswith(("card", "bench")))
    renderer += [root / "tasks" / "robot" / f"{m}.py" for m in ("visual", "panda", "trajectory")]  # the robot drawn
    code = source_digest([*renderer, root / "tasks" / "geometry" / "gaussians.py", root / "contracts" / "robot.py",
                          root / "contracts" / "grippers"],
                         ("imageio", "imageio-ffmpeg", "numpy", "opencv-python-headless", "opencv-python", "pybullet",
                          "scipy", "warp-lang"))
    return content_key("pick_and_place_video", code, work / "interaction" / f"attempt_{attempt:03d}")


def _files(work: Path) -> dict[str, str]:
    """Role -> relative path of what the asset directory holds."""
    roles = {"manifest": ASSET_JSON, "mesh": "mesh.glb", "collision": "collision", "particles": "particles.zarr",
             "gaussians": "gaussians.ply", "evidence": "evidence", "recordings": "recordings", "renders": "renders",
             "interaction": "interaction", "geometry_record": "geometry.json", "physical_record": "physical.json",
             "material_record": "material.json", "manipulation_record": "manipulation.json",
             "physgaussian_config": "export/physgaussian_config.json",
             "drop_video_front": "renders/drop_front.mp4", "drop_video_side": "renders/drop_side.mp4",
             "pick_and_place_video": "renders/pick_and_place.mp4", "card_png": "renders/card.png",
             "card_html": "renders/card.html"}
    return {role: rel for role, rel in roles.items() if (work / rel).exists() or role == "manifest"}


def write_physgaussian_export(adir: AssetDir) -> Path:
    """A PhysGaussian-style simulation config next to the Gaussians: the adopted material's E, nu (AssetDir.
    adopted_material), L1's density and the particle file (SI)."""
    phys, mat = adir.physical_model(), adir.adopted_material().material
    config = {
        "material": "jelly",  # PhysGaussian's name for its neo-Hookean model
        "E": mat.youngs_modulus_pa, "nu": mat.poisson_ratio, "density": phys.density_kg_per_m3,
        "damping_rate_per_s": mat.damping_rate_per_s,
        "g": list(phys.gravity_m_per_s2), "friction_ground": phys.ground_friction,
        "gaussians_ply": "../gaussians.ply", "particles_zarr": "../particles.zarr",
        "units": "SI (Pa, kg/m^3, m, s); frame z up, object resting on z = 0",
        "particle_volumes": "particles.zarr/volumes_m3", "n_particles": phys.particle_count,
    }
    path = adir.path / "export" / "physgaussian_config.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(config, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    return path


def write_asset_records(adir: AssetDir, manifest: AssetManifest) -> AssetManifest:
    """asset.json with the adopted material (AssetDir.adopted_material) and the file roles, and the PhysGaussian
    config and the card that carry the same material; returns the manifest as written."""
    manifest = manifest.model_copy(update={"material": adir.adopted_material().material})
    write_physgaussian_export(adir)
    renders.write_card(adir.path, manifest)  # the asset card: renders/card.png, card.html (what L0-L3 found)
    manifest = manifest.model_copy(update={"files": _files(adir.path)})
    adir.write_manifest(manifest)
    return manifest


def refresh_after_l3(work: Path, record: ManipulationRecord) -> AssetManifest | None:
    """After `deformsmith manipulate` re-ran L3 on a published asset (work: its staged working copy): everything that
    carries L3's result or the adopted material, rewritten from the new manipulation.json as generate writes it:
    asset.json (material, L3's validation line, action plan, outcome, L3's cache keys, file roles), the PhysGaussian
    config, the card and the pick-and-place video. None (nothing rewritten) when the directory has no asset.json."""
    adir = AssetDir(work)
    if not adir.has("manifest"):
        return None
    old = adir.manifest()
    write_pick_and_place_video(work, record)
    l3 = l3_summary(record)
    validation = [s for s in old.validation if s.stage != "L3"] + [l3]
    prov = old.provenance.model_copy(update={"cache_keys": cache_keys(work, record)})
    return write_asset_records(adir, old.model_copy(update={
        "validation": validation, "action_plan": reported_plan(record),
        "manipulation": manipulation_outcome(l3.metrics), "provenance": prov}))


def _partial_prefix(out_dir: Path) -> str:
    """Working directories are named .<name>.partial-<host>~<pid>~<random>, so a dead owner can be recognised."""
    return f".{out_dir.name}.partial-"


def remove_stale_partials(out_dir: Path) -> list[Path]:
    """Remove working directories of out_dir left by a process of this host that died (SIGKILL, power loss)."""
    return remove_paths(dead_partials(out_dir.parent, out_dir.name))[0]


def _set_aside(out_dir: Path) -> Path | None:
    """Move a previous asset out of the way, as tasks.publish.replace_directory does (`.<name>.old-<owner>`: a dead
    owner's is cleared by remove_stale_partials), so that removing its ~350 files does not hold up the publish."""
    if not out_dir.exists():
        return None
    aside = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.old-{owner_tag()}", dir=out_dir.parent))
    os.replace(out_dir, aside / "previous")
    return aside


def generate_asset(request: AssetRequest | CheckedRequest, out_dir: Path, device: Device = "cpu",
                   agents: AgentConfig | None = None, on_stage: StageCallback | None = None, manipulate: bool = True,
                   cpu_threads: int = 1, keep: KeepTrials = DEFAULT_KEEP) -> AssetManifest:
    """Run every layer for one request and publish the asset directory: the `generate` flow against the local Prefect
    runtime. Bad input (a rigid material, a bad target override, a size L0 cannot build, an output that is not an
    asset directory) fails before any flow starts; the request is checked here once (tasks.request), unless the
    caller checked it already (the CLI)."""
    checked = checked_request(request)
    check_out_dir(Path(out_dir).expanduser().absolute())
    with cache.local_runtime():
        return generate(checked, out_dir, device, agents, on_stage, manipulate, cpu_threads, keep)


@lean_flow(name="generate", validate_parameters=False, persist_result=False)
def generate(checked: AssetRequest | CheckedRequest, out_dir: Path, device: Device = "cpu",
             agents: AgentConfig | None = None, on_stage: StageCallback | None = None, manipulate: bool = True,
             cpu_threads: int = 1, keep: KeepTrials = DEFAULT_KEEP) -> AssetManifest:
    """L0 -> L1 -> L2 -> drop renders (-> L3) -> publish, each layer a subflow (l0-geometry, l1-physical, l2-material,
    l3-manipulation); StageFailure when L0, L1 or L2 says no.

    cpu_threads: on the CPU, threads sharing each MPM rollout's particles (SimConfig.cpu_threads).
    keep: 'adopted' (the default) publishes the reported L3 trial's states and recording alone, every other trial's
    staying in the cache (their rows name the key); 'all' (`--record all`) publishes every trial's.

    L3 (``manipulate``) validates the asset with a robot: its outcome (passed or not, with the failed gates and the
    labelled attempts) is part of the published asset, since the deformable asset itself was established by L0-L2.
    """
    import time

    report = on_stage or (lambda stage, message: None)
    clock: _StageClock = {"stage": "", "t": time.perf_counter()}
    TIMINGS.clear()

    def note(stage: str, message: str | None = None) -> None:  # no message: a stage timed apart, not said
        now = time.perf_counter()
        if clock["stage"]:
            TIMINGS[str(clock["stage"])] = now - float(clock["t"])
        clock["stage"], clock["t"] = stage, now
        if message is not None:
            report(stage, message)

    checked = checked_request(checked)  # checked at the boundary (generate_asset): not again
    request, targets = checked.request, checked.targets

    reset_fallbacks()  # an LLM found unusable in an earlier run of this process is asked again
    out_dir = Path(out_dir).expanduser().absolute()
    check_out_dir(out_dir)
    out_dir.parent.mkdir(parents=True, exist_ok=True)
    remove_stale_partials(out_dir)
    work = Path(tempfile.mkdtemp(prefix=_partial_prefix(out_dir) + owner_tag(), dir=out_dir.parent))
    try:
        note("L0", "geometry")
        l0 = l0_geometry.run_l0(request, quality=request.quality, agents=agents)  # a litellm Designer writes the shape too
        if not l0.checks.passed:
            raise StageFailure("L0", f"geometry gates failed: {', '.join(l0.checks.failed)}")
        for warning in l0.info.warnings:  # recorded in geometry.json; said here too, as the run goes
            report("L0", f"warning: {warning}")
        shutil.rmtree(work)  # write_l0 publishes into a path of its own choosing
        l0_geometry.write_l0(l0, work, extra={"request": request.model_dump(mode="json")})
        intent = request.material_intent or request.text
        note("L1", "physical model: rigid probes")
        physical, o1 = l1_physical.run_l1(work, intent, agents, keep=keep)
        if physical is None:
            raise StageFailure("L1", o1.message)
        note("L2", "material: MPM probes")
        if not targets.matched_words:
            report("L2", f"warning: no material named in '{targets.intent}': using the default material's target bands")
        sim = SimConfig(device=device, cpu_threads=cpu_threads)
        material, o2 = l2_material.run_l2(work, request, agents, sim=sim, physical=physical, keep=keep)
        if material is None:
            raise StageFailure("L2", o2.message)
        note("renders", "drop protocol: 5 s drop at 30 fps, two views")

        protocol = renders.render_drop_protocol(work, physical, material, sim)
        adir = AssetDir(work)  # what L0, L1 and L2 wrote, validated
        validation = [stage_summary(adir.geometry()), stage_summary(adir.physical()), stage_summary(adir.material())]
        plan, outcome, l3 = None, None, None
        if manipulate:
            note("L3", "manipulation: Panda pick-and-place in the MPM")
            l3 = run_manipulation(work, device, request.quality, agents, cpu_threads,  # "L3 trial k of n: ..." lines
                                  progress=lambda message: report("L3", message.removeprefix("L3").lstrip(": ")),
                                  keep=keep, on_video=lambda: note("pick_and_place_video"))
            validation.append(l3_summary(l3))
            plan = reported_plan(l3)  # adopted, else the best tried under the material the asset carries
            outcome = manipulation_outcome(validation[-1].metrics)
        note("card")  # the card, the PhysGaussian config and asset.json
        prov = provenance(device, agents, sim.cpu_threads, sim.kernel)
        prov = prov.model_copy(update={"cache_keys": cache_keys(work, l3),  # what made the shape (L0's generator)
                                       "backends": {**prov.backends, "geometry": l0.info.generator},
                                       "fallbacks": fallback_notes(work)})  # where the rule backend stood in
        manifest = write_asset_records(adir, AssetManifest(  # the material: L2's, or the revision L3 passed with
            request=request, physical_model=physical, validation=validation, action_plan=plan, manipulation=outcome,
            provenance=prov, extra={"drop_protocol": protocol}))
        note("publish", str(out_dir))
        previous = _set_aside(out_dir)
        try:
            replace_directory(work, out_dir)  # (out_dir is free: a rename)
        except BaseException:
            if previous is not None and not out_dir.exists():  # the previous asset stays in place
                os.replace(previous / "previous", out_dir)
                shutil.rmtree(previous, ignore_errors=True)
            raise
        if previous is not None:  # removed beside the rest of the run; the thread is joined before the process ends
            threading.Thread(target=shutil.rmtree, args=(previous,), kwargs={"ignore_errors": True},
                             name="remove-previous-asset").start()
        TIMINGS["publish"] = time.perf_counter() - float(clock["t"])
        return manifest
    finally:
        if work.exists():
            shutil.rmtree(work, ignore_errors=True)


def content_fingerprint(asset_dir: Path) -> dict[str, str]:
    """Relative path -> digest of every file: JSON canonically, `.rrd` by what it shows (Rerun stamps ids and
    wall-clock times on each write), everything else by bytes. Two runs of the same request on CPU match."""
    import hashlib

    root = Path(asset_dir)
    out: dict[str, str] = {}
    for path in sorted(p for p in root.rglob("*") if p.is_file()):
        rel = path.relative_to(root).as_posix()
        if path.suffix == ".rrd":
            out[rel] = recording_digest(path)
        elif path.suffix == ".json":
            doc = json.dumps(json.loads(path.read_text(encoding="utf-8")), sort_keys=True)
            out[rel] = hashlib.sha256(doc.encode()).hexdigest()
        elif path.suffix == ".jsonl":
            text = path.read_text(encoding="utf-8")
            lines = [json.dumps(json.loads(ln), sort_keys=True) for ln in text.splitlines() if ln.strip()]
            out[rel] = hashlib.sha256("\n".join(lines).encode()).hexdigest()
        else:
            out[rel] = hashlib.sha256(path.read_bytes()).hexdigest()
    return out


def load_manifest(asset_dir: Path) -> AssetManifest:
    """The manifest of a published asset directory (InputError when there is none or it is invalid): AssetDir's."""
    return AssetDir(asset_dir).manifest()
