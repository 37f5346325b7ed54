"""Household soft-goods body plans: flat sheets in a state (flat, rolled, folded, stacked), filled pouches and bags,
gloves and mittens, socks, hats, handled tools (spatulas, brushes, scrapers) and open moulds and trays (unit frame,
longest extent about 1).

Thin things are built no thinner than the mesher can see: a sheet's built layer is at least `MIN_LAYER` of its flat
length and a mould's wall at least `MIN_WALL` of its outline, and their lexicon entries carry the effective density
that gives the real object's mass at that built volume. Every state of one sheet keeps the built sheet's volume (a
folded or rolled sheet is the same sheet), except `stacked`, which is `layers` sheets; a rolled sheet is rolled with
its real thickness, so it keeps the real roll's diameter, and `state_change` in the grammar says how the density
carries over."""

from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import Field

from contracts.base import Model
from contracts.shape import Part
from tasks.geometry.grammar.parts import box, cone, cylinder, ellipsoid, limb, superellipsoid, torus

MIN_LAYER = 0.025  # a built sheet layer, / the flat sheet's length [-]
MIN_WALL = 0.03  # a built mould or hat wall, / the outline's size [-]

SheetState = Literal["flat", "rolled", "folded", "stacked"]


def _op(part: Part, op: str, blend: float = 0.0) -> Part:
    return part.model_copy(update={"operation": op, "blend_m": blend})


def _scaled(part: Part, scale: tuple[float, float, float]) -> Part:
    return part.model_copy(update={"transform": part.transform.model_copy(update={"scale": scale})})


# ----------------------------------------------------------------------------------------------------------- sheets
class SheetParams(Model):
    """A flat good: mat, towel, blanket, sheet, napkin, pad, tortilla, slice. Length 1 along x when flat."""

    state: SheetState = Field(default="flat", description="flat; rolled (a roll along the sheet's width, the layers "
                              "seen as rings at its ends); folded (halved `folds` times); stacked (`layers` sheets)")
    shape: Literal["rect", "round"] = Field(default="rect", description="a rectangle or a round sheet (tortilla, pad)")
    width: float = Field(default=0.5, gt=0.002, le=1.0, description="width / length [-]")
    thickness: float = Field(default=0.005, gt=0.0, le=0.2, description="the real sheet's thickness / length [-]")
    folds: int = Field(default=1, ge=1, le=3, description="halvings when folded [-]")
    layers: int = Field(default=4, ge=2, le=12, description="sheets in a stack [-]")
    core: float = Field(default=0.12, ge=0.0, le=0.6, description="a roll's hole radius / roll radius [-]")
    packing: float = Field(default=0.8, gt=0.2, le=1.0, description="share of a roll's cross-section that is sheet [-]")
    edge: float = Field(default=0.5, ge=0.0, le=1.0, description="edge rounding / half the layer [-]")


def sheet_layer(p: SheetParams) -> float:
    """The built thickness of one layer in the unit frame (the flat sheet's length is 1) [-]."""
    return max(p.thickness, MIN_LAYER)


def _slab(name: str, p: SheetParams, length: float, width: float, t: float, at: tuple[float, float, float],
          rot: tuple[float, float, float] = (0, 0, 0)) -> Part:
    e = p.edge * t / 2
    if p.shape == "round":
        return _scaled(cylinder(name, width / 2, t, at, edge=e, rot=rot), (length / width, 1, 1))
    return box(name, (length, width, t), at, edge=e, rot=rot)


def sheet(p: SheetParams) -> list[Part]:
    """Flat: length 1 along x, width along y. Rolled: the roll's axis along x (its length the sheet's width)."""
    t = sheet_layer(p)
    w = p.width
    if p.state == "flat":
        return [_slab("body", p, 1.0, w, t, (0, 0, t / 2))]
    if p.state == "stacked":
        parts = []
        for i in range(p.layers):
            jitter = (0.012 * np.sin(2.3 * i), 0.012 * np.cos(1.7 * i))
            parts.append(_slab("body" if i == 0 else f"layer {i + 1}", p.model_copy(update={"edge": 1.0}), 1.0, w, t,
                               (jitter[0], jitter[1] * w, t / 2 + 0.96 * t * i), rot=(0, 0, 1.5 * np.sin(3.1 * i))))
        return parts
    if p.state == "folded":
        return _folded(p, t)
    return _rolled(p)


