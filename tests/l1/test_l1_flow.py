"""L1 on a real L0 asset: priors -> mass model -> rigid probes -> gates; revision of an implausible density; cache."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from l1_assets import write_l0_dir

from cache import CacheStore, cache_resolve
from contracts.errors import InputError
from contracts.request import AssetRequest
from flows.l1_physical import load_physical, run_l1, run_rigid_probe
from tasks.record import read_recording

@pytest.fixture(scope="module")
def sponge_template(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """An L0 directory of a 10 x 7 x 3 cm kitchen sponge (built once per module)."""
    return write_l0_dir(AssetRequest(text="a kitchen sponge 10 x 7 x 3 cm"), tmp_path_factory.mktemp("l0") / "sponge",
                        stored=False)


@pytest.fixture
def sponge(sponge_template: Path, tmp_path: Path) -> Path:
    """A private copy of the sponge asset for one test."""
    import shutil

    dest = tmp_path / "sponge"
    shutil.copytree(sponge_template, dest)
    return dest


def test_l1_accepts_a_sponge_and_freezes_its_physical_model(sponge: Path, prefect_api: str) -> None:
    phys, outcome = run_l1(sponge)
    assert outcome.passed and phys is not None
    check = json.loads((sponge / "physical.json").read_text())["mass_check"]
    lo, hi = check["density_range_kg_per_m3"]  # the sponge prior range, or the named object's typical mass / volume
    assert lo / 1.5 <= phys.density_kg_per_m3 <= hi * 1.5
    if any(c.startswith("typical mass of kitchen_sponge") for c in check["checks"]):
        assert 0.009 <= phys.mass_kg <= 0.036  # a real kitchen sponge, dry: 12-25 g (it was ~70 g of sponge rubber)
    else:
        assert 260 / 1.5 <= phys.density_kg_per_m3 <= 400 * 1.5
    assert phys.mass_kg == pytest.approx(phys.density_kg_per_m3 * phys.volume_m3, rel=1e-6)
    assert phys.volume_m3 == pytest.approx(0.10 * 0.07 * 0.03, rel=0.15)  # a rounded block of the stated size
    assert outcome.metrics["place_penetration_m"] <= 1e-3 and outcome.metrics["place_tilt_deg"] < 5
    assert outcome.metrics["slide_below_sticks"] == 1 and outcome.metrics["slide_above_slides"] == 1
    assert load_physical(sponge) == phys
    # the probes' recordings stay in the cache by default (#38 item 5), physical.json naming each by its cache path
    assert not list((sponge / "recordings").glob("L1_place*.rrd"))
    cached = json.loads((sponge / "physical.json").read_text())["cached_recordings"]
    assert "-" in Path(cached["recordings/L1_place.rrd"]).stem  # L1_place-<the probe's cache key>.rrd
    rec = read_recording(cache_resolve(cached["recordings/L1_place.rrd"]))
    assert "world/object/particles" in rec.entity_paths and "sim_time" in rec.timelines


def test_implausible_density_is_revised_into_the_plausible_band(sponge: Path, prefect_api: str) -> None:
    phys, outcome = run_l1(sponge, intent="a kitchen sponge, density 1800 kg/m3")
    first = outcome.attempts[0]
    assert first.proposal["density_kg_per_m3"] == pytest.approx(1800)
    assert first.verdict != "accepted"
    assert outcome.passed and phys is not None and outcome.attempts_used >= 2
    assert phys.density_kg_per_m3 <= 400 * 1.5


def test_rerunning_l1_executes_no_probe(sponge: Path, prefect_api: str, cache_dir: Path) -> None:
    run_l1(sponge)
    store = CacheStore(cache_dir)
    before = [e for e in store.events() if e["outcome"] == "miss"]
    assert {e["task"] for e in before} == {"l1.place", "l1.drop", "l1.slide"}
    run_l1(sponge)
    after = [e for e in store.events() if e["outcome"] == "miss"]
    assert len(after) == len(before)


def test_rigid_probe_rejects_density_outside_the_contract(sponge: Path) -> None:
    with pytest.raises(InputError, match="density_kg_per_m3"):
        run_rigid_probe("drop", sponge, rho=1e6)
    with pytest.raises(InputError, match="unknown rigid probe"):
        run_rigid_probe("bounce", sponge)


def test_physical_command_on_a_non_asset_is_one_clear_error(tmp_path: Path, cli_env: dict[str, str]) -> None:
    out = subprocess.run([sys.executable, "-m", "flows.cli.main", "physical", "--asset", str(tmp_path)],
                         capture_output=True, text=True, timeout=120, env=cli_env)  # the session's Prefect server
    assert out.returncode != 0
    assert out.stderr.startswith("error:") and "geometry.json" in out.stderr and out.stderr.count("\n") == 1


def test_load_physical_without_l1_is_a_clear_error(sponge: Path) -> None:
    with pytest.raises(InputError, match="physical.json"):
        load_physical(sponge)
    (sponge / "physical.json").write_text(json.dumps({"physical_model": None, "message": "mass implausible"}))
    with pytest.raises(InputError, match=r"physical\.json: not a valid physical document: passed"):
        load_physical(sponge)  # a partial record names the file and what is missing
    from tasks.asset_dir import AssetDir
    from tests.asset_records import physical_record

    AssetDir(sponge).write_physical(physical_record(None, "mass implausible"))
    with pytest.raises(InputError, match="mass implausible"):
        load_physical(sponge)
