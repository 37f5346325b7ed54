"""State: the per-particle arrays that a step advances (x [m], v [m/s], F [-], C [1/s])."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import warp as wp

if TYPE_CHECKING:
    from tasks.mpm.model import Model


class State:
    """Particle positions, velocities, deformation gradients and APIC affine velocity fields of all scenes."""

    def __init__(self, x: wp.array, v: wp.array, F: wp.array, C: wp.array) -> None:
        self.x = x
        self.v = v
        self.F = F
        self.C = C

    @classmethod
    def initial(cls, model: Model) -> State:
        """The model's initial state: rest configuration (F = I, C = 0)."""
        d = model.device
        n = model.n_particles
        F = np.tile(np.eye(3, dtype=np.float32), (n, 1, 1))
        return cls(
            x=wp.array(model.x0, dtype=wp.vec3, device=d),
            v=wp.array(model.v0, dtype=wp.vec3, device=d),
            F=wp.array(F, dtype=wp.mat33, device=d),
            C=wp.zeros(n, dtype=wp.mat33, device=d),
        )

    def copy(self) -> State:
        """A deep copy on the same device."""
        return State(wp.clone(self.x), wp.clone(self.v), wp.clone(self.F), wp.clone(self.C))

    def assign(self, other: State) -> None:
        """Copy another state's arrays into this one (same sizes)."""
        wp.copy(self.x, other.x)
        wp.copy(self.v, other.v)
        wp.copy(self.F, other.F)
        wp.copy(self.C, other.C)

    def numpy(self, model: Model | None = None, scene: int | None = None) -> dict[str, np.ndarray]:
        """Host copies: x (N,3) [m], v (N,3) [m/s], F (N,3,3); one scene's slice if scene is given."""
        out = {"x": self.x.numpy(), "v": self.v.numpy(), "F": self.F.numpy()}
        if scene is not None:
            if model is None:
                raise ValueError("scene selection needs the model")
            sl = model.scene_slice(scene)
            out = {k: a[sl] for k, a in out.items()}
        return out
