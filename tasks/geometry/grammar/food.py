"""Produce and baked-goods body plans: round and pear-shaped fruit, elongated fruit and vegetables, berries,
florets, mushrooms, loaves, buns, croissants, muffins and pies (unit frame, longest extent about 1)."""

from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import Field

from contracts.base import Model
from contracts.shape import Part
from tasks.geometry.grammar.parts import (
    box,
    cone,
    cylinder,
    ellipsoid,
    limb,
    smooth_path,
    sphere_directions,
    squashed_parts,
    superellipsoid,
    swept,
    tapered,
    torus,
)


def _stem_and_leaves(top: np.ndarray, r: float, stem: bool, leaves: int, stem_length: float = 1.0) -> list[Part]:
    """A stem on top of a fruit of radius r and `leaves` leaves around it."""
    parts: list[Part] = []
    if stem:
        tip = top + np.array([0.03 * r, 0, 0.25 * r * stem_length])
        parts.append(limb("stem", top - np.array([0, 0, 0.08 * r]), tip, 0.05 * r, blend=0.03 * r))
    for i in range(leaves):
        a = 2 * np.pi * i / max(leaves, 1) + 0.4
        d = np.array([np.cos(a), np.sin(a), 0.0])
        at = top + d * 0.3 * r + np.array([0, 0, 0.06 * r])
        parts.append(ellipsoid(f"leaf {i + 1}" if leaves > 1 else "leaf", (0.32 * r, 0.15 * r, 0.035 * r), at,
                               blend=0.02 * r, rot=(0, -15, float(np.degrees(a)))))
    return parts


class RoundFruitParams(Model):
    """Apple, orange, peach, tomato, plum, lemon, melon, pumpkin, onion, potato ..."""

    aspect: float = Field(default=0.95, gt=0.3, le=2.0, description="height / width [-]")
    elongation: float = Field(default=1.0, gt=0.5, le=2.5, description="length (x) / width (y) [-]")
    squareness: float = Field(default=1.0, gt=0.3, le=1.0, description="superellipsoid exponent; 1 round [-]")
    stem: bool = True
    stem_length: float = Field(default=1.0, gt=0.1, le=4.0)
    leaves: int = Field(default=0, ge=0, le=8)
    dimple: bool = Field(default=False, description="a hollow around the stem (apple)")
    ribs: int = Field(default=0, ge=0, le=12, description="lobes around the vertical axis (pumpkin, pepper)")
    tips: bool = Field(default=False, description="pointed ends along x (lemon)")
    crease: bool = Field(default=False, description="a groove down one side (peach, plum)")
    lying: bool = Field(default=False, description="stem along x (a lemon or potato lies on its side)")


def round_fruit(p: RoundFruitParams) -> list[Part]:
    """A round body of radius 0.5 (width), its stem and leaves on top."""
    r = 0.5
    rx, ry, rz = r * p.elongation, r, r * p.aspect
    if p.ribs:
        parts = [superellipsoid("body", (0.8 * rx, 0.8 * ry, rz), (0, 0, rz), ns=p.squareness, ew=p.squareness)]
        for i in range(p.ribs):
            a = 2 * np.pi * i / p.ribs
            parts.append(ellipsoid(f"rib {i + 1}", (0.45 * r, 0.3 * r, 0.95 * rz),
                                   (0.55 * rx * np.cos(a), 0.55 * ry * np.sin(a), rz), blend=0.12 * r,
                                   rot=(0, 0, float(np.degrees(a)))))
    else:
        parts = [superellipsoid("body", (rx, ry, rz), (0, 0, rz), ns=p.squareness, ew=p.squareness)]
    if p.tips:
        for s, nm in ((1, "front tip"), (-1, "rear tip")):
            parts.append(tapered(nm, (s * 0.8 * rx, 0, rz), (s * (rx + 0.16 * r), 0, rz), 0.22 * r, 0.05 * r,
                                 blend=0.08 * r))
    if p.crease:
        parts.append(ellipsoid("crease", (0.04 * r, 0.08 * r, 0.9 * rz), (rx * 0.98, 0, rz)).model_copy(
            update={"operation": "subtract", "blend_m": 0.05 * r}))
    if p.dimple:
        parts.append(ellipsoid("dimple", (0.22 * r, 0.22 * r, 0.12 * r), (0, 0, 2 * rz + 0.02 * r)).model_copy(
            update={"operation": "subtract", "blend_m": 0.1 * r}))
    top = np.array([0.0, 0.0, 2 * rz - (0.08 * r if p.dimple else 0.0)])
    parts += _stem_and_leaves(top, r, p.stem, p.leaves, p.stem_length)
    return parts


class PearParams(Model):
    """Pear, avocado, eggplant, gourd, butternut squash: a big lower bulb and a smaller upper one."""

    neck: float = Field(default=0.6, gt=0.2, le=1.0, description="upper bulb radius / lower [-]")
    height: float = Field(default=1.5, gt=0.8, le=3.5, description="total height / lower bulb diameter [-]")
    stem: bool = True
    leaves: int = Field(default=0, ge=0, le=4)
    lying: bool = Field(default=False, description="lying along x (an eggplant)")


def pear(p: PearParams) -> list[Part]:
    """Lower bulb of radius 0.5 at the bottom, upper bulb above (or towards +x when lying)."""
    r = 0.5
    r2 = r * p.neck
    top_c = 2 * r * p.height - r2
    if p.lying:
        parts = [ellipsoid("body", (r, r, r), (0, 0, r)),
                 tapered("waist", (0.3 * r, 0, r), (top_c - r, 0, r), 0.85 * r, 0.95 * r2, blend=0.3 * r),
                 ellipsoid("neck", (r2, r2, r2), (top_c - r, 0, r), blend=0.2 * r)]
        parts.append(limb("stem", (top_c - r + 0.85 * r2, 0, r), (top_c - r + r2 + 0.25 * r, 0, r), 0.08 * r,
                          blend=0.04 * r))
        if p.leaves:
            parts.append(cone("calyx", 0.35 * r, 0.08 * r, 0.2 * r, (top_c - r + 0.85 * r2, 0, r), edge=0.03 * r,
                              blend=0.05 * r, rot=(0, 90, 0)))
        return parts
    parts = [ellipsoid("body", (r, r, r), (0, 0, r)),
             tapered("waist", (0, 0, 1.3 * r), (0, 0, top_c), 0.85 * r, 0.95 * r2, blend=0.3 * r),
             ellipsoid("neck", (r2, r2, 1.1 * r2), (0, 0, top_c), blend=0.2 * r)]
    parts += _stem_and_leaves(np.array([0.0, 0.0, top_c + 1.05 * r2]), r, p.stem, p.leaves)
    return parts


