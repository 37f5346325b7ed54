"""Part builders for body plans: primitives placed by centre or between two points, painted later by part name."""

from __future__ import annotations

import warnings
from collections.abc import Sequence

import numpy as np
from scipy.spatial.transform import Rotation

from contracts.shape import Part

Vec = Sequence[float] | np.ndarray

# part-name words that are positions, not what the part is ('front left leg' is a 'leg')
SIDE_WORDS = frozenset({"front", "rear", "back", "left", "right", "upper", "lower", "middle", "inner", "outer", "top",
                        "bottom", "hind", "fore", "tip", "base"})
DEFAULT_GREY = (0.45, 0.45, 0.45)


def _f3(v: Vec) -> tuple[float, float, float]:
    return (float(v[0]), float(v[1]), float(v[2]))


def ellipsoid(name: str, radii: Vec, at: Vec, blend: float = 0.0, rot: Vec = (0, 0, 0)) -> Part:
    """Ellipsoid part centred at `at` [m]."""
    return Part(name=name, primitive={"kind": "ellipsoid", "radii_m": _f3(radii)},
                transform={"translation_m": _f3(at), "rotation_deg": _f3(rot)}, blend_m=blend, color_rgb=DEFAULT_GREY)


def superellipsoid(name: str, radii: Vec, at: Vec, ns: float = 0.5, ew: float = 0.5, blend: float = 0.0,
                   rot: Vec = (0, 0, 0)) -> Part:
    """Superellipsoid part (ns, ew: roundness exponents; 1 = ellipsoid, -> 0 box)."""
    return Part(name=name, primitive={"kind": "superellipsoid", "radii_m": _f3(radii), "exponent_ns": ns,
                                      "exponent_ew": ew},
                transform={"translation_m": _f3(at), "rotation_deg": _f3(rot)}, blend_m=blend, color_rgb=DEFAULT_GREY)


def box(name: str, size: Vec, at: Vec, edge: float = 0.0, blend: float = 0.0, rot: Vec = (0, 0, 0),
        op: str = "union") -> Part:
    """Rounded box of full extents `size` [m]."""
    return Part(name=name, primitive={"kind": "rounded_box", "size_m": _f3(size), "edge_radius_m": float(edge)},
                transform={"translation_m": _f3(at), "rotation_deg": _f3(rot)}, blend_m=blend, operation=op,
                color_rgb=DEFAULT_GREY)


def cylinder(name: str, radius: float, height: float, at: Vec, edge: float = 0.0, blend: float = 0.0,
             rot: Vec = (0, 0, 0), op: str = "union") -> Part:
    """Cylinder along local z (rotate to lay it down)."""
    return Part(name=name, primitive={"kind": "cylinder", "radius_m": float(radius), "height_m": float(height),
                                      "edge_radius_m": float(edge)},
                transform={"translation_m": _f3(at), "rotation_deg": _f3(rot)}, blend_m=blend, operation=op,
                color_rgb=DEFAULT_GREY)


def torus(name: str, major: float, minor: float, at: Vec, blend: float = 0.0, rot: Vec = (0, 0, 0),
          scale: Vec = (1, 1, 1)) -> Part:
    """Torus in the local x-y plane."""
    return Part(name=name, primitive={"kind": "torus", "major_radius_m": float(major), "minor_radius_m": float(minor)},
                transform={"translation_m": _f3(at), "rotation_deg": _f3(rot), "scale": _f3(scale)}, blend_m=blend,
                color_rgb=DEFAULT_GREY)


def cone(name: str, r_bottom: float, r_top: float, height: float, at: Vec, edge: float = 0.0, blend: float = 0.0,
         rot: Vec = (0, 0, 0), scale: Vec = (1, 1, 1)) -> Part:
    """Frustum along local z (bottom at -height/2)."""
    return Part(name=name, primitive={"kind": "cone", "radius_bottom_m": float(r_bottom), "radius_top_m": float(r_top),
                                      "height_m": float(height), "edge_radius_m": float(edge)},
                transform={"translation_m": _f3(at), "rotation_deg": _f3(rot), "scale": _f3(scale)}, blend_m=blend,
                color_rgb=DEFAULT_GREY)


def _euler_z_to(direction: np.ndarray) -> tuple[float, float, float]:
    """XYZ Euler angles [deg] of a rotation taking local +z onto `direction`."""
    d = direction / max(float(np.linalg.norm(direction)), 1e-12)
    rot, _ = Rotation.align_vectors([d], [[0.0, 0.0, 1.0]])
    with warnings.catch_warnings():  # a limb along x or y is a gimbal-lock case; any of its equal angle sets will do
        warnings.simplefilter("ignore", UserWarning)
        return _f3(rot.as_euler("xyz", degrees=True))


def limb(name: str, a: Vec, b: Vec, radius: float, blend: float = 0.0) -> Part:
    """Capsule from point a to point b [m] (a leg, an arm, a tentacle segment)."""
    pa, pb = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    length = float(np.linalg.norm(pb - pa))
    return Part(name=name, primitive={"kind": "capsule", "radius_m": float(radius), "length_m": length},
                transform={"translation_m": _f3((pa + pb) / 2.0), "rotation_deg": _euler_z_to(pb - pa)},
                blend_m=blend, color_rgb=DEFAULT_GREY)


def tapered(name: str, a: Vec, b: Vec, r_a: float, r_b: float, blend: float = 0.0) -> Part:
    """Rounded frustum from a (radius r_a) to b (radius r_b) [m]: a horn, a beak, a carrot, a tail."""
    pa, pb = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    h = float(np.linalg.norm(pb - pa))
    edge = 0.3 * min(r_a, r_b) if min(r_a, r_b) > 0 else 0.1 * max(r_a, r_b)
    return Part(name=name, primitive={"kind": "cone", "radius_bottom_m": float(r_a), "radius_top_m": float(r_b),
                                      "height_m": h, "edge_radius_m": float(edge)},
                transform={"translation_m": _f3((pa + pb) / 2.0), "rotation_deg": _euler_z_to(pb - pa)},
                blend_m=blend, color_rgb=DEFAULT_GREY)


def mirrored(make, name: str, *args, **kwargs) -> list[Part]:  # noqa: ANN001
    """A left/right pair: make('left NAME', ...) at +y and make('right NAME', ...) with y and x/z rotations mirrored.
    The first positional argument after the name that is a 3-vector `at` is mirrored; rotations about x and z flip."""
    left = make(f"left {name}", *args, **kwargs)
    tf = left.transform
    t, r = tf.translation_m, tf.rotation_deg
    right = left.model_copy(update={"name": f"right {name}", "transform": tf.model_copy(
        update={"translation_m": (t[0], -t[1], t[2]), "rotation_deg": (-r[0], r[1], -r[2])})})
    return [left, right]


def part_group(name: str) -> str:
    """What a part is, without its position words: 'front left leg' -> 'leg', 'leaf 2' -> 'leaf'."""
    words = [w for w in name.lower().split() if w not in SIDE_WORDS and not w.isdigit()]
    return " ".join(words) if words else name.lower()
