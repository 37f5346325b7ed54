"""What an asset card shows, gathered from the typed asset directory (tasks.asset_dir.AssetDir) and the attempt
records (evidence/attempts.jsonl, tasks.record.tally): every number with the probe and the cache key / record it
came from. Pure data (no drawing): card_png and card_html draw it.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
from pydantic import BaseModel, ConfigDict

from contracts.agents import TargetBehaviour
from contracts.asset_dir import MANIPULATION_JSON, MATERIAL_JSON, PHYSICAL_JSON, MaterialRecord, attempt_path
from contracts.concept import ConceptMatch
from contracts.evidence import Attempt, StageTally
from contracts.manifest import AssetManifest
from contracts.probes import not_measured_reason
from tasks.asset_dir import AssetDir
from tasks.record.attempts import ATTEMPTS_FILE, read_attempts
from tasks.record.tally import stage_tallies
from tasks.record.trials import data_location
from tasks.render.card_calibration import CalibrationCard, calibration_card
from tasks.render.protocol_video import CARD_TIMES_S, VIEW_NAMES, card_still_name

STILL_VIEWS = ("iso", "front", "side", "top")  # renders/<view>.png (L0; iso since mesh version 17)
PROTOCOL_FPS = 30.0  # the drop videos' frame rate (tasks.probes.protocol.PROTOCOL_FPS)
# L2 band metric -> the selection probe that measures it (flows.l2_material: the bands come from the specimen)
L2_BAND_PROBE = {"effective_modulus_pa": "specimen_compress", "recovery_ratio": "specimen_compress",
                 "rebound_ratio": "specimen_drop", "sag_ratio": "lift"}
# L1 figures shown: metric -> (label, unit); the probe is the metric's prefix (place_, drop_, slide_)
L1_FIGURES = {"mass_kg": ("mass", "kg"), "volume_m3": ("volume", "m^3"),
              "drop_max_transient_penetration_m": ("drop: max penetration", "m"),
              "drop_penetration_m": ("drop: rest penetration", "m"), "drop_settle_time_s": ("drop: settle time", "s"),
              "place_tilt_deg": ("place: tilt at rest", "deg"),
              "slide_critical_angle_deg": ("slide: critical angle", "deg")}
L3_FIGURES = {"max_finger_force_n": ("max finger force", "N"), "hold_normal_force_n": ("hold normal force", "N"),
              "weight_n": ("object weight", "N"), "hold_friction_ratio": ("friction capacity / weight", "-"),
              "lift_rise_m": ("lift rise", "m"), "slip_distance_m": ("slip distance", "m"),
              "place_error_m": ("place error", "m"), "max_strain": ("max strain", "-")}
# why an L3 figure can have no value: the labels of a trial whose object was never held hold NaN there
L3_ABSENT = {"hold_normal_force_n": "no hold: the object was never held in the hand",
             "hold_friction_ratio": "no hold: the object was never held in the hand",
             "slip_distance_m": "no hold: the object was never held in the hand",
             "place_error_m": "not placed: the object never reached the release"}
PROTOCOL_FIGURES = {"drop_height_m": ("drop clearance", "m"), "shape_retention": ("shape retention", "-"),
                    "volume_ratio_end": ("volume ratio at 5 s", "-"), "tilt_deg_end": ("tilt at 5 s", "deg"),
                    "plausible": ("plausible (1 = yes)", "-")}


def request_title(request: dict[str, Any], limit: int = 60) -> str:
    """The card's title: the request's text, or its photo's or mesh's file name (never the asset's folder name, so an
    asset's files do not change when it is moved or renamed)."""
    text = str(request.get("text") or "").strip()
    if not text:
        source = request.get("image_path") or request.get("mesh_path") or "asset"
        text = Path(str(source)).name
    return text if len(text) <= limit else text[:limit - 3].rstrip() + "..."


class Figure(BaseModel):
    """One number on the card: its value, unit, target band (when it has one) and where it came from."""

    model_config = ConfigDict(frozen=True)

    label: str
    metric: str
    value: float | None
    unit: str
    band: tuple[float, float] | None = None
    met: bool | None = None
    source: str  # the probe / record that measured it
    key: str | None = None  # the cache key of that probe's result
    note: str | None = None  # value None: why there is no value (never a NaN on the card)

    @property
    def state(self) -> str:
        """'measured inside' / 'measured outside' (a band) / 'measured' (no band) / 'not measured'."""
        if self.value is None:
            return "not measured"
        if self.band is None:
            return "measured"
        return "measured inside" if self.met else "measured outside"


def figure(label: str, metric: str, value: float | None, unit: str, source: str, key: str | None = None,
           band: tuple[float, float] | None = None, note: str | None = None) -> Figure:
    """A card figure; a value that is absent or not a finite number is no value, with the reason (`note`)."""
    measured = value is not None and math.isfinite(value)
    why = None if measured else (note or ("the record holds no finite value" if value is not None
                                          else "the record holds no value"))
    met = (band[0] <= value <= band[1]) if (band is not None and measured and value is not None) else None
    return Figure(label=label, metric=metric, value=value if measured else None, unit=unit, band=band,
                  met=met, source=source, key=key, note=why)


class DropFrame(BaseModel):
    """One frame of the drop protocol on the card: the PNG written with the videos, else a frame of the video."""

    model_config = ConfigDict(frozen=True)

    view: str
    t_s: float
    still: str | None  # renders/drop_<view>_t<t>s.png, relative to the asset
    video: str | None  # renders/drop_<view>.mp4 (used when there is no still)
    video_frame: int


class L3Card(BaseModel):
    """L3 on the card: the gripper, the outcome, the finger-force curve of the reported trial (ran=False: no L3)."""

    ran: bool
    note: str
    gripper: str | None = None
    gripper_reason: str | None = None
    grasp_reason: str | None = None  # the part held and why (a soft toy by its body)
    passed: bool | None = None
    status: str | None = None
    outcome: dict[str, bool] = {}
    figures: list[Figure] = []
    force_budget_n: float | None = None
    attempt: int | None = None  # the interaction folder (interaction/attempt_NNN) of the reported trial
    data: str | None = None  # where its states are: 'interaction/attempt_NNN', or 'in the cache, key ...' (#38)
    others: str | None = None  # where the other trials' states and recordings are, in words
    trial: int | None = None  # the reported trial's number (tasks.record.trials: from 1, in the order run)
    trials: int = 0  # the simulated pick-and-places L3 ran
    key: str | None = None
    force_t_s: list[float] = []
    finger_force_n: list[tuple[float, float]] = []  # |force| on each finger per control step


class LayerVerdict(BaseModel):
    """One layer at a glance: PASSED / NOT PASSED and one plain sentence (the card's first section)."""

    model_config = ConfigDict(frozen=True)

    stage: str  # L0 .. L3
    title: str  # "Shape", "Weight and contact", "Material", "Robot pick-and-place"
    passed: bool | None  # None: the layer did not run
    sentence: str


class CardData(BaseModel):
    """Everything the asset card shows."""

    name: str
    request: dict[str, Any]
    views: dict[str, str]  # view -> renders/<view>.png
    drop_frames: list[DropFrame]
    videos: dict[str, str]  # label -> relative path of an existing MP4
    material: list[Figure]  # E, nu, damping
    bands: list[Figure]  # the L2 target bands with the measured values
    l1: list[Figure]
    protocol: list[Figure]
    l3: L3Card
    stages: list[str]  # one line per stage: status, attempts, simulations (tasks.record.tally)
    sources: list[str]  # probe -> cache key lines, and the records read
    built: str | None = None  # what L0 built: "plush dog (named in the lexicon)"
    analogy: list[str] = []  # when built by analogy: the one-line note, then the chain (geometry.json concept)
    layers: list[LayerVerdict] = []  # L0..L3 at a glance
    material_words: str | None = None  # "soft as a plush toy: E = 9.98 kPa"
    calibration: CalibrationCard | None = None  # calibrated from a video (calibration/video_fit.json), else None


def _number(value: Any) -> float | None:
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None


def _short(key: str | None) -> str:
    return key[:12] if key else "-"


def _probe_keys(attempts: list[Attempt], stage: str, iteration: int | None) -> dict[str, str]:
    """Probe kind -> cache key of one attempt's probes (its evidence lists keys and recordings in the same order;
    a recording recordings/L2_<kind>-<hash>.rrd names the kind). iteration None: the stage's accepted attempt, else
    its last."""
    mine = [a for a in attempts if a.stage == stage]
    if iteration is not None:
        mine = [a for a in mine if a.iteration == iteration]
    elif any(a.verdict == "accepted" for a in mine):
        mine = [a for a in mine if a.verdict == "accepted"]
    if not mine:
        return {}
    ev = mine[-1].evidence
    out = {}
    for key, rec in zip(ev.probe_keys, ev.recordings):
        kind = Path(rec).stem.split("-")[0].removeprefix(f"{stage}_")
        out[kind] = key
    return out


def _band_figures(targets: TargetBehaviour, metrics: dict[str, float], keys: dict[str, str],
                  record: str, not_measured: dict[str, str]) -> list[Figure]:
    """A figure per target band: the measured value, the band, whether it holds, the probe and its cache key."""
    out = []
    for b in targets.bands:
        value = metrics.get(b.metric)
        probe = L2_BAND_PROBE.get(b.metric, "probe")
        label = b.metric.removesuffix(f"_{b.unit.lower()}").replace("_", " ")  # effective_modulus_pa: effective modulus
        why = not_measured.get(b.metric) or not_measured_reason(b.metric, metrics)
        out.append(figure(label, b.metric, value, b.unit, f"{record}: {probe} ({b.source})", keys.get(probe),
                          band=(b.low, b.high), note=why))
    return out


def _drop_frames(adir: AssetDir) -> list[DropFrame]:
    frames = []
    for view in VIEW_NAMES:
        video = f"renders/drop_{view}.mp4"
        for t in CARD_TIMES_S:
            still = f"renders/{card_still_name(view, t)}"
            frames.append(DropFrame(view=view, t_s=t, still=still if (adir.path / still).is_file() else None,
                                    video=video if (adir.path / video).is_file() else None,
                                    video_frame=int(round(t * PROTOCOL_FPS))))
    return frames


def _l3(adir: AssetDir, manifest: AssetManifest) -> L3Card:
    if not adir.has("manipulation"):
        return L3Card(ran=False, note="L3 (robot pick-and-place) was not run for this asset (--no-l3)")
    rec = adir.manipulation()
    best = rec.best_attempt
    attempt = rec.attempt if rec.attempt is not None else (best.attempt if best else None)
    trial = rec.trial_of_attempt(attempt)
    labels = rec.labels or (best.labels if best else {})
    key = manifest.provenance.cache_keys.get("l3.trial") or (best.cache_key if best else None)
    figures = [figure(label, m, _number(labels.get(m)), unit, f"{MANIPULATION_JSON}: trial {trial}", key,
                      note=L3_ABSENT.get(m))
               for m, (label, unit) in L3_FIGURES.items() if m in labels]
    gripper = rec.plan.gripper if rec.plan else rec.gripper.name
    card = L3Card(ran=True, note=rec.message or rec.reason, gripper=gripper,
                  gripper_reason=rec.plan.gripper_reason if rec.plan else None,
                  grasp_reason=(rec.plan.grasp_reason or None) if rec.plan else None, passed=rec.passed,
                  status=rec.status,
                  outcome=dict(rec.outcome), figures=figures, force_budget_n=rec.force_budget_n, attempt=attempt,
                  trial=trial, trials=rec.simulated_trials(), key=key)
    row = next((r for r in rec.attempts if attempt is not None and r.attempt == attempt), None)
    cached = [r.trial or i + 1 for i, r in enumerate(rec.attempts) if r.attempt is not None and r is not row
              and data_location(r, adir.path) != attempt_path(r.attempt)]
    card = card.model_copy(update={
        "data": data_location(row, adir.path) if row is not None else None,
        "others": (f"trial{'s' if len(cached) > 1 else ''} {_ranges(cached)}: states and recordings in the cache "
                   f"(manipulation.json attempts[].data_key; deformsmith replay DIR --trial N)") if cached else None})
    folder = adir.path / attempt_path(attempt) if attempt is not None else None
    if folder is not None and folder.is_dir():
        curve = _force_curve(folder)
        if curve is not None:
            card = card.model_copy(update={"force_t_s": curve[0].tolist(),
                                           "finger_force_n": [(float(a), float(b)) for a, b in curve[1]]})
    return card


def _ranges(numbers: list[int]) -> str:
    """[1, 2, 3, 5] -> '1-3, 5'."""
    out: list[str] = []
    for n in sorted(numbers):
        if out and out[-1].split("-")[-1] == str(n - 1):
            out[-1] = f"{out[-1].split('-')[0]}-{n}"
        else:
            out.append(str(n))
    return ", ".join(out)


def _force_curve(folder: Path) -> tuple[np.ndarray, np.ndarray] | None:
    """Control times [s] and |force| on each finger (K, 2) [N] of a recorded trial (None when unreadable: the card
    then says there is no finger-force record)."""
    import zarr

    try:
        arrays = dict(zarr.open_group(str(folder), mode="r").arrays())
        t = np.asarray(arrays["control_t_s"][...], np.float64)
        f = np.linalg.norm(np.asarray(arrays["finger_force_n"][...], np.float64), axis=2)
    except (OSError, ValueError, KeyError, IndexError, TypeError):  # zarr's read errors are ValueError / KeyError kin
        return None
    return (t, f) if f.ndim == 2 and f.shape[1] == 2 and len(t) == len(f) else None


def _material_figures(adir: AssetDir, record: MaterialRecord,
                      attempts: list[Attempt]) -> tuple[list[Figure], list[Figure], str | None]:
    """The adopted material's rows (AssetDir.adopted_material: L2's, or an adopted L3 revision), its target bands as
    measured on it, and the material in words."""
    chosen = f"{MATERIAL_JSON} ({record.status}; evidence/attempts.jsonl L2 #{record.selection.best_iteration})"
    keys = _probe_keys(attempts, "L2", record.selection.best_iteration)
    measured_in, not_measured = f"{MATERIAL_JSON} metrics", record.not_measured
    if record.material is None:
        return [], _band_figures(record.targets, record.metrics, keys, measured_in, not_measured), None
    adopted = adir.adopted_material()
    if adopted.source == "L3 revision":  # its probes' keys are in manipulation.json, not named by kind
        chosen = f"{MANIPULATION_JSON} (L3 material revision, L2 revalidated)"
        keys, measured_in, not_measured = {}, f"{MANIPULATION_JSON} material_revision l2_revalidation metrics", {}
    mat = adopted.material
    rows = [Figure(label="Young's modulus E", metric="youngs_modulus_pa", value=mat.youngs_modulus_pa, unit="Pa",
                   source=chosen),
            Figure(label="Poisson ratio nu", metric="poisson_ratio", value=mat.poisson_ratio, unit="-", source=chosen),
            Figure(label="damping rate", metric="damping_rate_per_s", value=mat.damping_rate_per_s, unit="1/s",
                   source=chosen)]
    bands = _band_figures(record.targets, adopted.metrics, keys, measured_in, not_measured)
    return rows, bands, material_words(mat.youngs_modulus_pa, adopted.metrics.get("rebound_ratio"))


def card_data(asset_dir: Path | str, manifest: AssetManifest | None = None) -> CardData:
    """The card's content for an asset directory (InputError naming the file when a document is missing or invalid).

    manifest: the manifest about to be written (generate builds the card before asset.json is published)."""
    adir = AssetDir(asset_dir)
    manifest = manifest or adir.manifest()
    physical, material = adir.physical(), adir.material()
    path = adir.path / ATTEMPTS_FILE
    attempts = read_attempts(path) if path.is_file() else []
    l1_keys = _probe_keys(attempts, "L1", None)
    material_rows, bands, words = _material_figures(adir, material, attempts)
    mass_band = {b.metric: b for b in physical.targets.bands}
    l1_rows = []
    for m, (label, unit) in L1_FIGURES.items():
        if m not in physical.metrics:
            continue
        probe = m.split("_")[0] if m.split("_")[0] in l1_keys else "mass check"
        band = mass_band.get(m)
        l1_rows.append(figure(label, m, _number(physical.metrics[m]), unit, f"{PHYSICAL_JSON}: {probe}",
                              l1_keys.get(probe), band=(band.low, band.high) if band else None))
    pm = physical.physical_model
    if pm is not None:
        l1_rows += [Figure(label="density", metric="density_kg_per_m3", value=pm.density_kg_per_m3, unit="kg/m^3",
                           source=f"{PHYSICAL_JSON}: mass check ({physical.mass_check.get('source', '-')})"),
                    Figure(label="ground friction", metric="ground_friction", value=pm.ground_friction, unit="-",
                           source=f"{PHYSICAL_JSON}: slide", key=l1_keys.get("slide"))]
    drop = (manifest.extra or {}).get("drop_protocol") or {}
    protocol = [figure(label, m, _number(drop[m]), unit, "asset.json extra.drop_protocol: task renders.drop_protocol")
                for m, (label, unit) in PROTOCOL_FIGURES.items() if m in drop]
    tallies = stage_tallies(adir.path, attempts)
    l3 = _l3(adir, manifest)
    stages = [_stage_line(t, l3) for t in tallies]
    sources = [f"{name}: {_short(key)}" for name, key in sorted(manifest.provenance.cache_keys.items())]
    sources += [f"L1.{kind}: {_short(key)}" for kind, key in sorted(l1_keys.items())]
    videos = {label: rel for label, rel in (("drop, front", "renders/drop_front.mp4"),
                                            ("drop, side", "renders/drop_side.mp4"),
                                            ("pick and place", "renders/pick_and_place.mp4"))
              if (adir.path / rel).is_file()}
    views = {v: f"renders/{v}.png" for v in STILL_VIEWS if (adir.path / "renders" / f"{v}.png").is_file()}
    built, analogy = _built(adir)
    layers = _layers(adir, tallies, bands, l3, words, built)
    request = manifest.request.model_dump(mode="json")
    return CardData(name=request_title(request), request=request, views=views,
                    drop_frames=_drop_frames(adir), videos=videos, material=material_rows, bands=bands, l1=l1_rows,
                    protocol=protocol, l3=l3, stages=stages, sources=sources, built=built,
                    analogy=analogy, layers=layers, material_words=words, calibration=calibration_card(adir.path))


def _stage_line(t: StageTally, l3: L3Card) -> str:
    """The technical line of a stage: harness status, attempts, simulations; L3 in trials (tasks.record.trials)."""
    words = {"best_valid": ("best_valid (a measured target missed)" if t.unmet_targets else
                            "best_valid as recorded, yet every measured target was met")}
    if t.stage == "L3" and l3.ran:
        shown = f", reported: trial {l3.trial}" if l3.trial is not None else ""
        line = f"L3: {t.status}, {l3.trials} trial(s) (simulated pick-and-places, numbered from 1){shown}"
    else:
        line = f"{t.stage}: {words.get(t.status, t.status)}, {t.attempts} attempt(s), {t.sim_calls} simulation(s)"
    line += f"; targets missed: {', '.join(t.unmet_targets)}" if t.unmet_targets else ""
    line += "".join(f"; {m} not measured ({why})" for m, why in t.not_measured.items())
    return line


# (upper bound of E [Pa], the comparison) for the material in plain words
STIFFNESS_WORDS = ((4e3, "very soft, like a jelly"), (4e4, "soft as a plush toy"), (4e5, "squishy like a foam sponge"),
                   (4e6, "rubbery like a rubber duck"), (4e7, "firm like a shoe sole"),
                   (math.inf, "stiff like hard plastic"))


def si_short(value: float, unit: str) -> str:
    """10 kPa, 1.5 MPa: a value for a sentence."""
    for scale, prefix in ((1e9, "G"), (1e6, "M"), (1e3, "k"), (1.0, "")):
        if abs(value) >= scale * 0.9995:
            return f"{value / scale:.3g} {prefix}{unit}"
    return f"{value:.3g} {unit}"


def material_words(youngs_modulus_pa: float, rebound: float | None) -> str:
    """The material in plain words: 'soft as a plush toy: E = 9.98 kPa'; ', bouncy' / ', does not bounce' from the
    measured rebound."""
    feel = next(words for upper, words in STIFFNESS_WORDS if youngs_modulus_pa < upper)
    bounce = ""
    if rebound is not None and math.isfinite(rebound):
        bounce = ", bouncy" if rebound >= 0.4 else (", hardly bounces" if rebound < 0.15 else "")
    return f"{feel}{bounce}: E = {si_short(youngs_modulus_pa, 'Pa')}"


def _layers(adir: AssetDir, tallies: list[StageTally], bands: list[Figure], l3: L3Card, words: str | None,
            built: str | None) -> list[LayerVerdict]:
    """Each layer's PASSED / NOT PASSED and one plain sentence."""
    by = {t.stage: t for t in tallies}
    out = []
    t0 = by.get("L0")
    if t0 is not None:
        what = (built or "the object").removeprefix("built: ").split(" (named in the lexicon")[0]
        out.append(LayerVerdict(stage="L0", title="Shape", passed=t0.passed, sentence=(
            f"A closed 3D shape was built: {what}." if t0.passed else
            f"The shape failed a check: {t0.message or t0.status}.")))
    t1 = by.get("L1")
    if t1 is not None:
        pm = adir.physical().physical_model if t1.passed else None
        out.append(LayerVerdict(stage="L1", title="Weight and contact", passed=t1.passed, sentence=(
            f"It weighs {si_short(pm.mass_kg * 1000, 'g')}, a plausible mass, and it rests, drops and slides on a "
            "table as it should." if pm is not None else f"Its weight or contact failed a check: {t1.message}.")))
    t2 = by.get("L2")
    if t2 is not None:
        missed = [b.label for b in bands if b.state == "measured outside"]
        unmeasured = [b.label for b in bands if b.state == "not measured"]
        ok = t2.passed and not missed
        feel = (words or "").split(":")[0]
        sentence = f"{feel[:1].upper()}{feel[1:]}." if words else "No material was found."
        if t2.passed:
            sentence += (f" Measured outside its target: {', '.join(missed)}." if missed
                         else " Every measured behaviour is inside its target.")
            if unmeasured:
                sentence += f" Not measured: {', '.join(unmeasured)} (see below)."
        out.append(LayerVerdict(stage="L2", title="Material", passed=ok, sentence=sentence))
    if not l3.ran:
        out.append(LayerVerdict(stage="L3", title="Robot pick-and-place", passed=None,
                                sentence="Not run for this asset (--no-l3)."))
    else:
        trial = f" (trial {l3.trial} of {l3.trials})" if l3.trial is not None else ""
        out.append(LayerVerdict(stage="L3", title="Robot pick-and-place", passed=bool(l3.passed), sentence=(
            f"A robot arm with the {l3.gripper} gripper picked it up, carried it and put it down on target{trial}."
            if l3.passed else f"The robot did not complete the pick-and-place{trial}: {l3.note}.")))
    return out


def _built(adir: AssetDir) -> tuple[str | None, list[str]]:
    """(what L0 built, in words; the analogy note and chain when the object was not named in the lexicon)."""
    if not adir.has("geometry"):
        return None, []
    concept = adir.geometry().info.concept
    if not concept:
        return None, []
    match = ConceptMatch.model_validate(concept)
    what = (match.noun or match.concept).replace("_", " ")
    if not match.by_analogy:
        return f"built: {match.concept.replace('_', ' ')} (named in the lexicon as '{what}')", []
    return f"built: {what}, by analogy ({match.fallback_level})", [match.analogy_line() or "", *match.analogy]
