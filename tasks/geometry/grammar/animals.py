"""Animal body plans: quadruped, seated and standing bipeds, bird, fish, cetacean, pinniped, cephalopod, turtle,
insect, segmented worm and snake. Each returns unpainted parts in a unit frame (x front, y left, z up, body length
about 1); the registry scales them to the object's size."""

from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import Field

from contracts.base import Model
from contracts.shape import Part
from tasks.geometry.grammar.parts import (
    _euler_z_to,
    cone,
    cylinder,
    ellipsoid,
    limb,
    mirrored,
    rotated_parts,
    sphere_directions,
    superellipsoid,
    tapered,
    torus,
)

Ears = Literal["none", "round", "pointed", "floppy", "long", "lop", "big", "small", "gills"]
Snout = Literal["none", "short", "long", "trunk", "beak", "flat", "duckbill"]
Tail = Literal["none", "short", "long", "curly", "bushy", "thick", "pom", "tuft", "plume"]


def _ears(kind: str, head: np.ndarray, r: float, size: float = 1.0) -> list[Part]:
    """A pair of ears on a head of radius r centred at `head`."""
    hx, hz = float(head[0]), float(head[2])
    s = size * r
    if kind == "none":
        return []
    if kind == "round":
        return mirrored(ellipsoid, "ear", (0.25 * s, 0.38 * s, 0.38 * s), (hx - 0.1 * r, 0.62 * r, hz + 0.78 * r),
                        blend=0.1 * r)
    if kind == "small":
        return mirrored(ellipsoid, "ear", (0.15 * s, 0.22 * s, 0.22 * s), (hx - 0.1 * r, 0.6 * r, hz + 0.8 * r),
                        blend=0.06 * r)
    if kind == "pointed":
        return mirrored(cone, "ear", 0.33 * s, 0.04 * s, 0.6 * s, (hx - 0.05 * r, 0.55 * r, hz + 0.85 * r),
                        edge=0.05 * s, blend=0.08 * r, rot=(-15, 0, 0))
    if kind == "floppy":
        return mirrored(ellipsoid, "ear", (0.35 * s, 0.14 * s, 0.65 * s), (hx - 0.15 * r, 0.95 * r, hz + 0.05 * r),
                        blend=0.1 * r, rot=(20, 0, 0))
    if kind == "long":
        return mirrored(ellipsoid, "ear", (0.22 * s, 0.3 * s, 1.1 * s), (hx - 0.15 * r, 0.42 * r, hz + 1.75 * r),
                        blend=0.1 * r, rot=(-10, 0, 0))
    if kind == "lop":  # long ears hanging down the sides of the head, tips flared out (a lop rabbit, 'floppy ears')
        return mirrored(ellipsoid, "ear", (0.3 * s, 0.13 * s, 0.95 * s),
                        (hx - 0.1 * r, 1.0 * r + 0.12 * s, hz + 0.55 * r - 0.8 * s), blend=0.1 * r, rot=(12, 0, 0))
    if kind == "gills":  # an axolotl's three feathery gill stalks a side, fanned up and back from behind the cheeks
        out: list[Part] = []
        for side, sy in (("left", 1.0), ("right", -1.0)):
            root = np.array([hx - 0.35 * r, sy * 0.7 * r, hz + 0.1 * r])
            for k, a in enumerate((20.0, 55.0, 90.0)):
                d = np.array([-0.35, sy * np.cos(np.radians(a)), np.sin(np.radians(a))])
                d = d / np.linalg.norm(d)
                out.append(tapered(f"{side} ear" + (f" {k + 1}" if k else ""), root, root + d * 0.95 * s, 0.17 * s,
                                   0.1 * s, blend=0.06 * r))
        return out
    # big (elephant): wide flat ears on the sides of the head
    return mirrored(ellipsoid, "ear", (0.45 * s, 0.12 * s, 0.75 * s), (hx - 0.35 * r, 0.95 * r, hz + 0.1 * r),
                    blend=0.1 * r, rot=(0, 0, 15))


def _face(head: np.ndarray, r: float, snout: str, forward: np.ndarray | None = None) -> list[Part]:
    """Eyes and snout/trunk/beak on the front (+x) of a head of radius r."""
    hx, hz = float(head[0]), float(head[2])
    parts = mirrored(ellipsoid, "eye", (0.12 * r, 0.12 * r, 0.12 * r), (hx + 0.82 * r, 0.38 * r, hz + 0.28 * r))
    if snout == "short":
        parts.append(ellipsoid("snout", (0.4 * r, 0.45 * r, 0.35 * r), (hx + 0.85 * r, 0, hz - 0.2 * r), blend=0.1 * r))
        parts.append(ellipsoid("nose", (0.13 * r, 0.18 * r, 0.12 * r), (hx + 1.22 * r, 0, hz - 0.08 * r)))
    elif snout == "long":
        parts.append(ellipsoid("snout", (0.75 * r, 0.4 * r, 0.35 * r), (hx + 1.05 * r, 0, hz - 0.2 * r),
                               blend=0.15 * r))
        parts.append(ellipsoid("nose", (0.14 * r, 0.2 * r, 0.14 * r), (hx + 1.78 * r, 0, hz - 0.1 * r)))
    elif snout == "flat":
        parts.append(cylinder_snout(hx + 0.95 * r, hz - 0.15 * r, r))
    elif snout == "trunk":
        parts.append(tapered("trunk", (hx + 0.75 * r, 0, hz - 0.1 * r), (hx + 1.45 * r, 0, hz - 1.3 * r), 0.3 * r,
                             0.17 * r, blend=0.15 * r))
    elif snout == "beak":
        parts.append(tapered("beak", (hx + 0.8 * r, 0, hz - 0.05 * r), (hx + 1.55 * r, 0, hz - 0.15 * r), 0.28 * r,
                             0.03 * r, blend=0.05 * r))
    elif snout == "duckbill":
        parts.append(ellipsoid("beak", (0.6 * r, 0.4 * r, 0.14 * r), (hx + 1.1 * r, 0, hz - 0.15 * r), blend=0.05 * r))
    return parts


def cylinder_snout(x: float, z: float, r: float) -> Part:
    """A pig's flat round snout facing +x."""
    return cylinder("snout", 0.38 * r, 0.45 * r, (x, 0, z), edge=0.08 * r, blend=0.08 * r, rot=(0, 90, 0))


def _tail(kind: str, rear: np.ndarray, r: float, length: float, grounded: bool = False) -> list[Part]:
    """A tail leaving the body at `rear` (radius scale r, length in body lengths); a `grounded` thick tail ends on the
    ground (a dinosaur on its hind legs stands on its feet and its tail)."""
    x, z = float(rear[0]), float(rear[2])
    if kind == "none":
        return []
    if kind in ("short", "pom"):
        return [ellipsoid("tail", (0.5 * r, 0.5 * r, 0.5 * r), (x - 0.2 * r, 0, z + 0.2 * r), blend=0.2 * r)]
    if kind == "curly":
        return [limb("tail", (x, 0, z), (x - 0.25 * length, 0, z + 0.2 * length), 0.18 * r, blend=0.1 * r),
                ellipsoid("tail tip", (0.3 * r, 0.3 * r, 0.3 * r), (x - 0.27 * length, 0, z + 0.25 * length),
                          blend=0.1 * r)]
    if kind == "bushy":
        return [ellipsoid("tail", (0.55 * length, 0.3 * length, 0.22 * length),
                          (x - 0.35 * length, 0, z + 0.3 * length), blend=0.15 * r, rot=(0, 40, 0))]
    if kind == "tuft":  # a thin tail hanging down with a tuft of hair at its end (a lion, a cow, a donkey)
        end = (x - 0.45 * length, 0, max(z - 0.75 * length, 0.5 * r))
        return [limb("tail", (x, 0, z), end, 0.12 * r, blend=0.1 * r),
                ellipsoid("tuft", (0.32 * r, 0.32 * r, 0.55 * r), (end[0], 0, end[2]), blend=0.08 * r)]
    if kind == "plume":  # a bushy tail curled up and forward over the back (a samoyed, a shiba inu, a husky)
        return [ellipsoid("tail", (0.3 * length, 0.18 * length, 0.2 * length), (x + 0.05 * length, 0, z + 0.35 * length),
                          blend=0.1 * r, rot=(0, -60, 0)),
                ellipsoid("tail 2", (0.3 * length, 0.16 * length, 0.16 * length), (x + 0.3 * length, 0,
                                                                                   z + 0.5 * length),
                          blend=0.1 * r, rot=(0, 10, 0))]
    if kind == "thick":
        tip_z = 0.25 * r if grounded else max(z - 0.6 * length, 0.6 * r)
        return [tapered("tail", (x + 0.2 * r, 0, z), (x - length, 0, tip_z), 1.2 * r, 0.25 * r, blend=0.3 * r)]
    return [tapered("tail", (x, 0, z), (x - 0.8 * length, 0, z + 0.5 * length), 0.35 * r, 0.15 * r, blend=0.15 * r)]


class QuadrupedParams(Model):
    """A four- (or more-) legged animal standing on its legs."""

    body_width: float = Field(default=0.62, gt=0.1, le=1.5, description="body width / body length [-]")
    body_height: float = Field(default=0.58, gt=0.1, le=1.5, description="body height / body length [-]")
    leg_count: int = Field(default=4, ge=2, le=8, description="legs (pairs along the body)")
    leg_length: float = Field(default=0.25, ge=0.0, le=1.5, description="leg length below the body / body length")
    leg_radius: float = Field(default=0.115, gt=0.02, le=0.3, description="leg radius / body length")
    head_size: float = Field(default=0.42, gt=0.1, le=1.0, description="head diameter / body length")
    neck_length: float = Field(default=0.0, ge=0.0, le=2.0, description="neck length / body length")
    neck_angle_deg: float = Field(default=45.0, ge=0.0, le=90.0, description="neck elevation [deg]")
    ears: Ears = "round"
    ear_size: float = Field(default=1.0, gt=0.2, le=3.0)
    snout: Snout = "short"
    tail: Tail = "long"
    tail_length: float = Field(default=0.35, ge=0.0, le=2.0, description="tail length / body length")
    horns: int = Field(default=0, ge=0, le=2)
    head_length: float = Field(default=1.0, ge=1.0, le=2.5, description="head length / its height: above 1 a long "
                               "head sloping down to the muzzle (a horse, a donkey, a giraffe) [-]")
    hump: bool = False
    mane: bool = Field(default=False, description="a crest of hair along the top of the neck and head (horse, "
                       "unicorn, lion)")
    hind: Literal["straight", "folded"] = Field(default="straight", description="folded: long hind legs folded "
                                                 "along the body, thigh forward, shin back, a long flat foot splayed "
                                                 "out (a frog, a toad)")
    top_eyes: bool = Field(default=False, description="two bulging eyes on top of the head (a frog, a hippo)")
    spines: bool = Field(default=False, description="a coat of spines over the back, swept towards the tail (a "
                         "hedgehog, a porcupine)")
    stripes: int = Field(default=0, ge=0, le=14, description="raised bands round the body, neck and legs, coloured "
                         "'stripe' (a zebra, a tiger) [-]")
    spots: int = Field(default=0, ge=0, le=30, description="flat patches over the back and flanks, coloured 'spot' (a "
                       "cow, a leopard, a giraffe, a dalmatian) [-]")
    spot_size: float = Field(default=1.0, gt=0.2, le=3.0, description="patch size scale [-]")
    ruff: bool = Field(default=False, description="a lion's mane: a round ruff of hair lobes framing the face, "
                       "coloured 'mane'")
    hooves: bool = Field(default=False, description="a hoof at the foot of each leg, coloured 'hoof'")
    belly: bool = Field(default=False, description="a pale chest and belly patch, coloured 'belly'")
    beard: bool = Field(default=False, description="a goat's beard hanging under the chin")
    saddle: bool = Field(default=False, description="a dark patch over the back, coloured 'saddle' (a beagle, a "
                         "german shepherd)")
    pompoms: bool = Field(default=False, description="a poodle's clip: puffs round the ankles and a topknot on the "
                          "head, coloured 'pompom'")
    wings: bool = Field(default=False, description="a pair of feathered wings raised over the back (a pegasus, a "
                        "griffin)")
    horn_shape: Literal["straight", "curved", "antler"] = Field(default="straight", description="two horns: straight "
                                                                "stubs, curved back and down (a goat, a ram), or "
                                                                "branched antlers (a deer)")
    state: Literal["standing", "sitting", "lying", "curled"] = Field(
        default="standing", description="standing on its legs; sitting on its haunches, chest up; lying down, head on "
        "its front paws; curled up asleep, the body bent round into a ring, head on its tail")