def _folded(p: SheetParams, t: float) -> list[Part]:
    """Halved `folds` times, each fold across the longer side; the last crease rounded, the layers' open edges cut."""
    length, width = 1.0, p.width
    last = "x"
    for _ in range(p.folds):
        if length >= width:
            length, last = length / 2, "x"
        else:
            width, last = width / 2, "y"
    n = 2 ** p.folds
    h = n * t
    if p.shape == "round":
        parts = [_scaled(cylinder("body", p.width / 2, h, (0, 0, h / 2), edge=p.edge * t / 2), (1 / p.width, 1, 1))]
        parts.append(_op(box("fold", (2, 2, 2 * h), (1.0, 0, h / 2)), "intersect"))
        if p.folds >= 2:
            parts.append(_op(box("second fold", (2, 2, 2 * h), (0, 1.0, h / 2)), "intersect"))
        return parts
    r = h / 2
    if last == "x":
        parts = [box("body", (length - r, width, h), (r / 2, 0, r), edge=p.edge * t / 2),
                 cylinder("crease", r, width, (-length / 2 + r, 0, r), edge=p.edge * t / 2, rot=(90, 0, 0),
                          blend=0.2 * t)]
        cut = [box(f"gap {i}", (0.3 * length, width * 1.2, 0.18 * t), (length / 2, 0, i * t)) for i in range(1, n)]
    else:
        parts = [box("body", (length, width - r, h), (0, r / 2, r), edge=p.edge * t / 2),
                 cylinder("crease", r, length, (0, -width / 2 + r, r), edge=p.edge * t / 2, rot=(0, 90, 0),
                          blend=0.2 * t)]
        cut = [box(f"gap {i}", (length * 1.2, 0.3 * width, 0.18 * t), (0, width / 2, i * t)) for i in range(1, n)]
    return parts + [_op(c, "subtract") for c in cut]


def roll_radius(p: SheetParams) -> float:
    """Outer radius of the rolled sheet (unit frame): its real cross-section, loosely packed, around its hole."""
    area = 1.0 * p.thickness / p.packing  # the sheet's length x thickness, over the roll's packing
    r = float(np.sqrt(area / (np.pi * (1 - p.core**2))))
    return max(r, 0.04 * p.width)


def _rolled(p: SheetParams) -> list[Part]:
    """A roll of length `width` along x: a cylinder with a hole, rings cut into both ends one layer pitch apart, and
    the sheet's free end as a step along the outside."""
    w = p.width
    R = roll_radius(p)
    r0 = p.core * R
    if p.shape == "round":  # a rolled tortilla or pancake: a wrap, tapered at its ends
        return [_scaled(cylinder("body", R, w, (0, 0, R), edge=0.6 * R, rot=(0, 90, 0)), (1, 1, 1))]
    parts = [cylinder("body", R, w, (0, 0, R), edge=min(0.15 * R, 0.02), rot=(0, 90, 0))]
    layer = float(np.clip(p.thickness, 0.03 * R, 0.12 * R))
    parts.append(box("flap", (w, 0.5 * R, layer), (0, -0.25 * R, 2 * R + layer / 2 - 0.005 * R), edge=0.3 * layer,
                     blend=0.02 * R))
    # rings one sheet layer apart, as many as the mesher can see: a groove at least 2.6 % of the roll's length wide
    g = min(max(0.2 * p.thickness, 0.013 * w), 0.08 * (R - r0))
    rings = int(np.clip(np.floor((R - r0) / (5 * g)) - 1, 1, 5))
    pitch = (R - r0) / (rings + 1)
    depth = min(0.12 * w, 3 * g)
    for i in range(1, rings + 1):
        rad = r0 + pitch * i
        for side, s in (("left", 1), ("right", -1)):
            ring = _scaled(torus(f"{side} ring {i}", rad, g, (s * w / 2, 0, R), rot=(0, 90, 0)), (1, 1, depth / g))
            parts.append(_op(ring, "subtract"))
    if r0 > 0:
        parts.append(_op(cylinder("hole", r0, 1.2 * w, (0, 0, R), rot=(0, 90, 0)), "subtract"))
    return parts


