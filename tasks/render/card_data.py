"""What an asset card shows, gathered from the typed asset directory (tasks.asset_dir.AssetDir) and the attempt
records (evidence/attempts.jsonl, tasks.record.tally): every number with the probe and the cache key / record it
came from. Pure data (no drawing): card_png and card_html draw it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from pydantic import BaseModel, ConfigDict

from contracts.concept import ConceptMatch
from contracts.agents import TargetBehaviour
from contracts.asset_dir import MANIPULATION_JSON, MATERIAL_JSON, PHYSICAL_JSON, attempt_path
from contracts.evidence import Attempt
from contracts.manifest import AssetManifest
from tasks.asset_dir import AssetDir
from tasks.render.protocol_video import CARD_TIMES_S, VIEW_NAMES, card_still_name

STILL_VIEWS = ("front", "side", "top")  # renders/<view>.png (L0)
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
    passed: bool | None = None
    status: str | None = None
    outcome: dict[str, bool] = {}
    figures: list[Figure] = []
    force_budget_n: float | None = None
    attempt: int | None = None
    key: str | None = None
    force_t_s: list[float] = []
    finger_force_n: list[tuple[float, float]] = []  # |force| on each finger per control step


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
                  record: str) -> list[Figure]:
    """A figure per target band: the measured value, the band, whether it holds, the probe and its cache key."""
    out = []
    for b in targets.bands:
        value = metrics.get(b.metric)
        probe = L2_BAND_PROBE.get(b.metric, "probe")
        label = b.metric.removesuffix(f"_{b.unit.lower()}").replace("_", " ")  # effective_modulus_pa: effective modulus
        out.append(Figure(label=label, metric=b.metric, value=value, unit=b.unit, band=(b.low, b.high),
                          met=b.contains(value),
                          source=f"{record}: {probe} ({b.source})", key=keys.get(probe)))
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
    best = rec.best_attempt or {}
    attempt = rec.attempt if rec.attempt is not None else best.get("attempt")
    labels = rec.labels or best.get("labels") or {}
    key = manifest.provenance.cache_keys.get("l3.trial") or best.get("cache_key")
    figures = [Figure(label=label, metric=m, value=float(labels[m]), unit=unit,
                      source=f"{MANIPULATION_JSON}: trial {attempt}", key=key)
               for m, (label, unit) in L3_FIGURES.items() if m in labels]
    gripper = rec.plan.gripper if rec.plan else rec.gripper.get("name")
    card = L3Card(ran=True, note=rec.message or rec.reason, gripper=gripper,
                  gripper_reason=rec.plan.gripper_reason if rec.plan else None, passed=rec.passed, status=rec.status,
                  outcome=dict(rec.outcome), figures=figures, force_budget_n=rec.force_budget_n, attempt=attempt,
                  key=key)
    folder = adir.path / attempt_path(attempt) if attempt is not None else None
    if folder is not None and folder.is_dir():
        curve = _force_curve(folder)
        if curve is not None:
            card = card.model_copy(update={"force_t_s": curve[0].tolist(),
                                           "finger_force_n": [(float(a), float(b)) for a, b in curve[1]]})
    return card


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


def card_data(asset_dir: Path | str, manifest: AssetManifest | None = None) -> CardData:
    """The card's content for an asset directory (InputError naming the file when a document is missing or invalid).

    manifest: the manifest about to be written (generate builds the card before asset.json is published)."""
    from tasks.agents.records import ATTEMPTS_FILE, read_attempts
    from tasks.record.tally import stage_tallies

    adir = AssetDir(asset_dir)
    manifest = manifest or adir.manifest()
    physical, material = adir.physical(), adir.material()
    path = adir.path / ATTEMPTS_FILE
    attempts = read_attempts(path) if path.is_file() else []
    l1_keys = _probe_keys(attempts, "L1", None)
    l2_keys = _probe_keys(attempts, "L2", material.selection.best_iteration)
    mat = material.material
    chosen = f"{MATERIAL_JSON} ({material.status}; evidence/attempts.jsonl L2 #{material.selection.best_iteration})"
    material_rows = [] if mat is None else [
        Figure(label="Young's modulus E", metric="youngs_modulus_pa", value=mat.youngs_modulus_pa, unit="Pa",
               source=chosen),
        Figure(label="Poisson ratio nu", metric="poisson_ratio", value=mat.poisson_ratio, unit="-",
               source=chosen),
        Figure(label="damping rate", metric="damping_rate_per_s", value=mat.damping_rate_per_s, unit="1/s",
               source=chosen)]
    bands = _band_figures(material.targets, material.metrics, l2_keys, f"{MATERIAL_JSON} metrics")
    mass_band = {b.metric: b for b in physical.targets.bands}
    l1_rows = []
    for m, (label, unit) in L1_FIGURES.items():
        if m not in physical.metrics:
            continue
        probe = m.split("_")[0] if m.split("_")[0] in l1_keys else "mass check"
        band = mass_band.get(m)
        value = float(physical.metrics[m])
        l1_rows.append(Figure(label=label, metric=m, value=value, unit=unit,
                              band=(band.low, band.high) if band else None,
                              met=band.contains(value) if band else None,
                              source=f"{PHYSICAL_JSON}: {probe}", key=l1_keys.get(probe)))
    pm = physical.physical_model
    if pm is not None:
        l1_rows += [Figure(label="density", metric="density_kg_per_m3", value=pm.density_kg_per_m3, unit="kg/m^3",
                           source=f"{PHYSICAL_JSON}: mass check ({physical.mass_check.get('source', '-')})"),
                    Figure(label="ground friction", metric="ground_friction", value=pm.ground_friction, unit="-",
                           source=f"{PHYSICAL_JSON}: slide", key=l1_keys.get("slide"))]
    drop = (manifest.extra or {}).get("drop_protocol") or {}
    protocol = [Figure(label=label, metric=m, value=float(drop[m]), unit=unit,
                       source="asset.json extra.drop_protocol: task renders.drop_protocol")
                for m, (label, unit) in PROTOCOL_FIGURES.items() if m in drop]
    stages = [f"{t.stage}: {t.status}, {t.attempts} attempt(s), {t.sim_calls} simulation(s)"
              + (f", unmet: {', '.join(t.unmet_targets)}" if t.unmet_targets else "")
              for t in stage_tallies(adir.path, attempts)]
    sources = [f"{name}: {_short(key)}" for name, key in sorted(manifest.provenance.cache_keys.items())]
    sources += [f"L1.{kind}: {_short(key)}" for kind, key in sorted(l1_keys.items())]
    videos = {label: rel for label, rel in (("drop, front", "renders/drop_front.mp4"),
                                            ("drop, side", "renders/drop_side.mp4"),
                                            ("pick and place", "renders/pick_and_place.mp4"))
              if (adir.path / rel).is_file()}
    views = {v: f"renders/{v}.png" for v in STILL_VIEWS if (adir.path / "renders" / f"{v}.png").is_file()}
    built, analogy = _built(adir)
    return CardData(name=request_title(manifest.request.model_dump(mode="json")), request=manifest.request.model_dump(mode="json"), views=views,
                    drop_frames=_drop_frames(adir), videos=videos, material=material_rows, bands=bands, l1=l1_rows,
                    protocol=protocol, l3=_l3(adir, manifest), stages=stages, sources=sources, built=built,
                    analogy=analogy)


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
