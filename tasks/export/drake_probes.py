"""L2's drop and compression probes in Drake on the exported deformable body (tasks.export.probe_schedule's schedules).

The scene is the export's: its SDFormat deformable (`drake:deformable_properties`, the VTK tet mesh, neo-Hookean) and
its ground box, parsed by pydrake into a discrete MultibodyPlant with the SAP contact solver. The compression's plate
is a frictionless rigid box on a z prismatic joint, gravity off, whose position and velocity are set before every
step (prescribed motion); its force is the body's deformable contact force with it (ContactResults). Drake integrates
deformables with a Newmark scheme of gamma = 1, beta = 0.5 (DeformableModel; not configurable in 1.51): first order,
numerically dissipative like backward Euler in the velocities, so its timestep takes impact energy the way MuJoCo's
does and is the calibration's first damping knob.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from contracts.errors import SimulationError
from contracts.export import ExportMaterial
from tasks.export.drake import deformable_sdf, ground_sdf
from tasks.export.probe_schedule import PlateSetup, TetBody, drop_lift_m, plate_setup, run_compress, run_drop

TIME_STEP_S = 1e-3  # the exported scene's step (its README's MultibodyPlantConfig; Drake's default)
PLATE_MASS_PER_BODY_MASS = 100.0  # the plate's inertia within one step: its position is set again before the next


@dataclass(frozen=True)
class DrakeParams:
    """What Drake is given: the export's material (E, nu, rho, Rayleigh mass damping, friction) and the step."""

    material: ExportMaterial
    timestep_s: float = TIME_STEP_S


def node_masses_kg(nodes_m: np.ndarray, tets: np.ndarray, density_kg_per_m3: float) -> np.ndarray:
    """Lumped node masses [kg]: a quarter of each tet's mass to each of its nodes."""
    p = np.asarray(nodes_m, np.float64)[np.asarray(tets)]
    vol = np.abs(np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])) / 6.0
    m = np.zeros(len(nodes_m))
    np.add.at(m, np.asarray(tets).ravel(), np.repeat(vol * density_kg_per_m3 / 4.0, 4))
    return m


