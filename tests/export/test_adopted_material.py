"""One final material (#37): an L3 material revision that L3 passed with is the asset's material in the manifest, the
exports, the PhysGaussian config and the card, all read from AssetDir.adopted_material; material.json stays L2's."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest

from contracts.material import Material
from tasks.asset_dir import AssetDir
from tasks.export import inputs as export_inputs
from tasks.export import registry
from tests.export.assets import copy_sponge
from tests.export.test_export_cmd import grid_tets

MANIPULATION = Path(__file__).parents[1] / "test_contracts" / "asset_fixture" / "manipulation.json"  # a passed L3


def _adopt_revision(adir: AssetDir, passed: bool = True) -> Material:
    """Write manipulation.json as an L3 that revised the L2 material (E x 2.5, more damping), had it revalidated by L2,
    confirmed it with the robot and (passed) adopted it; the revised material."""
    l2 = adir.material_model()
    revised = l2.model_copy(update={"youngs_modulus_pa": 2.5 * l2.youngs_modulus_pa,
                                    "damping_rate_per_s": l2.damping_rate_per_s + 4.0})
    raw: dict[str, Any] = json.loads(MANIPULATION.read_text(encoding="utf-8"))
    measured = adir.material().metrics
    metrics = {**measured, **{k: 2.4 * measured[k] for k in ("effective_modulus_pa", "object_effective_modulus_pa")}}
    raw.update(passed=passed, material=revised.model_dump(mode="json"),
               material_source="L3 material revision (L2 revalidated)" if passed else "L2",
               physical_model=adir.physical_model().model_dump(mode="json"),
               material_revision={"trigger": "robustness", "from": l2.model_dump(mode="json"),
                                  "to": revised.model_dump(mode="json"), "reason": "slip at the squeeze limit",
                                  "failed_gates": ["lifted"], "plan_values": raw["values"], "accepted": passed,
                                  "l2_revalidation": {"passed": True, "gates": {}, "bands": {}, "metrics": metrics,
                                                      "probe_keys": []}})
    if not passed:
        raw["material"] = l2.model_dump(mode="json")
    adir.file("manipulation").write_text(json.dumps(raw), encoding="utf-8")
    return revised


@pytest.fixture
def asset(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> AssetDir:
    """A copy of the committed sponge (L0-L2, asset.json), meshed for export by the stand-in."""
    monkeypatch.setattr(export_inputs, "tetrahedralize", grid_tets)
    monkeypatch.setattr(registry, "MESHER", None)
    return AssetDir(copy_sponge(tmp_path / "sponge"))


def _usd_material(path: Path) -> tuple[float, float, float]:
    """(E, nu, density) of the exported USD stage's physics material."""
    from pxr import Usd

    stage = Usd.Stage.Open(str(path))
    for prim in stage.Traverse():
        e = prim.GetAttribute("omniphysics:youngsModulus")
        if e and e.HasValue():
            return (float(e.Get()), float(prim.GetAttribute("omniphysics:poissonsRatio").Get()),
                    float(prim.GetAttribute("omniphysics:density").Get()))
    raise AssertionError(f"{path}: no physics material")


def _exported(root: Path, slug: str) -> dict[str, tuple[float, float, float]]:
    """Target -> (E, nu, density) as written in its own files (MuJoCo: E and nu; its density is the flex's mass)."""
    def number(text: str, pattern: str) -> float:
        found = re.search(pattern, text)
        assert found, pattern
        return float(found.group(1))

    drake = (root / "drake" / f"{slug}.sdf").read_text(encoding="utf-8")
    sofa = (root / "sofa" / "scene.py").read_text(encoding="utf-8")
    genesis = json.loads((root / "genesis" / "params.json").read_text(encoding="utf-8"))
    mujoco = json.loads((root / "mujoco" / "parameters.json").read_text(encoding="utf-8"))
    out = {
        "drake": (number(drake, r"<drake:youngs_modulus>([^<]+)<"), number(drake, r"<drake:poissons_ratio>([^<]+)<"),
                  number(drake, r"<drake:mass_density>([^<]+)<")),
        "sofa": (number(sofa, r"YOUNGS_MODULUS_PA = (\S+)"), number(sofa, r"POISSON_RATIO = (\S+)"),
                 number(sofa, r"DENSITY_KG_PER_M3 = (\S+)")),
        "genesis": (genesis["youngs_modulus_pa"], genesis["poisson_ratio"], genesis["density_kg_per_m3"]),
        "mujoco": (mujoco["young_pa"], mujoco["poisson"], float("nan")),
    }
    usd = root / "usd" / f"{slug}.usda"
    if usd.is_file():
        out["usd"] = _usd_material(usd)
    return out


