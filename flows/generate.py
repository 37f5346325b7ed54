"""`generate`: L0 -> L1 -> L2 (-> L3) on one working directory, then an atomic publish of the asset directory.

Resume is the cache's job: every expensive unit is a content-cached task, so a rerun after a crash rebuilds the
working directory from hits and re-executes only what never finished. The working directory is private
(`.<name>.partial-<pid>` next to the output) and is renamed into place only when every layer passed.
"""

from __future__ import annotations

import contextvars
import shutil
import time
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path
from typing import TypedDict, TypeVar

import cache  # (sets the local Prefect environment before prefect is imported)
from cache.prefect_flow import lean_flow
from contracts.agents import AgentConfig
from contracts.asset_dir import DEFAULT_KEEP, KeepTrials
from contracts.errors import RequirementNotMet, StageFailure
from contracts.manifest import AssetManifest
from contracts.manipulation import ManipulationRecord, TrialRow
from contracts.request import AssetRequest
from contracts.sim import Device, SimConfig
from flows import l0_geometry, l1_physical, l2_material, l3_manipulation, renders
from tasks.agents.fallbacks import fallback_notes, reset as reset_fallbacks
from tasks.asset_dir import AssetDir
from tasks.export.physgaussian import write_physgaussian_export
from tasks.manifest_summary import (
    asset_files, cache_keys, l3_summary, manipulation_outcome, provenance, reported_plan, stage_summary,
)
from tasks.manipulation.pick_place_video import prerender_pick_and_place_video, write_pick_and_place_video
from tasks.publish import check_out_dir, publish_directory, working_dir
from tasks.request import CheckedRequest, checked_request

T = TypeVar("T")
StageCallback = Callable[[str, str], None]  # (stage, message)
TIMINGS: dict[str, float] = {}  # wall time per layer of the last generate_asset call in this process [s]


class _StageClock(TypedDict):
    """The stage being timed and when it started (time.perf_counter() [s])."""

    stage: str
    t: float


def timed_stage(stage: str, work: Callable[[], T]) -> T:
    """work(), its wall time recorded in TIMINGS[stage] (a stage run beside another one, in a thread of its own)."""
    start = time.perf_counter()
    try:
        return work()
    finally:
        TIMINGS[stage] = time.perf_counter() - start


def require_l3(manifest: AssetManifest, out_dir: Path) -> None:
    """`--require-l3`: RequirementNotMet (exit 7) when L3 ran and did not pass; the asset is already published."""
    l3 = next((s for s in manifest.validation if s.stage == "L3"), None)
    if l3 is not None and not l3.passed:
        raise RequirementNotMet("L3", l3.reason or ", ".join(l3.failed_gates), str(out_dir))


def run_manipulation(work: Path, device: Device, quality: str, agents: AgentConfig | None,
                     cpu_threads: int = 1, progress: Callable[[str], None] | None = None,
                     keep: KeepTrials = DEFAULT_KEEP, on_video: Callable[[], None] | None = None,
                     beside: ThreadPoolExecutor | None = None) -> ManipulationRecord:
    """L3 on the working directory and the pick-and-place video of the shown attempt; the manipulation record.
    keep: which trials' states and recordings the asset keeps (tasks.manipulation.keep; the rest stay cached).
    on_video: called as the video starts (generate times it apart).
    beside: a pool that draws the video of the first selection trial that passes while L3's later trials run (it is
    the trial reported unless a later one fails); the video then only copies it from the cache."""
    options = (l3_manipulation.L3Options(device=device, cpu_threads=cpu_threads) if quality == "draft"
               else l3_manipulation.L3Options.standard(device, cpu_threads))
    early: list[Future[bool]] = []

    def draw_early(row: TrialRow, passed: bool) -> None:
        if beside is not None and not early and row.role == "selection" and passed and row.data_key:
            early.append(beside.submit(contextvars.copy_context().run, prerender_pick_and_place_video, row.data_key,
                                       device))

    try:
        record, _ = l3_manipulation.run_l3(work, options, agents, progress=progress, keep=keep, on_stored=draw_early)
    finally:
        for drawn in early:  # (L3's error waits for it: the cache entry is complete or absent)
            drawn.exception()
    if on_video is not None:
        on_video()
    write_pick_and_place_video(work, record, device)
    return record