# ---------------------------------------------------------------------------------------------------------- pouches
class PouchParams(Model):
    """A filled pouch or bag: IV fluid bag, ice pack, gel pack, bean bag, hand warmer, drink pouch, sandbag."""

    width: float = Field(default=0.6, gt=0.2, le=1.0, description="width / length [-]")
    fill: float = Field(default=0.6, ge=0.0, le=1.0, description="how full: 0 an empty, flat bag; 1 a round pillow [-]")
    seam: float = Field(default=0.04, ge=0.0, le=0.15, description="width of the sealed or sewn border / length [-]")
    squareness: float = Field(default=0.35, gt=0.1, le=1.0, description="1 an oval pouch, small a square one [-]")
    port: Literal["none", "iv", "cap", "spout"] = Field(default="none", description="iv: two ports at the front and "
                                                         "a hanger hole; cap: a screw neck; spout: one tube")


def pouch(p: PouchParams) -> list[Part]:
    """Length 1 along x, lying flat; ports at +x."""
    w = p.width
    s = p.seam
    h = max(MIN_LAYER * 1.6, p.fill * 0.42 * w)
    st = MIN_LAYER
    parts = [superellipsoid("body", (0.5 - s, w / 2 - s, h / 2), (0, 0, h / 2), ns=0.55 + 0.3 * p.fill,
                            ew=p.squareness)]
    if s > 0:
        parts.append(box("seam", (1.0, w, st), (0, 0, h / 2), edge=0.45 * st, blend=0.3 * h))
    if p.port == "iv":
        for i, y in enumerate((-0.12 * w, 0.12 * w)):
            parts.append(limb(f"port {i + 1}", (0.45, y, h / 2), (0.58, y, h / 2), 0.022, blend=0.01))
        hole = cylinder("hanger hole", 0.03, 2 * h, (-0.51, 0, h / 2))
        parts.append(box("hanger tab", (0.1, 0.16, st), (-0.51, 0, h / 2), edge=0.45 * st, blend=0.02))
        parts.append(_op(hole, "subtract"))
    elif p.port == "cap":
        parts.append(cylinder("neck", 0.08, 0.12, (0.5, 0, h / 2), edge=0.01, rot=(0, 90, 0), blend=0.03))
        parts.append(cylinder("cap", 0.1, 0.08, (0.58, 0, h / 2), edge=0.015, rot=(0, 90, 0), blend=0.005))
    elif p.port == "spout":
        parts.append(limb("spout", (0.42, 0, h / 2), (0.58, 0, h / 2), 0.035, blend=0.02))
        parts.append(cylinder("cap", 0.05, 0.05, (0.6, 0, h / 2), edge=0.01, rot=(0, 90, 0), blend=0.005))
    return parts


# -------------------------------------------------------------------------------------------------- hands and feet
class GloveParams(Model):
    """A glove (palm and five fingers) or a mitten (palm, mitt and thumb), lying flat, fingers towards +x."""

    mitten: bool = False
    finger_length: float = Field(default=1.0, gt=0.4, le=1.6, description="middle finger / palm length [-]")
    thickness: float = Field(default=0.12, gt=0.04, le=0.5, description="thickness / palm width [-]")
    cuff: float = Field(default=0.6, ge=0.0, le=2.0, description="cuff length / palm length [-]")
    flare: float = Field(default=1.1, gt=0.8, le=1.6, description="cuff width at its opening / palm width [-]")
    spread: float = Field(default=6.0, ge=0.0, le=20.0, description="angle between fingers [deg]")


_FINGERS = (("index finger", 0.88), ("middle finger", 1.0), ("ring finger", 0.93), ("little finger", 0.72))


def _flat_limb(name: str, a: np.ndarray, b: np.ndarray, r: float, t: float, blend: float) -> Part:
    """A finger-like capsule from a to b in the x-y plane, flattened to thickness t."""
    d = b - a
    angle = float(np.degrees(np.arctan2(d[1], d[0])))
    part = Part(name=name, primitive={"kind": "capsule", "radius_m": float(r),
                                      "length_m": float(np.linalg.norm(d))},
                transform={"translation_m": tuple(float(x) for x in (a + b) / 2), "rotation_deg": (0.0, 90.0, angle),
                           "scale": (min(1.0, t / (2 * r)), 1.0, 1.0)}, blend_m=blend)
    return part


