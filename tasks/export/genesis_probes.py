"""L2's drop probe in Genesis, run on the exported scene.py (tasks.export.genesis) with genesis-world's MPM.

The body is released with its lowest surface point height_fraction x H above Genesis's grid contact layer (1.5
cells above the ground plane, as L2 does on its own grid) and sampled every Genesis
step (2 ms) for at least 0.6 s, until it has been quiet for 0.1 s (2 s at most). The particles are Genesis's own
(sampled in the exported surface at DeformSmith's spacing, equal masses); the impact strain is L2's, from Genesis's
per-particle deformation gradients. Genesis reports no ground force, so first contact is the first sample whose
centre-of-mass acceleration exceeds -g / 2 (the ground pushing). The compression probe (a kinematic rigid plate in Genesis's
MPM with its force read back) is not implemented, so Genesis gets the drop metrics only, and no calibration (its
MPM.Elastic has no damping parameter either).
"""

from __future__ import annotations

import importlib.util
import time
from pathlib import Path
from types import ModuleType

import numpy as np

from contracts.errors import InputError, SimulationError
from tasks.export.crosscheck import drop_metrics
from tasks.probes.metrics import compressive_strain

G = 9.81


def load_scene_module(scene_py: Path) -> ModuleType:
    """Import an exported scene.py (needs genesis-world)."""
    if importlib.util.find_spec("genesis") is None:
        from tasks.export.genesis import GENESIS_INSTALL

        raise InputError(f"crosscheck --sim genesis needs genesis-world: {GENESIS_INSTALL}")
    spec = importlib.util.spec_from_file_location(f"deformsmith_genesis_scene_{abs(hash(str(scene_py)))}", scene_py)
    if spec is None or spec.loader is None:
        raise InputError(f"{scene_py}: not a loadable scene file")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _numpy(t: object) -> np.ndarray:
    return np.asarray(t.detach().cpu().numpy() if hasattr(t, "detach") else t, np.float64)


def drop(scene_py: Path, height_fraction: float, young_pa: float | None = None,
         duration_s: float = 2.0) -> dict[str, float]:
    """rebound_ratio, dissipated_energy_fraction, max_impact_strain, settle_time_s, ... of the drop in Genesis."""
    t_wall = time.perf_counter()
    mod = load_scene_module(Path(scene_py))
    p = mod.PARAMS
    h = height_fraction * float(p["height_m"])
    # as L2: Genesis's grid ground reaches the particles ~1.5 cells above the plane (the MPM contact layer), so the
    # body is released that much higher and falls h before it touches
    scene, body = mod.build_scene(young_pa=young_pa, lift_m=h + 1.5 / float(p["grid_density_per_m"]))
    dt = float(p["dt_s"])
    M = float(p["mass_kg"])
    quiet = 1e-3 * M * G * h
    t: list[float] = []
    z: list[float] = []
    vz: list[float] = []
    ke: list[float] = []
    fg: list[float] = []
    s95: list[float] = []
    calm = 0
    k = 0
    x = np.zeros((0, 3))
    while k * dt < duration_s - 1e-9:
        scene.step()
        k += 1
        st = body.get_state()
        x, v, F = _numpy(st.pos)[0], _numpy(st.vel)[0], _numpy(st.F)[0]
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
            raise SimulationError(f"Genesis diverged (non-finite particles) at t = {k * dt:.3f} s")
        m = M / len(x)
        t.append(k * dt)
        z.append(float(x[:, 2].mean()))
        vz.append(float(v[:, 2].mean()))
        ke.append(float(0.5 * m * np.sum(v * v)))
        s95.append(float(np.percentile(compressive_strain(F), 95)))
        pushed = len(vz) >= 2 and (vz[-1] - vz[-2]) / dt > -0.5 * G
        fg.append(1.0 if pushed or (fg and fg[-1] > 0 and x[:, 2].min() < 2.0 * float(p["particle_size_m"])) else 0.0)
        calm = calm + 1 if (ke[-1] < quiet and fg[-1] > 0) else 0
        if t[-1] >= 0.6 and calm * dt >= 0.1:
            break
    out = drop_metrics(np.array(t), np.array(z), np.array(vz), np.array(ke), np.array(fg), np.array(s95), M, h, dt)
    out["sim_time_s"] = t[-1]
    out["wall_time_s"] = time.perf_counter() - t_wall
    out["particles"] = float(len(x))
    return out


__all__ = ["drop", "load_scene_module"]