def write_asset_records(adir: AssetDir, manifest: AssetManifest) -> AssetManifest:
    """asset.json with the adopted material (AssetDir.adopted_material) and the file roles, and the PhysGaussian
    config and the card that carry the same material; returns the manifest as written."""
    manifest = manifest.model_copy(update={"material": adir.adopted_material().material})
    write_physgaussian_export(adir)
    renders.write_card(adir.path, manifest)  # the asset card: renders/card.png, card.html (what L0-L3 found)
    manifest = manifest.model_copy(update={"files": asset_files(adir.path)})
    adir.write_manifest(manifest)
    return manifest


def refresh_after_l3(work: Path, record: ManipulationRecord, device: Device = "cpu") -> AssetManifest | None:
    """After `deformsmith manipulate` re-ran L3 on a published asset (work: its staged working copy): everything that
    carries L3's result or the adopted material, rewritten from the new manipulation.json as generate writes it:
    asset.json (material, L3's validation line, action plan, outcome, L3's cache keys, file roles), the PhysGaussian
    config, the card and the pick-and-place video (drawn on `device`, L3's). None (nothing rewritten) when the
    directory has no asset.json."""
    adir = AssetDir(work)
    if not adir.has("manifest"):
        return None
    old = adir.manifest()
    write_pick_and_place_video(work, record, device)
    l3 = l3_summary(record)
    validation = [s for s in old.validation if s.stage != "L3"] + [l3]
    prov = old.provenance.model_copy(update={"cache_keys": cache_keys(work, record)})
    return write_asset_records(adir, old.model_copy(update={
        "validation": validation, "action_plan": reported_plan(record),
        "manipulation": manipulation_outcome(l3.metrics), "provenance": prov}))


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
    work = working_dir(out_dir)  # .<name>.partial-<owner>: a dead run's of out_dir are removed first
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
        beside = manipulate and device == "cpu"  # (on CUDA, a second thread's launches would break L3's graph capture)
        note("renders", "drop protocol: 5 s drop at 30 fps, two views" + (" (beside L3)" if beside else ""))
        adir = AssetDir(work)  # what L0, L1 and L2 wrote, validated
        validation = [stage_summary(adir.geometry()), stage_summary(adir.physical()), stage_summary(adir.material())]
        plan, outcome, l3 = None, None, None
        with ThreadPoolExecutor(max_workers=1, thread_name_prefix="beside-l3") as pool:
            if beside:  # the drop renders carry L2's material, not L3's: drawn in a thread while L3 runs on the
                # other core, then the pick-and-place video of L3's first passed trial (run_manipulation)
                drawn = pool.submit(contextvars.copy_context().run, timed_stage, "renders",
                                    lambda: renders.render_drop_protocol(work, physical, material, sim))
                clock["stage"] = ""  # the renders' time is the thread's own (timed_stage), not the clock's
            else:
                protocol = renders.render_drop_protocol(work, physical, material, sim)
            if manipulate:
                note("L3", "manipulation: Panda pick-and-place in the MPM")
                l3 = run_manipulation(work, device, request.quality, agents, cpu_threads,  # "L3 trial k of n" lines
                                      progress=lambda message: report("L3", message.removeprefix("L3").lstrip(": ")),
                                      keep=keep, on_video=lambda: note("pick_and_place_video"),
                                      beside=pool if beside else None)
            if beside:
                protocol = drawn.result()  # (an L3 error waits for the renders here before the work dir goes)
        if l3 is not None:
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
        publish_directory(work, out_dir)  # one rename; the previous asset is removed beside the rest of the run
        TIMINGS["publish"] = time.perf_counter() - float(clock["t"])
        return manifest
    finally:
        if work.exists():
            shutil.rmtree(work, ignore_errors=True)


def load_manifest(asset_dir: Path) -> AssetManifest:
    """The manifest of a published asset directory (InputError when there is none or it is invalid): AssetDir's."""
    return AssetDir(asset_dir).manifest()