def glove(p: GloveParams) -> list[Part]:
    """Palm length 0.34, width 0.3 (the glove's parts in proportion); lying palm down."""
    pl, pw = 0.34, 0.3
    t = p.thickness * pw
    z = t / 2
    parts = [superellipsoid("palm", (pl / 2, pw / 2, t / 2), (0, 0, z), ns=0.6, ew=0.45)]
    fr = pw / 8.6
    if p.mitten:
        ml = 0.8 * p.finger_length * pl
        parts.append(superellipsoid("mitt", (ml / 2 + 0.03, pw / 2, t / 2), (pl / 2 + ml / 2 - 0.05, 0, z), ns=0.7,
                                    ew=0.9, blend=0.04))
    else:
        for i, (name, share) in enumerate(_FINGERS):
            y = pw / 2 - fr - i * (pw - 2 * fr) / 3
            a = np.radians(p.spread * (1.5 - i))
            length = share * p.finger_length * pl * 0.85
            base = np.array([pl / 2 - 0.03, y, z])
            tip = base + length * np.array([np.cos(a), np.sin(a), 0.0])
            parts.append(_flat_limb(name, base, tip, fr, t, blend=0.02))
    ta = np.radians(40 + p.spread)
    tb = np.array([-0.05, pw / 2 - 0.02, z])
    parts.append(_flat_limb("thumb", tb, tb + 0.6 * pl * np.array([np.cos(ta), np.sin(ta), 0.0]), 1.1 * fr, t,
                            blend=0.03))
    if p.cuff > 0:
        cl = p.cuff * pl
        c = cone("cuff", pw / 2, pw / 2 * p.flare, cl + 0.04, (-pl / 2 - cl / 2 + 0.02, 0, z), edge=0.2 * t,
                 blend=0.03, rot=(0, -90, 0))
        parts.append(_scaled(c, (min(1.0, t / pw), 1, 1)))
    return parts


class SockParams(Model):
    """A sock lying flat on its side: the leg tube down to the heel, the foot along x to the toe (an L)."""

    leg_length: float = Field(default=0.9, ge=0.15, le=3.0, description="leg / foot length [-]")
    width: float = Field(default=0.33, gt=0.15, le=0.6, description="flat width / foot length [-]")
    thickness: float = Field(default=0.1, gt=0.03, le=0.5, description="thickness / foot length [-]")
    angle: float = Field(default=100.0, ge=90.0, le=150.0, description="angle between leg and foot [deg]")
    cuff: bool = Field(default=True, description="a ribbed band at the opening")


def sock(p: SockParams) -> list[Part]:
    """Foot length 1 along x (heel at the origin); the leg rises towards +y."""
    w, t = p.width, p.thickness
    z = t / 2
    r = w / 2
    heel = np.array([0.0, 0.0, z])
    toe = np.array([1.0 - r, 0.0, z])
    a = np.radians(p.angle)
    top = heel + p.leg_length * np.array([np.cos(a), np.sin(a), 0.0])
    parts = [_flat_limb("foot", heel, toe, r, t, blend=0.0),
             _flat_limb("leg", heel, top, 0.95 * r, t, blend=0.06 * w),
             ellipsoid("heel", (0.62 * r, 0.62 * r, t / 2), heel + np.array([-0.25 * r, -0.25 * r, 0]), blend=0.3 * r),
             ellipsoid("toe", (0.7 * r, 0.98 * r, t / 2), toe + np.array([0.15 * r, 0, 0]), blend=0.2 * r)]
    if p.cuff:
        d = (top - heel) / np.linalg.norm(top - heel)
        parts.append(_flat_limb("cuff", top - d * 0.12, top, 1.0 * r, 1.1 * t, blend=0.01))
    return parts


class HatParams(Model):
    """A soft hat: an open dome (a beanie, a bucket or sun hat with a brim, a baby bonnet), opening down."""

    height: float = Field(default=0.85, gt=0.3, le=1.5, description="crown height / crown diameter [-]")
    wall: float = Field(default=0.04, gt=0.0, le=0.2, description="wall thickness / crown diameter [-]")
    cuff: float = Field(default=0.2, ge=0.0, le=0.5, description="folded-up cuff band height / crown diameter [-]")
    brim: float = Field(default=0.0, ge=0.0, le=0.6, description="brim width / crown diameter [-]")
    pompom: bool = False


def hat(p: HatParams) -> list[Part]:
    """Crown diameter 1, resting on its opening at z = 0."""
    R, H = 0.5, p.height
    w = max(p.wall, MIN_WALL)
    parts = [ellipsoid("body", (R, R, H), (0, 0, 0))]
    if p.cuff > 0:
        parts.append(cylinder("cuff", R + 0.6 * w, p.cuff, (0, 0, p.cuff / 2), edge=0.4 * w, blend=0.01))
    if p.brim > 0:
        parts.append(cylinder("brim", R + p.brim, w, (0, 0, w / 2), edge=0.45 * w, blend=0.02))
    if p.pompom:
        parts.append(ellipsoid("pompom", (0.15, 0.15, 0.14), (0, 0, H + 0.08), blend=0.03))
    parts.append(_op(ellipsoid("inside", (R - w, R - w, H - w), (0, 0, 0)), "subtract"))
    parts.append(_op(box("ground", (4, 4, 4), (0, 0, 2)), "intersect"))
    return parts


