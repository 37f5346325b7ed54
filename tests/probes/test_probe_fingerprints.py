"""Cache fingerprints of the L1 and L2 probe tasks: the content keys (and recording names) a fixed small input gets.

The values were recorded before the probes moved behind one Probe protocol (#37); a change of a task's name,
version, input names or input values would change them, and with them every cached result and recording name of
the default asset. The measurements are replaced by stand-ins (the keys do not depend on them), the cached tasks and
the flows' input building run as they are.
"""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace
from typing import Any, cast

import numpy as np
import pytest

import flows.l1_physical as l1
import flows.l2_material as l2
from cache import CacheStore, cache_root
from contracts.material import Material
from contracts.probes import HealthStatus, ProbeResult
from contracts.stage import load_contract
from tasks.probes import deformable, rigid
from tasks.probes.rollout import make_result
from tests.l2.helpers import box_asset

FIXTURE = Path(__file__).parents[1] / "record" / "fixtures" / "plush_turtle"

L1_EXECUTED = [  # (the rigid probes' VERSION 3, slide 4, session 40: at rest by the pose's net change)
    ("l1.drop", "62301b4e9e2476cbaf3181865f07b69f44e6254fccc536ccb2d2e677eff66d68"),
    ("l1.place", "c2704b521f2e18d389fbc9cfba1cc26b89dc42d7808b7160000cef257b54b1a1"),
    ("l1.slide", "3596ec2be36cbfbf962e483612ddcecbbb5218405d3bfebe22162bf2145ea83c"),
]
L1_RECORDINGS = {"place": "L1_place-d826a6cb4b5d7663.rrd", "rigid_drop": "L1_drop-00be9819d51df611.rrd",
                 "slide": "L1_slide-dc6cb286d9c79e6d.rrd"}
L2_EXECUTED = [  # (compress, specimen_compress and stability at VERSION 3, session 55: a stiff body mass-scaled)
    ("l2.compress", "2920bcb9ab1dc348f8735563bd5b041b24620b50755d571363b23c7e3d0d95a8"),
    ("l2.compress", "867c7276979846daad8bf2ef0b8bf500627f0d7da8a68881bb09be78ad6e4f55"),
    ("l2.drop", "86d762f77a2d102db07b0cb3eddf6a8f62b35c7e049bc637d77d74a16976c477"),
    ("l2.drop", "b792fda9ebebabf244b66c585c97046a7c7b455ca02b726c71c76d02df0014c5"),
    ("l2.lift", "a059916499bcfdece2d45dce8c8567efb9c555cb26da2304761106740e3a3ef7"),
    ("l2.specimen_compress", "6da64c09ec1deae8b28e8934a2a2b79a265777bba1b429000a95f4ab41fc8cc9"),
    ("l2.specimen_compress", "fef59572a5797eedff0744abcb43f3dd530c5a826ae6b06062abfe5234cf5f1d"),
    ("l2.specimen_drop", "21850ecd48a22a4bf201efe0d4a5d923fba23bcbad6da509923c24dde8cd3660"),
    ("l2.specimen_drop", "9beded2da274bb0a2dc9256902fa8e98350897095feeb9bd8ef54f2c9db68d7e"),
    ("l2.stability", "285bf09a89f33a98828c3b9066b08e871b425735626d83e0d19a088c4eb0da61"),
]
L2_RECORDINGS = {
    "compress": "L2_compress-87e4a452a522f455.rrd", "drop": "L2_drop-9e5982be63dad9e9.rrd",
    "lift": "L2_lift-f113f55d10e3e3c2.rrd", "stability": "L2_stability-8b1e4085fc468160.rrd",
    "specimen_compress": "L2_specimen_compress-61c5729ac79fbf64.rrd",
    "specimen_drop": "L2_specimen_drop-ed9127b243bf4d70.rrd",
    "compress_held_out": "L2_compress-1675614ed2275e0b.rrd", "drop_held_out": "L2_drop-88864fb5285454af.rrd",
    "specimen_compress_held_out": "L2_specimen_compress-f900c762779cbf82.rrd",
    "specimen_drop_held_out": "L2_specimen_drop-dc0ad39cc821ea3b.rrd",
}


def _material() -> Material:
    """The default asset's L2 material (the recorded plush turtle)."""
    return Material(**json.loads((FIXTURE / "material.json").read_text())["material"])


