"""Object body plans: cushion, ball, block, disc, ring, tube, cone, dome, star, heart, bone, egg, teardrop, cloud,
cactus and blob (unit frame, longest extent about 1)."""

from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import Field

from contracts.base import Model
from contracts.shape import Part
from tasks.geometry.grammar.parts import (
    Vec,
    _euler_z_to,
    box,
    cone,
    cylinder,
    ellipsoid,
    limb,
    relief,
    scaled,
    sphere_directions,
    squashed_parts,
    superellipsoid,
    swept,
    tapered,
    torus,
)


class CushionParams(Model):
    """A cushion or pillow: a puffed square, rectangle, round pad or bolster."""

    shape: Literal["square", "round", "bolster", "beanbag"] = "square"
    width: float = Field(default=1.0, gt=0.1, le=2.0, description="width / length [-]")
    thickness: float = Field(default=0.3, gt=0.05, le=1.0, description="thickness / length [-]")
    puff: float = Field(default=0.6, gt=0.1, le=1.0, description="1 a round pillow, small a boxy one [-]")
    piping: bool = False
    channels: int = Field(default=0, ge=0, le=8, description="stitched sections: seams across its length (a wheat "
                          "bag's channels) [-]")


def cushion(p: CushionParams) -> list[Part]:
    """Length 1 along x, lying flat (a bolster lies along x)."""
    t = p.thickness
    if p.shape == "beanbag":
        return beanbag(p)
    if p.shape == "bolster":
        parts = [cylinder("body", t / 2, 1.0, (0, 0, t / 2), edge=0.3 * t, rot=(0, 90, 0))]
        for i in range(p.channels):  # a seam round the tube pinches it into sections
            x = -0.5 + (i + 1) / (p.channels + 1)
            parts.append(torus(f"stitch {i + 1}", t / 2 + 0.02 * t, 0.09 * t, (x, 0, t / 2),
                               rot=(0, 90, 0)).model_copy(update={"operation": "subtract"}))
        return parts
    if p.shape == "round":
        parts = [superellipsoid("body", (0.5, 0.5 * p.width, t / 2), (0, 0, t / 2), ns=p.puff, ew=1.0)]
    else:
        parts = [superellipsoid("body", (0.5, 0.5 * p.width, t / 2), (0, 0, t / 2), ns=p.puff, ew=0.25)]
    for i in range(p.channels):  # stitched lines across the pad
        x = -0.5 + (i + 1) / (p.channels + 1)
        parts.append(cylinder(f"stitch {i + 1}", 0.12 * t, 1.2 * p.width, (x, 0, t), rot=(90, 0, 0), op="subtract"))
    if p.piping:
        parts.append(superellipsoid("piping", (0.51, 0.51 * p.width, 0.04), (0, 0, t / 2), ns=0.2,
                                    ew=0.25 if p.shape == "square" else 1.0, blend=0.01))
    return parts


def beanbag(p: CushionParams) -> list[Part]:
    """A bean bag chair: a slumped sack (length 1 along x, the back at -x) with the seat pressed in at its front and
    the back heaped up behind it."""
    t, w = p.thickness, p.width
    parts = [superellipsoid("body", (0.5, 0.5 * w, 0.42 * t), (0, 0, 0.42 * t), ns=0.8, ew=1.0),
             ellipsoid("back", (0.28, 0.42 * w, 0.5 * t), (-0.22, 0, 0.62 * t), blend=0.15),
             ellipsoid("seat", (0.3, 0.3 * w, 0.3 * t), (0.12, 0, 0.95 * t), blend=0.12).model_copy(
                 update={"operation": "subtract"})]
    return parts


class BallParams(Model):
    """A ball: sphere or spheroid (a rugby ball is prolate; `tips` makes its ends pointed, a football's)."""

    aspect: float = Field(default=1.0, gt=0.3, le=3.0, description="length (x) / diameter [-]")
    squash: float = Field(default=1.0, gt=0.3, le=1.0, description="height / diameter [-]")
    panels: bool = Field(default=False, description="a seam band around the equator (a second colour)")
    tips: float = Field(default=0.0, ge=0.0, le=1.0, description="pointed ends along x: 0 a spheroid, 1 a spindle "
                        "whose ends come to a point (an American football, a rugby ball) [-]")
    laces: bool = Field(default=False, description="a row of stitched laces along the top (an American football)")
    patches: int = Field(default=0, ge=0, le=32, description="panels of another colour set into the surface, evenly "
                         "spread (a soccer ball's 12 pentagons) [-]")
    gores: int = Field(default=0, ge=0, le=16, description="panels from pole to pole, their seams raised along the "
                       "meridians (a medicine ball's or a volleyball's stitched panels) [-]")
    face: bool = Field(default=False, description="a printed smiley face (two eyes and a smile) on its front (+x), "
                       "tilted up")
    bands: int = Field(default=0, ge=0, le=24, description="rubber bands wound round it, each a raised great circle "
                       "at its own tilt ('band a' ... 'band f' take their own colours: a rubber band ball) [-]")
    lines: Literal["none", "tennis", "baseball", "basketball"] = Field(
        default="none", description="raised seam lines in their own colour ('seam'): tennis, one closed curve "
        "winding round it (a tennis ball's); baseball, that curve with red stitches ('stitch') across it; "
        "basketball, the equator, a meridian and the two curved lines")
    holes: int = Field(default=0, ge=0, le=40, description="round holes set into the shell, evenly spread "
                       "('hole': a pickleball's, a wiffle ball's) [-]")
    relief: Literal["none", "spikes", "nubs", "folds", "strands", "ruffles", "crumples", "lumps"] = Field(
        default="none", description="raised surface detail (tasks.geometry.grammar.parts.relief): spikes, nubs, "
        "strands (a wound ball), lumps (a hand-rolled meatball) ...")
    stick: float = Field(default=0.0, ge=0.0, le=3.0, description="a stick standing under it, its length / the "
                         "ball's diameter ('stick': a cake pop) [-]")
    sprinkles: int = Field(default=0, ge=0, le=60, description="small sprinkles on its upper half ('sprinkle a' ... "
                           "'sprinkle c' take their own colours) [-]")
    cut: bool = Field(default=False, description="a wedge cut out of its top front, showing its inside ('inside': "
                      "a wax-coated cheese's paste)")
    knot: bool = Field(default=False, description="a pinched, gathered knot on top (a burrata's, a pouch's)")
    lip: bool = Field(default=False, description="a ragged lip of lumps round its foot, where it was pressed out of "
                      "the scoop (a scoop of ice cream)")


