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


def scaled(part: Part, scale: Vec) -> Part:
    """A part with its transform's scale set to `scale` (a flattened or oval primitive; builders make them at 1)."""
    return part.model_copy(update={"transform": part.transform.model_copy(update={"scale": _f3(scale)})})


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


def rotated_parts(parts: Sequence[Part], euler_deg: Vec, centre: Vec = (0.0, 0.0, 0.0)) -> list[Part]:
    """Parts turned as one rigid body about `centre` by extrinsic XYZ Euler angles [deg] (a pose: an animal lying on
    its side is the standing one turned 90 degrees about its long axis); each part's own rotation is composed."""
    turn = Rotation.from_euler("xyz", euler_deg, degrees=True)
    c = np.asarray(centre, dtype=np.float64)
    out = []
    for p in parts:
        tf = p.transform
        own = Rotation.from_euler("xyz", tf.rotation_deg, degrees=True)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # gimbal lock: any equal angle set will do
            euler = (turn * own).as_euler("xyz", degrees=True)
        at = turn.apply(np.asarray(tf.translation_m, dtype=np.float64) - c) + c
        out.append(p.model_copy(update={"transform": tf.model_copy(update={"translation_m": _f3(at),
                                                                           "rotation_deg": _f3(euler)})}))
    return out


def sphere_directions(n: int, seed: float = 0.0) -> np.ndarray:
    """n nearly even unit directions (a Fibonacci sphere, turned by `seed` radians about z) (n, 3)."""
    k = np.arange(n) + 0.5
    z = 1.0 - 2.0 * k / n
    phi = np.pi * (3.0 - np.sqrt(5.0)) * k + seed
    r = np.sqrt(np.clip(1.0 - z * z, 0.0, 1.0))
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


# surface relief a ball-like body can carry, with the words that ask for it
RELIEF_KINDS = ("spikes", "nubs", "folds", "strands", "ruffles", "crumples", "lumps")


