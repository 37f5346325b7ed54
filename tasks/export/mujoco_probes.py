"""L2's drop and compression probes in MuJoCo on the exported flex body (tasks.export.probe_schedule's schedules).

The table is MuJoCo's ground; the compression's plate is a frictionless mocap box moved one timestep at a time, its
force the normal force of its contacts.
"""

from __future__ import annotations

from collections import deque
from dataclasses import replace

import numpy as np

from contracts.errors import SimulationError
from tasks.export.mujoco_scene import FLEX_NAME, PLATE_NAME, TABLE_NAME, FlexParams, scene_xml
from tasks.export.probe_schedule import TetBody, drop_lift_m, plate_setup, run_compress, run_drop, unrotated

MUJOCO_WARNINGS: deque[str] = deque(maxlen=20)  # MuJoCo's last warnings (not printed, nor logged to a file)


def quiet_mujoco_warnings() -> None:
    """Route MuJoCo's warnings to MUJOCO_WARNINGS instead of stderr and MUJOCO_LOG.TXT in the working directory (the
    flex solver warns of an under-converged M+K solve on sliver tets; the probes check the state for NaN instead)."""
    import mujoco

    mujoco.set_mju_user_warning(MUJOCO_WARNINGS.append)


class _Sim:
    """One MuJoCo model of the body with index maps for the flex nodes (a probe_schedule.ProbeSim)."""

    def __init__(self, xml: str, timestep_s: float):
        import mujoco

        quiet_mujoco_warnings()
        self.mj = mujoco
        self.model = mujoco.MjModel.from_xml_string(xml)
        self.data = mujoco.MjData(self.model)
        m = self.model
        f = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_FLEX, FLEX_NAME)
        adr, num = int(m.flex_vertadr[f]), int(m.flex_vertnum[f])
        self.vbody = np.asarray(m.flex_vertbodyid[adr:adr + num])
        self.masses = np.asarray(m.body_mass[self.vbody], np.float64)
        dof = np.asarray(m.body_dofadr[self.vbody])
        self.dofs = (dof[:, None] + np.arange(3)[None, :]).ravel()
        self.table = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, TABLE_NAME)
        self.plate = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, PLATE_NAME)
        self._f6 = np.zeros(6)
        self.timestep_s = timestep_s  # the model's, as given (the XML's text may round it)

    @property
    def time_s(self) -> float:
        return float(self.data.time)

    def x(self) -> np.ndarray:
        return np.array(self.data.xpos[self.vbody], np.float64)

    def v(self) -> np.ndarray:
        return np.array(self.data.qvel[self.dofs], np.float64).reshape(-1, 3)

    def _contacts_of(self, geom: int) -> np.ndarray:
        g = np.asarray(self.data.contact.geom)[: self.data.ncon]
        return np.flatnonzero((g[:, 0] == geom) | (g[:, 1] == geom)) if len(g) else np.zeros(0, int)

    def touching(self, geom: int) -> bool:
        """Whether any contact involves the geom."""
        return len(self._contacts_of(geom)) > 0

    def normal_force(self, geom: int) -> float:
        """Total normal contact force on a geom [N] (frictionless contacts: their constraint force directly)."""
        d = self.data
        idx = self._contacts_of(geom)
        if len(idx) == 0:
            return 0.0
        dim = np.asarray(d.contact.dim)[idx]
        if np.all(dim == 1):
            return float(np.asarray(d.efc_force)[np.asarray(d.contact.efc_address)[idx]].sum())
        total = 0.0
        for i in idx:
            self.mj.mj_contactForce(self.model, d, int(i), self._f6)
            total += float(self._f6[0])
        return total

    def touching_ground(self) -> bool:
        return self.touching(self.table)

    def plate_force_n(self) -> float:
        return self.normal_force(self.plate)

    def move_plate(self, vz_m_per_s: float, duration_s: float) -> None:
        """Move the mocap plate at vz, one timestep at a time."""
        dt = self.timestep_s
        for _ in range(max(1, int(round(duration_s / dt)))):
            self.data.mocap_pos[0, 2] += vz_m_per_s * dt
            self.advance(dt)

    def advance(self, duration_s: float) -> None:
        """Step for duration_s; SimulationError on a non-finite state."""
        m, d = self.model, self.data
        n = max(1, int(round(duration_s / m.opt.timestep)))
        self.mj.mj_step(m, d, nstep=n)
        if d.warning[self.mj.mjtWarning.mjWARN_BADQACC].number > 0 or not np.all(np.isfinite(d.qpos)):
            raise SimulationError(f"MuJoCo diverged (non-finite state) at t = {d.time:.4f} s")


def _scene(body: TetBody, p: FlexParams, lift_m: float, **kw: object) -> str:
    return scene_xml(body.nodes_m + np.array([0.0, 0.0, lift_m]), body.tets, p, **kw)  # type: ignore[arg-type]


def drop(body: TetBody, p: FlexParams, height_fraction: float, duration_s: float = 2.0) -> dict[str, float]:
    """L2's drop probe in MuJoCo: rebound_ratio, dissipated_energy_fraction, max_impact_strain, settle_time_s, ..."""
    sim = _Sim(_scene(body, p, drop_lift_m(body, height_fraction)), p.timestep_s)
    return run_drop(sim, body, height_fraction, duration_s)


def compress(body: TetBody, p: FlexParams, strain: float, area_m2: float) -> dict[str, float]:
    """L2's compression probe in MuJoCo: effective_modulus_pa, recovery_ratio, compression_strain/force."""
    setup = plate_setup(body)
    sim = _Sim(_scene(body, p, -float(body.nodes_m[:, 2].min()), frictionless=True, plate_half_m=setup.half_m,
                      plate_pos_m=setup.centre_m), p.timestep_s)
    return run_compress(sim, body, setup, strain, area_m2)


def with_values(p: FlexParams, young_pa: float | None = None, damping_s: float | None = None) -> FlexParams:
    """A copy of p with another Young's modulus and/or damping time."""
    return replace(p, young_pa=p.young_pa if young_pa is None else young_pa,
                   damping_s=p.damping_s if damping_s is None else damping_s)


__all__ = ["TetBody", "compress", "drop", "unrotated", "with_values"]  # TetBody, unrotated: probe_schedule's
