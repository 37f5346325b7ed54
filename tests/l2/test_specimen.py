"""The target bands are measured on a specimen of the material: the object's compression measures its structure."""

from __future__ import annotations

import numpy as np
import pytest

from contracts.errors import InputError
from contracts.material import Material
from contracts.stage import load_contract
from tasks.probes.l2_record import l2_metrics, object_view
from tasks.probes.screening import specimen_arrays
from tasks.probes.deformable import compress
from tasks.probes.rollout import DeformableBody
from tasks.probes.specimen import specimen_particles
from tests.l2.helpers import box_asset


def _table(s: float) -> tuple[np.ndarray, np.ndarray]:
    """A 'table' of particles at spacing s: a 8 x 8 x 4 slab on four 2 x 2 x 2 legs at its corners (z up, on z = 0);
    the probe's mid-height cross-section is the slab's, the load goes through legs of a quarter of that area."""
    c = (np.arange(8) + 0.5) * s - 4 * s
    pts = [(x, y, (k + 0.5) * s) for x in c for y in c for k in range(2, 6)]
    for lx in (c[:2], c[-2:]):
        for ly in (c[:2], c[-2:]):
            pts += [(x, y, (k + 0.5) * s) for x in lx for y in ly for k in range(2)]
    pos = np.array(pts)
    return pos, np.full(len(pos), s ** 3)


def test_specimen_is_a_cube_on_the_ground_at_the_given_spacing() -> None:
    pos, vol = specimen_particles(0.004, 10)
    assert pos.shape == (1000, 3) and np.allclose(vol, 0.004 ** 3)
    assert np.isclose(pos[:, 2].min(), 0.002) and np.allclose(pos[:, :2].mean(axis=0), 0.0, atol=1e-12)
    assert np.allclose(pos.max(axis=0) - pos.min(axis=0), 9 * 0.004)
    with pytest.raises(InputError):
        specimen_particles(0.0)
    with pytest.raises(InputError):
        specimen_particles(0.004, 4)
    with pytest.raises(InputError):
        specimen_particles(0.004, 10, "pyramid")
    ball, _ = specimen_particles(0.004, 10, "ball")
    assert 0.45 < len(ball) / 1000 < 0.6  # pi/6 of the cube
    assert np.isclose(ball[:, 2].min(), 0.002) and np.allclose(ball[:, :2].mean(axis=0), 0.0, atol=1e-12)
    assert np.ptp(ball[:, 0]) <= 9 * 0.004 + 1e-12


def test_specimen_follows_the_contract_and_the_physical_spacing() -> None:
    _, phys = box_asset((0.1, 0.08, 0.06), 6)
    contract = load_contract("L2")
    pos, _ = specimen_arrays(phys, contract)
    n = int(contract.parameters["specimen_particles_per_axis"])
    assert len(pos) == n ** 3
    assert np.isclose(pos[1, 2] - pos[0, 2], phys.particle_spacing_m)
    ball, _ = specimen_arrays(phys, contract, "specimen_drop")
    assert len(ball) < len(pos) and np.isclose(np.ptp(ball[:, 2]), np.ptp(pos[:, 2]))


def test_a_rubber_ball_specimen_rebounds_like_rubber_where_a_flat_landing_cube_cannot() -> None:
    """At damping 0 a 1.5 MPa rubber ball specimen (10-particle lattice) rebounds into rubber's band [0.4, 0.8]; the
    cube of the same lattice landing flat on the grid ground stays far below it (why the drop uses the ball)."""
    from tasks.probes.deformable import drop

    rubber = Material(youngs_modulus_pa=1.5e6, poisson_ratio=0.48, damping_rate_per_s=0.0)
    out = {}
    for shape in ("ball", "cube"):
        x, v = specimen_particles(0.004, 10, shape)
        out[shape] = drop(DeformableBody(x, v, 0.004, 950.0, 0.9, 1.0), [rubber], height_fraction=0.25)[0]
    assert out["ball"].health.ok and 0.4 <= out["ball"].metrics["rebound_ratio"] <= 0.8
    assert out["cube"].metrics["rebound_ratio"] < out["ball"].metrics["rebound_ratio"] - 0.1


def test_a_structure_is_softer_than_its_material_and_the_bands_read_the_specimen() -> None:
    """Plate compression of a table on four legs gives far less than E (the legs carry the load); the same material's
    specimen gives E within 15 %. l2_metrics reports the specimen's as effective_modulus_pa and the table's as
    object_effective_modulus_pa, and keeps the worst gate metric of the two."""
    s, rho = 0.01, 100.0
    mat = Material(youngs_modulus_pa=2.0e4, poisson_ratio=0.3, damping_rate_per_s=5.0)
    table = DeformableBody(*_table(s), s, rho)
    cube = DeformableBody(*specimen_particles(s, 8), s, rho)
    r_obj = compress(table, [mat], strain=0.05)[0]
    r_spec = compress(cube, [mat], strain=0.05)[0]
    r_spec = r_spec.model_copy(update={"spec": r_spec.spec.model_copy(update={"kind": "specimen_compress"})})
    assert r_obj.health.ok and r_spec.health.ok
    e_obj, e_spec = r_obj.metrics["effective_modulus_pa"], r_spec.metrics["effective_modulus_pa"]
    assert abs(e_spec - 2.0e4) / 2.0e4 < 0.15, e_spec
    assert e_obj < 0.6 * e_spec, (e_obj, e_spec)
    contract = load_contract("L2")
    merged = l2_metrics([r_obj, r_spec], contract)
    assert merged["effective_modulus_pa"] == e_spec and merged["object_effective_modulus_pa"] == e_obj
    assert merged["j_min"] == min(r_obj.metrics["j_min"], r_spec.metrics["j_min"])
    viewed = object_view([r_obj], contract)[0]
    assert "effective_modulus_pa" not in viewed.metrics and viewed.metrics["finite"] == 1.0
    assert object_view([viewed], contract)[0].metrics == viewed.metrics  # viewing twice renames nothing more
