"""Particle frames of an attempt as 16-bit fixed point (the interaction data's two large arrays, ~3x smaller).

particles_x_m (T, N, 3) is stored as particles_x_center_m (T, 3) float64 (the midpoint of each frame's bounding box)
and particles_x_offset_steps (T, N, 3) int16 with the array attribute ``step_m``:
    particles_x_m = float32(particles_x_center_m[:, None, :] + particles_x_offset_steps * step_m)
particles_F (T, N, 3, 3) is stored as particles_F_offset_steps (T, N, 3, 3) int16 with the attribute ``step``:
    particles_F = float32(I + particles_F_offset_steps * step)
Each step is the smallest power of two that fits the array's range in 16 bits, so the error is at most step / 2 plus
the float32 rounding of the result (an object within 25 cm of its centre: step_m = 7.6 um, error <= 3.8 um).
Decoding is element-wise IEEE arithmetic in float64 (no reduction): the same stored data gives the same frames on every
machine. An array with a non-finite value, or a range 16 bits cannot hold at MAX_X_STEP_M / MAX_F_STEP, is stored as
float32 unchanged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

X, F = "particles_x_m", "particles_F"
X_CENTER, X_OFFSET, F_OFFSET = "particles_x_center_m", "particles_x_offset_steps", "particles_F_offset_steps"
ENCODED = (X_CENTER, X_OFFSET, F_OFFSET)
LIMIT = 32767             # |int16| used
MIN_STEP = 2.0 ** -40     # the step of an array with no range at all
MAX_X_STEP_M = 2.0 ** -12  # 0.24 mm (an object within 8 m of its centre); coarser is stored as float32
MAX_F_STEP = 2.0 ** -10   # |F - I| < 32; beyond it (a blown-up trial) F is stored as float32


@dataclass(frozen=True)
class Stored:
    """One array as written: its stored name, data and array attributes."""

    name: str
    data: np.ndarray
    attrs: dict[str, Any] = field(default_factory=dict)


def power_of_two_step(max_abs: float) -> float:
    """The smallest power of two s (>= MIN_STEP) with max_abs / s <= LIMIT."""
    if not max_abs > 0.0:
        return MIN_STEP
    s = max(MIN_STEP, 2.0 ** math.ceil(math.log2(max_abs / LIMIT)))
    while max_abs / s > LIMIT:
        s *= 2.0
    while s > MIN_STEP and max_abs / (s / 2.0) <= LIMIT:
        s /= 2.0
    return s


def _quantize(values: np.ndarray, step: float) -> np.ndarray:
    """values / step rounded to the nearest integer (half to even), as int16 (|values| / step <= LIMIT)."""
    return np.rint(values / step).astype(np.int16)


def encode_positions(x: np.ndarray) -> list[Stored]:
    """particles_x_m as a per-frame centre and 16-bit offsets (float32 unchanged when it cannot be)."""
    x64 = np.asarray(x, dtype=np.float64)
    if x64.ndim != 3 or x64.size == 0 or not np.isfinite(x64).all():
        return [Stored(X, np.asarray(x, dtype=np.float32))]
    center = 0.5 * (x64.min(axis=1) + x64.max(axis=1))  # exact and independent of the particle order
    offset = x64 - center[:, None, :]
    step = power_of_two_step(float(np.abs(offset).max()))
    if step > MAX_X_STEP_M:
        return [Stored(X, np.asarray(x, dtype=np.float32))]
    attrs = {"step_m": step, "decodes_to": X, "decode": f"{X} = float32({X_CENTER}[:, None, :] + {X_OFFSET} * step_m)"}
    return [Stored(X_CENTER, center), Stored(X_OFFSET, _quantize(offset, step), attrs)]


def encode_gradients(f: np.ndarray) -> list[Stored]:
    """particles_F as 16-bit offsets from the identity (float32 unchanged when it cannot be)."""
    f64 = np.asarray(f, dtype=np.float64)
    if f64.ndim != 4 or f64.size == 0 or not np.isfinite(f64).all():
        return [Stored(F, np.asarray(f, dtype=np.float32))]
    offset = f64 - np.eye(3)
    step = power_of_two_step(float(np.abs(offset).max()))
    if step > MAX_F_STEP:
        return [Stored(F, np.asarray(f, dtype=np.float32))]
    attrs = {"step": step, "decodes_to": F, "decode": f"{F} = float32(I + {F_OFFSET} * step)"}
    return [Stored(F_OFFSET, _quantize(offset, step), attrs)]


def encode(name: str, values: np.ndarray) -> list[Stored]:
    """How an interaction array is stored: the particle frames encoded, any other array as it is."""
    if name == X:
        return encode_positions(values)
    if name == F:
        return encode_gradients(values)
    return [Stored(name, np.asarray(values))]


def decode(arrays: dict[str, np.ndarray], attrs: dict[str, dict[str, Any]]) -> dict[str, np.ndarray]:
    """The stored arrays with the encoded particle frames decoded (float32) in place of their stored parts; attrs:
    the array attributes by stored name. Arrays stored unchanged pass through."""
    out = {k: v for k, v in arrays.items() if k not in ENCODED}
    if X_OFFSET in arrays:
        q = np.asarray(arrays[X_OFFSET], dtype=np.float64)
        center = np.asarray(arrays[X_CENTER], dtype=np.float64)
        out[X] = (center[:, None, :] + q * float(attrs[X_OFFSET]["step_m"])).astype(np.float32)
    if F_OFFSET in arrays:
        q = np.asarray(arrays[F_OFFSET], dtype=np.float64)
        out[F] = (np.eye(3) + q * float(attrs[F_OFFSET]["step"])).astype(np.float32)
    return out


def max_error(name: str, stored: list[Stored], values: np.ndarray) -> float:
    """The bound on |decoded - values| of an encoded array: step / 2 plus the float32 rounding of the largest value
    (0 when stored unchanged)."""
    for s in stored:
        step = s.attrs.get("step_m", s.attrs.get("step"))
        if step is not None:
            ulp = float(np.spacing(np.float32(np.abs(np.asarray(values, np.float64)).max())))
            return 0.5 * float(step) + ulp
    return 0.0