def relief(kind: str, centre: Vec, radii: Vec, budget: int = 48) -> list[Part]:
    """Raised detail over the ellipsoid (centre, radii) [m] that bounds a ball-like body, at most `budget` parts,
    each at least ~8 % of the smallest radius thick so that it shows at draft meshing (64 cells across):

    spikes: soft cones along the normals (a spiky sensory or massage ball); nubs: half-buried bumps (a knobbly ball);
    folds: short ridges lying on the surface in every direction and a groove from front to back (a brain);
    strands: great circles of round strand in many planes (a wound ball of yarn or string); ruffles: radial frills
    of thin sheet around a smaller core (a mesh bath pouf); crumples: shallow creases over a flattened body (a
    deflated inflatable); lumps: a few broad bulges (a hand-formed lump of dough or clay)."""
    c = np.asarray(centre, dtype=np.float64)
    r = np.asarray(radii, dtype=np.float64)
    rmin = float(r.min())

    def surface(d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        p = c + d / np.linalg.norm(d / r)  # on the ellipsoid along direction d
        n = d / r ** 2
        return p, n / np.linalg.norm(n)

    parts: list[Part] = []
    if kind == "spikes":
        for i, d in enumerate(sphere_directions(min(budget, 34))):
            p, n = surface(d)
            h = 0.42 * rmin
            parts.append(cone(f"spike {i + 1}", 0.17 * rmin, 0.035 * rmin, h, p + n * (0.5 * h - 0.12 * rmin),
                              edge=0.02 * rmin, blend=0.06 * rmin, rot=_euler_z_to(n)))
    elif kind == "nubs":
        for i, d in enumerate(sphere_directions(min(budget, 42))):
            p, _n = surface(d)
            parts.append(ellipsoid(f"nub {i + 1}", (0.13 * rmin,) * 3, p, blend=0.04 * rmin))
    elif kind == "folds":  # winding ridges packed over the surface (loops half sunk in it) and a midline groove
        dirs = sphere_directions(min(budget - 1, 46), seed=0.7)
        for i, d in enumerate(dirs):
            p, n = surface(d)
            spin = np.array([np.cos(2.4 * i), np.sin(2.4 * i), 0.5 * np.cos(1.3 * i)])
            x_axis = np.cross(n, spin)
            x_axis = x_axis / max(float(np.linalg.norm(x_axis)), 1e-9)
            rot = Rotation.align_vectors([n, x_axis], [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])[0]
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)
                euler = rot.as_euler("xyz", degrees=True)
            parts.append(torus(f"fold {i + 1}", 0.16 * rmin, 0.07 * rmin, p - 0.04 * rmin * n, blend=0.02 * rmin,
                               rot=euler, scale=(2.0, 1.0, 1.0)))
        parts.append(box("fissure", (2.2 * r[0], 0.12 * rmin, 0.6 * r[2]), c + np.array([0.0, 0.0, 1.05 * r[2]]),
                         op="subtract", blend=0.02 * rmin))
    elif kind == "strands":
        for i, d in enumerate(sphere_directions(min(budget, 16), seed=0.3)):
            rot = _euler_z_to(d)
            parts.append(torus(f"strand {i + 1}", float(r.mean()) * 0.99, 0.085 * rmin, c, blend=0.015 * rmin,
                               rot=rot, scale=tuple(float(x) for x in r / r.mean())))
    elif kind == "ruffles":
        for i, d in enumerate(sphere_directions(min(budget, 26), seed=1.1)):
            p, n = surface(d)
            t = np.cross(n, np.array([np.cos(1.7 * i), np.sin(1.7 * i), 0.3]))
            t = t / max(float(np.linalg.norm(t)), 1e-9)  # the frill's thin axis: tangent, so the sheet stands radially
            rot = Rotation.align_vectors([t, n], [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])[0]
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)
                euler = rot.as_euler("xyz", degrees=True)
            parts.append(ellipsoid(f"ruffle {i + 1}", (0.42 * rmin, 0.5 * rmin, 0.085 * rmin), p - 0.2 * rmin * n,
                                   blend=0.03 * rmin, rot=euler))
    elif kind == "crumples":  # broad low ridges of skin lying over the top in every direction
        rmax = float(r.max())
        for i in range(min(budget, 11)):
            a, rho = 2.4 * i, 0.7 * rmax * np.sqrt((i + 0.5) / 11)
            at = c + np.array([rho * np.cos(a) * r[0] / rmax, rho * np.sin(a) * r[1] / rmax, 0.55 * r[2]])
            parts.append(ellipsoid(f"crease {i + 1}", (0.32 * rmax, 0.1 * rmax, 1.0 * rmin), at, blend=0.5 * rmin,
                                   rot=(0.0, 0.0, float(np.degrees(1.7 * i)))))
    elif kind == "lumps":  # a hand-formed lump: a few broad bulges, none alike
        for i, d in enumerate(sphere_directions(7, seed=0.9)[:min(budget, 7)]):
            p, n = surface(d * np.array([1.0, 1.0, 0.6]))
            s = (0.55 + 0.12 * np.sin(3.1 * i)) * rmin
            parts.append(ellipsoid(f"lump {i + 1}", (1.2 * s, s, 0.8 * s), p - 0.35 * s * n, blend=0.3 * rmin,
                                   rot=(0.0, 0.0, float(np.degrees(2.3 * i)))))
    else:
        raise ValueError(f"unknown relief '{kind}' (known: {', '.join(RELIEF_KINDS)})")
    return parts


def squashed_parts(parts: Sequence[Part], factors: Vec) -> list[Part]:
    """Parts scaled per world axis about the origin by `factors` (a deflated ball is the ball squashed flat and
    spread): each part keeps its primitive and takes a local scale and rotation whose axes are the scaled images of
    its own (exact for parts turned by multiples of 90 degrees; the nearest rotation otherwise)."""
    f = np.diag(np.asarray(factors, dtype=np.float64))
    out = []
    for p in parts:
        tf = p.transform
        m = f @ Rotation.from_euler("xyz", tf.rotation_deg, degrees=True).as_matrix() @ np.diag(tf.scale)
        u, _s, vt = np.linalg.svd(m)
        rot = u @ vt
        if np.linalg.det(rot) < 0:
            u[:, -1] *= -1
            rot = u @ vt
        scale = np.clip(np.diag(rot.T @ m), 1e-3, None)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            euler = Rotation.from_matrix(rot).as_euler("xyz", degrees=True)
        at = f @ np.asarray(tf.translation_m, dtype=np.float64)
        blend = p.blend_m * float(np.asarray(factors, dtype=np.float64).min())
        out.append(p.model_copy(update={"blend_m": blend, "transform": tf.model_copy(update={
            "translation_m": _f3(at), "rotation_deg": _f3(euler), "scale": _f3(scale)})}))
    return out