SIT_TILT_DEG = 40.0  # a sitting animal's body, nose up [deg]


def quadruped(p: QuadrupedParams) -> list[Part]:
    """Body on legs, head in front (optionally on a neck), ears, face, tail."""
    if p.state == "sitting" and p.leg_length > 0:
        return _sitting_quadruped(p)
    if p.state == "curled":
        return _curled_quadruped(p)
    bw, bh = p.body_width, p.body_height
    lying = p.state == "lying"
    zb = 0.5 * bh if lying else p.leg_length + 0.42 * bh
    core = 0.82 if p.stripes else 1.0  # a striped coat's slices make the body's surface over a smaller core
    parts = [ellipsoid("body", (0.5, core * bw / 2, core * bh / 2), (0, 0, zb))]
    if lying and p.leg_length > 0:
        r = p.leg_radius
        reach = 0.55 * p.leg_length + 0.12
        parts += mirrored(limb, "front leg", (0.3, 0.55 * bw / 2, 0.3 * bh), (0.3 + reach, 0.5 * bw / 2, r), r,
                          blend=0.04)
        parts += mirrored(limb, "rear leg", (-0.3, 0.62 * bw / 2, 0.3 * bh), (-0.3 + reach, 0.8 * bw / 2, r), r,
                          blend=0.04)
        return [*parts, *_quadruped_head_and_tail(p, zb, lying=True, paws_x=0.3 + reach), *_coat(p, zb, [])]
    if p.hump:
        parts.append(ellipsoid("hump", (0.2, 0.2, 0.2), (-0.05, 0, zb + 0.4 * bh), blend=0.08))
    if p.leg_length > 0:
        pairs = p.leg_count // 2
        xs = np.linspace(0.3, -0.3, pairs) if pairs > 1 else np.array([0.0])
        names = ["front", "rear"] if pairs == 2 else [f"{i + 1}" for i in range(pairs)]
        for x, nm in zip(xs, names):
            top = (float(x), 0.55 * bw / 2, zb - 0.25 * bh)
            parts += mirrored(limb, f"{nm} leg", top, (float(x) + 0.02, 0.58 * bw / 2, p.leg_radius),
                              p.leg_radius, blend=0.04)
    else:
        parts.append(ellipsoid("legs", (0.42, 0.85 * bw / 2, 0.12), (0, 0, 0.12), blend=0.05))
    if p.hind == "folded":  # the rear pair replaced by folded jumping legs
        parts = [q for q in parts if "rear leg" not in q.name] + _folded_hind_legs(p, zb)
    head = _quadruped_head_and_tail(p, zb)
    spines = _back_spines(p, zb) if p.spines else []
    legs = [q for q in parts if q.name.endswith(" leg")] if p.leg_length > 0 and p.hind != "folded" else []
    return [*parts, *head, *(_top_eyes(head, p, zb) if p.top_eyes else []), *spines, *_coat(p, zb, legs)]


def _surface_patch(name: str, radii: np.ndarray, centre: np.ndarray, d: np.ndarray, size: float,
                   lift: float) -> Part:
    """A flat oval patch on an ellipsoid (radii about centre) in direction d, its face `lift` proud of the surface."""
    at = centre + d / np.linalg.norm(d / radii)
    n = d / radii ** 2
    n = n / np.linalg.norm(n)
    return ellipsoid(name, (size, 0.75 * size, 0.4 * size), tuple(at + n * (lift - 0.4 * size)), rot=_euler_z_to(n))


INK_COPIES = 3  # a small marking is drawn this many times over: a surface point takes the colours of the parts
# nearest it, blended over about a mesher cell and a half, so a stripe a cell wide would come out half body colour


def _inked(parts: list[Part], copies: int = INK_COPIES) -> list[Part]:
    """Parts followed by copies of themselves ('stripe 2' -> 'stripe 2 2'): the same solid, its colour weighted."""
    return [*parts, *(q.model_copy(update={"name": f"{q.name} {k + 2}"}) for k in range(copies - 1) for q in parts)]


def _banded_coat(p: QuadrupedParams, zb: float) -> list[Part]:
    """Slices of the body's outer layer from the rump to the shoulders, stripes ('stripe k') between body-coloured
    slices ('coat k'), each a flat-faced disc as wide as the body where the slice is widest: colours on a surface
    are the nearest parts', so a stripe standing only a little proud of a whole body would take its colour."""
    bw, bh = p.body_width, p.body_height
    centres = np.linspace(-0.34, 0.28, p.stripes)
    w = min(0.05, 0.62 / max(p.stripes - 1, 1) / 4)
    edges: list[tuple[float, float, str]] = []
    x0 = -0.44
    for c in centres:
        if c - w > x0 + 0.01:
            edges.append((x0, float(c) - w, "coat"))
        edges.append((float(c) - w, float(c) + w, "stripe"))
        x0 = float(c) + w
    edges.append((x0, 0.4, "coat"))
    out: list[Part] = []
    stripes: list[Part] = []
    counts = {"coat": 0, "stripe": 0}
    for a, b, kind in edges:
        counts[kind] += 1
        inner = min(abs(a), abs(b)) if a * b > 0 else 0.0
        s = float(np.sqrt(max(1.0 - (inner / 0.5) ** 2, 0.05)))
        (stripes if kind == "stripe" else out).append(superellipsoid(
            f"{kind} {counts[kind]}", (s * bh / 2 + 0.004, s * bw / 2 + 0.004, (b - a) / 2), ((a + b) / 2, 0, zb),
            ns=0.2, ew=1.0, blend=0.012, rot=(0, 90, 0)))
    return out + _inked(stripes)


def _coat(p: QuadrupedParams, zb: float, legs: list[Part]) -> list[Part]:
    """Markings and fittings on a standing or lying body: stripe bands, spot patches, a belly patch, hooves, wings."""
    bw, bh = p.body_width, p.body_height
    out: list[Part] = []
    lift = 0.022
    if p.stripes:  # the coat as slices, stripe and body colour in turn, over a core shrunk below them
        out += _banded_coat(p, zb)
        bands = [cylinder(f"{leg.name} stripe", p.leg_radius + lift, 0.07,
                          tuple(np.asarray(leg.transform.translation_m) * (1, 1, 1.05)), edge=0.01) for leg in legs]
        out += _inked(bands, 2)
    if p.spots:
        radii = np.array([0.5, bw / 2, bh / 2])
        dirs = sphere_directions(6 * p.spots, seed=0.7)
        dirs = dirs[(dirs[:, 2] > -0.35) & (np.abs(dirs[:, 0]) < 0.85)]
        dirs = dirs[np.unique(np.linspace(0, len(dirs) - 1, p.spots).round().astype(int))]  # spread over the coat
        out += _inked([_surface_patch(f"spot {i + 1}", radii, np.array([0.0, 0.0, zb]), d, 0.09 * p.spot_size,
                                      1.6 * lift) for i, d in enumerate(dirs)], 2 if p.spots > 10 else INK_COPIES)
    if p.belly:
        out.append(ellipsoid("belly", (0.36, 0.7 * bw / 2, 0.3 * bh), (0.04, 0, zb - 0.22 * bh), blend=0.0))
        out.append(ellipsoid("chest", (0.12, 0.6 * bw / 2, 0.36 * bh), (0.39, 0, zb - 0.02 * bh), blend=0.0))
    if p.saddle:
        out += _inked([ellipsoid("saddle", (0.3, 0.8 * bw / 2 + 0.01, 0.3 * bh), (-0.06, 0, zb + 0.27 * bh))], 2)
    if p.pompoms:
        for leg in legs:
            a = np.asarray(leg.transform.translation_m)
            out.append(ellipsoid(f"{leg.name.replace(' leg', '')} pompom", (1.5 * p.leg_radius,) * 3,
                                 (float(a[0]) + 0.01, float(a[1]), 0.6 * float(a[2]) + 0.5 * p.leg_radius),
                                 blend=0.02))
    if p.hooves:
        for leg in legs:
            a = np.asarray(leg.transform.translation_m)
            side = leg.name.replace(" leg", "")
            y = float(np.sign(a[1])) * 0.58 * bw / 2
            out.append(cylinder(f"{side} hoof", p.leg_radius + 0.03, 1.8 * p.leg_radius,
                                (float(a[0]) + 0.01, y, 0.9 * p.leg_radius), edge=0.25 * p.leg_radius))
    if p.wings:
        d = np.array([0.0, np.sin(np.radians(40)), np.cos(np.radians(40))])
        root = np.array([0.05, 0.3 * bw, zb + 0.38 * bh])
        out += mirrored(ellipsoid, "wing", (0.2, 0.035, 0.32), tuple(root + 0.26 * d), blend=0.03, rot=(-40, -25, 0))
        out += mirrored(ellipsoid, "wing 2", (0.13, 0.03, 0.22), tuple(root + 0.3 * d + np.array([-0.16, 0, -0.04])),
                        blend=0.02, rot=(-40, -45, 0))
    return out


SPINE_COUNT = 38


def _back_spines(p: QuadrupedParams, zb: float) -> list[Part]:
    """Soft cones over the upper body behind the head, each along the surface normal swept back towards the tail
    (the body ellipsoid's radii (0.5, bw / 2, bh / 2) about (0, 0, zb))."""
    radii = np.array([0.5, p.body_width / 2, p.body_height / 2])
    dirs = sphere_directions(4 * SPINE_COUNT, seed=0.4)
    dirs = dirs[(dirs[:, 2] > -0.1) & (dirs[:, 0] < 0.55)][:SPINE_COUNT]  # the back and flanks, not the belly or face
    out: list[Part] = []
    for i, d in enumerate(dirs):
        at = np.array([0.0, 0.0, zb]) + d / np.linalg.norm(d / radii)
        n = d / radii ** 2
        n = n / np.linalg.norm(n)
        axis = n + np.array([-0.7, 0.0, 0.0])  # swept back
        axis = axis / np.linalg.norm(axis)
        h = 0.3 * float(radii.min()) + 0.07
        out.append(cone(f"spine {i + 1}", 0.06, 0.008, h, at + axis * (0.5 * h - 0.05), blend=0.012,
                        rot=_euler_z_to(axis)))
    return out


