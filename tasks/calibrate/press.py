"""A flat-plate press test's force-displacement table (CSV with columns displacement_m and force_n) reduced to L2's
compression metric, the effective modulus (F / A) / strain at the compression probe's strain, A the body's
cross-section at mid height as the probe measures it; and the probe itself on the scaled body."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from contracts.errors import InputError
from contracts.material import Material
from contracts.sim import SimConfig
from contracts.video_fit import PressTest
from tasks.probes.deformable import compress
from tasks.probes.metrics import cross_section_area
from tasks.probes.rollout import DeformableBody

PRESS_STRAIN = 0.1  # L2's compression probe strain
MIN_STRAIN = 0.02


def read_press(path: Path) -> np.ndarray:
    """(N, 2) displacement [m], force [N], sorted by displacement (InputError with one line when unusable)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"press table not found: {path}")
    try:
        with path.open(newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise InputError(f"{path}: not a readable CSV ({exc})") from None
    if not rows or not {"displacement_m", "force_n"} <= set(rows[0]):
        raise InputError(f"{path}: needs a header with the columns displacement_m and force_n (SI units)")
    try:
        a = np.array([[float(r["displacement_m"]), float(r["force_n"])] for r in rows])
    except (TypeError, ValueError):
        raise InputError(f"{path}: every row needs a number in displacement_m and force_n") from None
    if len(a) < 2 or not np.all(np.isfinite(a)) or np.any(a[:, 0] < 0):
        raise InputError(f"{path}: needs at least two rows of finite, non-negative displacements")
    return a[np.argsort(a[:, 0])]


def press_test(path: Path, table: np.ndarray, positions_m: np.ndarray, volumes_m3: np.ndarray,
               spacing_m: float) -> PressTest:
    """The table's effective modulus on this body (its height and mid-height cross-section) at PRESS_STRAIN, or at the
    largest strain the table reaches when that is less (InputError below MIN_STRAIN)."""
    height = float(np.ptp(positions_m[:, 2]) + spacing_m)
    strain = min(PRESS_STRAIN, float(table[-1, 0]) / height)
    if strain < MIN_STRAIN:
        raise InputError(f"{path}: the press reaches {table[-1, 0]:.4g} m, a strain of {strain:.3f} of the object's "
                         f"{height:.4g} m; at least {MIN_STRAIN} is needed")
    force = float(np.interp(strain * height, table[:, 0], table[:, 1]))
    mid = 0.5 * (positions_m[:, 2].min() + positions_m[:, 2].max())
    area = cross_section_area(positions_m, volumes_m3, spacing_m, mid)
    if not (force > 0 and area > 0):
        raise InputError(f"{path}: no positive force at a strain of {strain:.3f}")
    return PressTest(path=str(path), rows=len(table), strain=strain, force_n=force, cross_section_m2=area,
                     effective_modulus_pa=force / area / strain)


def probe_modulus(body: DeformableBody, material: Material, strain: float, sim: SimConfig) -> float:
    """L2's compression probe's effective modulus of the body in this material at `strain` [Pa] (nan if it failed)."""
    r = compress(body, material, strain=strain, sim=sim)[0]
    v = r.metrics.get("effective_modulus_pa", math.nan)
    return float(v) if r.health.ok else math.nan


__all__ = ["MIN_STRAIN", "PRESS_STRAIN", "press_test", "probe_modulus", "read_press"]