def _fake_deformable(kind: str) -> Any:
    """A stand-in deformable probe: one result per material, an empty recording at each path."""

    def run(body: Any, materials: list[Material], *, record_paths: list[Path | None] | None = None,
            held_out: bool = False, **params: Any) -> list[ProbeResult]:
        for p in record_paths or []:
            if p is not None:
                p.parent.mkdir(parents=True, exist_ok=True)
                p.write_bytes(b"")
        keep = {k: float(v) for k, v in params.items() if isinstance(v, float)}
        return [make_result(kind, keep, {"finite": 1.0}, HealthStatus(), 0.0, held_out) for _ in materials]

    return run


def _stub_measurements(monkeypatch: pytest.MonkeyPatch) -> None:
    """Stand-ins for the MPM and pybullet measurements; probes one at a time."""
    for kind in ("compress", "drop", "lift", "stability"):
        fake = _fake_deformable(kind)
        if hasattr(deformable, "PROBES"):
            monkeypatch.setitem(deformable.PROBES, kind, fake)
        monkeypatch.setattr(deformable, kind, fake)
    monkeypatch.setattr(rigid, "placement_probe", lambda body, duration_s, trace: {"place_tilt_deg": 0.0})
    monkeypatch.setattr(rigid, "drop_probe", lambda body, c, d, trace: {"drop_penetration_m": 0.0})
    monkeypatch.setattr(rigid, "slide_probe", lambda body, m, s, trace: {"slide_below_sticks": 1.0})
    monkeypatch.setenv("DEFORMSMITH_PROBE_WORKERS", "1")


def _executed() -> list[tuple[str, str]]:
    """(task name, cache key) of every cached task that executed (the store's event log)."""
    return sorted((e["task"], e["key"]) for e in CacheStore(cache_root()).events() if e["outcome"] == "miss")


def _recordings(results: list[ProbeResult], suffix: str = "") -> dict[str, str | None]:
    return {r.spec.kind + suffix: Path(r.recording).name if r.recording else None for r in results}


def l1_fingerprints() -> tuple[list[tuple[str, str]], dict[str, str | None]]:
    """Cache key and recording name of each rigid probe of L1 on a small box and the L1 contract."""
    asset, _ = box_asset((0.1, 0.08, 0.06), 6)
    corners = np.array([[x, y, z] for x in (-0.05, 0.05) for y in (-0.04, 0.04) for z in (0.0, 0.06)])
    asset.proxy_parts = [SimpleNamespace(vertices=corners)]
    run = l1.l1_runner(cast(Any, asset), load_contract("L1"), "box", (50.0, 200.0))
    values = {"density_kg_per_m3": 100.0, "ground_friction": 0.5, "gripper_friction": 0.8}
    results = run(values, "propose_density")
    assert {r.spec.kind: r.cache_key for r in results if r.cache_key} == {t.split(".")[1].replace("drop", "rigid_drop"): k
                                                                        for t, k in _executed()}
    return _executed(), _recordings([r for r in results if r.spec.kind != "mass"])


def l2_fingerprints(tmp_path: Path,
                    monkeypatch: pytest.MonkeyPatch) -> tuple[list[tuple[str, str]], dict[str, str | None]]:
    """Cache key and recording name of each L2 selection probe and held-out test (kind + '_held_out')."""
    asset, phys = box_asset((0.1, 0.08, 0.06), 6)
    monkeypatch.setattr(l2, "load_l0", lambda d: asset)
    out = l2.evaluate_material(tmp_path, _material(), physical=phys, contract=load_contract("L2"))
    return _executed(), {**_recordings(out["selection"]), **_recordings(out["held_out"], "_held_out")}


def test_l1_probe_fingerprints(monkeypatch: pytest.MonkeyPatch, prefect_api: str) -> None:
    """The rigid probes' cache keys and recording names are those recorded before #37's clean-up."""
    _stub_measurements(monkeypatch)
    assert l1_fingerprints() == (L1_EXECUTED, L1_RECORDINGS)


def test_l2_probe_fingerprints(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, prefect_api: str) -> None:
    """The deformable probes' (selection and held-out) cache keys and recording names are those recorded before."""
    _stub_measurements(monkeypatch)
    assert l2_fingerprints(tmp_path, monkeypatch) == (L2_EXECUTED, L2_RECORDINGS)