class ElongatedParams(Model):
    """Banana, carrot, cucumber, zucchini, chili, corn cob, sausage, baguette: a long smooth body along x."""

    radius: float = Field(default=0.1, gt=0.02, le=0.4, description="radius / length [-]")
    taper: float = Field(default=0.0, ge=0.0, le=1.0, description="radius lost towards -x (a carrot's point) [-]")
    curvature: float = Field(default=0.0, ge=0.0, le=1.5, description="bend of the body [rad / length]")
    end_tips: float = Field(default=0.0, ge=0.0, le=1.0, description="both ends narrowed (banana, croissant) [-]")
    stem: Literal["none", "stub", "leafy"] = "none"
    stem_length: float = Field(default=0.07, gt=0.0, le=0.3, description="a stub stem's length / length [-]")
    blossom: bool = Field(default=False, description="a dark nub at the -x end (a banana's blossom end)")
    flatten: float = Field(default=1.0, gt=0.3, le=1.0, description="height / width of the cross-section [-]")
    segments: int = Field(default=14, ge=4, le=14, description="arcs the body is swept in (fewer for many of them "
                          "in one program: a hand of bananas) [-]")
    ridges: int = Field(default=0, ge=0, le=8, description="grooves along a straight body (a churro's star-piped "
                        "ridges): that many, evenly round it; 0 a smooth body [-]")
    peeled: float = Field(default=0.0, ge=0.0, le=1.0, description="share of the length peeled from the stem end "
                          "(a banana): the flesh bare there, the peel in three strips folded back from the peel line "
                          "(none when all of it is peeled) [-]")
    tied_ends: bool = Field(default=False, description="a sausage's casing twisted shut at both ends: a pinched neck "
                            "and a little knot (a clip: colour 'tie' silver) [-]")


ELONGATED_SEGMENTS = 14
PEEL_STRIPS = 3


def elongated_radius(p: ElongatedParams, t: float) -> float:
    """Body radius at t in [-0.5, 0.5] along the length: full at +x, `taper` lost towards -x, both ends narrowed
    to a tip by `end_tips` (a smooth profile: flat in the middle, falling fast near the ends)."""
    f = 1.0 - p.taper * (0.5 - t)
    f *= 1.0 - 0.9 * p.end_tips * (2 * abs(t)) ** 3
    return max(p.radius * f, 0.01)