class _Sim:
    """One Drake diagram of the body (lifted by lift_m), the ground and optionally the plate (a ProbeSim)."""

    def __init__(self, body: TetBody, vtk: Path, p: DrakeParams, lift_m: float, plate: PlateSetup | None = None):
        from pydrake.geometry import AddContactMaterial, Box, ProximityProperties
        from pydrake.math import RigidTransform
        from pydrake.multibody.parsing import Parser
        from pydrake.multibody.plant import AddMultibodyPlant, CoulombFriction, MultibodyPlantConfig
        from pydrake.multibody.tree import DeformableBodyIndex, PrismaticJoint, SpatialInertia
        from pydrake.systems.analysis import Simulator
        from pydrake.systems.framework import DiagramBuilder

        self.timestep_s = p.timestep_s
        self.masses = node_masses_kg(body.nodes_m, body.tets, p.material.density_kg_per_m3)
        builder = DiagramBuilder()
        plant, _ = AddMultibodyPlant(MultibodyPlantConfig(time_step=p.timestep_s, discrete_contact_approximation="sap"),
                                     builder)
        mu = 0.0 if plate is not None else p.material.ground_friction  # L2's compression is frictionless
        parser = Parser(plant)
        parser.AddModelsFromString(ground_sdf(mu), "sdf")
        parser.AddModelsFromString(deformable_sdf("body", Path(vtk).resolve().as_uri(), p.material), "sdf")
        self._plate_joint = None
        if plate is not None:
            instance = plant.AddModelInstance("plate")
            hx, hy, hz = plate.half_m
            mass = max(1.0, PLATE_MASS_PER_BODY_MASS * float(self.masses.sum()))
            rigid = plant.AddRigidBody("plate", instance, SpatialInertia.SolidBoxWithMass(mass, 2 * hx, 2 * hy, 2 * hz))
            props = ProximityProperties()
            AddContactMaterial(friction=CoulombFriction(0.0, 0.0), properties=props)
            offset = RigidTransform(np.array([plate.centre_m[0], plate.centre_m[1], 0.0]))  # type: ignore[arg-type]
            self._plate_geometry = plant.RegisterCollisionGeometry(rigid, offset, Box(2 * hx, 2 * hy, 2 * hz), "plate",
                                                                   props)
            z_axis = np.array([0.0, 0.0, 1.0])
            self._plate_joint = plant.AddJoint(PrismaticJoint("plate_z", plant.world_frame(), rigid.body_frame(),
                                                              z_axis))  # type: ignore[arg-type]
            plant.set_gravity_enabled(instance, False)
            self._plate_z = float(plate.centre_m[2])
        plant.Finalize()
        self._ground = set(plant.GetCollisionGeometriesForBody(plant.GetBodyByName("ground")))
        self.model = plant.deformable_model()
        self.body = self.model.GetBodyId(DeformableBodyIndex(0))
        self.simulator = Simulator(builder.Build())
        self.context = plant.GetMyContextFromRoot(self.simulator.get_mutable_context())
        self._contacts = plant.get_contact_results_output_port()
        self.model.SetPositions(self.context, self.body, (np.asarray(body.nodes_m) + [0.0, 0.0, lift_m]).T)
        if self._plate_joint is not None:
            self._plate_joint.set_translation(self.context, self._plate_z)
        self._steps = 0
        self.simulator.Initialize()

    @property
    def time_s(self) -> float:
        return self._steps * self.timestep_s

    def x(self) -> np.ndarray:
        return np.asarray(self.model.GetPositions(self.context, self.body), np.float64).T.copy()

    def v(self) -> np.ndarray:
        return np.asarray(self.model.GetVelocities(self.context, self.body), np.float64).T.copy()

    def _step_to(self, steps: int) -> None:
        try:
            self.simulator.AdvanceTo(steps * self.timestep_s)
        except RuntimeError as exc:  # SAP not converging, an inverted element, ...
            raise SimulationError(f"Drake failed at t = {self.time_s:.4f} s: {exc}") from None
        self._steps = steps
        if not np.all(np.isfinite(self.model.GetPositions(self.context, self.body))):
            raise SimulationError(f"Drake diverged (non-finite state) at t = {self.time_s:.4f} s")

    def advance(self, duration_s: float) -> None:
        """Step for duration_s (the plate, if any, held where it is)."""
        if self._plate_joint is not None:
            self.move_plate(0.0, duration_s)
            return
        self._step_to(self._steps + max(1, int(round(duration_s / self.timestep_s))))

    def move_plate(self, vz_m_per_s: float, duration_s: float) -> None:
        """Move the plate at vz, its position and velocity set before every step."""
        assert self._plate_joint is not None
        for _ in range(max(1, int(round(duration_s / self.timestep_s)))):
            self._plate_z += vz_m_per_s * self.timestep_s
            self._plate_joint.set_translation(self.context, self._plate_z)
            self._plate_joint.set_translation_rate(self.context, vz_m_per_s)
            self._step_to(self._steps + 1)

    def _contact_forces(self) -> list[tuple[object, float]]:
        """(the other geometry, z force of the contact on the body [N]) for every deformable contact."""
        results = self._contacts.Eval(self.context)
        out = []
        for i in range(results.num_deformable_contacts()):
            info = results.deformable_contact_info(i)
            fz = float(info.F_Ac_W().translational()[2])  # on A, the deformable (the body touches only rigid ones)
            out.append((info.id_B(), fz))
        return out

    def touching_ground(self) -> bool:
        return any(g in self._ground for g, _ in self._contact_forces())

    def plate_force_n(self) -> float:
        return float(sum(-fz for g, fz in self._contact_forces() if g == self._plate_geometry))


def drop(body: TetBody, vtk: Path, p: DrakeParams, height_fraction: float, duration_s: float = 2.0) -> dict[str, float]:
    """L2's drop probe in Drake: rebound_ratio, dissipated_energy_fraction, max_impact_strain, settle_time_s, ..."""
    return run_drop(_Sim(body, vtk, p, drop_lift_m(body, height_fraction)), body, height_fraction, duration_s)


def compress(body: TetBody, vtk: Path, p: DrakeParams, strain: float, area_m2: float) -> dict[str, float]:
    """L2's compression probe in Drake: effective_modulus_pa, recovery_ratio, compression_strain/force."""
    setup = plate_setup(body)
    return run_compress(_Sim(body, vtk, p, -float(body.nodes_m[:, 2].min()), setup), body, setup, strain, area_m2)


__all__ = ["DrakeParams", "TIME_STEP_S", "compress", "drop", "node_masses_kg"]