def _folded_hind_legs(p: QuadrupedParams, zb: float) -> list[Part]:
    """A frog's hind legs folded along its sides: the thigh from the hip forward and out, the shin back along the
    flank, and a long flat webbed foot splayed out behind."""
    bw, bh = p.body_width, p.body_height
    r = max(p.leg_radius, 0.07)
    hip = (-0.3, 0.6 * bw / 2, zb - 0.1 * bh)
    knee = (0.02, bw / 2 + 1.1 * r, 1.2 * r)
    ankle = (-0.42, bw / 2 + 1.2 * r, 0.9 * r)
    parts = mirrored(limb, "thigh", hip, knee, 1.25 * r, blend=0.05)
    parts += mirrored(limb, "shin", knee, ankle, 0.95 * r, blend=0.04)
    for side, sy in (("left", 1.0), ("right", -1.0)):
        parts.append(ellipsoid(f"{side} hind foot", (0.24, 0.11, 0.45 * r), (-0.36, sy * (bw / 2 + 2.4 * r), 0.45 * r),
                               rot=(0, 0, sy * -35.0), blend=0.03))
    return parts


def _top_eyes(parts: list[Part], p: QuadrupedParams, zb: float) -> list[Part]:
    """Two bulging eyes on top of the head, each a round bump with a dark pupil looking out."""
    head = next((q for q in parts if q.name == "head"), None)
    c = np.asarray(head.transform.translation_m) if head is not None else np.array([0.55, 0.0, zb + 0.2])
    hr = p.head_size / 2
    out: list[Part] = []
    for side, sy in (("left", 1.0), ("right", -1.0)):
        at = c + np.array([0.05 * hr, sy * 0.5 * hr, 0.78 * hr])
        out.append(ellipsoid(f"{side} eye bump", (0.3 * hr, 0.3 * hr, 0.3 * hr), tuple(at), blend=0.06 * hr))
        out.append(ellipsoid(f"{side} eye", (0.15 * hr, 0.15 * hr, 0.15 * hr),
                             tuple(at + np.array([0.2 * hr, sy * 0.1 * hr, 0.08 * hr])), blend=0.0))
    return out


def _curled_quadruped(p: QuadrupedParams) -> list[Part]:
    """Curled up asleep: the body bent into a ring (lobes along an arc), the head at the front end turned in towards
    the rear, the front paws tucked by the chin and the tail wrapped round the outside across the gap to the nose."""
    bw, bh = p.body_width, p.body_height
    ring = 0.27  # arc radius of the body's midline [body lengths]
    z = 0.34 * bh
    across = 0.3 * bw
    parts: list[Part] = []
    for k, deg in enumerate(np.linspace(-130.0, 80.0, 6)):
        a = np.radians(deg)
        parts.append(ellipsoid("body" if k == 2 else f"body {k + 1}", (0.17, across, 0.34 * bh),
                               (ring * np.cos(a), ring * np.sin(a), z), blend=0.1, rot=(0, 0, float(deg) + 90)))
    hr = p.head_size / 2
    a_head = np.radians(118.0)
    # the head rests on the front paws and the tail, raised above the ring so its ears and face show
    hz = max(0.9 * hr + 0.02, z + 0.45 * hr) + (0.6 * hr if p.snout == "trunk" else 0.0)
    at = np.array([ring * np.cos(a_head), ring * np.sin(a_head), hz])
    head = [ellipsoid("head", (hr, 0.95 * hr, 0.92 * hr), (0.0, 0.0, hz), blend=0.08)]
    head += _ears(p.ears, np.array([0.0, 0.0, hz]), hr, p.ear_size)
    head += _face(np.array([0.0, 0.0, hz]), hr, p.snout)
    head = rotated_parts(head, (0.0, 0.0, 118.0 + 90.0), (0.0, 0.0, hz))  # along the ring, nose to the rear end
    parts += [h.model_copy(update={"transform": h.transform.model_copy(update={"translation_m": tuple(
        float(v) for v in np.asarray(h.transform.translation_m) + np.array([at[0], at[1], 0.0]))})}) for h in head]
    r = p.leg_radius
    for side, deg in (("left", 95.0), ("right", 112.0)):
        a = np.radians(deg)
        parts.append(ellipsoid(f"front {side} paw", (1.6 * r, r, r), ((ring + across) * np.cos(a),
                                                                      (ring + across) * np.sin(a), r), blend=0.04,
                               rot=(0, 0, deg + 90)))
    if p.tail != "none" and p.tail_length > 0:
        rad = max(0.1 * p.tail_length, 0.05) if p.tail in ("bushy", "thick") else 0.045
        out = ring + across + 0.6 * rad
        degs = np.linspace(-135.0, -135.0 - 75.0 * min(p.tail_length / 0.35, 1.3), 5)
        pts = [np.array([out * np.cos(np.radians(d)), out * np.sin(np.radians(d)), rad]) for d in degs]
        for k in range(len(pts) - 1):
            parts.append(limb(f"tail {k + 1}" if k else "tail", pts[k], pts[k + 1], rad, blend=0.03))
    return parts


def _sitting_quadruped(p: QuadrupedParams) -> list[Part]:
    """Sitting on its haunches: the body tilted nose up, straight front legs, folded hind legs, the tail on the
    ground behind."""
    bw, bh, r = p.body_width, p.body_height, p.leg_radius
    t = np.radians(SIT_TILT_DEG)
    zc = 0.5 * np.sin(t) + 0.32 * bh
    parts = [ellipsoid("body", (0.5, bw / 2, bh / 2), (0, 0, zc), rot=(0, -SIT_TILT_DEG, 0))]
    chest = np.array([0.5 * np.cos(t) * 0.6, 0.0, zc + 0.5 * np.sin(t) * 0.6 - 0.3 * bh])
    parts += mirrored(limb, "front leg", (float(chest[0]), 0.5 * bw / 2, float(chest[2])),
                      (float(chest[0]) + 0.04, 0.55 * bw / 2, r), r, blend=0.04)
    parts += mirrored(ellipsoid, "haunch", (0.28, 0.2 * bw, 0.22 * bh), (-0.22, 0.62 * bw / 2, 0.22 * bh), blend=0.05)
    parts += mirrored(ellipsoid, "hind paw", (0.16, 0.09 * bw + r, r), (-0.02, 0.7 * bw / 2, r), blend=0.04)
    top = np.array([0.5 * np.cos(t), 0.0, zc + 0.5 * np.sin(t)])
    return [*parts, *_quadruped_head_and_tail(p, float(top[2]) - 0.15 * bh, neck_base=top - (0.08, 0, 0.05),
                                              tail_root=np.array([-0.5 * np.cos(t), 0.0, 0.1 * bh]))]


def _quadruped_head_and_tail(p: QuadrupedParams, zb: float, lying: bool = False, paws_x: float = 0.0,
                             neck_base: np.ndarray | None = None, tail_root: np.ndarray | None = None) -> list[Part]:
    """Head (on its neck), ears, face, horns and tail of a quadruped whose body centre is at height zb."""
    bh = p.body_height
    parts: list[Part] = []
    hr = p.head_size / 2
    a = np.radians(p.neck_angle_deg)
    base = np.array([0.42, 0.0, zb + 0.15 * bh]) if neck_base is None else np.asarray(neck_base, dtype=float)
    if lying and p.neck_length == 0:
        head = np.array([max(0.5 + 0.45 * hr, paws_x - 0.4 * hr), 0.0, 0.95 * hr + p.leg_radius])  # on its paws
    elif p.neck_length > 0:
        tip = base + p.neck_length * np.array([np.cos(a), 0.0, np.sin(a)])
        parts.append(limb("neck", base, tip, max(0.35 * hr, 0.6 * p.leg_radius), blend=0.05))
        head = tip + np.array([0.3 * hr, 0, 0.2 * hr])
    else:
        head = np.array([base[0] + 0.08 + 0.55 * hr, 0.0, base[2] + 0.05 * bh + 0.3 * hr])
    parts += _ears(p.ears, head, hr, p.ear_size)
    if p.head_length > 1.0:  # a long muzzle sloping down from a round crown, the nose at its end
        pitch = np.radians(30.0)
        ext = (p.head_length - 1.0) * hr
        d = np.array([np.cos(pitch), 0.0, -np.sin(pitch)])
        parts.append(ellipsoid("head", (hr, 0.9 * hr, 0.92 * hr), head, blend=0.08))
        parts.append(ellipsoid("snout base", (0.55 * hr + 0.5 * ext, 0.68 * hr, 0.64 * hr),
                               head + d * (0.6 * hr + 0.5 * ext), blend=0.12 * hr, rot=(0, 30.0, 0)))
        for q in _face(head, hr, "none"):
            parts.append(q)
        for q in _face(head + d * (0.35 * hr + ext) - np.array([0, 0, 0.1 * hr]), 0.75 * hr, p.snout):
            if "eye" not in q.name:
                parts.append(q)
    else:
        parts.append(ellipsoid("head", (hr, 0.95 * hr, 0.92 * hr), head, blend=0.08))
        parts += _face(head, hr, p.snout)
    if p.horns == 1:  # one long horn from the middle of the forehead, forward and up (a unicorn, a narwhal-like toy)
        parts += [tapered("horn", (head[0] + 0.3 * hr, 0.0, head[2] + 0.7 * hr),
                          (head[0] + 0.95 * hr, 0.0, head[2] + 2.3 * hr), 0.27 * hr, 0.03 * hr, blend=0.05 * hr)]
    if p.mane:
        parts += _mane(base, head, hr, p.neck_length)
    if p.ruff:  # lobes of hair in a ring round the face, and a disc behind it
        parts.append(ellipsoid("mane", (0.45 * hr, 1.25 * hr, 1.25 * hr), (head[0] - 0.4 * hr, 0, head[2] - 0.05 * hr),
                               blend=0.05 * hr))
        for k in range(12):
            a_k = 2 * np.pi * k / 12
            parts.append(ellipsoid(f"mane {k + 1}", (0.4 * hr, 0.42 * hr, 0.42 * hr),
                                   (head[0] - 0.3 * hr, 1.3 * hr * np.cos(a_k), head[2] - 0.05 * hr + 1.3 * hr *
                                    np.sin(a_k)), blend=0.08 * hr))
    if p.pompoms:
        parts.append(ellipsoid("topknot pompom", (0.6 * hr, 0.6 * hr, 0.55 * hr), (head[0] - 0.1 * hr, 0,
                                                                                  head[2] + 0.85 * hr),
                               blend=0.1 * hr))
    if p.beard:
        parts.append(tapered("beard", (head[0] + 0.55 * hr, 0.0, head[2] - 0.75 * hr),
                             (head[0] + 0.5 * hr, 0.0, head[2] - 1.6 * hr), 0.22 * hr, 0.05 * hr, blend=0.05 * hr))
    if p.horns == 2 and p.horn_shape == "curved":  # up from the crown, back and down behind the ears
        for side, sy in (("left", 1.0), ("right", -1.0)):
            pts = [(head[0] + 0.05 * hr, 0.3 * hr, head[2] + 0.8 * hr), (head[0] - 0.35 * hr, 0.42 * hr,
                                                                         head[2] + 1.35 * hr),
                   (head[0] - 0.95 * hr, 0.55 * hr, head[2] + 1.2 * hr), (head[0] - 1.15 * hr, 0.6 * hr,
                                                                          head[2] + 0.6 * hr)]
            radii = (0.2 * hr, 0.15 * hr, 0.11 * hr)
            for k in range(3):
                a_, b_ = np.array(pts[k]), np.array(pts[k + 1])
                a_[1] *= sy
                b_[1] *= sy
                parts.append(tapered(f"{side} horn" + (f" {k + 1}" if k else ""), a_, b_, radii[k], radii[k] * 0.75,
                                     blend=0.03 * hr))
    elif p.horns == 2 and p.horn_shape == "antler":  # a beam up and back with two tines forward
        for side, sy in (("left", 1.0), ("right", -1.0)):
            base_ = np.array([head[0] - 0.1 * hr, sy * 0.4 * hr, head[2] + 0.75 * hr])
            top_ = base_ + np.array([-0.3 * hr, sy * 0.7 * hr, 1.5 * hr])
            parts.append(tapered(f"{side} antler", base_, top_, 0.12 * hr, 0.07 * hr, blend=0.03 * hr))
            for k, t in enumerate((0.4, 0.75)):
                at = base_ + t * (top_ - base_)
                parts.append(tapered(f"{side} antler {k + 2}", at, at + np.array([0.45 * hr, sy * 0.15 * hr,
                                                                                 0.45 * hr]),
                                     0.08 * hr, 0.05 * hr, blend=0.02 * hr))
    elif p.horns == 2:
        parts += mirrored(tapered, "horn", (head[0] - 0.1 * hr, 0.35 * hr, head[2] + 0.75 * hr),
                          (head[0] - 0.2 * hr, 0.5 * hr, head[2] + 1.45 * hr), 0.14 * hr, 0.04 * hr, blend=0.03)
    root = np.array([-0.47, 0.0, zb + 0.1 * bh]) if tail_root is None else tail_root
    parts += _tail(p.tail, root, 0.1, p.tail_length)
    return parts


