"""A calibrated material the robot confirms becomes L3's result: `deformsmith calibrate` (flows.calibrate) runs its
checks in the staged working copy of the asset, and when the real robot (L3's trials in the MPM, not a stand-in)
picks and places the object with the fitted material under manipulation.json's plan, manipulation.json is rewritten
by L3's own writer (flows.l3_manipulation.write_l3_record) in that copy; a material the robot fails leaves the asset
as it was. The calibration tests' sphere (81 particles at 8 mm; L3 resamples it at a 5 mm trial lattice: 280
particles, ~7 s a trial on one core)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import zarr

from benchmarks.calibrate_roundtrip import write_sphere_asset
from contracts.errors import StageFailure
from contracts.manipulation import L2Check
from contracts.material import Material
from contracts.sim import SimConfig
from flows.l3_manipulation import L3Options, run_l3
from tasks.asset_dir import AssetDir
from tasks.manipulation.l3_record import PICK_AND_PLACE_RECORDING
from tasks.publish import staged_update
from tests.calibrate.test_calibrate_cli import digest

TRIAL_SPACING_M = 0.005
HELD_OUT = ((0.06, -0.08, 30.0),)


def _l2_passes(asset_dir: Path, material: Material, physical: object, sim: SimConfig | None = None,
               held_out: bool = False, **_: object) -> L2Check:
    """L2's revalidation (minutes of MPM probes, run for real by the command's tests): passes."""
    return L2Check(material=material, passed=True, gates={"finite": True}, bands={}, metrics={}, probe_keys=[],
                   held_out_gates={"finite": True}, held_out_probes=["compress"])


def _publish(asset: Path, material: Material) -> None:
    """What calibrate_asset does with the checks: run them in a staged copy with publish, raise on a failed gate."""
    import flows.calibrate as calibrate

    with staged_update(asset) as work:
        checks = calibrate.check_material(work, material, SimConfig(cpu_threads=1), True, lambda _: None,
                                          publish=True)
        if not checks.passed:
            raise StageFailure("calibrate", calibrate.failure_message(checks))


def test_the_robot_confirms_a_calibrated_material_into_manipulation_json(tmp_path: Path, prefect_api: str,
                                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    import flows.calibrate as calibrate

    asset = write_sphere_asset(tmp_path / "asset", 0.008)
    before, _ = run_l3(asset, L3Options(particle_spacing_m=TRIAL_SPACING_M, robustness=(), held_out=HELD_OUT,
                                        cpu_threads=1))
    assert before.passed and before.values is not None and before.trial is not None
    old_rows = before.attempts
    old_rrd = (asset / PICK_AND_PLACE_RECORDING).read_bytes()
    monkeypatch.setattr(calibrate, "revalidate_in_l2", _l2_passes)

    # a material the robot cannot carry (a 1 kPa ball of 33 g): the L3 gate fails, the asset is byte for byte as before
    soft = before.material.model_copy(update={"youngs_modulus_pa": 1e3})
    untouched = digest(asset)
    with pytest.raises(StageFailure, match="L3 robot confirmation"):
        _publish(asset, soft)
    assert digest(asset) == untouched

    fitted = before.material.model_copy(update={"youngs_modulus_pa": 2.5e5, "viscosity_pa_s": 30.0})
    _publish(asset, fitted)
    rec = AssetDir(asset).manipulation()
    rev = rec.material_revision
    assert rec.passed and rev is not None and rev.trigger == "calibration" and rev.accepted
    assert rev.from_ == before.material and rev.to == fitted and rev.plan_values == before.values
    assert rec.material == fitted and rec.material_source.startswith("calibrated from video")
    assert AssetDir(asset).adopted_material().material == fitted  # what exports, manifest and card carry
    # every trial L3 ran, then the confirmation (the reported trial) and the held-out condition with the fitted
    # material; numbered on, no interaction folder index reused
    n = len(old_rows)
    assert [a.model_dump(exclude={"recording", "kept_in", "recording_in_cache"}) for a in rec.attempts[:n]] == \
        [a.model_dump(exclude={"recording", "kept_in", "recording_in_cache"}) for a in old_rows]
    assert [a.role for a in rec.attempts[n:]] == ["confirmation", "held_out"]
    assert [a.trial for a in rec.attempts] == list(range(1, n + 3))
    stored = [a.attempt for a in rec.attempts if a.attempt is not None]
    assert len(stored) == len(set(stored)) == n + 2
    confirmation = rec.attempts[n]
    assert rec.trial == confirmation.trial and rec.attempt == confirmation.attempt
    assert rec.values == before.values and rec.labels == confirmation.labels == rev.confirmation
    assert rec.outcome["transported"] and rec.outcome["released_in_target"]
    assert rec.best_attempt is not None and rec.best_attempt.role == "confirmation"
    # the reported trial's data and recording are in the asset, simulated with the fitted material
    assert confirmation.kept_in == "asset" and confirmation.recording == PICK_AND_PLACE_RECORDING
    attrs = dict(zarr.open_group(str(asset / "interaction" / f"attempt_{rec.attempt:03d}"), mode="r").attrs)
    assert Material.model_validate(attrs["material"]) == fitted and attrs["role"] == "confirmation"
    assert (asset / PICK_AND_PLACE_RECORDING).read_bytes() != old_rrd
    # L3's earlier reported trial is an ordinary trial now: its data went to the cache, as any unreported trial's
    old = rec.attempts[before.trial - 1]
    assert old.kept_in == "cache" and old.recording is None and old.recording_in_cache
    assert not (asset / "interaction" / f"attempt_{old.attempt:03d}").exists()
    held = rec.held_out.conditions
    assert [(c.target_xy_m, c.initial_yaw_deg) for c in held] == [([0.06, -0.08], 30.0)]
    assert held[0].labels == rec.attempts[n + 1].labels
    assert json.loads((asset / "manipulation.json").read_text())["material_revision"]["trigger"] == "calibration"
