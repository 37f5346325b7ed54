"""Adding a deformable probe is one module plus its contract entry (#37): a toy probe module dropped into the probe
package is found by the registry, run by L2's flow as a cached task, gated by the harness and routed by its own
route defaults; nothing else is edited."""

from __future__ import annotations

import json
import textwrap
from pathlib import Path
from typing import Any

import pytest

import flows.l2_material as l2
import tasks.probes.deformable_probes as package
from cache import CacheStore, cache_resolve, cache_root
from contracts.stage import HardGate, load_contract
from tasks.probes.registry import with_probe_routes
from tasks.agents.vocab import stage_routes
from tasks.probes import registry
from tests.l2.helpers import box_asset

TOY = textwrap.dedent('''
    """A toy L2 probe: the material's bar wave speed sqrt(E / rho), and a recording of it."""

    from __future__ import annotations

    import math
    from typing import Any

    import numpy as np

    from cache import cache_relative, content_key
    from contracts.material import Material
    from contracts.physical import PhysicalModel
    from contracts.probes import ProbeMetrics, ProbeResult, ProbeSpec
    from contracts.sim import SimConfig
    from tasks.probes.mpm_probe import body_inputs
    from tasks.probes.probe import ProbeContext, ProbeModule, cache_recording_path
    from tasks.record import ProbeRecording


    class WaveSpeedMetrics(ProbeMetrics):
        wave_speed_m_per_s: float | None = None


    def run(positions_m: np.ndarray, volumes_m3: np.ndarray, physical: PhysicalModel, material: Material,
            sim: SimConfig) -> ProbeResult:
        c = math.sqrt(material.youngs_modulus_pa / physical.density_kg_per_m3)
        path = cache_recording_path("L2", "wave_speed", content_key("toy", physical, material))
        with ProbeRecording(path, recording_id="toy") as rec:
            rec.set_time(0, 0.0)
            rec.particles(positions_m.astype(np.float32))
            rec.scalar("wave_speed_m_per_s", c)
        return ProbeResult(spec=ProbeSpec(kind="wave_speed"), metrics={"wave_speed_m_per_s": c}, sim_calls=0,
                           recording=cache_relative(path))


    def inputs(ctx: ProbeContext) -> dict[str, Any]:
        return body_inputs(ctx)


    PROBE = ProbeModule(stage="L2", name="wave_speed", version="1", metrics=WaveSpeedMetrics, run=run, inputs=inputs,
                        gates={"wave_speed_m_per_s": {"diagnosis": "material",
                                                      "directions": {"youngs_modulus_pa": "increase"}}})
''')


@pytest.fixture
def toy_probe(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Any:
    """The toy module in a folder the deformable probe package also searches (as if dropped into it)."""
    folder = tmp_path / "probe_modules"
    folder.mkdir()
    (folder / "wave_speed.py").write_text(TOY)
    monkeypatch.setattr(package, "__path__", [*package.__path__, str(folder)])
    registry.reset()
    yield registry.probe("L2", "wave_speed")
    registry.reset()


def _contract(entry_only: bool) -> Any:
    """The L2 contract with the toy's entry: the probe listed, its metric observed and gated (entry_only: the
    toy is the only probe, so no MPM runs in the test)."""
    c = load_contract("L2")
    probes = [{"name": "wave_speed"}] if entry_only else [*c.parameters["probes"], {"name": "wave_speed"}]
    gate = HardGate(name="sound travels", metric="wave_speed_m_per_s", op=">=", threshold=1.0)
    return c.model_copy(update={
        "parameters": {**c.parameters, "probes": probes},
        "required_observations": ["wave_speed_m_per_s"] if entry_only else [*c.required_observations,
                                                                             "wave_speed_m_per_s"],
        "hard_gates": [gate] if entry_only else [*c.hard_gates, gate]})


def test_the_registry_and_the_routes_find_the_toy_probe(toy_probe: Any) -> None:
    """The registry lists it after the packaged probes; the harness's route table gets its gate route."""
    c = _contract(entry_only=False)
    assert [p.name for p in registry.stage_probes(c)][-1] == "wave_speed"
    routes = with_probe_routes(stage_routes("L2", c.parameters), c)
    assert routes.gates["wave_speed_m_per_s"].directions == {"youngs_modulus_pa": "increase"}
    assert "wave_speed_m_per_s" not in stage_routes("L2", c.parameters).gates


def test_l2_runs_the_toy_probe_as_a_cached_task(toy_probe: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                               prefect_api: str) -> None:
    """L2's flow runs it, gates and records it, copies its recording into the asset; a rerun executes nothing."""
    asset, phys = box_asset((0.1, 0.08, 0.06), 6)
    monkeypatch.setattr(l2, "load_l0", lambda d: asset)
    d = tmp_path / "asset"
    d.mkdir()
    store = CacheStore(cache_root())
    material, outcome = l2.run_l2(d, "a rubber ball", contract=_contract(entry_only=True), physical=phys,
                                  screen_first=False)
    assert outcome.passed and material is not None
    assert outcome.metrics["wave_speed_m_per_s"] > 1.0
    # (a rubber ball's material loss is calibrated first on its own impact: a cached task of its own, #39)
    assert [e["task"] for e in store.events() if e["outcome"] == "miss"] == ["l2.restitution_loss", "l2.wave_speed"]
    cached = json.loads((d / "material.json").read_text())["cached_recordings"]  # left in the cache by default (#38)
    assert cache_resolve(cached["recordings/L2_wave_speed.rrd"]).is_file()
    assert not (d / "recordings" / "L2_wave_speed.rrd").exists()
    n = len(store.events())
    l2.run_l2(d, "a rubber ball", contract=_contract(entry_only=True), physical=phys, screen_first=False)
    assert [e for e in store.events()[n:] if e["outcome"] == "miss"] == []