def _mane(base: np.ndarray, head: np.ndarray, hr: float, neck_length: float) -> list[Part]:
    """A crest of hair standing along the back of the neck from the withers to between the ears: lobes offset from
    the neck line on its upper-back side."""
    start = np.asarray(base, dtype=float)
    end = np.asarray(head, dtype=float) + np.array([-0.35 * hr, 0.0, 0.55 * hr])
    along = end - start
    along = along / max(float(np.linalg.norm(along)), 1e-9)
    back = np.array([-along[2], 0.0, along[0]])  # the neck line turned 90 degrees up and back
    n = 5 if neck_length > 0 else 3
    tilt = float(np.degrees(np.arctan2(along[0], along[2])))
    parts = []
    for i, t in enumerate(np.linspace(0.0, 1.0, n)):
        at = (1 - t) * start + t * end + back * 0.62 * hr
        parts.append(ellipsoid(f"mane {i + 1}", (0.32 * hr, 0.2 * hr, 0.48 * hr), at, blend=0.06 * hr,
                               rot=(0, tilt, 0)))
    return parts


class SeatedBipedParams(Model):
    """A teddy-style sitting figure: body, big head, legs forward, arms at the sides."""

    head_size: float = Field(default=1.0, gt=0.3, le=2.0, description="head scale relative to a teddy bear's [-]")
    body_width: float = Field(default=1.0, gt=0.4, le=2.0, description="body width scale [-]")
    arm_length: float = Field(default=1.0, ge=0.0, le=2.5)
    leg_length: float = Field(default=1.0, ge=0.0, le=2.5)
    ears: Ears = "round"
    ear_size: float = Field(default=1.0, gt=0.2, le=3.0)
    snout: Snout = "short"
    tail: Tail = "none"
    belly: bool = False
    eye_patches: Literal["none", "round", "stripe"] = Field(default="none", description="dark patches round the eyes: "
                                                            "round ovals (a panda), stripes slanting back (a sloth)")
    face: bool = Field(default=False, description="a pale face disc on the front of the head (a sloth, a monkey)")
    claws: bool = Field(default=False, description="three long claws on each hand (a sloth)")
    big_nose: bool = Field(default=False, description="a big dark oval nose down the middle of the face (a koala)")


def _eye_patches(kind: str, head: np.ndarray, r: float) -> list[Part]:
    """Dark patches round the eyes of a head of radius r facing +x: 'round' ovals tilted out, or 'stripe' bands
    from the eyes back to the temples."""
    hx, hz = float(head[0]), float(head[2])
    if kind == "round":
        return mirrored(ellipsoid, "eye patch", (0.1 * r, 0.2 * r, 0.27 * r), (hx + 0.84 * r, 0.4 * r, hz + 0.22 * r),
                        rot=(-30, 0, 0))
    if kind == "stripe":
        return mirrored(ellipsoid, "eye patch", (0.1 * r, 0.34 * r, 0.14 * r), (hx + 0.86 * r, 0.4 * r, hz + 0.2 * r),
                        rot=(25, 0, 0))
    return []


def biped_seated(p: SeatedBipedParams) -> list[Part]:
    """Seated body (teddy bear proportions in metres for a 0.31 m figure)."""
    w = p.body_width
    parts = [ellipsoid("body", (0.065, 0.06 * w, 0.085), (0, 0, 0.085))]
    if p.belly:
        parts.append(ellipsoid("belly", (0.03, 0.045 * w, 0.06), (0.04, 0, 0.08), blend=0.01))
    hr = 0.058 * p.head_size
    head = np.array([0.005, 0.0, 0.155 + hr * 0.9])
    parts.append(ellipsoid("head", (hr, 1.03 * hr, 0.97 * hr), head, blend=0.015))
    parts += _ears(p.ears, head, hr, p.ear_size)
    if p.face:
        parts.append(ellipsoid("face", (0.16 * hr, 0.78 * hr, 0.7 * hr), (head[0] + 0.7 * hr, 0, head[2] + 0.02 * hr),
                               blend=0.002))
    parts += _eye_patches(p.eye_patches, head, hr)
    parts += _face(head, hr, p.snout)
    if p.big_nose:
        parts.append(ellipsoid("nose", (0.22 * hr, 0.26 * hr, 0.36 * hr), (head[0] + 0.9 * hr, 0, head[2] - 0.05 * hr),
                               blend=0.03 * hr))
    if p.leg_length > 0:
        ll = 0.05 * p.leg_length
        parts += mirrored(limb, "leg", (0.02, 0.038 * w, 0.028), (0.02 + ll + 0.02, 0.04 * w, 0.028), 0.028,
                          blend=0.01)
    if p.arm_length > 0:
        al = 0.065 * p.arm_length
        hand = (0.03, 0.06 * w + 0.4 * al, 0.13 - 0.8 * al)
        parts += mirrored(limb, "arm", (0.005, 0.05 * w, 0.13), hand, 0.022, blend=0.01)
        if p.claws:
            for k, dy in enumerate((-0.012, 0.0, 0.012)):
                parts += mirrored(tapered, f"claw {k + 1}", (hand[0] + 0.012, hand[1] + dy, hand[2] - 0.01),
                                  (hand[0] + 0.04, hand[1] + dy, hand[2] - 0.035), 0.006, 0.002, blend=0.003)
    if p.tail == "bushy":  # a big plume curving up the back to the crown, its tip curled out (a squirrel)
        for k, (x, z, r) in enumerate(((-0.07, 0.035, 0.03), (-0.09, 0.09, 0.034), (-0.095, 0.15, 0.036),
                                       (-0.085, 0.21, 0.034), (-0.11, 0.25, 0.026))):
            parts.append(ellipsoid("tail" + (f" {k + 1}" if k else ""), (r, 0.6 * r, r), (x, 0, z), blend=0.015))
    elif p.tail == "long":  # a long thin tail out behind on the ground, its tip curled up (a monkey)
        for k, (a, b) in enumerate((((-0.06, 0, 0.03), (-0.13, 0.02, 0.018)), ((-0.13, 0.02, 0.018),
                                                                               (-0.17, 0.05, 0.06)),
                                    ((-0.17, 0.05, 0.06), (-0.15, 0.06, 0.1)))):
            parts.append(limb("tail" + (f" {k + 1}" if k else ""), a, b, 0.01, blend=0.006))
    else:
        parts += _tail(p.tail, np.array([-0.062, 0.0, 0.04]), 0.03, 0.05)
    return parts


class StandingBipedParams(Model):
    """An upright figure on two legs (doll, monkey, gingerbread-like plush, dinosaur on hind legs)."""

    head_size: float = Field(default=1.0, gt=0.3, le=2.5)
    body_width: float = Field(default=1.0, gt=0.4, le=2.5)
    body_depth: float = Field(default=1.0, gt=0.3, le=2.5)
    arm_length: float = Field(default=1.0, ge=0.0, le=2.5)
    leg_length: float = Field(default=1.0, ge=0.2, le=2.5)
    ears: Ears = "none"
    ear_size: float = Field(default=1.0, gt=0.2, le=3.0)
    snout: Snout = "none"
    tail: Tail = "none"
    tail_length: float = Field(default=0.4, ge=0.0, le=2.0)


def biped_standing(p: StandingBipedParams) -> list[Part]:
    """Legs, torso, head, arms hanging at the sides (height about 1)."""
    ll = 0.3 * p.leg_length
    w, d = p.body_width, p.body_depth
    parts = [ellipsoid("body", (0.11 * d, 0.15 * w, 0.2), (0, 0, ll + 0.17))]
    parts += mirrored(limb, "leg", (0, 0.07 * w, ll + 0.05), (0.02, 0.08 * w, 0.055), 0.055, blend=0.02)
    hr = 0.13 * p.head_size
    head = np.array([0.0, 0.0, ll + 0.36 + 0.85 * hr])
    parts.append(ellipsoid("head", (hr, hr, hr), head, blend=0.03))
    parts += _ears(p.ears, head, hr, p.ear_size)
    parts += _face(head, hr, p.snout)
    if p.arm_length > 0:
        al = 0.25 * p.arm_length
        parts += mirrored(limb, "arm", (0, 0.14 * w, ll + 0.3), (0.02, 0.19 * w, ll + 0.3 - al), 0.04, blend=0.02)
    parts += _tail(p.tail, np.array([-0.1 * d, 0.0, ll + 0.1]), 0.1, p.tail_length, grounded=True)
    return parts