def swept(names: Sequence[str], points: Vec, radii: Vec, blend: float = 0.0) -> list[Part]:
    """A smooth tube along a polyline (points (n, 3) [m], radius per point): a sharp-edged frustum per segment and a
    ball at every bend and at both ends (a sphere-swept cone chain: no rims, no bulges at the joints; round ends):
    a banana, a snake, a pretzel's rope. names[i] names segment i ('name') and the ball at its start ('name joint');
    a name used again gets a number ('arm 2')."""
    pts = np.asarray(points, dtype=np.float64)
    rad = np.asarray(radii, dtype=np.float64)
    parts: list[Part] = []
    n = len(pts) - 1
    for i in range(n + 1):
        name = names[min(i, n - 1, len(names) - 1)]
        if i in (0, n) or _bend(pts, i) > 1e-3:  # a straight joint needs no ball: the frustums share its rim
            parts.append(ellipsoid(f"{name} joint", (float(rad[i]),) * 3, pts[i], blend=blend))
        if i == n:
            break
        a, b = pts[i], pts[i + 1]
        ra, rb = float(rad[i]), float(rad[i + 1])
        length = float(np.linalg.norm(b - a))
        if length < 1e-9:
            continue
        u, slope = (b - a) / length, (rb - ra) / length
        if i > 0:  # reach a little into the neighbour: two caps meeting on one plane leave a crack in the field
            e = 0.25 * ra
            a, ra = a - u * e, ra - slope * e
        if i < n - 1:
            e = 0.25 * rb
            b, rb = b + u * e, rb + slope * e
        length = float(np.linalg.norm(b - a))
        parts.append(Part(name=name, primitive={"kind": "cone", "radius_bottom_m": max(ra, 1e-4),
                                                "radius_top_m": max(rb, 1e-4), "height_m": length,
                                                "edge_radius_m": 0.0},
                          transform={"translation_m": _f3((a + b) / 2.0), "rotation_deg": _euler_z_to(b - a)},
                          blend_m=blend, color_rgb=DEFAULT_GREY))
    return _unique_names(parts)


def _unique_names(parts: list[Part]) -> list[Part]:
    """Every part named once: a repeated name's later parts become 'name 2', 'name 3', ... (the first keeps it)."""
    seen: dict[str, int] = {}
    out = []
    for q in parts:
        seen[q.name] = seen.get(q.name, 0) + 1
        out.append(q if seen[q.name] == 1 else q.model_copy(update={"name": f"{q.name} {seen[q.name]}"}))
    return out


def _bend(pts: np.ndarray, i: int) -> float:
    """1 - cos of the turn of the polyline at interior point i."""
    a, b = pts[i] - pts[i - 1], pts[i + 1] - pts[i]
    return 1.0 - float(a @ b) / max(float(np.linalg.norm(a) * np.linalg.norm(b)), 1e-12)


def smooth_path(control: Vec, n: int, closed: bool = False) -> np.ndarray:
    """n points (n, 3) evenly spaced by arc length along a Catmull-Rom spline through the control points (m, 3)."""
    c = np.asarray(control, dtype=np.float64)
    if closed:
        c = np.vstack([c[-1:], c, c[:2]])
    else:
        c = np.vstack([2 * c[0] - c[1], c, 2 * c[-1] - c[-2]])
    dense = []
    for i in range(1, len(c) - 2):
        p0, p1, p2, p3 = c[i - 1], c[i], c[i + 1], c[i + 2]
        for t in np.linspace(0.0, 1.0, 24, endpoint=False):
            t2, t3 = t * t, t * t * t
            dense.append(0.5 * (2 * p1 + (p2 - p0) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t2
                                + (3 * p1 - p0 - 3 * p2 + p3) * t3))
    dense.append(c[-2])
    dense_arr = np.asarray(dense)
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(dense_arr, axis=0), axis=1))])
    target = np.linspace(0.0, s[-1], n)
    return np.stack([np.interp(target, s, dense_arr[:, k]) for k in range(3)], axis=1)
