"""Layer by layer (`geometry TEXT`, then `physical DIR`, then `material DIR`) gives the material `generate` gives:
`geometry` stores the whole request in geometry.json, and L1 / L2 read it through one path
(tasks.agents.intent.asset_targets). Run layer by layer, a 'gel pack' used to become rubber (the catalogue entry's
name) and 'very stiff' rubber ordinary rubber."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import trimesh
from l1_assets import asset_of

from contracts.agents import TargetBehaviour
from contracts.concept import ConceptMatch
from contracts.request import AssetRequest
from tasks.physical.plan import l1_plan, l1_targets
from flows.l2_material import l2_targets
from tasks.agents.vocab import load_material_vocab
from tasks.geometry.outputs import L0Asset, load_l0
from tests.cli_in_process import cli_run


def generate_path(asset: L0Asset, request: AssetRequest) -> tuple[TargetBehaviour, str, TargetBehaviour]:
    """What `generate` computes: L1 from material_intent or text (flows/generate.py), L2 from the request."""
    t1, material, _ = l1_targets(asset, request.material_intent or request.text)
    return t1, material, l2_targets(asset, request)


def layer_path(asset: L0Asset) -> tuple[TargetBehaviour, str, TargetBehaviour]:
    """What `physical DIR` then `material DIR` compute: nothing given, the directory's stored request."""
    t1, material, _ = l1_targets(asset, None)
    return t1, material, l2_targets(asset, None)


def _bands(t: TargetBehaviour) -> dict[str, tuple[float, float]]:
    return {b.metric: (b.low, b.high) for b in t.bands}


CASES = [
    (AssetRequest(text="a soft foam ball 8 cm"), "pu_foam"),
    (AssetRequest(text="a gel pack 15 cm"), "gel"),
    (AssetRequest(text="a very stiff rubber ball"), "rubber"),
    (AssetRequest(text="a kitchen sponge 10 x 7 x 3 cm"), "sponge"),
    (AssetRequest(text="a plush turtle toy, about 25 cm long"), "plush"),
    (AssetRequest(text="a ball 7 cm", material_intent="firm silicone"), "silicone"),
    (AssetRequest(text="a gel pack 12 cm", target_overrides={"rebound_ratio": (0.2, 0.3)}), "gel"),
]


@pytest.mark.parametrize("request_, material", CASES, ids=[c[0].text for c in CASES])
def test_layer_by_layer_gives_the_material_generate_gives(request_: AssetRequest, material: str) -> None:
    asset = asset_of(request_)
    g1, g_material, g2 = generate_path(asset, request_)
    l1, l_material, l2 = layer_path(asset)
    assert g_material == l_material == material
    assert g1.priors == l1.priors and _bands(g1) == _bands(l1)  # density, friction, mass band
    assert g2.priors == l2.priors and _bands(g2) == _bands(l2)  # E prior, modulus / rebound / recovery bands
    assert g2.priors["youngs_modulus_pa"] == l2.priors["youngs_modulus_pa"]
    lo, hi = load_material_vocab().materials[material].bands["effective_modulus_pa"]
    e_lo, e_hi = _bands(l2)["effective_modulus_pa"]
    assert lo * (1 - 1e-9) <= e_lo < e_hi <= hi * (1 + 1e-9)  # the material's band, narrowed by modifiers only
    for metric, band in request_.target_overrides.items():
        assert _bands(l2)[metric] == band


def test_modifier_words_survive_layer_by_layer() -> None:
    """'very stiff' rubber keeps the stiff end of rubber's band (it got the whole band from the entry's name);
    'soft' foam the soft end."""
    stiff = layer_path(asset_of(AssetRequest(text="a very stiff rubber ball")))[2]
    plain = layer_path(asset_of(AssetRequest(text="a rubber ball")))[2]
    (s_lo, s_hi), (p_lo, p_hi) = _bands(stiff)["effective_modulus_pa"], _bands(plain)["effective_modulus_pa"]
    assert s_hi == pytest.approx(p_hi) and s_lo > p_lo * 1.5
    assert stiff.priors["youngs_modulus_pa"] > plain.priors["youngs_modulus_pa"]
    soft = layer_path(asset_of(AssetRequest(text="a soft foam ball 8 cm")))[2]
    assert _bands(soft)["effective_modulus_pa"][1] < 1e5 and "soft" in soft.matched_words


def test_the_concept_gives_the_material_when_the_words_name_none() -> None:
    """An object named by no material word gets the material of the concept L0 built, in both paths."""
    request = AssetRequest(text="a water bead cluster 6 cm")
    concept = ConceptMatch(concept="water_bead_cluster", noun="cluster", body_plan="ball", category="toy",
                           fallback_level="exact", default_material="gel")
    asset = asset_of(request, concept)
    (g1, g_material, g2), (l1, l_material, l2) = generate_path(asset, request), layer_path(asset)
    assert g_material == l_material == "gel" and _bands(g2) == _bands(l2) and g1.priors == l1.priors
    assert l2.band("effective_modulus_pa").source == "concept:water_bead_cluster(gel)"
    assert layer_path(asset_of(request, None))[1] == "pu_foam"  # no concept known: the default material


def test_an_asset_stored_without_its_request_falls_back_to_what_l0_built() -> None:
    """Directories written before the request was stored still work: the name and category L0 recorded."""
    asset = asset_of(AssetRequest(text="a kitchen sponge 10 x 7 x 3 cm"), stored=False)
    assert layer_path(asset)[1] == "sponge"


def test_geometry_command_stores_the_request_and_physical_reads_it(tmp_path: Path, prefect_api: str,
                                                                   monkeypatch: pytest.MonkeyPatch,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    """`deformsmith geometry TEXT --intent ...` keeps the whole request (material words never key L0's cache) and L1
    on the directory derives the material generate derives (a mesh input keeps the check fast). (The command in this
    process: tests/cli_in_process.py.)"""
    box = tmp_path / "box.obj"
    trimesh.creation.box(extents=(0.12, 0.08, 0.03)).export(box)
    out = tmp_path / "asset"
    code, _, err = cli_run("geometry", "a gel pack", "--mesh", str(box), "--size-m", "0.12", "--intent",
                           "very soft gel", "--out", str(out), "--no-cache", api=prefect_api, monkeypatch=monkeypatch,
                           capsys=capsys)
    assert code == 0, err
    stored = json.loads((out / "geometry.json").read_text(encoding="utf-8"))["request"]
    assert stored["text"] == "a gel pack" and stored["material_intent"] == "very soft gel"
    assert stored["size_hint_m"] == 0.12 and Path(stored["mesh_path"]) == box
    asset = load_l0(out)
    request = AssetRequest.model_validate(stored)
    plan = l1_plan(asset, None)
    assert plan.material == "gel" and plan.targets.intent == "very soft gel"
    assert _bands(l2_targets(asset, None)) == _bands(l2_targets(asset, request))
    assert _bands(l2_targets(asset, None))["effective_modulus_pa"][1] < 2.8e5  # 'very soft' narrowed gel's band


def test_material_words_never_key_the_geometry() -> None:
    """The stored request carries the material words; L0's cache key (geometry_request) does not."""
    from flows.l0_geometry import geometry_request

    plain = AssetRequest(text="a gel pack 15 cm", seed=3)
    worded = plain.model_copy(update={"material_intent": "very stiff rubber",
                                      "target_overrides": {"rebound_ratio": (0.2, 0.3)}})
    assert geometry_request(worded) == geometry_request(plain)
    assert geometry_request(plain.model_copy(update={"seed": 4})) != geometry_request(plain)