class BirdParams(Model):
    """A bird: body, head, beak, wings, tail, feet; upright (penguin, owl) or horizontal (duck, chick)."""

    upright: float = Field(default=0.0, ge=0.0, le=1.0, description="0 horizontal body, 1 standing upright [-]")
    body_width: float = Field(default=0.6, gt=0.2, le=1.5)
    head_size: float = Field(default=0.45, gt=0.15, le=1.2)
    neck_length: float = Field(default=0.0, ge=0.0, le=1.5)
    beak: Literal["none", "short", "long", "duckbill", "hooked", "huge"] = Field(
        default="short", description="huge: a toucan's bill, as long as the body and deep")
    wing_size: float = Field(default=1.0, ge=0.0, le=3.0)
    wings_spread: bool = Field(default=False, description="wings held out to the sides, flying (an eagle, a bat)")
    tail: Literal["none", "short", "fan", "display", "long", "sickle"] = Field(
        default="short", description="display: a big fan raised upright behind the body (a turkey, a peacock); "
        "long: long streaming tail feathers down to the ground (a parrot, a phoenix); sickle: long feathers arching "
        "up and over behind (a rooster)")
    wattle: bool = Field(default=False, description="a red wattle hanging under the beak (a chicken, a turkey)")
    crest_kind: Literal["comb", "tuft", "plume"] = Field(default="comb", description="comb: a rooster's upright "
                                                        "comb; tuft: a pointed crest swept back (a blue jay, a "
                                                        "cardinal); plume: a few feathers standing up (a quail)")
    ears: bool = Field(default=False, description="two big pointed ears (a bat)")
    breast: bool = Field(default=False, description="a coloured breast patch on the front of the body, coloured "
                         "'breast' (a robin, a kingfisher)")
    leg_length: float = Field(default=0.0, ge=0.0, le=1.5)
    crest: bool = False
    belly: bool = False
    owl_face: bool = Field(default=False, description="an owl's face: two pale facial discs round big eyes and two "
                           "ear tufts on top of the head")


def bird(p: BirdParams) -> list[Part]:
    """Body of length 1 (tilted up to vertical with `upright`), head over the front, beak forward."""
    u = p.upright
    rx, rz = 0.5 - 0.22 * u, 0.3 + 0.22 * u
    zb = p.leg_length + 0.32 + 0.25 * u if p.leg_length > 0 else rz - 0.005  # a sitting bird rests on its belly
    parts = [ellipsoid("body", (rx, p.body_width / 2, rz), (0, 0, zb))]
    if p.belly:
        parts.append(ellipsoid("belly", (0.7 * rx, 0.8 * p.body_width / 2, 0.8 * rz), (0.25 * rx, 0, zb - 0.05),
                               blend=0.02))
    hr = p.head_size / 2
    head = np.array([rx * (0.75 - 0.55 * u), 0.0, zb + rz * (0.75 + 0.35 * u) + 0.4 * hr])
    if p.neck_length > 0:
        top = head + np.array([0.25 * p.neck_length, 0, 0.8 * p.neck_length])
        parts.append(limb("neck", head - np.array([0, 0, 0.3 * hr]), top, 0.35 * hr, blend=0.05))
        head = top
    parts.append(ellipsoid("head", (hr, 0.95 * hr, hr), head, blend=0.06))
    if p.owl_face:  # facial discs facing forward, big eyes in them, ear tufts up and out
        parts += mirrored(ellipsoid, "face disc", (0.12 * hr, 0.42 * hr, 0.42 * hr),
                          (head[0] + 0.82 * hr, 0.4 * hr, head[2] + 0.1 * hr), blend=0.02)
        parts += mirrored(ellipsoid, "eye", (0.1 * hr, 0.2 * hr, 0.2 * hr),
                          (head[0] + 0.93 * hr, 0.4 * hr, head[2] + 0.12 * hr))
        parts += mirrored(tapered, "ear tuft", (head[0], 0.55 * hr, head[2] + 0.7 * hr),
                          (head[0] - 0.05 * hr, 0.8 * hr, head[2] + 1.35 * hr), 0.22 * hr, 0.04 * hr, blend=0.04)
    else:
        parts += mirrored(ellipsoid, "eye", (0.12 * hr, 0.12 * hr, 0.12 * hr),
                          (head[0] + 0.7 * hr, 0.55 * hr, head[2] + 0.25 * hr))
    bx = head[0] + 0.85 * hr
    if p.beak == "none":
        pass
    elif p.beak == "huge":
        parts.append(ellipsoid("beak", (1.35 * hr, 0.5 * hr, 0.62 * hr), (bx + 1.0 * hr, 0, head[2] - 0.1 * hr),
                               blend=0.04 * hr, rot=(0, 12, 0)))
        parts.append(ellipsoid("beak tip", (0.35 * hr, 0.36 * hr, 0.4 * hr), (bx + 2.05 * hr, 0, head[2] - 0.4 * hr),
                               blend=0.1 * hr))
    elif p.beak == "duckbill":
        parts.append(ellipsoid("beak", (0.55 * hr, 0.45 * hr, 0.16 * hr), (bx + 0.35 * hr, 0, head[2] - 0.15 * hr),
                               blend=0.03))
    else:
        length = {"short": 0.55, "long": 1.3, "hooked": 0.6}[p.beak] * hr
        tip_z = head[2] - (0.35 * hr if p.beak == "hooked" else 0.1 * hr)
        parts.append(tapered("beak", (bx, 0, head[2] - 0.05 * hr), (bx + length, 0, tip_z), 0.3 * hr, 0.03 * hr,
                             blend=0.03))
    if p.crest and p.crest_kind == "tuft":
        parts.append(tapered("crest", (head[0] - 0.1 * hr, 0, head[2] + 0.6 * hr), (head[0] - 0.9 * hr, 0,
                                                                                     head[2] + 1.5 * hr),
                             0.4 * hr, 0.06 * hr, blend=0.06 * hr))
    elif p.crest and p.crest_kind == "plume":
        parts.append(limb("crest", (head[0] + 0.1 * hr, 0, head[2] + 0.8 * hr), (head[0] + 0.45 * hr, 0,
                                                                                  head[2] + 1.6 * hr), 0.06 * hr,
                          blend=0.03 * hr))
        parts.append(ellipsoid("crest 2", (0.2 * hr, 0.1 * hr, 0.14 * hr), (head[0] + 0.5 * hr, 0, head[2] + 1.6 * hr),
                               blend=0.03 * hr))
    elif p.crest:  # a comb of three lobes standing on the crown
        for k, dx in enumerate((0.35, 0.0, -0.35)):
            parts.append(ellipsoid("crest" + (f" {k + 1}" if k else ""), (0.2 * hr, 0.1 * hr, 0.35 * hr),
                                   (head[0] + dx * hr, 0, head[2] + (1.05 - 0.1 * abs(dx)) * hr), blend=0.05 * hr))
    if p.wattle:
        parts.append(ellipsoid("wattle", (0.14 * hr, 0.1 * hr, 0.3 * hr), (bx + 0.1 * hr, 0, head[2] - 0.55 * hr),
                               blend=0.05 * hr))
    if p.ears:
        parts += mirrored(cone, "ear", 0.42 * hr, 0.05 * hr, 1.2 * hr, (head[0], 0.55 * hr, head[2] + 1.1 * hr),
                          edge=0.05 * hr, blend=0.06 * hr, rot=(-25, 0, 0))
    if p.breast:
        parts.append(ellipsoid("breast", (0.35 * rx + 0.1 * u, 0.75 * p.body_width / 2, 0.7 * rz),
                               (0.5 * rx * (1 - 0.4 * u), 0, zb - 0.05), blend=0.0))
    if p.wing_size > 0 and p.wings_spread:
        ws = p.wing_size
        parts += mirrored(ellipsoid, "wing", (0.32 * ws, 0.55 * ws, 0.075), (-0.05, p.body_width / 2 + 0.45 * ws,
                                                                            zb + 0.1), blend=0.05, rot=(-12, 0, -8))
        parts += mirrored(ellipsoid, "wing 2", (0.22 * ws, 0.3 * ws, 0.065),
                          (-0.18, p.body_width / 2 + 0.65 * ws, zb + 0.12), blend=0.03, rot=(-12, 0, 20))
    elif p.wing_size > 0:
        ws = p.wing_size
        parts += mirrored(ellipsoid, "wing", (0.6 * rx * ws, 0.08, 0.55 * rz * ws), (-0.1 * rx, p.body_width / 2, zb),
                          blend=0.04, rot=(-10, 10 - 30 * u, 0))
    if p.tail == "short":
        parts.append(ellipsoid("tail", (0.22, 0.15, 0.06), (-rx * (1.0 - 0.3 * u), 0, zb - 0.1 * u + 0.1 * (1 - u)),
                               blend=0.05, rot=(0, -20 + 60 * u, 0)))
    elif p.tail == "fan":
        parts.append(ellipsoid("tail", (0.35, 0.3, 0.06), (-rx - 0.15, 0, zb + 0.15), blend=0.05, rot=(0, -35, 0)))
    elif p.tail == "display":  # a half-disc of tail feathers standing up behind the body, banded
        parts.append(ellipsoid("tail", (0.05, 0.7, 0.55), (-0.75 * rx, 0, zb + 0.25), blend=0.05, rot=(0, -10, 0)))
        parts.append(ellipsoid("tail band", (0.05, 0.58, 0.44), (-0.75 * rx + 0.025, 0, zb + 0.22), rot=(0, -10, 0)))
    elif p.tail == "sickle":  # long arching tail feathers rising up and over behind (a rooster)
        for k, dy in enumerate((-0.08, 0.0, 0.08)):
            root = np.array([-0.8 * rx, dy, zb + 0.2 * rz])
            top = root + np.array([-0.15, 0.0, 0.4 + 0.08 * (k == 1)])
            end = top + np.array([-0.22, dy, -0.2])
            parts.append(tapered("tail" + (f" {2 * k + 1}" if k else ""), root, top, 0.08, 0.06, blend=0.04))
            parts.append(tapered(f"tail {2 * k + 2}", top, end, 0.06, 0.03, blend=0.03))
    elif p.tail == "long":  # long tail feathers streaming back and down, fanned
        for k, dy in enumerate((-0.1, 0.0, 0.1)):  # down and back to the ground, a prop behind the feet
            parts.append(tapered("tail" + (f" {k + 1}" if k else ""), (-0.7 * rx, 0, zb - 0.3 * rz),
                                 (-rx - 0.45 - 0.1 * (k == 1), dy, 0.04), 0.07, 0.035, blend=0.04))
    if p.leg_length > 0:
        parts += mirrored(limb, "leg", (0, 0.12, zb - 0.7 * rz), (0.02, 0.12, 0.05), 0.04, blend=0.02)
    if p.leg_length > 0:
        parts += mirrored(ellipsoid, "foot", (0.14, 0.09, 0.04), (0.1, 0.12, 0.04), blend=0.02)
    else:  # sitting on its belly, feet splayed forward and out: a base it stands on without tipping
        parts += mirrored(ellipsoid, "foot", (0.17, 0.1, 0.04), (0.06, 0.14, 0.04), blend=0.02, rot=(0, 0, 12))
    return parts


class FishParams(Model):
    """A fish: laterally flattened body, tail fin, dorsal and side fins."""

    body_height: float = Field(default=0.55, gt=0.1, le=1.5, description="body height / length [-]")
    body_width: float = Field(default=0.35, gt=0.05, le=1.5, description="body width / length [-]")
    tail: Literal["fan", "fork", "round"] = "fan"
    tail_size: float = Field(default=1.0, gt=0.2, le=2.5)
    dorsal: bool = True
    side_fins: bool = True
    flat: bool = Field(default=False, description="a ray or flatfish lying on its belly (wide, low)")
    fin_size: float = Field(default=1.0, gt=0.2, le=3.0, description="dorsal, belly and side fin size; big flowing "
                            "fins above 1.5 (a betta, an angelfish) [-]")
    sword: bool = Field(default=False, description="a long pointed bill forward from the snout (a swordfish)")
    barbels: bool = Field(default=False, description="long whiskers from the corners of the mouth (a catfish)")
    teeth: bool = Field(default=False, description="an open mouth with a row of pointed teeth, coloured 'tooth' "
                        "(a piranha)")
    spikes: bool = Field(default=False, description="short spikes all over the body (a pufferfish)")
    stripes: int = Field(default=0, ge=0, le=5, description="bands down the sides, coloured 'stripe' (an angelfish, "
                         "a clownfish) [-]")
    lips: bool = Field(default=False, description="a big droopy nose and mouth on the front (a blobfish)")