def elongated(p: ElongatedParams) -> list[Part]:
    """A smooth tube swept along a circular arc in the x-z plane (bending up at both ends), tapering as
    `elongated_radius` says; the stem at +x, a blossom nub at -x."""
    n = min(p.segments, ELONGATED_SEGMENTS)
    s = np.linspace(-0.5, 0.5, n + 1)
    k = p.curvature
    if k > 1e-6:
        big_r = 1.0 / k
        ang = s * k
        xs, zs = big_r * np.sin(ang), big_r * (1 - np.cos(ang))
    else:
        xs, zs = s, np.zeros_like(s)
    radii = np.array([elongated_radius(p, float(t)) for t in s])
    zs = zs - zs.min()
    r0 = float(radii.max())
    pts = np.stack([xs, np.zeros_like(xs), zs + r0], axis=1)
    names = [f"segment {i + 1}" for i in range(n)]
    names[n // 2] = "body"
    bare = n - int(round(p.peeled * n))  # segments from here to the stem end are peeled
    if p.peeled > 0:
        radii[bare:] *= 0.82  # the flesh, thinner than the fruit in its peel
        names = [f"flesh {i + 1}" if i >= bare else nm for i, nm in enumerate(names)]
        if bare <= n // 2:
            names[max(bare - 1, 0)] = "body"
    parts = swept(names, pts, radii)
    k = next(i for i, q in enumerate(parts) if q.name == "body" and q.primitive.kind == "cone")  # drawn first
    parts = [parts[k]] + parts[:k] + parts[k + 1:]
    if p.flatten < 1.0:  # a flat cross-section (a pea pod): the whole sweep squashed in height
        parts = squashed_parts(parts, (1.0, 1.0, p.flatten))
    end = pts[-1]
    d = end - pts[-2]
    d /= np.linalg.norm(d)
    if 0 < bare < n:  # the peel's strips hang from the peel line back along the fruit, flaring out and down
        a0 = pts[bare]
        axis = (pts[bare] - pts[bare - 1]) / np.linalg.norm(pts[bare] - pts[bare - 1])
        side = np.cross(axis, [0.0, 0.0, 1.0])
        side /= np.linalg.norm(side)
        up = np.cross(side, axis)
        length = (n - bare) / n
        r = float(radii[bare - 1])
        for j in range(PEEL_STRIPS):
            phi = np.radians(90.0 + 120.0 * j)
            out = np.cos(phi) * up + np.sin(phi) * side
            mid = a0 - 0.15 * length * axis + 1.7 * r * out
            tip = a0 - 0.5 * length * axis + 2.4 * r * out
            mid[2], tip[2] = max(0.4 * r, mid[2]), max(0.35 * r, tip[2] - 1.5 * r)
            parts.append(limb(f"peel {j + 1}", a0 + 0.8 * r * out, mid, 0.32 * r, blend=0.2 * r))
            parts.append(limb(f"peel {j + 1} strip", mid, tip, 0.3 * r, blend=0.2 * r))
    if p.stem == "stub" and p.peeled == 0:
        parts.append(tapered("stem", end - d * 0.5 * radii[-1], end + d * p.stem_length, 0.3 * p.radius,
                             0.22 * p.radius, blend=0.15 * p.radius))
    elif p.stem == "leafy":
        for j, deg in enumerate((-25, 0, 25)):
            v = np.array([np.cos(np.radians(deg)) * 0.8, np.sin(np.radians(deg)) * 0.6, 0.4])
            parts.append(limb(f"leaf {j + 1}", end, end + v * 0.18, 0.22 * p.radius, blend=0.2 * p.radius))
    if p.ridges and p.curvature <= 1e-6:  # grooves cut along the straight body end to end: a star seen from its end
        r_groove = 0.32 * r0
        for j in range(p.ridges):
            phi = 2.0 * np.pi * (j + 0.5) / p.ridges
            centre = (0.0, 1.0 * r0 * np.cos(phi), r0 + 1.0 * r0 * np.sin(phi))
            parts.append(cylinder(f"groove {j + 1}", r_groove, 1.2, centre, blend=0.15 * r_groove, rot=(0, 90, 0),
                                  op="subtract"))
    if p.tied_ends:  # the casing twisted into a neck and a knot beyond each end
        for which, i0, i1 in (("left", 0, 1), ("right", n, n - 1)):
            out = pts[i0] - pts[i1]
            out /= np.linalg.norm(out)
            r_end = float(radii[i0])
            neck = pts[i0] + out * 0.75 * r_end
            parts.append(tapered(f"{which} tie", pts[i0] + out * 0.3 * r_end, neck + out * 0.45 * r_end, 0.4 * r_end,
                                 0.17 * r_end, blend=0.12 * r_end))
            parts.append(ellipsoid(f"{which} tie end", (0.22 * r_end,) * 3, neck + out * 0.6 * r_end,
                                   blend=0.05 * r_end))
    if p.blossom:
        back = pts[0] - pts[1]
        back /= np.linalg.norm(back)
        parts.append(ellipsoid("blossom end", (0.8 * radii[0],) * 3, pts[0] + back * 0.9 * radii[0],
                               blend=0.05 * p.radius))
    return parts


class PretzelParams(Model):
    """A pretzel knot lying flat: a thick belly arc, two arms that rise from it, cross in a twist and fall back onto
    the belly's opposite sides (three holes)."""

    rope: float = Field(default=0.075, gt=0.02, le=0.15, description="belly rope radius / width [-]")
    arms: float = Field(default=0.65, gt=0.3, le=1.0, description="arm rope radius / belly's [-]")
    salt: int = Field(default=0, ge=0, le=12, description="coarse salt grains on top [-]")


# the knot's centre line in plan (x across, y from the belly up), from one end on the belly round to the other
_PRETZEL_PATH = ((-0.2, -0.26), (-0.09, -0.1), (0.0, 0.02), (0.12, 0.17), (0.26, 0.3), (0.42, 0.3), (0.5, 0.14),
                 (0.48, -0.06), (0.36, -0.24), (0.18, -0.34), (0.0, -0.37), (-0.18, -0.34), (-0.36, -0.24),
                 (-0.48, -0.06), (-0.5, 0.14), (-0.42, 0.3), (-0.26, 0.3), (-0.12, 0.17), (0.0, 0.02),
                 (0.09, -0.1), (0.2, -0.26))


def pretzel(p: PretzelParams) -> list[Part]:
    """Width 1 along x lying flat; the arms cross at the centre, one over the other (a twist)."""
    ctrl = np.array([(x, y, 0.0) for x, y in _PRETZEL_PATH])
    ctrl[2, 2] = 0.5 * p.rope  # the twist: one arm over the other (the other stays on the ground)
    pts = smooth_path(ctrl, 19)
    s = np.linspace(0.0, 1.0, len(pts))
    belly = np.clip(1.0 - np.abs(s - 0.5) / 0.22, 0.0, 1.0)  # thickest at the bottom of the belly
    radii = p.rope * (p.arms + (1.0 - p.arms) * np.sin(0.5 * np.pi * belly))
    radii[[0, -1]] *= 0.85  # the ends pressed onto the belly
    pts[:, 2] += radii  # every part of the rope rests on the ground
    names = ["arm" if abs(t - 0.5) > 0.22 else "belly" for t in s[:-1]]
    parts = swept(names, pts, radii)
    k = next(i for i, q in enumerate(parts) if q.name == "belly")
    parts = [parts[k]] + parts[:k] + parts[k + 1:]  # the belly first (patterns draw on part 0)
    for i in range(p.salt):
        j = int(3 + (i * 7919) % (len(pts) - 6))
        a = 2.4 * i
        at = pts[j] + np.array([0.4 * radii[j] * np.cos(a), 0.4 * radii[j] * np.sin(a), 0.85 * radii[j]])
        parts.append(box(f"salt {i + 1}", (0.022, 0.018, 0.014), at, edge=0.004, rot=(0, 0, float(np.degrees(a)))))
    return parts


class BerryParams(Model):
    """Strawberry-like: a rounded cone pointing down under a green crown."""

    aspect: float = Field(default=1.15, gt=0.5, le=2.0, description="height / width [-]")
    leaves: int = Field(default=5, ge=0, le=8)


def berry(p: BerryParams) -> list[Part]:
    """Width 1 berry, tip at the bottom."""
    h = p.aspect
    parts = [ellipsoid("body", (0.5, 0.5, 0.35 * h), (0, 0, 0.62 * h)),
             cone("tip", 0.18, 0.45, 0.6 * h, (0, 0, 0.33 * h), edge=0.12, blend=0.15)]
    parts += _stem_and_leaves(np.array([0.0, 0.0, 0.95 * h]), 0.5, True, p.leaves)
    return parts


class FloretParams(Model):
    """Broccoli, cauliflower: a stalk under a cluster of florets."""

    head_width: float = Field(default=1.0, gt=0.3, le=1.5)
    stalk: float = Field(default=0.5, ge=0.1, le=1.5, description="stalk length / head width [-]")


def floret(p: FloretParams) -> list[Part]:
    """Lying on its side: stalk towards -x, head at +x."""
    w = p.head_width
    L = p.stalk
    parts = [limb("stalk", (-L, 0, 0.12), (0.05, 0, 0.18), 0.1, blend=0.05)]
    for i, (dy, dz, r) in enumerate(((0, 0.25, 0.25), (0.22, 0.15, 0.2), (-0.22, 0.15, 0.2), (0.1, 0.38, 0.18),
                                     (-0.1, 0.38, 0.18), (0, 0.05, 0.2))):
        parts.append(ellipsoid("head" if i == 0 else f"floret {i}", (0.22 * w, r * w, r * w),
                               (0.25 * w, dy * w, 0.05 + dz * w), blend=0.06))
    return parts


class MushroomParams(Model):
    """A mushroom: a cap on a stem."""

    cap_width: float = Field(default=1.0, gt=0.3, le=2.0)
    cap_height: float = Field(default=0.45, gt=0.1, le=1.5, description="cap height / width [-]")
    stem_height: float = Field(default=0.55, gt=0.1, le=2.0, description="stem height / cap width [-]")


def mushroom(p: MushroomParams) -> list[Part]:
    """Stem from the ground, cap on top (cap width 1 at the default)."""
    w = p.cap_width
    sh = p.stem_height * w
    parts = [ellipsoid("cap", (0.5 * w, 0.5 * w, p.cap_height * w), (0, 0, sh)),
             box("cap underside", (1.2 * w, 1.2 * w, 2 * p.cap_height * w), (0, 0, sh - 0.02 * w - p.cap_height * w),
                 op="subtract"),
             cylinder("stem", 0.17 * w, sh + 0.05 * w, (0, 0, (sh + 0.05 * w) / 2), edge=0.03 * w, blend=0.03 * w)]
    return parts


class LoafParams(Model):
    """A loaf of bread or a cake: a rounded block with a domed top."""

    width: float = Field(default=0.5, gt=0.1, le=1.5, description="width / length [-]")
    height: float = Field(default=0.45, gt=0.1, le=1.5, description="height / length [-]")
    dome: float = Field(default=0.35, ge=0.0, le=1.0, description="share of the height in the domed top [-]")
    roundness: float = Field(default=0.6, gt=0.1, le=1.0, description="1 an oval loaf, small a tin loaf [-]")
    scores: int = Field(default=0, ge=0, le=6, description="diagonal slashes across the top (a baker's scoring), "
                        "their floors the crumb's colour [-]")
    cut_end: bool = Field(default=False, description="the +x end sliced off: the lighter crumb on the cut face, the "
                          "crust all round the rest")


def loaf(p: LoafParams) -> list[Part]:
    """Length 1 along x."""
    base_h = p.height * (1 - p.dome)
    parts = [superellipsoid("crumb", (0.5, p.width / 2, base_h / 2), (0, 0, base_h / 2), ns=0.3 + 0.3 * p.roundness,
                            ew=0.3 + 0.7 * p.roundness)]
    if p.dome > 0:
        parts.append(ellipsoid("crust", (0.48, 0.98 * p.width / 2, p.height * p.dome + 0.02), (0, 0, base_h * 0.95),
                               blend=0.05))
    parts[0] = parts[0].model_copy(update={"name": "crust" if p.dome == 0 else ("lower crust" if p.cut_end
                                                                                  else "crumb")})
    top = base_h * 0.95 + p.height * p.dome + 0.02 if p.dome > 0 else base_h
    for i in range(p.scores):  # slashes across the top, 45 deg to the length, their floors pale
        x = (i - (p.scores - 1) / 2) * 0.62 / max(p.scores, 1)
        fall = (1 - (x / 0.48) ** 2) ** 0.5 if p.dome > 0 else 1.0
        z = base_h * 0.95 + (top - base_h * 0.95) * fall if p.dome > 0 else top
        length = 0.26 * p.width
        parts.append(ellipsoid(f"score {i + 1}", (0.035, length, 0.05), (x, 0, z + 0.01), rot=(0, 0, 40))
                     .model_copy(update={"operation": "subtract"}))
        parts.append(ellipsoid(f"score crumb {i + 1}", (0.02, 0.8 * length, 0.02), (x, 0, z - 0.035), rot=(0, 0, 40),
                               blend=0.005))
    if p.cut_end:  # sliced at x = 0.3: the crust ring round a pale crumb face
        parts.append(box("cut", (0.4, 2.0, 2.0), (0.5, 0, 0.5)).model_copy(update={"operation": "subtract"}))
        hz = top / 2
        parts.append(ellipsoid("crumb", (0.006, 0.86 * p.width / 2, 0.84 * hz), (0.3, 0, 0.96 * hz)))
    return parts


class PoultryParams(Model):
    """An oven-ready bird lying breast up (a whole raw or roast chicken, a turkey, a duck): the plump body, the two
    drumsticks folded back along it with their knuckles up at the tail end, the wings tucked at its sides."""

    width: float = Field(default=0.74, gt=0.4, le=1.0, description="body width / length [-]")
    height: float = Field(default=0.55, gt=0.3, le=0.9, description="body height / length [-]")
    legs: float = Field(default=0.42, ge=0.2, le=0.6, description="a drumstick's length / the body's length [-]")


def poultry(p: PoultryParams) -> list[Part]:
    """Length 1 along x, the neck end at +x, the legs' knuckles at -x; resting on its back, breast up."""
    w, h = p.width, p.height
    parts = [superellipsoid("body", (0.5, w / 2, h / 2), (0.0, 0.0, h / 2), ns=0.8, ew=0.75),
             ellipsoid("breast", (0.3, 0.3 * w, 0.16 * h), (0.08, 0.0, 0.86 * h), blend=0.12)]
    for side, sgn in (("left", 1.0), ("right", -1.0)):
        thigh = (-0.08, sgn * 0.36 * w, 0.55 * h)
        knuckle = (-0.08 - p.legs, sgn * 0.2 * w, 0.88 * h)
        parts.append(ellipsoid(f"{side} thigh", (0.2, 0.11, 0.13), thigh, blend=0.06, rot=(0.0, -15.0, sgn * 12.0)))
        parts.append(tapered(f"{side} drumstick", thigh, knuckle, 0.13, 0.055, blend=0.05))
        parts.append(ellipsoid(f"{side} knuckle", (0.065, 0.065, 0.06), knuckle, blend=0.02))
        parts.append(ellipsoid(f"{side} wing", (0.2, 0.06, 0.1), (0.22, sgn * 0.47 * w, 0.32 * h), blend=0.05,
                               rot=(sgn * 20.0, 0.0, -sgn * 18.0)))
    parts.append(ellipsoid("tail", (0.06, 0.07, 0.05), (-0.5, 0.0, 0.35 * h), blend=0.05))
    parts.append(ellipsoid("neck flap", (0.07, 0.13, 0.09), (0.5, 0.0, 0.45 * h), blend=0.06))
    return parts


class BunParams(Model):
    """A bun, roll, scone, dumpling, cookie, mochi: a flattened dome."""

    height: float = Field(default=0.55, gt=0.05, le=1.5, description="height / diameter [-]")
    elongation: float = Field(default=1.0, gt=0.5, le=3.0, description="length / width [-]")
    flat_bottom: float = Field(default=0.6, ge=0.0, le=1.0, description="0 an ellipsoid, 1 a flat base [-]")
    topping: bool = Field(default=False, description="a cap of a different colour (frosting, glaze, seeds)")


def bun(p: BunParams) -> list[Part]:
    """Diameter 1 (width), resting on a flattened base."""
    h = p.height
    e = 1.0 - 0.5 * p.flat_bottom
    parts = [superellipsoid("body", (0.5 * p.elongation, 0.5, h / 2), (0, 0, h / 2), ns=e, ew=1.0)]
    if p.topping:
        parts.append(ellipsoid("topping", (0.47 * p.elongation, 0.47, 0.32 * h), (0, 0, 0.72 * h), blend=0.02))
    return parts


class CroissantParams(Model):
    """A croissant or crescent: a thick middle tapering to two curled horns."""

    bend: float = Field(default=0.9, ge=0.0, le=1.5, description="how far the horns curl [-]")
    thickness: float = Field(default=0.3, gt=0.1, le=0.6, description="middle height / length [-]")
    ridges: bool = Field(default=False, description="the rolled dough's bands as distinct ridges across the "
                         "crescent (a croissant), creases between them, lighter pastry at the creases")


def croissant(p: CroissantParams) -> list[Part]:
    """Crescent in the x-y plane (horns towards -x)."""
    if p.ridges:
        return _croissant_ridged(p)
    n = 7
    parts = []
    for i in range(n):
        t = (i - (n - 1) / 2) / ((n - 1) / 2)  # -1 .. 1
        a = t * p.bend * 1.4
        x, y = 0.3 * np.cos(a) - 0.1, 0.45 * np.sin(a)
        r = p.thickness / 2 * (1 - 0.6 * t * t)
        name = "body" if i == n // 2 else f"segment {i + 1}"
        parts.append(ellipsoid(name, (r * 1.1, r * 1.25, r), (x, y, r), blend=0.08, rot=(0, 0, float(np.degrees(a)))))
    return parts


def _croissant_ridged(p: CroissantParams) -> list[Part]:
    """Bands of rolled dough round a crescent arc: each a flat ellipsoid across the arc, fattest in the middle, a
    pointed horn curling in at each end; a pale 'crease' under each join."""
    n = 7
    span = 0.45 + 0.8 * p.bend  # half the arc's angle [rad]
    big_r = 0.42
    step = 2 * span * big_r / (n - 1)
    parts: list[Part] = []
    creases: list[Part] = []

    def at(t: float) -> tuple[float, float, float, float]:
        a = t * span
        r = p.thickness / 2 * (1 - 0.7 * abs(t) ** 1.5)
        return big_r * np.cos(a) - 0.2, big_r * np.sin(a), r, float(np.degrees(a))

    for i in range(n):
        t = (i - (n - 1) / 2) / ((n - 1) / 2)  # -1 .. 1
        x, y, r, deg = at(t)
        name = "body" if i == n // 2 else f"segment {i + 1}"
        parts.append(ellipsoid(name, (1.5 * r, 0.68 * step, 0.8 * r), (x, y, 0.8 * r), blend=0.012, rot=(0, 0, deg)))
        if i < n - 1:
            x, y, rr, deg = at(t + 1 / (n - 1))
            creases.append(ellipsoid(f"crease {i + 1}", (1.3 * rr, 0.16 * step, 0.7 * rr), (x, y, 0.8 * rr),
                                     blend=0.005, rot=(0, 0, deg)))
    for side, t in (("left", -1.0), ("right", 1.0)):  # the horns: thin points curling in past the last band
        x, y, r, deg = at(t * 1.3)
        parts.append(ellipsoid(f"{side} horn", (0.5 * r, 1.2 * step, 0.45 * r), (x, y, 0.45 * r), blend=0.03,
                               rot=(0, 0, deg)))
    return parts + creases


class MuffinParams(Model):
    """A muffin or cupcake: a flared paper cup under a domed top."""

    cup_height: float = Field(default=0.5, gt=0.1, le=1.5, description="cup height / top diameter [-]")
    top_height: float = Field(default=0.35, gt=0.05, le=1.0, description="dome height / top diameter [-]")
    frosting: bool = Field(default=False, description="a piped swirl of frosting on the top (a cupcake)")


FROSTING_TIERS = ((0.42, 0.11), (0.33, 0.1), (0.23, 0.09), (0.13, 0.08))  # (ring radius, tube radius) bottom up [-]


def muffin(p: MuffinParams) -> list[Part]:
    """Top diameter 1. A frosted cupcake: its swirl piped as rings narrowing upward to a point."""
    ch = p.cup_height
    parts = [cone("cup", 0.36, 0.44, ch, (0, 0, ch / 2), edge=0.03),
             ellipsoid("top", (0.5, 0.5, p.top_height), (0, 0, ch), blend=0.04)]
    if p.frosting:
        z = ch + 0.6 * p.top_height
        for i, (ring, tube) in enumerate(FROSTING_TIERS):
            parts.append(torus(f"frosting {i + 1}", ring, tube, (0.02 * (i % 2), 0.0, z), blend=0.04))
            z += 1.45 * tube
        parts.append(cone("frosting tip", 0.1, 0.0, 0.16, (0, 0, z + 0.02), blend=0.05))
    return parts


class NigiriParams(Model):
    """Nigiri sushi: an oval mound of rice under a slice of fish draped over it and past its ends."""

    width: float = Field(default=0.5, gt=0.2, le=0.8, description="rice width / fish length [-]")
    fish: float = Field(default=0.07, gt=0.02, le=0.2, description="fish slice thickness / fish length [-]")
    stripes: int = Field(default=0, ge=0, le=8, description="white fat lines across the fish (salmon) [-]")


def nigiri(p: NigiriParams) -> list[Part]:
    """Fish length 1 along x: the rice (body) 0.8 long, the fish slice over its top a little wider, its ends dipping
    past the rice, and `stripes` fat lines slanting across the fish's top. (A two-layer block read as a pink eraser
    to blind reviewers, development set 21.)"""
    w = p.width
    rice_h = 0.38
    parts = [ellipsoid("body", (0.4, w / 2, rice_h), (0, 0, 0.0)),
             _op_ground()]
    top = rice_h
    for k, (x, tilt) in enumerate(((0.0, 0.0), (0.33, 14.0), (-0.33, -14.0))):
        z = top - (0.035 if k else 0.0) - p.fish / 2 + 0.01
        parts.append(ellipsoid("fish" if k == 0 else f"fish {k + 1}", (0.26 if k else 0.3, 0.55 * w + 0.02, p.fish / 2),
                               (x, 0.0, z), rot=(0.0, tilt, 0.0), blend=0.05))
    for i in range(p.stripes):
        x = -0.27 + 0.54 * i / max(p.stripes - 1, 1)
        parts.append(box(f"fat {i + 1}", (0.05, 0.8 * w, 0.5 * p.fish), (x, 0.0, top + 0.006 - 0.08 * abs(x)),
                         rot=(0.0, float(np.degrees(np.arctan(0.08)) * np.sign(x)), 30.0), edge=0.01, blend=0.01))
    return parts


def _op_ground() -> Part:
    """A half-space keeping z >= 0 (the rice sits flat on the plate)."""
    return box("ground", (8, 8, 8), (0, 0, 4)).model_copy(update={"operation": "intersect"})


class PieParams(Model):
    """A pie, tart or pizza: a disc with a raised rim."""

    height: float = Field(default=0.15, gt=0.02, le=0.6, description="height / diameter [-]")
    rim: float = Field(default=0.05, ge=0.0, le=0.2, description="rim tube radius / diameter [-]")
    cheese: bool = Field(default=False, description="a melted cheese layer over the sauce, short of the rim (a pizza)")
    pepperoni: int = Field(default=0, ge=0, le=16, description="pepperoni rounds standing proud of the top (a pizza)")


def pie(p: PieParams) -> list[Part]:
    """Diameter 1."""
    h = p.height
    parts = [cylinder("filling", 0.48, h, (0, 0, h / 2), edge=0.3 * h)]
    if p.rim > 0:
        parts.append(torus("crust", 0.5 - p.rim, p.rim, (0, 0, h - 0.3 * p.rim), blend=0.02))
    top = h
    if p.cheese:  # a pale layer proud of the red sauce, leaving a ring of sauce inside the crust
        c = 0.03
        parts.append(cylinder("cheese", 0.5 - 2.2 * p.rim - 0.04, c, (0, 0, h + c / 2 - 0.005), edge=0.4 * c,
                              blend=0.005))
        top = h + c - 0.005
    for i in range(p.pepperoni):  # rounds on two rings (a third of them near the middle)
        inner = p.pepperoni // 3
        k, n, r = (i, inner, 0.13) if i < inner else (i - inner, p.pepperoni - inner, 0.29)
        a = 2 * np.pi * k / max(n, 1) + (0.4 if i < inner else 0.0)
        t = 0.03
        parts.append(cylinder(f"pepperoni {i + 1}", 0.07, t, (r * np.cos(a), r * np.sin(a), top + t / 2 - 0.004),
                              edge=0.4 * t, blend=0.004))
    return parts


def _wedge_box(name: str, angle_deg: float, z0: float, thick: float, edge: float = 0.0) -> Part:
    """The bounding box of a sector of radius 1 and `angle_deg` around +x (cut to the sector by `_wedge_cut`)."""
    half = min(np.radians(angle_deg / 2), np.pi / 2)
    return box(name, (1.0, 2 * np.sin(half) + 0.02, thick), (0.5, 0, z0 + thick / 2), edge=edge)


def _wedge_cut(angle_deg: float, height: float) -> list[Part]:
    """A cylinder of radius 1 and two half-spaces (intersected) that keep a sector of `angle_deg` around +x, its
    point at the origin."""
    half = np.radians(angle_deg / 2)
    big = 4.0
    out = [cylinder("crust cut", 1.0, 2 * height + 1, (0, 0, height / 2)).model_copy(
        update={"operation": "intersect"})]
    for side, s in (("left", 1), ("right", -1)):
        phi = -s * half  # the box's inner face, rotated about z by phi, passes through the origin
        at = (-np.sin(phi) * s * big / 2, np.cos(phi) * s * big / 2, height / 2)
        out.append(box(f"{side} cut", (big, big, 2 * height + 1), at, rot=(0, 0, float(np.degrees(phi))))
                   .model_copy(update={"operation": "intersect"}))
    return out


class HoleyParams(Model):
    """Food with holes: a slice, wedge or block of Swiss cheese (Emmental), a crumpet-like holey slice."""

    shape: Literal["slice", "wedge", "block"] = "slice"
    width: float = Field(default=0.9, gt=0.2, le=1.0, description="width / length [-]")
    height: float = Field(default=0.04, gt=0.02, le=1.0, description="height / length [-]")
    holes: int = Field(default=7, ge=0, le=20)
    hole_size: float = Field(default=0.09, gt=0.02, le=0.25, description="largest hole radius / length [-]")
    angle_deg: float = Field(default=35.0, gt=10.0, le=120.0, description="a wedge's angle [deg]")


def holey(p: HoleyParams) -> list[Part]:
    """Length 1 along x. A slice's holes go through it; a wedge's or block's holes are round, some cut by its faces."""
    h = p.height
    rng = np.random.default_rng(7)  # fixed: the same cheese every time
    if p.shape == "wedge":
        parts = [_wedge_box("body", p.angle_deg, 0.0, h, edge=min(0.02, 0.3 * h))] + _wedge_cut(p.angle_deg, h)
        tan = np.tan(np.radians(p.angle_deg / 2))
        for i in range(p.holes):
            x, v = rng.uniform(0.2, 0.95), rng.choice((-1.0, 1.0, rng.uniform(-0.8, 0.8)))  # most on a face
            r = p.hole_size * (0.4 + 0.6 * rng.random()) * min(1.0, 3 * x * tan)
            zf = rng.choice((0.0, 1.0, rng.uniform(0.2, 0.8))) if abs(v) < 1 else rng.uniform(0.2, 0.8)
            parts.append(ellipsoid(f"hole {i + 1}", (r, r, r), (x, v * x * tan, zf * h))
                         .model_copy(update={"operation": "subtract"}))
        return _shift_x(parts, -0.5)
    w = p.width
    parts = [box("body", (1.0, w, h), (0, 0, h / 2), edge=min(0.02, 0.3 * h))]
    for i in range(p.holes):
        x, y = rng.uniform(-0.42, 0.42), rng.uniform(-0.42, 0.42) * w
        r = p.hole_size * (0.35 + 0.65 * rng.random())
        if p.shape == "slice":
            parts.append(cylinder(f"hole {i + 1}", r, 3 * h, (x, y, h / 2), op="subtract"))
        else:
            parts.append(ellipsoid(f"hole {i + 1}", (r, r, r), (x, y, rng.uniform(0.1, 0.9) * h)).model_copy(
                update={"operation": "subtract"}))
    return parts


class LayeredParams(Model):
    """Food in layers: sandwich, layer-cake slice, lasagna, trifle, club sandwich, mille-feuille."""

    shape: Literal["block", "wedge", "round"] = "block"
    width: float = Field(default=0.8, gt=0.2, le=1.0, description="width / length (block) [-]")
    height: float = Field(default=0.4, gt=0.05, le=1.5, description="height / length (or diameter) [-]")
    layers: int = Field(default=2, ge=2, le=8, description="main layers (bread, sponge, pasta) [-]")
    filling: float = Field(default=0.5, gt=0.05, le=2.0, description="a filling layer's thickness / a main "
                           "layer's [-]")
    topping: float = Field(default=0.0, ge=0.0, le=0.5, description="top coat (frosting, cheese) / main layer [-]")
    angle_deg: float = Field(default=40.0, gt=10.0, le=120.0, description="a wedge's angle [deg]")
    puff: float = Field(default=0.3, ge=0.0, le=1.0, description="rounding of the main layers (a bun's dome) [-]")
    ruffle: bool = Field(default=False, description="a block's main layers rippled along their long edges (lasagna "
                         "sheets' ruffled sides) [-]")
    coat: bool = Field(default=False, description="a round cake frosted all over: the topping's coat down its sides "
                       "too (a bare golden side read as a loaf of bread)")


def layered(p: LayeredParams) -> list[Part]:
    """Length 1 along x (a wedge's point at x = -0.5): main layers ('layer') and fillings ('filling') alternating
    from the bottom, a 'topping' over the top."""
    n = p.layers
    unit = p.height / (n + (n - 1) * p.filling + p.topping)
    parts: list[Part] = []
    z = 0.0
    w = p.width
    for i in range(n):
        names = ("body" if i == 0 else f"layer {i + 1}", f"filling {i + 1}")
        thick = unit
        parts.append(_layer(names[0], p, thick, z, edge=min(p.puff * thick / 2, 0.45 * thick) if p.shape == "block"
                            else 0.15 * thick, w=w))
        if p.ruffle and p.shape == "block":  # the sheet's wavy edges standing out of both long sides
            for sgn in (1.0, -1.0):
                for j in range(7):
                    parts.append(ellipsoid(f"ruffle {len(parts)}", (0.05, 0.018, 0.4 * thick),
                                           (-0.44 + 0.88 * j / 6, sgn * w / 2, z + thick / 2), blend=0.01))
        z += thick
        if i < n - 1:
            ft = unit * p.filling
            parts.append(_layer(names[1], p, ft * 1.02, z - 0.01 * ft, edge=0.3 * ft, w=w * 1.01 if
                                p.shape == "block" else w, grow=0.01))
            z += ft
    if p.topping > 0:
        tt = unit * p.topping
        parts.append(_layer("topping", p, tt, z - 0.02 * tt, edge=0.45 * tt, w=w))
    if p.coat and p.shape == "round":
        coat = 0.03 if p.topping > 0 else 0.0
        parts.append(cylinder("side topping", 0.5 + coat, z, (0, 0, z / 2), edge=0.02, blend=0.01))
        top = z + unit * p.topping
        for k, (at, n) in enumerate(((top, 20), (0.03, 20))):  # beaded piping round its top edge and its foot
            for j in range(n):
                a = 2 * np.pi * (j + 0.5 * k) / n
                rr = 0.5 + coat - 0.01
                parts.append(ellipsoid(f"{('top', 'foot')[k]} bead {j + 1} topping", (0.05, 0.05, 0.04),
                                       (rr * np.cos(a), rr * np.sin(a), at), blend=0.01))
    if p.shape == "wedge":
        return _shift_x(parts + _wedge_cut(p.angle_deg, p.height), -0.5)
    return parts


def _shift_x(parts: list[Part], dx: float) -> list[Part]:
    out = []
    for q in parts:
        t = q.transform.translation_m
        out.append(q.model_copy(update={"transform": q.transform.model_copy(update={"translation_m": (t[0] + dx, t[1],
                                                                                                     t[2])})}))
    return out


def _layer(name: str, p: LayeredParams, thick: float, z0: float, edge: float, w: float, grow: float = 0.0) -> Part:
    if p.shape == "block":
        return box(name, (1.0 + grow, w, thick), (0, 0, z0 + thick / 2), edge=edge)
    if p.shape == "wedge":
        return _wedge_box(name, p.angle_deg, z0, thick, edge=min(edge, 0.02))
    return cylinder(name, 0.5 + grow, thick, (0, 0, z0 + thick / 2), edge=edge)


class LeafyHeadParams(Model):
    """A head of leaves: lettuce, cabbage, radicchio. Leaves in rings around a heart, each ring tilted further out;
    a tight head (cabbage, iceberg) has little tilt, a loose leaf lettuce opens like a rose and its leaves are ruffled."""

    rings: int = Field(default=3, ge=1, le=4, description="rings of leaves around the heart")
    leaves: int = Field(default=6, ge=3, le=9, description="leaves per ring")
    openness: float = Field(default=0.5, ge=0.0, le=1.0, description="0 a tight ball, 1 leaves splayed out [-]")
    ruffle: bool = Field(default=False, description="frilled leaf edges (leaf lettuce, lollo rosso, savoy)")
    aspect: float = Field(default=0.85, gt=0.4, le=1.3, description="height / width of the heart [-]")


def leafy_head(p: LeafyHeadParams) -> list[Part]:
    """Width about 1: a heart (ellipsoid) and rings of cupped leaves (thin ellipsoids whose thin axis points out from
    the heart), tilted out by ring; ruffled leaves carry a second, offset frill at their top edge."""
    r = 0.24
    h = p.aspect * r
    parts = [ellipsoid("heart", (r, r, h), (0, 0, h + 0.02))]
    parts.append(cylinder("stem", 0.1, 0.06, (0, 0, 0.03), edge=0.02, blend=0.03))
    for k in range(p.rings):
        tilt = np.radians(6 + 40 * p.openness * (k + 1) / p.rings)
        rho = r * (0.55 + 0.3 * k)
        length = (0.6 + 0.15 * k) * p.aspect * 1.25
        width = 0.36 + 0.06 * k
        for i in range(p.leaves):
            a = 2 * np.pi * (i + 0.5 * k) / p.leaves
            radial = np.array([np.cos(a), np.sin(a), 0.0])
            axis = np.array([np.sin(tilt) * np.cos(a), np.sin(tilt) * np.sin(a), np.cos(tilt)])  # up the leaf
            base = radial * rho + np.array([0.0, 0.0, 0.04])
            centre = base + axis * 0.45 * length
            # local x across the leaf, local y up it, local z (thin) out from the heart
            up = axis
            thin = np.cross(up, np.array([-np.sin(a), np.cos(a), 0.0]))
            across = np.cross(up, thin)
            euler = _frame_euler(across, up)
            parts.append(ellipsoid(f"leaf {k + 1} {i + 1}", (width / 2, length / 2, 0.045), centre, blend=0.025,
                                   rot=euler))
    if p.ruffle:  # crinkled leaf tops filling the head: wavy fins standing out of its upper surface

        top_r = r * (0.55 + 0.3 * (p.rings - 1))
        dirs = [d for d in sphere_directions(40, seed=0.4) if d[2] > 0.15][:18]
        for i, d in enumerate(dirs):
            at = np.array([d[0] * top_r, d[1] * top_r, h + 0.02 + d[2] * h * 1.3])
            tangent = np.cross(d, np.array([np.cos(1.9 * i), np.sin(1.9 * i), 0.4]))
            parts.append(ellipsoid(f"frill {i + 1}", (0.17, 0.15, 0.035), at, blend=0.03,
                                   rot=_frame_euler(np.cross(tangent, d), d)))
    return parts


def _frame_euler(x_axis: np.ndarray, y_axis: np.ndarray) -> tuple[float, float, float]:
    """XYZ Euler angles [deg] of the rotation taking local x and y onto the given directions (y made orthogonal)."""
    import warnings

    from scipy.spatial.transform import Rotation

    x = x_axis / np.linalg.norm(x_axis)
    y = y_axis - np.dot(y_axis, x) * x
    y = y / np.linalg.norm(y)
    m = np.stack([x, y, np.cross(x, y)], axis=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        e = Rotation.from_matrix(m).as_euler("xyz", degrees=True)
    return (float(e[0]), float(e[1]), float(e[2]))


class CollapsibleParams(Model):
    """A collapsible silicone cup or bowl: stepped rings of wall that fold down into each other, a handle tab."""

    rings: int = Field(default=3, ge=2, le=5, description="wall rings (steps)")
    height: float = Field(default=0.6, gt=0.2, le=1.2, description="open height / rim diameter [-]")
    handle: bool = True
    state: Literal["open", "folded"] = Field(default="open", description="open as a cup; folded flat, the rings "
                                             "nested in each other")


def collapsible(p: CollapsibleParams) -> list[Part]:
    """Rim diameter 1. Open: stepped frustum rings round a cavity, base closed. Folded: the base with the rings as
    concentric ridges, each a little higher than the one inside it."""
    n, wall = p.rings, 0.035
    r0 = 0.5 - 0.07 * n  # the base ring's radius
    parts: list[Part] = []
    if p.state == "open":
        dh = p.height / n
        for k in range(n):
            rb, rt = r0 + 0.07 * k, r0 + 0.07 * (k + 1)
            parts.append(cone(f"ring {k + 1}", rb, rt, dh, (0, 0, dh * (k + 0.5)), edge=0.01, blend=0.01))
        for k in range(n):
            rb, rt = r0 + 0.07 * k - wall, r0 + 0.07 * (k + 1) - wall
            z0 = wall if k == 0 else 0.0
            parts.append(cone(f"cavity {k + 1}", rb, rt, dh - z0 + (0.02 if k == n - 1 else 0.0),
                              (0, 0, dh * k + z0 + (dh - z0 + (0.02 if k == n - 1 else 0.0)) / 2)).model_copy(
                                  update={"operation": "subtract"}))
        top = p.height
        rim = 0.5
    else:
        parts.append(cylinder("base", r0, wall * 1.4, (0, 0, wall * 0.7), edge=0.01))
        for k in range(n):  # each ring a standing wall, a step higher than the one inside it
            parts.append(torus(f"ring {k + 1}", r0 + 0.07 * (k + 0.5), 0.03, (0, 0, 0.06 + 0.025 * k), blend=0.012,
                               scale=(1.0, 1.0, 2.0)))
        top = 0.1 + 0.025 * n
        rim = r0 + 0.07 * n
    if p.handle:
        parts.append(box("handle", (0.3, 0.14, 0.045), (rim + 0.1, 0, top - 0.03), edge=0.02, blend=0.015))
    return parts