# ----------------------------------------------------------------------------------------------------------- tools
class ToolParams(Model):
    """A soft tool with a handle, lying flat along x: silicone spatula, spoonula, brush, toothbrush, scraper."""

    head: Literal["paddle", "spoon", "brush", "toothbrush", "scraper", "turner"] = "paddle"
    handle: float = Field(default=0.6, ge=0.0, le=0.85, description="handle length / total length [-]")
    handle_radius: float = Field(default=0.035, gt=0.01, le=0.12, description="handle radius / total length [-]")
    head_width: float = Field(default=0.2, gt=0.03, le=1.0, description="head width / total length [-]")
    thickness: float = Field(default=0.03, gt=0.01, le=0.3, description="head thickness / total length [-]")


def tool(p: ToolParams) -> list[Part]:
    """Total length 1 along x: the handle from x = -0.5, the head ending at x = 0.5."""
    hl = p.handle
    hr = p.handle_radius
    hw = p.head_width
    t = max(p.thickness, MIN_LAYER)
    z = max(hr, t / 2)
    x0 = -0.5 + hl
    head_len = 1.0 - hl
    parts: list[Part] = []
    if hl > 0:
        parts.append(limb("handle", (-0.5 + hr, 0, z), (x0, 0, z), hr))
    if p.head in ("paddle", "spoon", "turner"):
        blade = superellipsoid("head", (head_len / 2, hw / 2, t / 2), (x0 + head_len / 2, 0, z), ns=0.3,
                               ew=0.3 if p.head != "spoon" else 0.8, blend=0.03)
        parts.append(blade)
        if p.head == "spoon":
            parts.append(_op(ellipsoid("bowl", (0.4 * head_len, 0.38 * hw, t), (x0 + head_len / 2, 0, z + 0.9 * t)),
                             "subtract", blend=0.005))
        if p.head == "turner":
            for i, y in enumerate((-0.22 * hw, 0.0, 0.22 * hw)):
                parts.append(_op(box(f"slot {i + 1}", (0.5 * head_len, 0.07 * hw, 3 * t),
                                     (x0 + 0.55 * head_len, y, z), edge=0.03 * hw), "subtract"))
    elif p.head == "scraper":
        parts.append(box("head", (0.6 * head_len, hw, t), (x0 + 0.3 * head_len, 0, z), edge=0.45 * t, blend=0.02))
        parts.append(_scaled(cylinder("blade", hw / 2, t, (x0 + 0.6 * head_len, 0, z), edge=0.45 * t, blend=0.005),
                             (0.8 * head_len / hw, 1, 1)))
    elif p.head == "brush":
        fl = 0.3 * head_len
        parts.append(box("ferrule", (fl, hw, 2.2 * t), (x0 + fl / 2, 0, z), edge=0.3 * t, blend=0.01))
        parts.append(box("bristles", (head_len - fl, 0.95 * hw, 2.0 * t), (x0 + fl + (head_len - fl) / 2, 0, z),
                         edge=0.5 * t, blend=0.005))
    else:  # toothbrush: a small head with a bristle block on top
        parts.append(superellipsoid("head", (head_len / 2, hw / 2, t / 2), (x0 + head_len / 2, 0, z), ns=0.5, ew=0.5,
                                    blend=0.02))
        parts.append(box("bristles", (0.8 * head_len, 0.8 * hw, 1.6 * t), (x0 + head_len / 2, 0, z + 1.1 * t),
                         edge=0.3 * t, blend=0.005))
    return parts


# ----------------------------------------------------------------------------------------------------------- moulds
class MouldParams(Model):
    """An open mould or tray: baking mould, cupcake liner, ice cube tray, muffin tray; cavities shaped round, square,
    heart or star, walls `wall` thick."""

    outline: Literal["round", "square", "heart", "star"] = "round"
    height: float = Field(default=0.45, gt=0.08, le=1.5, description="depth / cavity size [-]")
    wall: float = Field(default=0.04, gt=0.0, le=0.25, description="wall thickness / cavity size [-]")
    flare: float = Field(default=1.15, ge=1.0, le=1.6, description="top / bottom width of a round cavity [-]")
    columns: int = Field(default=1, ge=1, le=8, description="cavities along x (a tray) [-]")
    rows: int = Field(default=1, ge=1, le=4, description="cavities along y [-]")
    rim: bool = Field(default=False, description="a lip around the top of a single mould")