def fish(p: FishParams) -> list[Part]:
    """Body of length 1 along x; tail towards -x."""
    if p.flat:
        parts = [ellipsoid("body", (0.5, max(p.body_width, 0.4), 0.08), (0, 0, 0.08))]
        parts += mirrored(ellipsoid, "eye", (0.03, 0.03, 0.03), (0.3, 0.08, 0.14))
        parts.append(tapered("tail", (-0.45, 0, 0.06), (-0.95 * p.tail_size, 0, 0.06), 0.05, 0.015, blend=0.02))
        return parts
    h, w = p.body_height, p.body_width
    zc = h / 2
    parts = [ellipsoid("body", (0.5, w / 2, h / 2), (0, 0, zc))]
    t = p.tail_size
    tail_len = 0.3 * t
    parts.append(cone("tail", 0.04, 0.22 * t * (h / 0.55) ** 0.5, tail_len, (-0.5 - tail_len / 2 + 0.03, 0, zc),
                      edge=0.03, blend=0.06, rot=(0, 90, 0), scale=(1, 0.3, 1)))
    if p.tail == "fork":
        parts.append(ellipsoid("tail notch", (0.12 * t, 0.2, 0.08 * t), (-0.5 - tail_len - 0.06 * t, 0, zc)))
        parts[-1] = parts[-1].model_copy(update={"operation": "subtract", "blend_m": 0.02})
    fs = p.fin_size
    if p.dorsal:
        parts.append(ellipsoid("dorsal fin", (0.2 * fs ** 0.5, 0.05, 0.12 * fs), (-0.05 - 0.03 * (fs - 1), 0,
                                                                                  zc + 0.46 * h + 0.06 * (fs - 1)),
                               blend=0.04, rot=(0, -15 * (fs > 1.4), 0)))
        if fs > 1.4:  # a belly fin to match the dorsal one
            parts.append(ellipsoid("belly fin", (0.2 * fs ** 0.5, 0.05, 0.12 * fs), (-0.08, 0, zc - 0.46 * h
                                                                                    - 0.06 * (fs - 1)),
                                   blend=0.04, rot=(0, 15, 0)))
    if p.side_fins:
        parts += mirrored(ellipsoid, "fin", (0.12 * fs, 0.04, 0.07 * fs), (0.12, w / 2, zc - 0.15 * h), blend=0.03,
                          rot=(30, 0, 0))
    parts += mirrored(ellipsoid, "eye", (0.05, 0.035, 0.05), (0.33, 0.33 * w, zc + 0.12 * h))
    if p.stripes:
        bands = []
        for i, x in enumerate(np.linspace(0.25, -0.25, p.stripes)):
            sc = float(np.sqrt(max(1.0 - (x / 0.5) ** 2, 0.05)))
            bands.append(superellipsoid(f"stripe {i + 1}", (sc * h / 2 + 0.012, sc * w / 2 + 0.012, 0.045),
                                        (float(x), 0, zc), ns=0.2, ew=1.0, blend=0.01, rot=(0, 90, 0)))
        parts += _inked(bands, 2)
    if p.sword:
        parts.append(tapered("sword", (0.45, 0, zc + 0.05 * h), (1.05, 0, zc + 0.07 * h), 0.05, 0.008, blend=0.03))
    if p.barbels:
        for k, dz in enumerate((0.0, -0.1)):
            parts += mirrored(tapered, "whisker" + (f" {k + 1}" if k else ""), (0.46, 0.22 * w, zc - 0.1 * h + dz * h),
                              (0.62, 0.55 * w + 0.1, zc - 0.35 * h + dz * h), 0.02, 0.008, blend=0.01)
    if p.teeth:
        parts.append(ellipsoid("mouth", (0.06, 0.45 * w / 2, 0.06 * h / 0.55), (0.49, 0, zc - 0.15 * h)))
        parts[-1] = parts[-1].model_copy(update={"operation": "subtract", "blend_m": 0.01})
        for k, y in enumerate(np.linspace(-0.3 * w / 2, 0.3 * w / 2, 4)):
            parts.append(cone(f"tooth {k + 1}", 0.018, 0.002, 0.05, (0.47, float(y), zc - 0.12 * h), blend=0.004,
                              rot=(180, 0, 0)))
    if p.spikes:
        radii = np.array([0.5, w / 2, h / 2])
        dirs = sphere_directions(60, seed=0.2)
        dirs = dirs[(dirs[:, 0] < 0.75) & (dirs[:, 2] > -0.6)][:24]
        for i, d in enumerate(dirs):
            at = np.array([0.0, 0.0, zc]) + d / np.linalg.norm(d / radii)
            n = d / radii ** 2
            n = n / np.linalg.norm(n)
            parts.append(cone(f"spike {i + 1}", 0.03, 0.004, 0.09, tuple(at + n * 0.03), blend=0.01,
                              rot=_euler_z_to(n)))
    if p.lips:
        parts.append(ellipsoid("nose", (0.1, 0.09, 0.11), (0.47, 0, zc - 0.02 * h), blend=0.04))
        parts.append(ellipsoid("mouth", (0.06, 0.2 * w + 0.05, 0.04), (0.44, 0, zc - 0.3 * h), blend=0.03))
    return parts


class CetaceanParams(Model):
    """A whale, dolphin or shark: long body, flukes (horizontal) or tail fin (vertical), dorsal fin, flippers."""

    body_width: float = Field(default=0.4, gt=0.1, le=1.0)
    body_height: float = Field(default=0.38, gt=0.1, le=1.0)
    tail_vertical: bool = Field(default=False, description="a shark's vertical tail fin instead of flukes")
    dorsal_size: float = Field(default=1.0, ge=0.0, le=3.0)
    beak: bool = Field(default=False, description="a dolphin's beak")
    blunt_head: bool = Field(default=False, description="a sperm whale's square head")
    spots: int = Field(default=0, ge=0, le=30, description="pale spots over the back, coloured 'spot' (a whale "
                       "shark) [-]")
    belly: bool = Field(default=False, description="a pale underside, coloured 'belly' (an orca, a shark)")


def cetacean(p: CetaceanParams) -> list[Part]:
    """Streamlined body along x, tail towards -x."""
    w, h = p.body_width, p.body_height
    zc = h / 2
    if p.blunt_head:
        parts = [superellipsoid("body", (0.5, w / 2, h / 2), (0, 0, zc), ns=0.7, ew=0.8)]
    else:
        parts = [ellipsoid("body", (0.5, w / 2, h / 2), (0, 0, zc))]
    parts.append(tapered("tail stock", (-0.35, 0, zc), (-0.68, 0, zc + 0.02), 0.33 * min(w, h), 0.06, blend=0.06))
    if p.tail_vertical:
        parts.append(ellipsoid("tail", (0.09, 0.03, 0.22), (-0.7, 0, zc + 0.05), blend=0.03, rot=(0, -25, 0)))
    else:
        parts += mirrored(ellipsoid, "fluke", (0.08, 0.16, 0.025), (-0.72, 0.1, zc + 0.02), blend=0.03, rot=(0, 0, -30))
    if p.dorsal_size > 0:
        d = p.dorsal_size
        parts.append(tapered("dorsal fin", (-0.05, 0, zc + 0.35 * h), (-0.12, 0, zc + 0.45 * h + 0.12 * d),
                             0.07 * d, 0.015, blend=0.04))
    parts += mirrored(ellipsoid, "flipper", (0.1, 0.1, 0.025), (0.18, w / 2 + 0.03, zc - 0.3 * h), blend=0.03,
                      rot=(-25, 0, -30))
    if p.beak:
        parts.append(tapered("beak", (0.42, 0, zc - 0.05 * h), (0.62, 0, zc - 0.1 * h), 0.08, 0.04, blend=0.04))
    parts += mirrored(ellipsoid, "eye", (0.025, 0.02, 0.025), (0.33, 0.38 * w, zc + 0.05 * h))
    if p.spots:
        radii = np.array([0.5, w / 2, h / 2])
        dirs = sphere_directions(5 * p.spots, seed=0.5)
        dirs = dirs[(dirs[:, 2] > -0.1) & (np.abs(dirs[:, 0]) < 0.8)]
        dirs = dirs[np.unique(np.linspace(0, len(dirs) - 1, p.spots).round().astype(int))]
        parts += _inked([_surface_patch(f"spot {i + 1}", radii, np.array([0.0, 0.0, zc]), d, 0.045, 0.022)
                         for i, d in enumerate(dirs)], 2)
    if p.belly:
        parts.append(ellipsoid("belly", (0.42, 0.8 * w / 2, 0.3 * h), (0.02, 0, zc - 0.22 * h)))
    if p.blunt_head:  # the square brow of a sperm whale and its narrow lower jaw
        parts.append(superellipsoid("brow", (0.16, 0.9 * w / 2, 0.85 * h / 2), (0.38, 0, zc + 0.05 * h), ns=0.4,
                                    ew=0.6, blend=0.04))
        parts.append(tapered("jaw", (0.2, 0, zc - 0.38 * h), (0.45, 0, zc - 0.42 * h), 0.05, 0.03, blend=0.03))
    return parts


class PinnipedParams(Model):
    """A seal, sea lion or walrus lying on its belly: tapered body, raised head, fore and hind flippers."""

    body_width: float = Field(default=0.4, gt=0.1, le=1.0)
    head_raise: float = Field(default=0.3, ge=0.0, le=1.0, description="how far the head is raised [-]")
    tusks: bool = False
    whiskers: bool = False


def pinniped(p: PinnipedParams) -> list[Part]:
    """Body along x lying on the ground, head at +x."""
    w = p.body_width
    parts = [ellipsoid("body", (0.35, w / 2, 0.17), (0.05, 0, 0.17)),
             tapered("rear body", (-0.1, 0, 0.165), (-0.42, 0, 0.08), 0.16, 0.06, blend=0.08)]
    head = np.array([0.42, 0.0, 0.2 + 0.25 * p.head_raise])
    parts.append(ellipsoid("head", (0.12, 0.11, 0.11), head, blend=0.06))
    parts.append(ellipsoid("muzzle", (0.07, 0.075, 0.055), head + np.array([0.1, 0, -0.03]), blend=0.03))
    parts.append(ellipsoid("nose", (0.02, 0.03, 0.02), head + np.array([0.17, 0, -0.0])))
    parts += mirrored(ellipsoid, "eye", (0.018, 0.018, 0.018), (head[0] + 0.08, 0.05, head[2] + 0.04))
    parts += mirrored(ellipsoid, "front flipper", (0.11, 0.05, 0.02), (0.15, w / 2 + 0.02, 0.022), blend=0.03,
                      rot=(0, 0, 35))
    parts += mirrored(ellipsoid, "rear flipper", (0.1, 0.06, 0.02), (-0.5, 0.05, 0.03), blend=0.02, rot=(0, 8, -25))
    if p.tusks:  # two long tusks down from big whiskered muzzle pads
        parts += mirrored(ellipsoid, "muzzle pad", (0.06, 0.055, 0.05), head + np.array([0.13, 0.045, -0.05]),
                          blend=0.02)
        parts += mirrored(tapered, "tusk", head + np.array([0.15, 0.04, -0.08]), head + np.array([0.21, 0.05, -0.2]),
                          0.024, 0.01, blend=0.006)
    return parts