BAND_RADIUS = 0.022  # a wound rubber band's raised round section / the ball's diameter [-]


def ball(p: BallParams) -> list[Part]:
    """Diameter 1; x is the long axis of a prolate ball."""
    rz = 0.5 * p.squash
    if p.tips > 0:  # a prolate body and a cone to each end, smoothly joined: one smooth spindle, pointed ends
        half = 0.5 * p.aspect
        ex = half * (1.0 - 0.25 * p.tips)
        parts = [ellipsoid("body", (ex, 0.5, 0.5), (0, 0, 0.5))]
        xt = ex * ex / half  # where a line from the end (half, 0) touches the body's outline: each cone starts there
        yt = 0.5 * np.sqrt(max(1.0 - (ex / half) ** 2, 0.0))
        r_end = 0.02 + 0.08 * (1.0 - p.tips)
        x_end = half - r_end * (half - xt) / yt  # along that tangent line until it is r_end from the axis
        back = 0.015  # each cone's base a little behind the touching point along the line, its rim barely rounded
        xb, yb = xt - back, yt + back * yt / (half - xt)
        for s in (1, -1):  # each cone tangent to the body where it leaves it (no blend: a blend would bulge there)
            tip = tapered(f"{'front' if s > 0 else 'back'} tip", (s * xb, 0, 0.5), (s * x_end, 0, 0.5), yb, r_end)
            parts.append(tip.model_copy(update={"primitive": tip.primitive.model_copy(update={"edge_radius_m": 0.004})}))
        if p.squash < 1.0:
            parts = squashed_parts(parts, (1.0, 1.0, p.squash))
    else:
        parts = [ellipsoid("body", (0.5 * p.aspect, 0.5, rz), (0, 0, rz))]
    lift = SEAM_LIFT  # raised enough that its own colour wins over the body's at draft meshing
    if p.panels:
        parts.append(ellipsoid("seam", (0.5 * p.aspect + lift, 0.05, rz + lift), (0, 0, rz)))
    if p.laces:
        parts += _laces(p.aspect, rz)
    for i in range(p.gores // 2):  # each seam a great circle through the poles: two panels' edges
        parts.append(ellipsoid(f"panel seam {i + 1}", (0.5 * p.aspect + lift, 0.03, rz + lift), (0, 0, rz),
                               rot=(0, 0, 180.0 * i / (p.gores // 2))))
    if p.lines != "none":
        parts += _ball_lines(p.lines, (0.5 * p.aspect, 0.5, rz), rz)
    if p.face:
        parts += smiley((0.0, 0.0, rz), (0.5 * p.aspect, 0.5, rz))
    for i, d in enumerate(sphere_directions(p.bands, seed=1.1) if p.bands else ()):
        parts.append(torus(f"band {'abcdef'[i % 6]} {i + 1}", 0.5, BAND_RADIUS, (0, 0, rz), rot=_euler_z_to(d)))
    if p.patches:
        for i, d in enumerate(sphere_directions(p.patches, seed=0.4)):
            n = d / np.linalg.norm(d)
            parts.append(cylinder(f"patch {i + 1}", 0.2, 0.09, np.array([0, 0, rz]) + 0.5 * n * (1, 1, p.squash),
                                  edge=0.01, rot=_euler_z_to(n), op="subtract"))  # a panel set in, its own colour
    radii = np.array([0.5 * p.aspect, 0.5, rz])
    centre = np.array([0.0, 0.0, rz])
    for i, d in enumerate(sphere_directions(p.holes, seed=0.2) if p.holes else ()):
        n = d / np.linalg.norm(d)
        parts.append(cylinder(f"hole {i + 1}", 0.055, 0.16, centre + radii * n, edge=0.01, rot=_euler_z_to(n),
                              op="subtract"))
    if p.relief != "none":
        parts += relief(p.relief, tuple(centre), tuple(radii))
    if p.cut:  # a quarter wedge out of the upper front: a box's corner at the centre, its faces the inside
        parts.append(box("inside", (0.8, 0.8, 0.8), (0.4 * np.sqrt(2.0), 0.0, rz + 0.4), rot=(0.0, 0.0, 45.0),
                         op="subtract"))
    if p.knot:
        top = 2 * rz
        parts += [tapered("knot neck", (0, 0, top - 0.08), (0, 0, top + 0.07), 0.16, 0.06, blend=0.05),
                  ellipsoid("knot", (0.1, 0.08, 0.07), (0, 0, top + 0.1), blend=0.03)]
        for j in range(5):
            a = 2 * np.pi * j / 5
            parts.append(ellipsoid(f"knot fold {j + 1}", (0.045, 0.045, 0.1), (0.09 * np.cos(a), 0.09 * np.sin(a),
                                   top - 0.02), rot=(float(np.degrees(-0.5 * np.sin(a))),
                                                     float(np.degrees(0.5 * np.cos(a))), 0.0), blend=0.03))
    if p.lip:  # a ring of uneven lumps round the foot, standing out of the body's lower flank
        foot = 0.2 * rz
        flank = 0.5 * p.aspect * np.sqrt(1.0 - ((foot - rz) / rz) ** 2)
        parts.append(torus("lip", flank, 0.07, (0.0, 0.0, foot), blend=0.03))
        for j in range(9):
            a = 2 * np.pi * j / 9 + 0.3 * np.sin(3.0 * j)
            s = 0.085 + 0.03 * np.sin(2.1 * j)
            parts.append(ellipsoid(f"lip lump {j + 1}", (1.4 * s, s, 0.8 * s), (flank * np.cos(a), flank * np.sin(a),
                                   foot + 0.02 * np.cos(1.7 * j)), rot=(0.0, 0.0, float(np.degrees(a)) + 90.0),
                                   blend=0.04))
    for i, d in enumerate(sphere_directions(2 * p.sprinkles, seed=0.5)[:p.sprinkles] if p.sprinkles else ()):
        n = d / np.linalg.norm(d)
        t = np.cross(n, (np.cos(2.3 * i), np.sin(2.3 * i), 0.4))
        parts.append(limb(f"sprinkle {'abc'[i % 3]} {i + 1}", centre + radii * n * 1.01 - 0.035 * t,
                          centre + radii * n * 1.01 + 0.035 * t, 0.022))
    if p.stick > 0:  # the ball raised onto a stick standing under it
        h = p.stick
        parts = [q.model_copy(update={"transform": q.transform.model_copy(update={"translation_m": (
            q.transform.translation_m[0], q.transform.translation_m[1], q.transform.translation_m[2] + h)})})
            for q in parts]
        parts.append(cylinder("stick", 0.045, h + 0.2, (0.0, 0.0, 0.5 * (h + 0.2)), edge=0.01))
    return parts


SEAM_LIFT = 0.03  # how far a seam line stands out of the ball / its diameter [-] (~2 draft cells: its colour shows)


def _loop(name: str, pts: np.ndarray, radius: float) -> list[Part]:
    """A closed line of capsules through the points (n, 3)."""
    n = len(pts)
    return [limb(f"{name} {i + 1}", pts[i], pts[(i + 1) % n], radius) for i in range(n)]


def _ball_lines(kind: str, radii: Vec, rz: float) -> list[Part]:
    """A ball's seam lines as raised round lines centred on its surface (radii along x, y, z; centre at height
    rz): see BallParams.lines."""
    r = np.asarray(radii, dtype=np.float64)
    c = np.array([0.0, 0.0, rz])
    w = SEAM_LIFT
    t = np.linspace(0.0, 2.0 * np.pi, 48, endpoint=False)

    def on(d: np.ndarray) -> np.ndarray:
        return c + d / np.linalg.norm(d, axis=-1, keepdims=True) * r

    if kind in ("tennis", "baseball"):
        a, b = 0.72, 0.28  # the tennis-ball curve: on the unit sphere for any a + b = 1
        d = np.stack([a * np.cos(t) + b * np.cos(3 * t), a * np.sin(t) - b * np.sin(3 * t),
                      2 * np.sqrt(a * b) * np.sin(2 * t)], axis=1)
        d = d @ np.array([[1, 0, 0], [0, 0, 1], [0, -1, 0]], dtype=np.float64)  # its lobes front, back and up
        pts = on(d)
        if kind == "tennis":
            return _loop("seam", pts, w)
        parts: list[Part] = []
        for i in range(0, len(pts), 2):  # red stitches in two rows along the curve, each pair a chevron
            tan = pts[(i + 1) % len(pts)] - pts[i - 1]
            nrm = (pts[i] - c) / np.linalg.norm(pts[i] - c)
            side = np.cross(nrm, tan)
            side = 0.06 * side / np.linalg.norm(side)
            tan = 0.03 * tan / np.linalg.norm(tan)
            for s in (1, -1):
                parts.append(limb(f"stitch {len(parts) + 1}", pts[i] + 0.2 * s * side - tan + 0.01 * nrm,
                                  pts[i] + s * side + tan + 0.01 * nrm, w))
        return parts
    if kind == "basketball":  # grooves (a torus each, cut in): two great circles and a small circle round each y pole
        g = 1.0 + 0.01 / r[1]  # each groove's centre line just outside the surface: cut ~0.025 deep and ~0.06 wide
        k = 1.0 - 0.01 / (g * r[1])
        grooves: list[Part] = []

        def groove(name: str, major: float, dy: float, rot: Vec, scale: Vec) -> None:
            # each groove cut twice, the second narrower with the same floor (its centre line moved in towards the
            # centre): two parts' colour against the body's one there, so the seam's colour shows ~2 cells deep
            for label, f, minor in ((f"{name} seam", 1.0, w), (f"{name} channel seam", k, w - 0.01)):
                grooves.append(torus(label, f * major, minor, c + (0.0, f * dy, 0.0), rot=rot, scale=scale))

        groove("equator", g * r[1], 0.0, (0.0, 0.0, 0.0), (r[0] / r[1], 1.0, r[2] / r[1]))
        groove("meridian", g * r[1], 0.0, (90.0, 0.0, 0.0), (r[0] / r[1], r[2] / r[1], 1.0))
        th = np.radians(50.0)
        for sign, label in ((1, "left"), (-1, "right")):
            groove(f"{label} curve", g * r[1] * np.sin(th), sign * g * r[1] * np.cos(th), (90.0, 0.0, 0.0),
                   (1.0, 1.0, 1.0))
        return [q.model_copy(update={"operation": "subtract"}) for q in grooves]
    raise ValueError(f"unknown ball lines '{kind}'")


def smiley(centre: Vec, radii: Vec) -> list[Part]:
    """A printed smiley face on the front of a ball-like body (centre, radii along x, y, z): two upright oval eyes and
    a smile's arc, thin raised decals facing +x tilted 25 deg up (seen from the front and from above)."""
    c = np.asarray(centre, dtype=np.float64)
    rad = np.asarray(radii, dtype=np.float64)
    k = 2.0 * float(rad[1])  # the features' sizes are for a ball of diameter 1 across y

    def on(az: float, el: float, lift: float = 0.0) -> np.ndarray:
        tilt = np.radians(25.0)
        d = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
        d = np.array([d[0] * np.cos(tilt) - d[2] * np.sin(tilt), d[1], d[0] * np.sin(tilt) + d[2] * np.cos(tilt)])
        return c + (1.0 + lift) * d * rad

    parts = []
    for side, name in ((1, "left"), (-1, "right")):
        at = on(side * np.radians(18), np.radians(15), 0.0)
        n = (at - c) / np.linalg.norm(at - c)
        parts.append(ellipsoid(f"{name} eye", (0.06 * k, 0.09 * k, 0.04 * k), tuple(at), rot=_euler_z_to(n),
                               blend=0.004 * k))
    arc = [on(np.radians(a), np.radians(-8 - 16 * np.cos(np.radians(a) * 2.4)), 0.01) for a in np.linspace(-36, 36, 9)]
    parts += [limb(f"mouth {m + 1}", arc[m], arc[m + 1], 0.03 * k, blend=0.005 * k) for m in range(len(arc) - 1)]
    return [q.model_copy(update={"color_rgb": (0.02, 0.02, 0.02)}) for q in parts]  # printed black


def _laces(aspect: float, rz: float) -> list[Part]:
    """A seam along the top and short stitches across it (an American football's laces), about a third of its
    length."""
    top = 2 * rz
    parts = [box("middle lace", (0.34 * aspect, 0.04, 0.08), (0, 0, top + 0.005), edge=0.015)]
    for i, x in enumerate(np.linspace(-0.14, 0.14, 7) * aspect):  # standing ~2 draft cells proud: white shows
        parts.append(box(f"lace {i + 1}", (0.045, 0.16, 0.08), (float(x), 0, top + 0.01), edge=0.015))
    return parts


class BlockParams(Model):
    """A block, brick, cube, bar or slab: a rounded box."""

    width: float = Field(default=0.7, gt=0.02, le=1.0, description="width / length [-]")
    height: float = Field(default=0.4, gt=0.02, le=1.0, description="height / length [-]")
    edge: float = Field(default=0.1, ge=0.0, le=0.5, description="edge radius / the smallest side [-]")
    layer: float = Field(default=0.0, ge=0.0, le=0.9, description="top layer share (a scrub pad on a sponge) [-]")
    pips: bool = Field(default=False, description="a die's pips pressed into its six faces, one to six (opposite "
                       "faces adding to seven)")


# a die's faces: (outward axis, sign, pips) with opposite faces adding to seven
DIE_FACES = ((2, 1, 1), (2, -1, 6), (0, 1, 2), (0, -1, 5), (1, 1, 3), (1, -1, 4))
_PIP_LAYOUT = {1: [(0, 0)], 2: [(-1, -1), (1, 1)], 3: [(-1, -1), (0, 0), (1, 1)],
               4: [(-1, -1), (-1, 1), (1, -1), (1, 1)], 5: [(-1, -1), (-1, 1), (0, 0), (1, -1), (1, 1)],
               6: [(-1, -1), (-1, 0), (-1, 1), (1, -1), (1, 0), (1, 1)]}


def die_pips(size: tuple[float, float, float], centre: tuple[float, float, float]) -> list[Part]:
    """Dimples for a die's pips on a box of full extents `size` centred at `centre`: a small sphere cut into each
    face at its pip's place (1 on top, 6 below, 2-5 round the sides)."""
    side = min(size)
    r, step = 0.085 * side, 0.26 * side
    parts: list[Part] = []
    for axis, sign, n in DIE_FACES:
        u, v = [a for a in range(3) if a != axis]
        for a, b in _PIP_LAYOUT[n]:
            at = list(centre)
            at[axis] += sign * (size[axis] / 2 + 0.45 * r)
            at[u] += a * step
            at[v] += b * step
            parts.append(ellipsoid(f"pip {len(parts) + 1}", (r, r, r), tuple(at)).model_copy(
                update={"operation": "subtract", "blend_m": 0.15 * r}))
    return parts


def block(p: BlockParams) -> list[Part]:
    """Length 1 along x."""
    w, h = p.width, p.height
    e = p.edge * min(1.0, w, h)
    if p.pips:
        return [box("body", (1.0, w, h), (0, 0, h / 2), edge=e), *die_pips((1.0, w, h), (0, 0, h / 2))]
    if p.layer > 0:
        hb = h * (1 - p.layer)
        return [box("body", (1.0, w, hb), (0, 0, hb / 2), edge=e),
                box("top layer", (1.0, w, h * p.layer + e), (0, 0, hb + (h * p.layer - e) / 2),
                    edge=min(e, h * p.layer / 2))]
    return [box("body", (1.0, w, h), (0, 0, h / 2), edge=e)]


class DiscParams(Model):
    """A disc or cylinder standing on its face: pancake, tortilla, coaster, puck, pouf, can-shaped cushion."""

    height: float = Field(default=0.1, gt=0.005, le=2.0, description="height / diameter [-]")
    edge: float = Field(default=0.4, ge=0.0, le=1.0, description="rim rounding / half the height [-]")
    elongation: float = Field(default=1.0, gt=0.5, le=2.0, description="an oval disc's length / width [-]")
    swirl: float = Field(default=0.0, ge=0.0, le=4.0, description="turns of a rolled dough's spiral, raised over the "
                         "top and ending down the side (a cinnamon roll); 0 none [-]")
    layers: int = Field(default=1, ge=1, le=12, description="discs stacked one on another, the height shared among "
                        "them, each rim rounded so the stack shows its layers (a stack of pancakes); 1 one disc [-]")


SWIRL_POINTS = 22  # points along a cinnamon roll's spiral [-]


STACK_RADIUS_STEP = 0.025  # a stacked disc's radius varies by up to this share of the stack's (hand-made layers) [-]
STACK_OFFSET = 0.02  # and its centre sits up to this much off the stack's axis [-]


def disc_stack(p: DiscParams) -> list[Part]:
    """`p.layers` discs one on another, each a rounded cylinder of height / layers, a little larger or smaller and
    off-centre in turn so the rims show as layers; diameter 1."""
    t = p.height / p.layers
    parts = []
    for k in range(p.layers):
        wobble = ((3 * k) % 4) / 3.0 - 0.5  # -0.5..0.5, the same stack for the same words
        r = 0.5 * (1.0 - STACK_RADIUS_STEP * (1.0 + wobble))
        at = (STACK_OFFSET * wobble, STACK_OFFSET * ((k % 2) - 0.5), t * (k + 0.5))
        part = cylinder("body" if k == 0 else f"body {k + 1}", r, 1.02 * t, at, edge=0.9 * t / 2, blend=0.04 * t)
        if p.elongation != 1.0:
            part = part.model_copy(update={"transform": part.transform.model_copy(update={
                "scale": (p.elongation, 1, 1)})})
        parts.append(part)
    return parts


def disc(p: DiscParams) -> list[Part]:
    """Diameter 1."""
    if p.layers > 1:
        return disc_stack(p)
    h = p.height
    part = cylinder("body", 0.5, h, (0, 0, h / 2), edge=p.edge * min(h / 2, 0.5))
    if p.elongation != 1.0:
        part = part.model_copy(update={"transform": part.transform.model_copy(update={"scale": (p.elongation, 1, 1)})})
    if p.swirl <= 0:
        return [part]
    # the rolled layer's seam: an Archimedean spiral from the centre out to the rim, half sunk in the top, then
    # down the side where the dough's end lies
    r_tube = 0.05
    theta = np.linspace(0.0, 2 * np.pi * p.swirl, SWIRL_POINTS)
    rad = 0.06 + (0.5 - 0.06 - 0.4 * r_tube) * theta / theta[-1]
    top = h - 0.3 * r_tube - 0.12 * p.edge * min(h / 2, 0.5) * (rad / 0.5) ** 4
    pts = np.stack([rad * np.cos(theta), rad * np.sin(theta), top], axis=1)
    end = np.array([[pts[-1, 0], pts[-1, 1], 0.25 * h]])
    path = np.vstack([pts, end])
    return [part, *swept(["swirl"], path, np.full(len(path), r_tube), blend=0.01)]


class RingParams(Model):
    """A ring: bagel, doughnut, teether, swim ring, ring cushion (a torus with a real hole)."""

    tube: float = Field(default=0.2, gt=0.05, le=0.24, description="tube radius / outer diameter; below 0.25 "
                        "the hole stays open [-]")
    squash: float = Field(default=0.8, gt=0.3, le=1.5, description="tube height / tube width (over 1: a raised rim) [-]")
    icing: bool = Field(default=False, description="a top layer of another colour (a glazed doughnut)")
    floor: float = Field(default=0.0, ge=0.0, le=0.8, description="a padded floor across the hole (a pet bed): its "
                         "thickness / the rim's height; 0 an open ring [-]")
    gap: float = Field(default=0.0, ge=0.0, le=0.4, description="an open C: the gap's width at the rim / the outer "
                       "diameter (a nursing pillow's, a horseshoe cushion's opening), its ends rounded; 0 closed [-]")


def ring(p: RingParams) -> list[Part]:
    """Outer diameter 1 lying flat."""
    minor = p.tube
    major = 0.5 - minor
    zc = minor * p.squash
    parts = [torus("body", major, minor, (0, 0, zc), scale=(1, 1, p.squash))]
    if p.icing:
        parts.append(torus("icing", major, minor * 0.92, (0, 0, zc + 0.25 * minor * p.squash),
                           scale=(1, 1, 0.8 * p.squash)))
    if p.floor > 0:  # a bed's cushioned floor inside its raised rim, stitched round where it meets the rim
        fh = p.floor * 2 * zc
        parts.append(superellipsoid("floor", (major + 0.3 * minor, major + 0.3 * minor, fh / 2), (0, 0, fh / 2),
                                    ns=0.45, ew=1.0, blend=0.25 * minor))
        parts.append(torus("floor seam", major - 0.45 * minor, 0.06 * minor, (0, 0, fh)).model_copy(
            update={"operation": "subtract"}))
    if p.gap > 0:  # the opening at +x, its cut ends rounded off by the subtraction's blend
        parts.append(box("opening", (minor * 2.6, p.gap, 4 * zc), (0.5 - minor, 0, zc), op="subtract",
                         blend=0.6 * minor))
    return parts


class TubeParams(Model):
    """A tube or roll lying along x: pool noodle, rolled towel, foam roller, hose (optional through-hole)."""

    radius: float = Field(default=0.2, gt=0.02, le=0.5, description="outer radius / length [-]")
    hole: float = Field(default=0.0, ge=0.0, le=0.92, description="inner radius / outer radius (a fabric tube ~0.9) [-]")
    style: Literal["plain", "dart", "rocket", "sword", "javelin", "rolltop"] = Field(
        default="plain", description="dart: a foam dart's soft rounded tip at +x (part 'tip'); rocket: a foam "
        "rocket's nose cone at +x and four fins round its tail; sword: a foam sword's blade to a rounded point at "
        "+x, a crossguard, a grip and a pommel at -x; javelin: a foam javelin's rounded nose, its grip band and "
        "tail fins; rolltop: a dry bag's top rolled down and buckled at +x (the roll, its strap and buckle)")


def tube(p: TubeParams) -> list[Part]:
    """Length 1 along x."""
    r = p.radius
    if p.style == "sword":
        return _foam_sword(r)
    parts = [cylinder("body", r, 1.0, (0, 0, r), edge=0.15 * r, rot=(0, 90, 0))]
    if p.hole > 0:
        parts.append(cylinder("hole", r * p.hole, 1.2, (0, 0, r), rot=(0, 90, 0), op="subtract"))
    if p.style == "dart":  # the soft tip: a rounded cap a little wider than the shaft, the shaft's end hollow
        parts[0] = cylinder("body", r, 0.8, (-0.1, 0, r), edge=0.1 * r, rot=(0, 90, 0))
        parts.append(cylinder("tip", 1.08 * r, 0.2, (0.4, 0, r), edge=0.9 * r, rot=(0, 90, 0), blend=0.1 * r))
        parts.append(cylinder("hollow", 0.55 * r, 0.2, (-0.5, 0, r), rot=(0, 90, 0), op="subtract"))
    elif p.style == "rocket":  # nose cone at +x, four swept fins round the tail
        parts[0] = cylinder("body", r, 0.78, (-0.11, 0, r), edge=0.1 * r, rot=(0, 90, 0))
        parts.append(cone("nose", r, 0.15 * r, 0.22, (0.39, 0, r), edge=0.1 * r, rot=(0, 90, 0), blend=0.1 * r))
        for k in range(4):
            a = np.radians(45 + 90 * k)
            parts.append(box(f"fin {k + 1}", (0.2, 0.25 * r, 1.2 * r), (-0.4, 1.5 * r * np.cos(a), r + 1.5 * r * np.sin(a)),
                             edge=0.1 * r, rot=(np.degrees(a) - 90, 0, 0), blend=0.15 * r))
    elif p.style == "javelin":  # a rounded nose, a grip band at the balance point, small fins at the tail
        parts[0] = cylinder("body", r, 0.86, (-0.07, 0, r), edge=0.1 * r, rot=(0, 90, 0))
        parts.append(ellipsoid("nose", (0.09, 1.25 * r, 1.25 * r), (0.4, 0, r), blend=0.2 * r))
        parts.append(cylinder("grip", 1.12 * r, 0.12, (0.05, 0, r), edge=0.2 * r, rot=(0, 90, 0), blend=0.05 * r))
        for k in range(3):
            a = np.radians(90 + 120 * k)
            parts.append(box(f"fin {k + 1}", (0.12, 0.3 * r, 1.6 * r), (-0.44, 1.3 * r * np.cos(a), r + 1.3 * r * np.sin(a)),
                             edge=0.1 * r, rot=(np.degrees(a) - 90, 0, 0), blend=0.15 * r))
    elif p.style == "rolltop":  # the top rolled down flat at +x and its strap buckled across
        parts[0] = cylinder("body", r, 0.86, (-0.07, 0, r), edge=0.3 * r, rot=(0, 90, 0))
        parts.append(scaled(cylinder("roll", 0.45 * r, 2.3 * r, (0.42, 0, r), edge=0.3 * r, rot=(90, 0, 0),
                                     blend=0.2 * r), (1.0, 1.0, 1.0)))
        parts.append(limb("strap", (0.42, -1.1 * r, 1.42 * r), (0.42, 1.1 * r, 1.42 * r), 0.14 * r, blend=0.05 * r))
        parts.append(box("buckle", (0.1, 0.5 * r, 0.25 * r), (0.42, 0, 1.55 * r), edge=0.08 * r, blend=0.05 * r))
    return parts


def _foam_sword(r: float) -> list[Part]:
    """A foam sword lying along x: the blade to a rounded point at +x, a crossguard across it, the grip and a round
    pommel at -x."""
    z = 1.6 * r  # the guard's half-width off the ground
    return [cylinder("body", r, 0.68, (0.12, 0, z), edge=0.3 * r, rot=(0, 90, 0)),
            ellipsoid("point", (0.08, r, r), (0.46, 0, z), blend=0.2 * r),
            box("crossguard", (0.05, 6.2 * r, 1.8 * r), (-0.24, 0, z), edge=0.6 * r, blend=0.1 * r),
            cylinder("grip", 0.7 * r, 0.2, (-0.36, 0, z), edge=0.2 * r, rot=(0, 90, 0), blend=0.1 * r),
            ellipsoid("pommel", (1.1 * r, 1.1 * r, 1.1 * r), (-0.47, 0, z), blend=0.1 * r)]


class ConeParams(Model):
    """A cone, frustum or dome: party hat, ice-cream scoop, foam cone, dome (hemisphere)."""

    kind: Literal["cone", "dome"] = "cone"
    height: float = Field(default=1.2, gt=0.1, le=3.0, description="height / base diameter [-]")
    top: float = Field(default=0.1, ge=0.0, le=0.9, description="top radius / base radius (a frustum) [-]")


def cone_plan(p: ConeParams) -> list[Part]:
    """Base diameter 1 on the ground."""
    h = p.height
    if p.kind == "dome":
        return [box("body", (1.0, 1.0, h), (0, 0, h / 2)),
                ellipsoid("dome", (0.5, 0.5, h), (0, 0, 0)).model_copy(update={"operation": "intersect"})]
    return [cone("body", 0.5, 0.5 * p.top, h, (0, 0, h / 2), edge=0.04)]


class BottleParams(Model):
    """A soft plastic bottle standing on its base: a PET water bottle, a shampoo or lotion bottle, a travel bottle."""

    height: float = Field(default=2.6, gt=0.8, le=4.5, description="height with its cap / body width [-]")
    depth: float = Field(default=1.0, gt=0.3, le=1.0, description="body depth / width: 1 round, less an oval [-]")
    neck: float = Field(default=0.4, gt=0.1, le=0.9, description="neck diameter / body width [-]")
    shoulder: float = Field(default=0.18, ge=0.02, le=0.5, description="the shoulder's height / the height [-]")
    cap: Literal["screw", "flip", "pump", "nozzle", "none"] = Field(default="screw", description="nozzle: a lab "
                                                                     "wash bottle's screw cap with a thin delivery "
                                                                     "tube rising from it and bent over to the side")
    ribs: int = Field(default=0, ge=0, le=8, description="grip grooves round the body (a water bottle) [-]")
    dent: float = Field(default=0.0, ge=0.0, le=0.6, description="a side squeezed in (a half-empty bottle "
                        "crushed in a hand): the dent's depth / the body's radius [-]")


def bottle(p: BottleParams) -> list[Part]:
    """Body width 1 along y (its depth along x), standing on its base at z = 0; the cap on top."""
    h = p.height
    cap_h = {"screw": 0.09, "flip": 0.11, "pump": 0.16, "nozzle": 0.09, "none": 0.0}[p.cap] * h
    neck_h = 0.04 * h
    sh = p.shoulder * h
    zb = h - cap_h - neck_h - sh  # the body's straight wall
    rn = 0.5 * p.neck
    sx = (p.depth, 1.0, 1.0)
    parts = [scaled(cylinder("body", 0.5, zb + 0.02, (0, 0, zb / 2 + 0.01), edge=0.1), sx),
             scaled(cone("shoulder", 0.5, rn, sh, (0, 0, zb + sh / 2),
                               blend=0.06), sx),
             cylinder("neck", rn, neck_h + 0.04, (0, 0, zb + sh + neck_h / 2), blend=0.02)]
    top = zb + sh + neck_h
    if p.cap == "screw":
        parts.append(cylinder("cap", 1.12 * rn, cap_h, (0, 0, top + cap_h / 2), edge=0.15 * cap_h))
    elif p.cap == "flip":  # a flip-top cap nearly as wide as the bottle's depth (a shampoo or lotion bottle)
        rc = max(0.42, 1.2 * rn)
        parts.append(scaled(cylinder("cap", rc, cap_h, (0, 0, top + cap_h / 2), edge=0.25 * cap_h, blend=0.01),
                                  (p.depth, 1.0, 1.0)))
    elif p.cap == "pump":
        parts.append(cylinder("cap", 1.2 * rn, 0.3 * cap_h, (0, 0, top + 0.15 * cap_h), edge=0.05 * cap_h))
        parts.append(cylinder("pump stem", 0.3 * rn, 0.5 * cap_h, (0, 0, top + 0.5 * cap_h)))
        parts.append(box("pump head", (0.9 * rn, 1.6 * rn, 0.25 * cap_h), (0, 0.3 * rn, top + 0.85 * cap_h),
                         edge=0.1 * cap_h, blend=0.01))
    elif p.cap == "nozzle":  # the cap, the tube rising from it, bent over and down to a fine tip
        parts.append(cylinder("cap", 1.12 * rn, cap_h, (0, 0, top + cap_h / 2), edge=0.15 * cap_h))
        rt = 0.045
        rise = top + cap_h + 0.55
        parts.append(limb("nozzle", (0, 0, top + cap_h - 0.02), (0, 0, rise), rt, blend=0.01))
        parts.append(limb("nozzle bend", (0, 0, rise), (0, 0.42, rise - 0.08), rt, blend=0.02))
        parts.append(limb("nozzle tip", (0, 0.42, rise - 0.08), (0, 0.5, rise - 0.22), 0.7 * rt, blend=0.02))
    for i in range(p.ribs):  # grip grooves round the lower body
        z = zb * (0.25 + 0.5 * (i + 0.5) / p.ribs)
        groove = scaled(torus(f"rib {i + 1}", 0.5, 0.025, (0, 0, z)), sx)
        parts.append(groove.model_copy(update={"operation": "subtract", "blend_m": 0.02}))
    if p.dent > 0:  # the side pushed in by a hand, rounded
        dent = ellipsoid("dent", (0.35, 0.5 * p.dent + 0.1, 0.3 * zb), (0, 0.5 + 0.1 - 0.5 * p.dent, 0.5 * zb))
        parts.append(dent.model_copy(update={"operation": "subtract", "blend_m": 0.08}))
    return parts


class StarParams(Model):
    """A puffy five-pointed star lying flat (a star cushion, a star squishy)."""

    points: int = Field(default=5, ge=3, le=8)
    thickness: float = Field(default=0.25, gt=0.05, le=0.6, description="thickness / diameter [-]")
    inner: float = Field(default=0.42, gt=0.2, le=0.8, description="inner radius / outer radius [-]")


def star(p: StarParams) -> list[Part]:
    """Outer diameter 1, a point towards +x."""
    t = p.thickness
    parts = [cylinder("body", 0.5 * p.inner, t, (0, 0, t / 2), edge=0.4 * t)]
    for i in range(p.points):
        a = 2 * np.pi * i / p.points
        d = np.array([np.cos(a), np.sin(a), 0.0])
        rb = 0.5 * p.inner * np.sin(np.pi / p.points) * 1.6
        squash = min(1.0, t / 2 / rb)  # the point's local x is vertical: Rz(a) Ry(90) takes z to d and x to -z
        parts.append(cone(f"point {i + 1}", rb, 0.03, 0.37, d * 0.285 + np.array([0, 0, t / 2]), edge=0.02,
                          blend=0.04, rot=(0, 90, float(np.degrees(a))), scale=(squash, 1, 1)))
    return parts


class HeartParams(Model):
    """A puffy heart lying flat, its point towards -x."""

    thickness: float = Field(default=0.3, gt=0.05, le=0.8, description="thickness / width [-]")


def heart(p: HeartParams) -> list[Part]:
    """Width 1 along y."""
    t = p.thickness
    lobes = [ellipsoid(f"{side} lobe", (0.27, 0.27, t / 2), (0.12, s * 0.22, t / 2), blend=0.05)
             for side, s in (("left", 1), ("right", -1))]
    body = tapered("body", (0.05, 0, t / 2), (-0.5, 0, t / 2), 0.4, 0.03, blend=0.08)
    tf = body.transform
    body = body.model_copy(update={"transform": tf.model_copy(update={"scale": (t / 0.8, 1, 1)})})
    return [body] + lobes


class BoneParams(Model):
    """A dog-bone chew toy: a shaft with two knobs at each end."""

    shaft_radius: float = Field(default=0.09, gt=0.02, le=0.25, description="shaft radius / length [-]")
    knob_radius: float = Field(default=0.12, gt=0.03, le=0.3)


def bone(p: BoneParams) -> list[Part]:
    """Length 1 along x, lying flat."""
    k = p.knob_radius
    z = k
    parts = [limb("shaft", (-0.35, 0, z), (0.35, 0, z), p.shaft_radius)]
    for sx, nx in ((1, "front"), (-1, "rear")):
        for sy, ny in ((1, "left"), (-1, "right")):
            parts.append(ellipsoid(f"{nx} {ny} knob", (k, k, k), (sx * (0.5 - k), sy * 0.8 * k, z), blend=0.03))
    return parts


class EggParams(Model):
    """An egg, a teardrop or a pebble (one end blunter than the other), lying on its side."""

    aspect: float = Field(default=0.75, gt=0.3, le=1.0, description="width / length [-]")
    pointiness: float = Field(default=0.35, ge=0.0, le=0.9, description="how much narrower the front end is [-]")
    squash: float = Field(default=1.0, gt=0.2, le=1.0, description="height / width (a pebble) [-]")
    knot: bool = Field(default=False, description="a tied neck and knot at the narrow end (a blown-up balloon)")


FLAT_EGG_SQUASH = 0.5  # an egg plan flatter than this lies on the table along its length [-]


def egg(p: EggParams) -> list[Part]:
    """Length 1 along x, blunt end at -x."""
    w = p.aspect * 0.5
    h = w * p.squash
    # a flattened one (a fillet, a pebble) lies on the table along its length, its narrow end thinning a little and
    # resting on it too (held up at the blunt end's mid-height and thinned as much as narrowed, it left a step, read
    # as a seam); a round egg's axis stays level
    flat = p.squash < FLAT_EGG_SQUASH
    hf = h * (1 - (0.35 if flat else 1.0) * p.pointiness)
    zf = hf if flat else h
    parts = [ellipsoid("body", (0.32, w, h), (-0.18, 0, h)),
             ellipsoid("front", (0.36, w * (1 - p.pointiness), hf), (0.14, 0, zf), blend=0.25)]
    if p.knot:  # the neck pinched beyond the tip, a tied knot and its rolled lip
        tip = 0.14 + 0.36
        parts += [limb("neck", (tip - 0.03, 0, h), (tip + 0.05, 0, h), 0.022, blend=0.02),
                  ellipsoid("knot", (0.035, 0.045, 0.045), (tip + 0.075, 0, h), blend=0.01),
                  cylinder("knot lip", 0.04, 0.025, (tip + 0.115, 0, h), edge=0.01, rot=(0, 90, 0), blend=0.008)]
    return parts


class CloudParams(Model):
    """A cloud-shaped cushion: overlapping puffs along x."""

    puffs: int = Field(default=4, ge=2, le=8)
    thickness: float = Field(default=0.35, gt=0.1, le=1.0, description="thickness / length [-]")


def cloud(p: CloudParams) -> list[Part]:
    """Length about 1 along x, standing in the x-z plane on a flat base."""
    t = p.thickness
    parts = [superellipsoid("body", (0.5, t / 2, 0.16), (0, 0, 0.16), ns=0.5, ew=0.8)]
    xs = np.linspace(-0.3, 0.3, p.puffs)
    for i, x in enumerate(xs):
        r = 0.18 + 0.06 * np.cos(np.pi * x / 0.6)
        parts.append(ellipsoid(f"puff {i + 1}", (r, t / 2, r), (float(x), 0, 0.16 + 0.4 * r), blend=0.05))
    return parts


class CactusParams(Model):
    """A cactus plush: an upright column with arms."""

    arms: int = Field(default=2, ge=0, le=2)
    pot: bool = True


def cactus(p: CactusParams) -> list[Part]:
    """Height about 1."""
    z0 = 0.22 if p.pot else 0.0
    parts = [limb("body", (0, 0, z0 + 0.12), (0, 0, z0 + 0.65), 0.12)]
    for i, (s, h) in enumerate(((1, 0.4), (-1, 0.5))[: p.arms]):
        parts.append(limb(f"arm {i + 1}", (0, s * 0.1, z0 + h), (0, s * 0.25, z0 + h), 0.06, blend=0.03))
        parts.append(limb(f"arm {i + 1} tip", (0, s * 0.25, z0 + h), (0, s * 0.25, z0 + h + 0.18), 0.06, blend=0.03))
    if p.pot:
        parts.append(cone("pot", 0.14, 0.18, 0.24, (0, 0, 0.12), edge=0.02, blend=0.02))
    return parts


class BlobParams(Model):
    """A blob of slime, putty or dough: a slumped rounded lump."""

    height: float = Field(default=0.45, gt=0.1, le=1.0, description="height / width [-]")
    elongation: float = Field(default=1.0, gt=0.5, le=2.5)


def blob(p: BlobParams) -> list[Part]:
    """Width 1, flat underside."""
    h = p.height
    return [superellipsoid("body", (0.5 * p.elongation, 0.5, h / 2), (0, 0, h / 2), ns=0.55, ew=1.0)]


# ------------------------------------------------------------------------------------------------------ bath pouf
class PoufParams(Model):
    """A bath pouf (shower puff): a ball of gathered nylon netting, its ruffled layers standing out all round a small
    gathered core, a cord loop tied at the middle. Diameter 1."""

    ruffles: int = Field(default=40, ge=8, le=64, description="ruffled layers of netting round the core [-]")
    cord: bool = Field(default=True, description="the hanging cord loop")


def pouf(p: PoufParams) -> list[Part]:
    """A gathered core (z = 0.5) under many small ruffles; each ruffle a thin disc whose plane holds its radial
    direction (the netting's layers fan out like a peony's petals), spread evenly (a Fibonacci sphere); the doubled
    cord out of its side on the table."""
    centre = np.array([0.0, 0.0, 0.5])
    parts = [ellipsoid("core", (0.45, 0.45, 0.43), tuple(centre))]
    n = p.ruffles
    golden = np.pi * (3.0 - np.sqrt(5.0))
    for i in range(n):
        z = 1.0 - 2.0 * (i + 0.5) / n
        r = np.sqrt(max(1.0 - z * z, 0.0))
        d = np.array([r * np.cos(golden * i), r * np.sin(golden * i), z])
        side = np.cross(d, [0.31, 0.52, 0.79] if abs(d[2]) < 0.9 else [1.0, 0.0, 0.0])
        side = side / np.linalg.norm(side)
        normal = np.cos(1.7 * i) * side + np.sin(1.7 * i) * np.cross(d, side)  # each layer turned its own way
        rad = 0.13 + 0.02 * np.sin(3.1 * i)  # a ridge of gathered netting standing ~0.05 out of the core
        parts.append(ellipsoid(f"ruffle {i + 1}", (rad, 0.8 * rad, 0.045), tuple(centre + (0.5 - rad) * d),
                               blend=0.05, rot=_euler_z_to(normal)))
    if p.cord:  # the cord, doubled, out of its side and lying on the table (no open loop: a hull would fill it)
        a = centre + np.array([0.38, 0.0, -0.22])
        b = np.array([0.66, 0.0, 0.025])
        for k, dy in enumerate((-0.022, 0.022)):
            parts.append(limb(f"cord {k + 1}", a + np.array([0.0, dy, 0.0]), b + np.array([0.0, dy, 0.0]), 0.022,
                              blend=0.01))
        parts.append(ellipsoid("cord knot", (0.035, 0.05, 0.03), tuple(b), blend=0.01))
    return parts