def _outline(name: str, kind: str, size: float, z0: float, z1: float, at: tuple[float, float], slope: float,
             edge: float) -> list[Part]:
    """The solid of an outline of width `size` at z0, from z0 to z1, centred at `at` (several parts for heart and
    star); a round outline widens by `slope` per unit height."""
    h = z1 - z0
    zc = (z0 + z1) / 2
    x, y = at
    if kind == "round":
        r = size / 2
        return [cone(name, r, r + slope * h, h, (x, y, zc), edge=edge)]
    if kind == "square":
        return [box(name, (size, size, h), (x, y, zc), edge=min(edge, 0.1 * size))]
    if kind == "heart":  # a square on its corner with two half-circles on its upper sides; the point towards -x
        a = size / 1.707
        c = a / (2 * np.sqrt(2))
        dx = -0.075 * a
        return [box(name, (a, a, h), (x + dx, y, zc), edge=min(edge, 0.05 * a), rot=(0, 0, 45)),
                cylinder(f"{name} lobe 1", a / 2, h, (x + dx + c, y + c, zc), edge=min(edge, 0.05 * a)),
                cylinder(f"{name} lobe 2", a / 2, h, (x + dx + c, y - c, zc), edge=min(edge, 0.05 * a))]
    ri = 0.2 * size  # star: a core and five rhombic points
    parts = [cylinder(name, ri * 1.1, h, (x, y, zc), edge=min(edge, 0.05 * size))]
    for i in range(5):
        ang = 2 * np.pi * i / 5
        rl = (size / 2 - 0.3 * ri) / 2 + 0.25 * ri
        cx, cy = x + np.cos(ang) * (size / 2 - rl), y + np.sin(ang) * (size / 2 - rl)
        parts.append(superellipsoid(f"{name} point {i + 1}", (rl, 0.85 * ri, h / 2), (cx, cy, zc), ns=0.1, ew=2.0,
                                    rot=(0, 0, float(np.degrees(ang)))))
    return parts


def mould(p: MouldParams) -> list[Part]:
    """Cavity size 1 (a tray: cavities 1 apart plus walls); open at the top, resting on its base."""
    w = max(p.wall, MIN_WALL)
    h = p.height
    # a round cavity widens from radius 0.5 / flare at its floor to 0.5 at the top
    slope = (0.5 - 0.5 / p.flare) / h if p.outline == "round" else 0.0
    rb = 0.5 / p.flare if p.outline == "round" else 0.5
    top = h + 0.5
    if p.columns == 1 and p.rows == 1:
        parts = _outline("body", p.outline, 2 * (rb + w), 0.0, h, (0, 0), slope, 0.4 * w)
        if p.rim:
            parts.append(_scaled(torus("rim", 0.5 + w, 1.2 * w, (0, 0, h - 0.6 * w)), (1, 1, 0.6))
                         if p.outline == "round" else
                         box("rim", (1.0 + 5 * w, 1.0 + 5 * w, w), (0, 0, h - w / 2), edge=0.4 * w, blend=0.01))
        cavity = _outline("cavity", p.outline, 2 * (rb + slope * w), w, top, (0, 0), slope, 0.3 * w)
        return parts + [_op(c, "subtract") for c in cavity]
    n = max(p.columns, p.rows)
    w = max(w, 0.025 * n / (1 - 0.025 * (n + 1)))  # a tray's walls: 2.5 % of its length, as for one mould
    pitch = 1.0 + w
    lx, ly = p.columns * pitch + w, p.rows * pitch + w
    parts = [box("body", (lx, ly, h), (0, 0, h / 2), edge=0.6 * w)]
    for i in range(p.columns):
        for j in range(p.rows):
            at = ((i - (p.columns - 1) / 2) * pitch, (j - (p.rows - 1) / 2) * pitch)
            cav = _outline(f"cavity {i + 1} {j + 1}", p.outline, 2 * (rb + slope * w), w, top, at, slope, 0.3 * w)
            parts += [_op(c, "subtract") for c in cav]
    return parts