class CephalopodParams(Model):
    """An octopus, squid or jellyfish: a mantle/dome with arms around it."""

    arm_count: int = Field(default=8, ge=0, le=12)
    arm_length: float = Field(default=1.0, ge=0.0, le=3.0, description="arm length / mantle diameter [-]")
    mantle_height: float = Field(default=1.0, gt=0.3, le=3.0, description="mantle height / a round head's [-]")
    curl: float = Field(default=0.5, ge=0.0, le=1.0, description="how far the arm tips curl up [-]")
    hanging: bool = Field(default=False, description="a jellyfish: a domed bell with a frilled rim, thin wavy "
                          "tentacles hanging from under it down to the ground")
    limp: bool = Field(default=False, description="a real (dead, raw) octopus on a slab: the mantle a sagging sack "
                       "lying back, the arms tapering to fine tips, wavy and curled, flat on the ground (a round "
                       "head over even arms reads as a toy)")


def _jellyfish(p: CephalopodParams) -> list[Part]:
    """A bell standing on its tentacles: each a wavy chain of thin limbs from under the rim down and out."""
    r = 0.25
    L = max(2 * r * p.arm_length, 0.25)
    zb = L
    parts = [ellipsoid("head", (r, r, 0.75 * r * p.mantle_height), (0, 0, zb)),
             torus("rim", 0.92 * r, 0.09 * r, (0, 0, zb - 0.05 * r), blend=0.02)]
    parts += mirrored(ellipsoid, "eye", (0.03, 0.03, 0.03), (0.93 * r, 0.3 * r, zb + 0.15 * r))
    n = max(p.arm_count, 3)
    for i in range(n):
        a = 2 * np.pi * (i + 0.5) / n
        d = np.array([np.cos(a), np.sin(a), 0.0])
        side = np.array([-np.sin(a), np.cos(a), 0.0])
        pts = [d * 0.7 * r + np.array([0, 0, zb - 0.1 * r])]
        for k in range(1, 4):
            t = k / 3
            pts.append(d * (0.75 * r + 0.3 * r * t) + side * 0.025 * (-1) ** k + np.array([0, 0, (zb - 0.1 * r)
                                                                                             * (1 - t) + 0.025]))
        for k in range(3):
            parts.append(limb(f"arm {i + 1}" + (f" {k + 1}" if k else ""), pts[k], pts[k + 1], 0.024 - 0.003 * k,
                              blend=0.012))
    return parts


def _limp_octopus(p: CephalopodParams) -> list[Part]:
    """A real octopus laid out: a sagging mantle lying back from a low hub, arms in tapering wavy segments."""
    r = 0.25
    h = r * p.mantle_height
    parts = [ellipsoid("hub", (0.55 * r, 0.55 * r, 0.3 * r), (0, 0, 0.3 * r)),
             ellipsoid("head", (0.95 * h, 0.7 * r, 0.42 * r), (-0.95 * h, 0, 0.42 * r), blend=0.1 * r,
                       rot=(0, -6, 0))]
    parts += mirrored(ellipsoid, "eye", (0.1 * r, 0.1 * r, 0.09 * r), (0.1 * r, 0.36 * r, 0.52 * r), blend=0.03 * r)
    L = 2 * r * p.arm_length
    radii = (0.17 * r, 0.12 * r, 0.08 * r, 0.045 * r, 0.018 * r)
    for i in range(p.arm_count):
        a = 2 * np.pi * (i + 0.5) / p.arm_count + 0.12 * np.sin(3.1 * i)  # (laid out by hand, not a star)
        if np.cos(a) < -0.6:  # (the arms fan forward and to the sides, the mantle lies back between them)
            a += 0.45 * np.sign(np.sin(a) or 1.0)
        turn = (0.5 + 0.5 * p.curl) * (0.7 + 0.3 * np.cos(2.3 * i)) * (1, 1, -1, 1, -1, -1, 1, -1, 1, -1, 1, -1)[i]  # each segment bends the same way: a curling arm
        pos = np.array([0.35 * r * np.cos(a), 0.35 * r * np.sin(a), 0.0])
        for k in range(4):
            seg = L * (0.34, 0.28, 0.22, 0.16)[k]
            ang = a + turn * k * k / 3.0
            nxt = pos + seg * np.array([np.cos(ang), np.sin(ang), 0.0])
            z0, z1 = radii[k] * 0.9, radii[k + 1] * 0.9
            parts.append(tapered(f"arm {i + 1}{'' if k == 0 else f' tip {k}'}", (*pos[:2], z0), (*nxt[:2], z1),
                                 radii[k], radii[k + 1], blend=0.02 * r))
            pos = nxt
    return parts


def cephalopod(p: CephalopodParams) -> list[Part]:
    """Mantle on top of a ring of arms lying on the ground (mantle radius 0.25)."""
    if p.hanging:
        return _jellyfish(p)
    if p.limp:
        return _limp_octopus(p)
    r = 0.25
    zc = 0.12 + r * p.mantle_height * 0.8
    parts = [ellipsoid("head", (r, r, r * p.mantle_height), (0, 0, zc))]
    parts += mirrored(ellipsoid, "eye", (0.03, 0.03, 0.03), (0.92 * r, 0.3 * r, zc - 0.1 * r * p.mantle_height))
    L = 2 * r * p.arm_length
    for i in range(p.arm_count):
        a = 2 * np.pi * (i + 0.5) / p.arm_count
        d = np.array([np.cos(a), np.sin(a), 0.0])
        start = d * 0.5 * r + np.array([0, 0, 0.09])
        mid = d * (0.5 * r + 0.7 * L) + np.array([0, 0, 0.05])
        tip = d * (0.5 * r + L) + np.array([0, 0, 0.05 + 0.15 * L * p.curl])
        parts.append(limb(f"arm {i + 1}", start, mid, 0.055, blend=0.03))
        parts.append(limb(f"arm {i + 1} tip", mid, tip, 0.035, blend=0.02))
    return parts


class TurtleParams(Model):
    """A turtle or tortoise: domed shell, belly, head, four flippers or legs, short tail (the catalogue's turtle at
    the default parameters, in metres for a 0.29 m toy)."""

    shell_height: float = Field(default=1.0, gt=0.3, le=2.5, description="shell dome height scale [-]")
    head_size: float = Field(default=1.0, gt=0.3, le=2.5)
    flipper_length: float = Field(default=1.0, gt=0.3, le=2.5)


def turtle(p: TurtleParams) -> list[Part]:
    """Shell, belly, head, flippers, tail and eyes (centimetre numbers of the hand-written catalogue entry)."""
    c = 0.01
    sh, hs, fl = p.shell_height, p.head_size, p.flipper_length
    parts = [superellipsoid("shell", (11 * c, 8.5 * c, 4.5 * c * sh), (0, 0, 4.8 * c * (0.4 + 0.6 * sh)), ns=0.7,
                            ew=1.0),
             ellipsoid("belly", (10 * c, 8 * c, 2.5 * c), (0, 0, 2.6 * c), blend=1.0 * c),
             ellipsoid("head", (3.6 * c * hs, 3.0 * c * hs, 2.8 * c * hs), (12.5 * c + 3.6 * c * (hs - 1), 0, 4.6 * c),
                       blend=1.5 * c)]
    parts += mirrored(ellipsoid, "front flipper", (3.8 * c * fl, 2.0 * c, 1.0 * c), (6 * c, 8 * c, 1.6 * c),
                      blend=1.0 * c, rot=(0, 0, 35))
    parts += mirrored(ellipsoid, "rear flipper", (3.0 * c * fl, 1.8 * c, 1.0 * c), (-7 * c, 7 * c, 1.6 * c),
                      blend=1.0 * c, rot=(0, 0, -30))
    parts.append(cone("tail", 1.2 * c, 0.2 * c, 3 * c, (-11.5 * c, 0, 3 * c), edge=0.2 * c, blend=0.8 * c,
                      rot=(0, -90, 0)))
    hx = 12.5 * c + 3.6 * c * (hs - 1) + 2.7 * c * hs
    parts += mirrored(ellipsoid, "eye", (0.6 * c, 0.6 * c, 0.6 * c), (hx, 1.4 * c * hs, 5.6 * c))
    return parts


class InsectParams(Model):
    """A ladybird, bee or beetle: domed body, head, six short legs, optional wings and antennae."""

    body_width: float = Field(default=0.75, gt=0.2, le=1.5)
    body_height: float = Field(default=0.45, gt=0.1, le=1.5)
    wings: bool = False
    antennae: bool = True
    stripes: int = Field(default=0, ge=0, le=4, description="bands across the body (a bee) [-]")
    legs: int = Field(default=6, ge=0, le=10, description="legs, in pairs [-]")
    leg_length: float = Field(default=1.0, gt=0.2, le=4.0, description="leg reach scale; long arched legs above 1.5 "
                              "(a spider) [-]")
    spots: int = Field(default=0, ge=0, le=10, description="round spots on the back, coloured 'spot' (a ladybird) [-]")
    claws: bool = Field(default=False, description="two big pincer claws held out in front (a crab)")
    wing_shape: Literal["oval", "butterfly"] = Field(default="oval", description="butterfly: two big rounded wings "
                                                     "a side, spread flat out from the body")
    glow: bool = Field(default=False, description="a glowing rear end, coloured 'glow' (a firefly)")
    split: bool = Field(default=False, description="a line down the middle of the back between the wing cases, "
                        "coloured 'line' (a ladybird)")


