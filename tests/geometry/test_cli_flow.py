"""`deformsmith geometry` writes a complete, loadable L0 directory; bad input leaves nothing; the flow caches."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pybullet
import pytest
import trimesh
from plyfile import PlyData

from contracts.request import AssetRequest
from tests.cli_in_process import cli_run

REPO = Path(__file__).resolve().parents[2]


def test_geometry_command_writes_a_loadable_asset(tmp_path: Path, prefect_api: str, monkeypatch: pytest.MonkeyPatch,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "turtle"
    code, stdout, err = cli_run("geometry", "a soft plush turtle toy, about 25 cm long", "--out", str(out),
                                "--no-cache", "--json", api=prefect_api, monkeypatch=monkeypatch, capsys=capsys)
    assert code == 0, err
    record = json.loads(stdout)
    assert record["passed"] and record["info"]["entry"] == "plush_turtle"
    for rel in ("mesh.glb", "gaussians.ply", "geometry.json", "renders/front.png", "renders/side.png",
                "renders/top.png", record["files"]["urdf"], "particles.zarr"):
        assert (out / rel).exists(), rel
    assert [p.name for p in tmp_path.iterdir()] == ["turtle"]  # no temp directories left over

    from tasks.geometry.outputs import load_l0

    asset = load_l0(out)
    assert asset.volumes_m3.sum() == pytest.approx(asset.mesh.volume, rel=1e-9)
    assert asset.mesh.is_watertight and asset.particles_m.shape[1] == 3
    assert asset.gaussians["particle_index"].shape == (len(asset.gaussians["positions_m"]), 4)
    assert PlyData.read(str(out / "gaussians.ply"))["vertex"].count == len(asset.gaussians["positions_m"])
    # the binding is the particle indices and weights; the Gaussians themselves are stored once, in gaussians.ply
    import zarr

    assert sorted(zarr.open_group(str(out / "particles.zarr"), mode="r")["gaussian_binding"].array_keys()) == [
        "particle_index", "particle_weight"]
    glb = trimesh.load(out / "mesh.glb", force="mesh")
    assert glb.volume == pytest.approx(asset.mesh.volume, rel=1e-3)

    cid = pybullet.connect(pybullet.DIRECT)
    try:
        body = pybullet.loadURDF(str(asset.urdf), physicsClientId=cid)
        lo, hi = pybullet.getAABB(body, physicsClientId=cid)
        assert np.allclose(np.subtract(hi, lo), asset.mesh.extents, atol=0.02)
        assert pybullet.getNumJoints(body, physicsClientId=cid) == 0
    finally:
        pybullet.disconnect(cid)


@pytest.mark.parametrize("args, message", [
    (["a 50 m teddy bear"], "outside the supported range"),
    (["--mesh", "/no/such/file.obj"], "not found"),
    (["--image", __file__], "cannot read image"),
])
def test_bad_input_is_one_clear_line_and_leaves_nothing(tmp_path: Path, args: list[str], message: str,
                                                       cli_env: dict[str, str]) -> None:
    """(A subprocess: no traceback on the process's stderr, where Prefect's log handlers write too.)"""
    out = tmp_path / "asset"
    proc = subprocess.run([sys.executable, "-m", "flows.cli.main", "geometry", *args, "--out", str(out), "--no-cache"],
                          cwd=REPO, capture_output=True, text=True, env=cli_env, timeout=300)
    assert proc.returncode != 0
    assert message in proc.stderr and "Traceback" not in proc.stderr
    assert list(tmp_path.iterdir()) == []


def test_flow_reruns_from_the_cache(prefect_api: str) -> None:
    from cache import CacheStore, cache_root
    from flows.l0_geometry import run_l0

    req = AssetRequest(text="a tofu block 10 x 7 x 4 cm")
    first = run_l0(req, "draft", coacd_overrides={"method": "hull"})
    n = len(CacheStore(cache_root()).events())
    second = run_l0(req, "draft", coacd_overrides={"method": "hull"})
    events = CacheStore(cache_root()).events()[n:]
    # mesh, proxy, rest on the proxy (a text request's), particles, Gaussians, checks
    assert {e["outcome"] for e in events} == {"hit"} and len(events) == 6
    assert second.checks == first.checks
    np.testing.assert_array_equal(second.particles["positions_m"], first.particles["positions_m"])
    # material words never invalidate L0
    third = run_l0(req.model_copy(update={"material_intent": "firm rubber"}), "draft", coacd_overrides={"method": "hull"})
    assert {e["outcome"] for e in CacheStore(cache_root()).events()[n + 6:]} == {"hit"}
    assert third.checks == first.checks