def test_an_adopted_l3_revision_is_the_material_everywhere(asset: AssetDir) -> None:
    from flows.export import export_asset
    from flows.generate import write_asset_records
    from tasks.render.card_data import card_data
    from tasks.render.card_text import si

    l2 = asset.material_model()
    revised = _adopt_revision(asset)
    density = asset.physical_model().density_kg_per_m3
    adopted = asset.adopted_material()
    assert adopted.material == revised and adopted.source == "L3 revision" and adopted.document == "manipulation.json"
    assert asset.material().material == l2  # material.json stays L2's record

    stale = asset.manifest()
    assert stale.material == l2  # the sponge's asset.json as L2 left it
    written = write_asset_records(asset, stale)  # asset.json, the PhysGaussian config and the card, as generate does
    manifest = asset.manifest()
    assert written == manifest and manifest.material == revised
    assert manifest.physical_model is not None and manifest.physical_model.density_kg_per_m3 == density

    config = json.loads((asset.path / "export" / "physgaussian_config.json").read_text(encoding="utf-8"))
    assert (config["E"], config["nu"], config["density"]) == (revised.youngs_modulus_pa, revised.poisson_ratio, density)
    assert config["damping_rate_per_s"] == revised.damping_rate_per_s

    card = card_data(asset.path)
    rows = {f.metric: f for f in card.material}
    assert rows["youngs_modulus_pa"].value == revised.youngs_modulus_pa
    assert rows["poisson_ratio"].value == revised.poisson_ratio
    assert rows["damping_rate_per_s"].value == revised.damping_rate_per_s
    assert "manipulation.json" in rows["youngs_modulus_pa"].source
    assert next(f.value for f in card.l1 if f.metric == "density_kg_per_m3") == density
    band = next(f for f in card.bands if f.metric == "effective_modulus_pa")
    assert band.value == adopted.metrics["effective_modulus_pa"]  # the bands as L2 revalidated the revision
    html = (asset.path / "renders" / "card.html").read_text(encoding="utf-8")
    assert si(revised.youngs_modulus_pa, "Pa") in html and si(l2.youngs_modulus_pa, "Pa") not in html

    from tasks.export.crosscheck import probe_targets

    assert probe_targets(asset.path).ours["effective_modulus_pa"] == adopted.metrics["object_effective_modulus_pa"]
    export = export_asset(asset.path, "all" if _usd() else "mujoco,genesis,drake,sofa")
    want = (revised.youngs_modulus_pa, revised.poisson_ratio, density)
    for name, target in export.targets.items():
        m = target.material
        assert (m.youngs_modulus_pa, m.poisson_ratio, m.density_kg_per_m3) == want, name
        assert m.damping_rate_per_s == revised.damping_rate_per_s, name
    slug = export_inputs.load_export_inputs(asset.path).slug
    for name, (e, nu, rho) in _exported(asset.path / "export", slug).items():
        assert e == pytest.approx(want[0], rel=1e-6) and nu == pytest.approx(want[1], rel=1e-6), name
        assert name == "mujoco" or rho == pytest.approx(density, rel=1e-6), name


def _usd() -> bool:
    """usd-core is installed (the usd target needs it)."""
    import importlib.util

    return importlib.util.find_spec("pxr") is not None


def test_without_an_adopted_revision_the_material_is_l2s(asset: AssetDir) -> None:
    l2 = asset.material_model()
    adopted = asset.adopted_material()  # no L3 (the sponge ran --no-l3)
    assert (adopted.material, adopted.source, adopted.document) == (l2, "L2", "material.json")
    assert adopted.metrics == asset.material().metrics
    _adopt_revision(asset, passed=False)  # L3 revised, the robot did not pass with it: the asset keeps L2's
    assert asset.adopted_material().material == l2 and asset.adopted_material().source == "L2"
    assert export_inputs.export_material(asset).youngs_modulus_pa == l2.youngs_modulus_pa


def test_a_manipulate_rerun_that_adopts_a_revision_refreshes_the_asset(asset: AssetDir, tmp_path: Path,
                                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    """`deformsmith manipulate DIR` re-run on a published asset (L3 itself stood in for: it writes manipulation.json
    as an L3 that adopted a revision, then as one that did not pass): asset.json (material, L3's line, plan, outcome),
    the PhysGaussian config and the card follow manipulation.json each time, swapped in with it."""
    from typer.testing import CliRunner

    import flows.l3_manipulation as l3
    from contracts.agents import StageOutcome
    from flows.cli.main import app
    from tasks.render.card_text import si

    l2 = asset.material_model()
    passed = {"now": True}
    revised: dict[str, Material] = {}

    def fake_l3(work: Path, *args: object, **kwargs: object) -> tuple[Any, StageOutcome]:
        revised["material"] = _adopt_revision(AssetDir(work), passed=passed["now"])
        return AssetDir(work).manipulation(), StageOutcome(stage="L3", status="accepted" if passed["now"] else
                                                           "no_valid_candidate")

    monkeypatch.setattr(l3, "run_l3", fake_l3)
    assert asset.manifest().material == l2 and all(s.stage != "L3" for s in asset.manifest().validation)

    def rerun() -> None:
        result = CliRunner().invoke(app, ["manipulate", str(asset.path), "--cache", str(tmp_path / "cache")])
        assert result.exit_code == 0, result.output

    def e_of_config() -> float:
        return json.loads((asset.path / "export" / "physgaussian_config.json").read_text(encoding="utf-8"))["E"]

    rerun()  # L3 adopts the revision
    manifest, record = asset.manifest(), asset.manipulation()
    assert manifest.material == revised["material"] == asset.adopted_material().material != l2
    line = manifest.validation[-1]
    assert [s.stage for s in manifest.validation] == ["L0", "L1", "L2", "L3"] and line.passed
    assert manifest.action_plan == record.plan and manifest.manipulation is not None
    assert e_of_config() == revised["material"].youngs_modulus_pa
    html = (asset.path / "renders" / "card.html").read_text(encoding="utf-8")
    assert si(revised["material"].youngs_modulus_pa, "Pa") in html and si(l2.youngs_modulus_pa, "Pa") not in html
    assert {"card_png", "card_html", "manipulation_record"} <= set(manifest.files)
    assert (asset.path / manifest.files["card_png"]).is_file()

    passed["now"] = False
    rerun()  # L3 re-run, did not pass with its revision: the asset's material is L2's again
    manifest = asset.manifest()
    assert manifest.material == l2 and e_of_config() == l2.youngs_modulus_pa
    assert [s.stage for s in manifest.validation] == ["L0", "L1", "L2", "L3"] and not manifest.validation[-1].passed
    html = (asset.path / "renders" / "card.html").read_text(encoding="utf-8")
    assert si(l2.youngs_modulus_pa, "Pa") in html