def insect(p: InsectParams) -> list[Part]:
    """Body of length 1 along x."""
    w, h = p.body_width, p.body_height
    parts = [ellipsoid("body", (0.45, w / 2, h / 2), (-0.05, 0, h / 2 + 0.04))]
    radii = np.array([0.45, w / 2, h / 2])
    centre = np.array([-0.05, 0.0, h / 2 + 0.04])
    if p.spots:
        dirs = sphere_directions(8 * p.spots, seed=0.3)
        dirs = dirs[(dirs[:, 2] > 0.35) & (np.abs(dirs[:, 1]) > 0.15) & (dirs[:, 0] < 0.7)]
        dirs = dirs[np.unique(np.linspace(0, len(dirs) - 1, p.spots).round().astype(int))]
        for i, d in enumerate(dirs):
            parts.append(_surface_patch(f"spot {i + 1}", radii, centre, d, 0.1, 0.02))
    if p.split:
        parts.append(ellipsoid("line", (0.42, 0.02, h / 2 + 0.015), (-0.07, 0, h / 2 + 0.04)))
    if p.glow:
        parts.append(ellipsoid("glow", (0.2, 0.85 * w / 2, 0.85 * h / 2), (-0.38, 0, h / 2 + 0.02), blend=0.0))
    for i in range(p.stripes):
        x = -0.25 + 0.5 * (i + 0.5) / p.stripes
        parts.append(ellipsoid(f"stripe {i + 1}", (0.05, w / 2 + 0.01, h / 2 + 0.01), (x - 0.05, 0, h / 2 + 0.04)))
    head = np.array([0.45, 0.0, 0.22])
    parts.append(ellipsoid("head", (0.16, 0.2, 0.16), head, blend=0.04))
    parts += mirrored(ellipsoid, "eye", (0.04, 0.04, 0.04), head + np.array([0.13, 0.09, 0.05]))
    pairs = p.legs // 2
    xs = np.linspace(0.2, -0.3, pairs) if pairs > 1 else np.array([0.0] * pairs)
    L = p.leg_length
    for i, x in enumerate(xs):
        x = float(x)
        if L > 1.5:  # long legs: up from the body to a knee, then down and out to the ground
            knee = (-0.05 + (x + 0.05) * 1.6, 0.3 * w + 0.25 * L, h + 0.12 * L)  # fanned out forward and back
            foot = (-0.05 + (x + 0.05) * 2.6, 0.3 * w + 0.5 * L, 0.03)
            parts += mirrored(limb, f"leg {i + 1}", (x, 0.3 * w, h / 2 + 0.04), knee, 0.04, blend=0.02)
            parts += mirrored(limb, f"lower leg {i + 1}", knee, foot, 0.035, blend=0.015)
        else:
            parts += mirrored(limb, f"leg {i + 1}", (x, 0.3 * w, 0.08), (x + 0.05, 0.3 * w + 0.25 * L * w, 0.03),
                              0.03, blend=0.02)
    if p.claws:  # an arm forward and out, then a pincer of two fingers
        for side, sy in (("left", 1.0), ("right", -1.0)):
            elbow = np.array([0.45, sy * (0.55 * w + 0.05), 0.14])
            parts.append(limb(f"{side} arm", (0.25, sy * 0.35 * w, 0.12), elbow, 0.05, blend=0.03))
            claw = elbow + np.array([0.17, sy * 0.06, 0.04])
            parts.append(ellipsoid(f"{side} claw", (0.16, 0.09, 0.075), claw, blend=0.03, rot=(0, 0, sy * 20)))
            parts.append(tapered(f"{side} claw 2", claw + np.array([0.1, 0, 0.03]), claw + np.array([0.3, -sy * 0.04,
                                                                                                    0.09]),
                                 0.05, 0.018, blend=0.02))
            parts.append(tapered(f"{side} claw 3", claw + np.array([0.1, 0, -0.03]), claw + np.array([0.28, -sy * 0.05,
                                                                                                     -0.06]),
                                 0.045, 0.016, blend=0.02))
    if p.antennae:
        parts += mirrored(limb, "antenna", head + np.array([0.08, 0.06, 0.12]), head + np.array([0.2, 0.14, 0.3]),
                          0.018, blend=0.01)
    if p.wings and p.wing_shape == "butterfly":  # fore and hind wings each side, spread and tilted up a little
        parts += mirrored(ellipsoid, "wing", (0.38, 0.5, 0.06), (0.18, 0.52, h / 2 + 0.14), blend=0.03,
                          rot=(-15, 0, 30))
        parts += mirrored(ellipsoid, "wing 2", (0.3, 0.38, 0.055), (-0.22, 0.42, h / 2 + 0.1), blend=0.03,
                          rot=(-15, 0, -25))
        parts += _inked(mirrored(ellipsoid, "wing spot", (0.12, 0.14, 0.06), (0.3, 0.7, h / 2 + 0.2),
                                 rot=(-15, 0, 30)), 2)
    elif p.wings:
        parts += mirrored(ellipsoid, "wing", (0.25, 0.18, 0.03), (-0.1, 0.2, h + 0.06), blend=0.02, rot=(20, 0, 20))
    return parts


class SegmentedParams(Model):
    """A caterpillar, worm or centipede: a chain of round segments with a head."""

    segments: int = Field(default=6, ge=2, le=16)
    segment_size: float = Field(default=1.35, gt=0.3, le=2.0, description="segment radius scale [-]")
    taper: float = Field(default=0.3, ge=0.0, le=0.9, description="radius loss from head to tail [-]")
    wave: float = Field(default=0.3, ge=0.0, le=1.0, description="vertical wave amplitude / segment radius [-]")
    antennae: bool = True
    legs: bool = False
    shell: bool = Field(default=False, description="a snail's coiled shell standing on the back, its spiral a "
                        "raised coil coloured 'coil'")
    claws: bool = Field(default=False, description="two big pincer claws held forward (a lobster, a crayfish)")
    tail_fan: bool = Field(default=False, description="a fan of flat tail plates at the rear end (a lobster, a "
                           "shrimp)")
    curl: float = Field(default=0.0, ge=0.0, le=1.0, description="how far the rear end curls down and under (a "
                        "shrimp) [-]")


def segmented(p: SegmentedParams) -> list[Part]:
    """Segments along x (tail at -x), head at the front."""
    n = p.segments
    r0 = 0.5 / (n + 1) * 1.25 * p.segment_size
    parts: list[Part] = []
    for i in range(n):
        f = i / max(n - 1, 1)
        r = r0 * (1 - p.taper * (1 - f))
        x = -0.5 + (i + 0.5) / (n + 1)
        z = r + p.wave * r0 * 0.5 * (1 + np.sin(np.pi * i * 0.9))
        y = 0.0
        if p.curl > 0:  # lying on its side curled into a C: the segments along an arc in the ground plane
            sweep = np.radians(220.0) * p.curl
            rad = (n / (n + 1)) / sweep
            th = sweep * (n - 1 - i) / max(n - 1, 1)  # 0 at the head end
            x = -0.5 + (n - 0.5) / (n + 1) - rad * np.sin(th)
            y = rad * (1 - np.cos(th))
            z = r
        parts.append(ellipsoid(f"segment {i + 1}" if i else "body", (1.05 * r, r, r), (x, y, z), blend=0.3 * r0,
                               rot=(0, 0, -float(np.degrees(th))) if p.curl > 0 else (0, 0, 0)))
        if p.legs and p.curl > 0:
            parts.append(limb(f"leg {i + 1}", (x, y, 0.5 * r), (x + 1.3 * r * np.sin(th), y + 1.3 * r * np.cos(th),
                                                                0.15 * r0), 0.12 * r0, blend=0.05 * r0))
        elif p.legs:
            parts += mirrored(limb, f"leg {i + 1}", (x, 0.6 * r, 0.5 * r), (x, 1.1 * r, 0.12 * r0), 0.12 * r0,
                              blend=0.05 * r0)
    hr = 1.1 * r0
    head = np.array([-0.5 + (n + 0.5) / (n + 1) + 0.1 * r0, 0, hr * 1.1])
    parts.append(ellipsoid("head", (hr, hr, hr), head, blend=0.3 * r0))
    parts += mirrored(ellipsoid, "eye", (0.15 * hr, 0.15 * hr, 0.15 * hr),
                      head + np.array([0.8 * hr, 0.35 * hr, 0.3 * hr]))
    if p.antennae:
        parts += mirrored(limb, "antenna", head + np.array([0.2 * hr, 0.3 * hr, 0.8 * hr]),
                          head + np.array([0.5 * hr, 0.6 * hr, 1.8 * hr]), 0.1 * hr, blend=0.05 * hr)
    if p.shell:  # a round shell on the middle of the back, a raised spiral coil on each face
        sr = 2.1 * r0
        sc = np.array([-0.05, 0.0, 2 * r0 + 0.75 * sr])
        parts.append(ellipsoid("shell", (sr, 0.72 * sr, sr), tuple(sc), blend=0.3 * r0))
        for side, sy in (("left", 1.0), ("right", -1.0)):
            for k, (rr, t) in enumerate(((0.72, 0.09), (0.42, 0.08), (0.16, 0.07))):
                parts.append(torus(f"{side} coil" + (f" {k + 1}" if k else ""), rr * sr, t * sr,
                                   (sc[0] + 0.08 * k * sr, sy * (0.6 + 0.04 * k) * sr, sc[2] + 0.05 * k * sr),
                                   rot=(90, 0, 0)))
    if p.claws:
        for side, sy in (("left", 1.0), ("right", -1.0)):
            elbow = head + np.array([1.3 * hr, sy * 1.4 * hr, -0.3 * hr])
            parts.append(limb(f"{side} arm", head + np.array([0.0, sy * 0.6 * hr, -0.4 * hr]), elbow, 0.3 * hr,
                              blend=0.1 * hr))
            claw = elbow + np.array([1.1 * hr, sy * 0.2 * hr, 0.0])
            parts.append(ellipsoid(f"{side} claw", (1.0 * hr, 0.55 * hr, 0.4 * hr), claw, blend=0.1 * hr,
                                   rot=(0, 0, sy * 10)))
            parts.append(tapered(f"{side} claw 2", claw + np.array([0.7 * hr, 0, 0]),
                                 claw + np.array([1.6 * hr, -sy * 0.15 * hr, 0.1 * hr]), 0.3 * hr, 0.1 * hr,
                                 blend=0.05 * hr))
    if p.tail_fan:
        rear = np.asarray(parts[0].transform.translation_m)  # the rear segment
        back = 0.0 if p.curl == 0 else 180.0 - np.degrees(np.radians(220.0) * p.curl)  # its outward direction
        for k, a in enumerate((-35.0 + back, back, 35.0 + back)):
            d = np.array([-np.cos(np.radians(a)), np.sin(np.radians(a)), 0.0])
            parts.append(ellipsoid("tail fan" + (f" {k + 1}" if k else ""), (1.0 * r0, 0.5 * r0, 0.12 * r0),
                                   (float(rear[0] + 1.3 * r0 * d[0]), float(rear[1] + 1.3 * r0 * d[1]), 0.14 * r0),
                                   blend=0.15 * r0,
                                   rot=(0, 0, -a)))
    return parts


class SnakeParams(Model):
    """A snake (or eel) lying in S-curves: a chain of tapering segments."""

    thickness: float = Field(default=1.0, gt=0.3, le=3.0, description="body radius scale [-]")
    bends: float = Field(default=1.5, ge=0.0, le=3.0, description="S-curve periods along the body [-]")
    bands: bool = Field(default=False, description="every other segment a 'band' part (its own colour): a toy "
                        "snake's rings, a gummy snake's two-tone stripes")


def snake(p: SnakeParams) -> list[Part]:
    """Body along x in the ground plane, head at +x."""
    n = 10
    xs = np.linspace(-0.5, 0.45, n + 1)
    amp = 0.08 if p.bends > 0 else 0.0
    ys = amp * np.sin(2 * np.pi * p.bends * (xs + 0.5) / 0.95)
    ys = ys - ys[-1]  # the head on the x axis, so its eyes mirror about y = 0
    r0 = 0.035 * p.thickness
    parts: list[Part] = []
    for i in range(n):
        r = r0 * (0.35 + 0.65 * (i + 1) / n)
        name = "body" if i == n - 1 else ("tail" if i == 0 else f"segment {i + 1}")
        if p.bands and i % 2 == 1 and i < n - 1:
            name = f"band {i + 1}"
        parts.append(limb(name, (xs[i], ys[i], r0), (xs[i + 1], ys[i + 1], r0), r, blend=0.2 * r0))
    head = np.array([0.5, ys[-1], r0 * 1.1])
    parts.append(ellipsoid("head", (1.8 * r0, 1.3 * r0, 1.05 * r0), head, blend=0.3 * r0))
    parts += mirrored(ellipsoid, "eye", (0.25 * r0,) * 3, head + np.array([0.9 * r0, 0.7 * r0, 0.5 * r0]))
    return parts
