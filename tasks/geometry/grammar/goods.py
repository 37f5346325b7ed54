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

import warnings
from collections.abc import Iterator
from typing import Literal

import numpy as np
from pydantic import Field
from scipy.spatial.transform import Rotation

from contracts.base import Model
from contracts.shape import MAX_PARTS, Part
from tasks.geometry.grammar.parts import (
    box,
    cone,
    cylinder,
    ellipsoid,
    limb,
    part_group,
    rotated_parts,
    scaled,
    superellipsoid,
    swept,
    tapered,
    torus,
)

MIN_LAYER = 0.025  # a built sheet layer, / the flat sheet's length [-]
CRISP_STACK_DRAWN = 2  # cut sheets drawn in a stack of them (the rest in the pad's thickness) [-]
MIN_WALL = 0.03  # a built mould or hat wall, / the outline's size [-]

SheetState = Literal["flat", "rolled", "folded", "stacked", "crumpled", "loop", "twisted", "knotted", "draped"]


def _op(part: Part, op: str, blend: float = 0.0) -> Part:
    return part.model_copy(update={"operation": op, "blend_m": blend})


# ----------------------------------------------------------------------------------------------------------- sheets
class SheetParams(Model):
    """A flat good: mat, towel, blanket, sheet, napkin, pad, tortilla, slice. Length 1 along x when flat."""

    state: SheetState = Field(default="flat", description="flat; crumpled (a bunched heap); rolled (a roll along the "
                              "sheet's width, the layers "
                              "seen as rings at its ends); folded (halved `folds` times); stacked (`layers` sheets); "
                              "knotted (tied in a loose knot at its middle, a scarf); draped (hung over a bar at its "
                              "middle: two panels falling from a rounded fold, their hems splayed)")
    shape: Literal["rect", "round", "bib", "hourglass", "envelope", "mask", "bread", "puzzle", "hammock"] = Field(
        default="rect", description="a rectangle or a round sheet (tortilla, pad); laid flat: a bib (its neck cut out, "
        "the straps' snap), an hourglass (a nappy: leg cut-outs, padded core, waist tabs), an envelope (a padded "
        "mailer: sealed edges and its flap), a mask (a pleated face mask with its nose wire and ear loops), bread (a "
        "slice of sandwich bread: a square foot, a rounded top, the crust round the crumb), puzzle (a foam floor "
        "tile: round tabs along two sides, their sockets cut in the other two), hammock (its bed between two spreader "
        "bars, the cords fanning to a ring at each end, a rope beyond)")
    width: float = Field(default=0.5, gt=0.002, le=1.0, description="width / length [-]")
    thickness: float = Field(default=0.005, gt=0.0, le=0.2, description="the real sheet's thickness / length [-]")
    folds: int = Field(default=1, ge=1, le=3, description="halvings when folded [-]")
    layers: int = Field(default=4, ge=2, le=12, description="sheets in a stack [-]")
    core: float = Field(default=0.12, ge=0.0, le=0.6, description="a roll's hole radius / roll radius [-]")
    packing: float = Field(default=0.8, gt=0.2, le=1.0, description="share of a roll's cross-section that is sheet [-]")
    edge: float = Field(default=0.5, ge=0.0, le=1.0, description="edge rounding / half the layer [-]")
    crisp: bool = Field(default=False, description="cut sheets with square edges (paper, felt, craft foam): stacked, "
                        "a squared pad of a few sheets, not soft folded layers")
    tail: float = Field(default=0.0, ge=0.0, le=12.0, description="a roll partly unrolled: its free end lying out "
                        "flat on the ground in front of it, this many roll diameters long; 0 none [-]")
    thirds: bool = Field(default=False, description="folded in thirds (a letter fold: three layers, a crease at each "
                         "end) before any further halving")
    quilt: int = Field(default=0, ge=0, le=16, description="puffy baffles across the length (a duvet, a sleeping bag, "
                       "a quilted mat): stitched grooves between rounded channels [-]")
    grid: bool = Field(default=False, description="quilted in squares (grooves along the length too)")
    fringe: bool = Field(default=False, description="a fringe of tassels at both short ends (a scarf, a rug)")
    ribs: int = Field(default=0, ge=0, le=9, description="knit ribs: shallow grooves along the length [-]")
    zip: bool = Field(default=False, description="a zip along one long side (a sleeping bag)")
    curl: float = Field(default=0.0, ge=0.0, le=0.45, description="flat: each corner lifted, curling up from a "
                        "hinge across it this share of the width from the corner (a baking mat's curling corners) [-]")
    bubbles: bool = Field(default=False, description="rolled: the outer layer's air bubbles, rows of them over the "
                          "roll, and its loose end lying out in front covered in them (bubble wrap); flat: a "
                          "staggered grid of them over the top")
    spiral: bool = Field(default=False, description="rolled: the sheet's spiral cut into both ends of the roll, "
                         "coarse enough to see, no hole (a rolled yoga mat, not a foam tube)")
    stiff: bool = Field(default=False, description="a stiff sheet (paper, foil, baking paper): crumpled, it is a round "
                        "wad of creased facets in the hand's size, not a heap of cloth")
    stripes: int = Field(default=0, ge=0, le=9, description="woven or printed bands across the length over the top "
                         "(a tea towel's, a blanket's or a scarf's stripes), parts 'stripe', their own colour [-]")
    checks: bool = Field(default=False, description="with stripes: bands along the length too, a gingham check")
    hem: bool = Field(default=False, description="a hemmed border round the top's edge, its own colour (part 'hem')")
    printed: Literal["none", "newspaper", "magazine"] = Field(
        default="none", description="printing over the top: newspaper (a headline band, columns of grey text lines and "
        "a photo); magazine (a cover: a masthead band, a cover photo, cover lines)")
    grommets: int = Field(default=0, ge=0, le=6, description="metal eyelets along each long edge, corners included "
                          "(a tarp), parts 'grommet' [-]")
    open_end: bool = Field(default=False, description="one short end open (a pillowcase): a wide hem band across "
                           "it (part 'cuff'), and laid flat the mouth cut into its edge")
    hood: bool = Field(default=False, description="flat: a sleeping bag's hood at the +x end (a rounded raised head "
                       "end, its face opening a dark oval) and a foot tapered toward -x")
    border: bool = Field(default=False, description="folded: a towel's woven border (dobby) band across the top near "
                         "each end, a raised stripe (parts 'border'); a towel's strongest cue")
    straps: bool = Field(default=False, description="rolled: two compression straps round the roll, each with its "
                         "buckle, the roll cinched under them (a rolled sleeping bag; a yoga mat has none)")


CURL_DEG = 38.0  # how far a curling corner lifts about its hinge [deg]


def curled_corners(length: float, width: float, t: float, c: float) -> list[Part]:
    """A flat sheet's four corners curling up: each corner's triangle (legs `c`) cut from the sheet and a flap over
    it turned up CURL_DEG about the hinge across the corner (two short layers, the second turned further, read as a
    curl)."""

    cuts: list[Part] = []
    flaps: list[Part] = []
    for k, (sx, sy) in enumerate(((1, 1), (-1, 1), (-1, -1), (1, -1))):
        corner = np.array([sx * length / 2, sy * width / 2, 0.0])
        d = np.array([sx, sy, 0.0]) / np.sqrt(2)  # outward along the corner's diagonal
        hinge_dir = np.array([sx, -sy, 0.0]) / np.sqrt(2) * (sx * sy)  # turning d about it lifts d towards +z
        mid = corner - np.array([sx, sy, 0.0]) * c / 2
        cuts.append(box(f"corner cut {k + 1}", (c, c, 4 * t), (corner[0], corner[1], t / 2),
                        rot=(0, 0, 45.0), op="subtract"))
        yaw = Rotation.from_euler("z", np.degrees(np.arctan2(d[1], d[0])), degrees=True)
        reach = c / np.sqrt(2)  # from the hinge to the corner
        start = mid.copy()
        for j, (share, angle) in enumerate(((0.55, CURL_DEG * 0.6), (0.45, CURL_DEG * 1.6))):
            turn = Rotation.from_rotvec(np.radians(angle) * hinge_dir) * yaw
            seg = share * reach
            centre = start + turn.apply(np.array([seg / 2, 0.0, 0.0])) + np.array([0.0, 0.0, t / 2])
            euler = tuple(float(e) for e in turn.as_euler("xyz", degrees=True))
            flaps.append(box(f"corner {k + 1} curl {j + 1}", (seg * 1.06, 2 * reach, t), tuple(centre), edge=0.45 * t,
                             rot=euler, blend=0.3 * t))
            start = start + turn.apply(np.array([seg, 0.0, 0.0]))
    return cuts + flaps


QUILT_DEPTH = 0.45  # a baffle groove's depth / the quilted layer [-]
PUFF = 2.2  # a quilted (down-filled) layer / the sheet's built layer [-]


def sheet_layer(p: SheetParams) -> float:
    """The built thickness of one layer in the unit frame (the flat sheet's length is 1) [-]."""
    return max(p.thickness, MIN_LAYER)


def _slab(name: str, p: SheetParams, length: float, width: float, t: float, at: tuple[float, float, float],
          rot: tuple[float, float, float] = (0, 0, 0)) -> Part:
    e = p.edge * t / 2
    if p.shape == "round":
        return scaled(cylinder(name, width / 2, t, at, edge=e, rot=rot), (length / width, 1, 1))
    return box(name, (length, width, t), at, edge=e, rot=rot)


def sheet(p: SheetParams) -> list[Part]:
    """Flat: length 1 along x, width along y. Rolled: the roll's axis along x (its length the sheet's width)."""
    t = sheet_layer(p)
    w = p.width
    if p.state == "flat" and p.shape in FORMED_SHEETS:
        return FORMED_SHEETS[p.shape](w, t)
    if p.state == "flat":
        if p.quilt:
            t = PUFF * t
        rects = decor_rects(p, 1.0, w) if p.shape == "rect" else []
        parts = tiled_top(rects, 1.0, w, 0.0, t, "body", reserve=sheet_extras(p)) if rects else [_slab("body", p, 1.0, w, t, (0, 0, t / 2))]
        parts += grommets(p, 1.0, w, t) if p.grommets else []
        parts += quilting(1.0, w, t, p.quilt, p.quilt if p.grid else 0)
        parts += knit_ribs(1.0, w, t, p.ribs) + (fringe(1.0, w, t) if p.fringe else [])
        if p.zip:
            parts.append(box("zip", (0.96, 0.018, 0.5 * t), (0, -w / 2 + 0.02, t), edge=0.2 * t, blend=0.004))
        if p.curl > 0 and p.shape == "rect":
            parts += curled_corners(1.0, w, t, p.curl * w)
        if p.hood:
            parts += _hood(w, t)
        if p.open_end:
            parts += _open_end(w, t)
        if p.bubbles:
            parts += _bubble_grid(1.0, w, t, MAX_PARTS - len(parts))
        return parts
    if p.state == "loop":
        return _strip_loop(p, t)
    if p.state == "stacked" and p.shape in FORMED_SHEETS:  # a stack of bread slices: each its own outline
        one = FORMED_SHEETS[p.shape](w, t)
        if p.shape == "bread" and len(one) * p.layers > MAX_PARTS:
            one = bread_slice(w, t, arc=5)  # (the crust's arc in fewer segments: three slices in one program)
        return stacked_formed(one, min(p.layers, MAX_PARTS // len(one)), t)
    if p.state == "stacked" and p.crisp:  # cut sheets (paper, felt, craft foam): a squared pad as thick as the
        # stack (at least a built layer per sheet drawn), a few sheets drawn, each a little askew so their edges show
        total = max(p.thickness * p.layers, MIN_LAYER * min(p.layers, CRISP_STACK_DRAWN))
        n = int(min(p.layers, CRISP_STACK_DRAWN, max(total // MIN_LAYER, 1)))
        tl = total / n
        flat = p.model_copy(update={"edge": 0.15})
        return [_slab("body" if i == 0 else f"layer {i + 1}", flat, 1.0, w, 1.02 * tl,
                      (0.01 * np.sin(2.3 * i), 0.01 * np.cos(1.7 * i) * w, tl / 2 + tl * i),
                      rot=(0, 0, 1.2 * np.sin(3.1 * i))) for i in range(n)]
    if p.state == "stacked":
        parts = []
        for i in range(p.layers):
            jitter = (0.012 * np.sin(2.3 * i), 0.012 * np.cos(1.7 * i))
            parts.append(_slab("body" if i == 0 else f"layer {i + 1}", p.model_copy(update={"edge": 1.0}), 1.0, w, t,
                               (jitter[0], jitter[1] * w, t / 2 + 0.96 * t * i), rot=(0, 0, 1.5 * np.sin(3.1 * i))))
        return parts
    if p.state == "folded":
        return _folded(p, t)
    if p.state == "crumpled":
        if p.stiff:
            return wad(wad_size(w), seed=0.3 + 3 * w)
        if p.quilt:  # a sleeping bag or a duvet bunched up: its flaps puffy baffled tubes, its zip along one
            d, height = crumpled_size(w)
            return quilted_heap(d, height, t * PUFF, seed=0.3 + 3 * w, zip_=p.zip)
        return cloth_heap(p, t)
    if p.state == "twisted":
        return _twisted(p)
    if p.state == "knotted":
        return _knotted(p)
    if p.state == "draped":
        return _draped(p, t)
    return _rolled(p)


DRAPE_BAR = 0.025  # the radius of the bar a draped sheet hangs over, / the sheet's length [-]
DRAPE_SPLAY = 0.22  # how far a draped panel's hem swings out, / the panel's drop [-]
DRAPE_RIPPLES = 3  # soft vertical folds down each draped panel [-]
DRAPE_WAVE = 0.05  # the folds' depth / the sheet's width [-]


def _draped(p: SheetParams, t: float) -> list[Part]:
    """A sheet hung over a bar at its middle (a towel over a rail, a scarf over a bar): the fold round the bar's top
    (the bar along y, not drawn) and the two panels falling from it, each splayed out toward its hem and waved by
    soft vertical folds (strips turned alternately); standing on the hems, its length and area the flat sheet's."""
    w, r = p.width, DRAPE_BAR + t / 2
    drop = max(0.5 - 0.5 * np.pi * r, 0.05)  # each panel's length below the fold
    splay = np.arcsin(DRAPE_SPLAY)  # the panel's tilt from vertical [rad]
    top = drop * np.cos(splay)  # the fold's centre above the ground
    parts = []
    n_arc = 5
    for k in range(n_arc):  # the fold: short slabs round the bar's top half
        a0, a1 = np.pi * k / n_arc, np.pi * (k + 1) / n_arc
        mid = 0.5 * (a0 + a1)
        seg = 2 * r * np.sin(0.5 * (a1 - a0)) + 0.6 * t
        parts.append(box("body" if k == 2 else f"fold {k + 1}", (seg, w, t),
                         (r * np.cos(mid), 0.0, top + r * np.sin(mid)), edge=0.45 * t,
                         rot=(0.0, -np.degrees(mid) + 90.0, 0.0)))
    strips = 2 * DRAPE_RIPPLES
    dy = w / strips
    amp = DRAPE_WAVE * w  # the folds' depth, across the panel
    theta = np.degrees(np.arctan2(amp, dy))
    for side, sgn in (("left", -1.0), ("right", 1.0)):
        x0 = sgn * r
        panel = [box(f"{side} panel" if j == 0 else f"{side} panel {j + 1}", (t, np.hypot(dy, amp) + 0.5 * t,
                                                                           drop + 0.3 * t),
                     (x0 + sgn * amp / 2, -w / 2 + (j + 0.5) * dy, top - drop / 2), edge=0.45 * t,
                     rot=(0.0, 0.0, theta if j % 2 else -theta)) for j in range(strips)]
        parts += rotated_parts(panel, (0.0, -sgn * np.degrees(splay), 0.0), (x0, 0.0, top))
    return parts


def stacked_formed(one: list[Part], layers: int, t: float) -> list[Part]:
    """`layers` copies of a formed sheet (a slice of bread, a bib) stacked as they fall, each turned and shifted a
    little; a copy's parts keep their names' groups (its crust is crust)."""
    parts: list[Part] = []
    for i in range(layers):
        turned = rotated_parts(one, (0.0, 0.0, 4.0 * np.sin(3.1 * i)))
        for q in turned:
            tf = q.transform
            x, y, z = tf.translation_m
            at = (x + 0.012 * np.sin(2.3 * i), y + 0.012 * np.cos(1.7 * i), z + 0.96 * t * i)
            parts.append(q.model_copy(update={"name": q.name if i == 0 else f"{q.name} {i + 1}",
                                              "transform": tf.model_copy(update={"translation_m": at})}))
    return parts


TWIST_LOBES = 7  # the twisted rope's turns drawn as lobes along it [-]
TWIST_PACKING = 0.5  # share of a wrung cloth's rope that is cloth [-]


def _twisted(p: SheetParams) -> list[Part]:
    """A cloth wrung out: twisted along its diagonal into a rope (0.65 of the diagonal long, its cross-section holding
    the cloth at TWIST_PACKING), lobes turning round it, the cloth's two corners flared at the ends; along x, on the
    ground."""
    w = p.width
    length = 0.65 * float(np.hypot(1.0, w))
    r = float(np.sqrt(w * max(p.thickness, 1e-4) / (TWIST_PACKING * np.pi * length)))
    r = max(r, 0.03 * length)
    parts = [cylinder("body", 0.85 * r, length, (0, 0, r), edge=0.4 * r, rot=(0, 90, 0))]
    for k in range(TWIST_LOBES):
        x = -0.5 * length + (k + 0.5) * length / TWIST_LOBES
        parts.append(ellipsoid(f"twist {k + 1}", (0.8 * length / TWIST_LOBES, 1.1 * r, 0.75 * r), (x, 0, r),
                               blend=0.35 * r, rot=(45.0 * k, 0, 25.0)))
    for side, sgn in (("left", 1.0), ("right", -1.0)):
        parts.append(ellipsoid(f"{side} corner", (0.7 * r, 1.4 * r, 0.35 * r), (sgn * (0.5 * length + 0.3 * r), 0, 0.6 * r),
                               blend=0.3 * r, rot=(30.0 * sgn, 0, 20.0 * sgn)))
    return parts


KNOT_TAIL = 0.3  # each tail of a scarf tied in a knot at its middle, / the flat scarf's length [-]


def _knotted(p: SheetParams) -> list[Part]:
    """A long cloth tied in a loose knot at its middle, lying on the ground along x: the knot (a lump with the band
    wrapped round it), the two tails out of it, gathered at the knot and spreading to the cloth's full width at the
    ends, a little curved."""
    w = p.width
    t = sheet_layer(p)
    r = max(float(np.sqrt(w * max(p.thickness, 1e-4) / (TWIST_PACKING * np.pi))), 0.035)
    parts = [ellipsoid("body", (2.0 * r, 1.7 * r, 1.0 * r), (0, 0, 1.0 * r)),
             scaled(torus("knot wrap", 1.25 * r, 0.6 * r, (0, 0, 1.0 * r), rot=(90, 0, 15), blend=0.3 * r),
                     (1.0, 1.0, 0.8))]
    seg = KNOT_TAIL / 3
    for side, sgn in (("left", -1.0), ("right", 1.0)):
        x, y = sgn * 1.5 * r, 0.0
        for i, (share, high, turn) in enumerate(((0.35, 1.0, 8.0), (0.6, 0.55, -4.0), (0.9, 0.0, 10.0))):
            yaw = sgn * turn
            cx = x + sgn * 0.5 * seg * np.cos(np.radians(yaw))
            cy = y + 0.5 * seg * np.sin(np.radians(yaw)) * sgn
            thick = max(high * r, t)
            parts.append(box(f"{side} tail" if i < 2 else f"{side} end", (seg * 1.1, share * w, thick),
                             (cx, cy, thick / 2), edge=0.45 * thick, blend=0.5 * r, rot=(0, 0, yaw)))
            x, y = x + sgn * seg * np.cos(np.radians(yaw)), y + seg * np.sin(np.radians(yaw)) * sgn
    return parts


def bib(w: float, t: float) -> list[Part]:
    """A baby bib lying flat, length 1 along x: a rounded body, the neck cut out near +x and opened to that edge
    between the two straps, a snap on each strap's end, a piped edge."""
    rn = 0.2 * min(w, 1.0)  # the neck's radius
    xn = 0.5 - 0.3 * min(w, 1.0)
    parts = [scaled(cylinder("body", w / 2, t, (0, 0, t / 2), edge=0.45 * t), (1.0 / w, 1, 1)),
             scaled(torus("piping", w / 2 - 0.4 * t, 0.7 * t, (0, 0, 0.7 * t)), (1.0 / w, 1, 0.8)),
             _op(cylinder("neck", rn, 4 * t, (xn, 0, t / 2)), "subtract", 0.2 * t),
             _op(box("neck opening", (0.6, 1.1 * rn, 4 * t), (xn + 0.3, 0, t / 2)), "subtract", 0.2 * t)]
    for side, y in (("left", -1.0), ("right", 1.0)):
        parts.append(cylinder(f"{side} snap", 0.04, 1.0 * t, (xn + 0.55 * rn, y * (rn + 0.07), 1.1 * t),
                              edge=0.3 * t, blend=0.2 * t))
    return parts


def hourglass(w: float, t: float) -> list[Part]:
    """A disposable nappy opened flat, length 1 along x: the padded core down its middle, the leg openings cut from
    both sides, a waistband across the front (+x) and the fastening tabs out from the back (-x)."""
    depth = 0.2 * w  # each leg cut-out's depth from the side
    r = 0.42
    parts = [box("body", (1.0, w, t), (0, 0, t / 2), edge=0.45 * t)]
    for side, y in (("left", -1.0), ("right", 1.0)):
        leg = scaled(cylinder(f"{side} leg opening", r, 4 * t, (0.0, 0.0, t / 2)), (1.0, depth / r * 1.6, 1.0))
        leg = leg.model_copy(update={"transform": leg.transform.model_copy(update={
            "translation_m": (0.04, y * (w / 2 + 1.6 * depth - depth), t / 2)})})
        parts.append(_op(leg, "subtract", 0.3 * t))
        parts.append(box(f"{side} tab", (0.09, 0.1, 0.5 * t), (-0.4, y * (w / 2 + 0.03), 0.25 * t), edge=0.2 * t,
                         blend=0.2 * t))
    parts.append(superellipsoid("core", (0.38, 0.5 * (w - 2 * depth), 1.3 * t), (0.0, 0.0, t), ns=0.5, ew=0.4,
                                blend=0.5 * t))
    parts.append(box("waistband", (0.07, 0.96 * w, 0.4 * t), (0.45, 0, t), edge=0.2 * t, blend=0.2 * t))
    return parts


def envelope(w: float, t: float) -> list[Part]:
    """A padded mailer lying flat, length 1 along x: a flat padded body, its crimped seals along both sides and the
    closed end, the open end's flap (a trapezoid) folded over at +x with its peel strip."""
    parts = [superellipsoid("body", (0.5, w / 2, t / 2), (0, 0, t / 2), ns=0.35, ew=0.1)]
    for side, y in (("left", -1.0), ("right", 1.0)):
        parts.append(box(f"{side} seal", (0.98, 0.035, 0.45 * t), (0, y * (w / 2 - 0.02), 0.75 * t), edge=0.15 * t,
                         blend=0.1 * t))
    parts.append(box("end seal", (0.035, w - 0.02, 0.45 * t), (-0.48, 0, 0.75 * t), edge=0.15 * t, blend=0.1 * t))
    flap = 0.16
    parts.append(box("flap", (flap, 0.98 * w, 0.35 * t), (0.5 - flap / 2, 0, 1.05 * t), edge=0.12 * t,
                     blend=0.1 * t))
    for side, y in (("left", -1.0), ("right", 1.0)):  # the flap's cut corners
        parts.append(_op(box(f"{side} flap corner", (0.3, 0.3, 0.5 * t), (0.5 - flap - 0.02, y * (w / 2 + 0.02),
                                                                            1.1 * t), rot=(0, 0, 45)), "subtract"))
    parts.append(box("peel strip", (0.03, 0.8 * w, 0.2 * t), (0.5 - flap + 0.04, 0, 1.25 * t), edge=0.08 * t))
    return parts


def face_mask(w: float, t: float) -> list[Part]:
    """A pleated face mask lying flat, length 1 along x: the body, three pleats across its height (ridges along x),
    the nose wire along the top edge, and an elastic ear loop lying flat at each short end."""
    parts = [box("body", (1.0, w, t), (0, 0, t / 2), edge=0.3 * t)]
    for k, y in enumerate((-0.24, 0.0, 0.24)):
        parts.append(box(f"pleat {k + 1}", (0.97, 0.06 * w + t, 0.7 * t), (0, y * w, 1.05 * t), edge=0.3 * t,
                         blend=0.25 * t))
    parts.append(box("nose wire", (0.55, 0.03 + 0.5 * t, 0.5 * t), (0, w / 2 - 0.05, 1.0 * t), edge=0.2 * t))
    loop = max(0.6 * t, 0.012)  # the elastic's radius, as thick as the body shows it at draft
    for side, x in (("left", -1.0), ("right", 1.0)):
        parts.append(scaled(torus(f"{side} ear loop", 0.4 * w, loop, (x * 0.52, 0, loop)), (0.55, 1.0, 1.0)))
    return parts


def bread_slice(w: float, t: float, arc: int = 15) -> list[Part]:
    """A slice of sandwich bread lying flat, length 1 along x (the loaf's height): the crumb, a square foot and a
    rounded top a little wider than it, and the crust a rounded rim along its outline (`arc` points round the top)."""
    parts = [box("body", (0.8, 0.9 * w, 0.9 * t), (-0.1, 0, t / 2), edge=0.15 * t),
             scaled(cylinder("top crumb", w / 2, 0.9 * t, (0.28, 0, t / 2), edge=0.15 * t), (0.44 / w, 1.0, 1.0))]
    top = [(0.28 + 0.22 * np.cos(a), (w / 2) * np.sin(a), t / 2) for a in np.radians(np.linspace(-100, 100, arc))]
    outline = np.array([(-0.5, 0.45 * w, t / 2), (-0.5, -0.45 * w, t / 2), (0.2, -0.45 * w, t / 2), *top,
                        (0.2, 0.45 * w, t / 2), (-0.5, 0.45 * w, t / 2)])
    return parts + swept(["crust"], outline, np.full(len(outline), 0.5 * t), blend=0.1 * t)


PUZZLE_TABS = 4  # tabs along each side of a foam puzzle mat tile [-]


def puzzle_tile(w: float, t: float) -> list[Part]:
    """An interlocking foam floor tile lying flat, length 1 along x: a square slab whose +x and +y sides carry round
    tabs and whose -x and -y sides are cut with the sockets they fit (a playroom or gym floor's EVA mat)."""
    r = 0.055
    inner = (1.0 - 2 * r, w - 2 * r)  # the slab between the tabs' reach
    parts = [box("body", (inner[0], inner[1], t), (0, 0, t / 2), edge=0.2 * t)]
    for axis in (0, 1):
        span = inner[1 - axis]
        for k in range(PUZZLE_TABS):
            along = -span / 2 + (k + 0.5) * span / PUZZLE_TABS
            edge = inner[axis] / 2
            for kind, sgn in (("tab", 1.0), ("socket", -1.0)):
                c = sgn * (edge + (0.55 * r if kind == "tab" else -0.55 * r))
                at = (c, along, t / 2) if axis == 0 else (along, c, t / 2)
                head = cylinder(f"{kind} {axis * PUZZLE_TABS + k + 1}", r * (1.0 if kind == "tab" else 1.08),
                                t * (1.0 if kind == "tab" else 1.5), at, edge=0.15 * t)
                parts.append(head if kind == "tab" else _op(head, "subtract"))
    return parts


HAMMOCK_SAG = 0.12  # how far a hung hammock's bed sags below its spreader bars, / its length [-]
HAMMOCK_BED_SEGMENTS = 6  # straight pieces of the sagging bed [-]


def hammock(w: float, t: float) -> list[Part]:
    """A hammock as it hangs, length 1 along x: the fabric bed sagging in a curve between two spreader bars across
    its ends, resting on the ground at its lowest, the suspension cords fanning up from each bar to a ring, and a
    short rope beyond each ring. (Laid out flat between its bars it read as a folding camp cot, session 38.)"""
    bed = 0.66
    sag = HAMMOCK_SAG
    rb = max(0.6 * t, 0.016)

    def z_bed(x: float) -> float:  # the bed's middle surface: a parabola, its lowest at t / 2
        return t / 2 + sag * (2 * x / bed) ** 2

    parts = []
    n = HAMMOCK_BED_SEGMENTS
    for i in range(n):
        x0, x1 = -bed / 2 + bed * i / n, -bed / 2 + bed * (i + 1) / n
        dz = z_bed(x1) - z_bed(x0)
        seg = float(np.hypot(x1 - x0, dz)) + 0.5 * t
        pitch = -float(np.degrees(np.arctan2(dz, x1 - x0)))
        parts.append(box("body" if i == 0 else f"bed {i + 1}", (seg, w, t), (0.5 * (x0 + x1), 0.0, 0.5 * (z_bed(x0) + z_bed(x1))),
                         edge=0.45 * t, rot=(0, pitch, 0), blend=0.3 * t))
    cords = 4
    for side, sx in (("left", -1.0), ("right", 1.0)):
        xb = sx * (bed / 2 + 0.01)
        zb = z_bed(bed / 2) + 0.5 * rb
        parts.append(limb(f"{side} spreader bar", (xb, -0.56 * w, zb), (xb, 0.56 * w, zb), rb, blend=0.2 * t))
        ring = np.array([sx * 0.45, 0.0, zb + 0.06])
        for k in range(cords):
            y = -0.45 * w + 0.9 * w * k / (cords - 1)
            parts.append(limb(f"{side} cord {k + 1}", (xb, y, zb), tuple(ring), 0.7 * rb, blend=0.1 * rb))
        parts.append(torus(f"{side} ring", 0.02, 0.6 * rb, tuple(ring + np.array([sx * 0.015, 0, 0])),
                           blend=0.2 * rb))
        parts.append(limb(f"{side} rope", tuple(ring + np.array([sx * 0.04, 0, 0])),
                          (sx * (0.5 - 0.5 * rb), 0.0, float(ring[2]) + 0.02), 0.5 * rb, blend=0.1 * rb))
    return parts


FORMED_SHEETS = {"hammock": hammock, "bib": bib, "hourglass": hourglass, "envelope": envelope, "mask": face_mask, "bread": bread_slice,
                 "puzzle": puzzle_tile}


def fold_layers(p: SheetParams) -> int:
    """Layers of a folded sheet: 3 for a letter fold, doubled by each further halving; 2 ** folds otherwise."""
    return 3 * 2 ** (p.folds - 1) if p.thirds else 2 ** p.folds


def folded_footprint(p: SheetParams) -> tuple[float, float, str]:
    """(length, width, the axis of the last fold) of the folded sheet: each fold across the longer side."""
    length, width, last = 1.0, p.width, "x"
    for i in range(p.folds):
        k = 3.0 if (p.thirds and i == 0) else 2.0
        if length >= width:
            length, last = length / k, "x"
        else:
            width, last = width / k, "y"
    return length, width, last


def _folded(p: SheetParams, t: float) -> list[Part]:
    """Folded `folds` times (the first in thirds when `thirds`), each fold across the longer side: the layers stacked,
    the creases rounded, the open edges cut apart and the top layer's open edge set back (a double layer seen from
    any side)."""
    length, width, last = folded_footprint(p)
    n = fold_layers(p)
    h = n * t
    if p.shape == "round":
        parts = [scaled(cylinder("body", p.width / 2, h, (0, 0, h / 2), edge=p.edge * t / 2), (1 / p.width, 1, 1))]
        parts.append(_op(box("fold", (2, 2, 2 * h), (1.0, 0, h / 2)), "intersect"))
        if p.folds >= 2:
            parts.append(_op(box("second fold", (2, 2, 2 * h), (0, 1.0, h / 2)), "intersect"))
        return parts
    if p.shape == "bib":
        return _folded_bib(p.width, t)
    if last == "y":  # built along x, turned a quarter about z
        q = p.model_copy(update={"width": 1.0})
        return _turned(_folded_layers(length=width, width=length, n=n, t=t, p=q), 90.0)
    return _folded_layers(length, width, n, t, p)


BIB_FOLD_AT = -0.22  # a folded bib's crease across it, its round bottom folded up over the front, / its length [-]


def _folded_bib(w: float, t: float) -> list[Part]:
    """A baby bib with its round bottom folded up over its front: the neck cut-out, the straps and their snaps and
    the piped edge still seen at +x, the folded flap (the bib's own round outline, piped) lying over the middle, and
    the crease a round roll across it at -x (folded in half it was a plain pad: a microfibre cloth or foam sheet)."""
    xf = BIB_FOLD_AT
    flat = bib(w, t)
    body, piping, snaps = flat[0], flat[1], flat[4:]
    flap = [q.model_copy(update={"name": f"flap {name}" if name else "flap", "transform": q.transform.model_copy(
        update={"translation_m": (2 * xf, 0.0, q.transform.translation_m[2] + t)})})
        for q, name in ((body, ""), (piping, "piping"))]
    chord = (w / 2) * float(np.sqrt(max(1.0 - (2 * xf) ** 2, 0.0)))  # the crease's half-length: the outline there
    roll = cylinder("crease", t, 2 * chord, (xf, 0, t), edge=0.4 * t, rot=(90, 0, 0), blend=0.2 * t)
    return [body, piping, *flat[2:4], *flap, _op(box("fold", (2.0, 2.0, 2.0), (xf + 1.0, 0, 0.5)), "intersect"),
            roll, *snaps]


FOLD_GAP_MAX = 0.011  # the gap between a folded sheet's open edges at most this / its length (a thick foam pad's
# 0.22 layer was 2.2 cm wide: particles centred in it sat outside the mesh) [-]
FOLD_SOFT = 0.42  # a folded cloth's edges rounded by this / its layer: soft cloth, not a foam slab's crisp edge [-]
CREASE_ROUND = 0.8  # a folded sheet's crease rounded by this / its half-height (1: a half round) [-]
FOLD_NOTCH = 0.4  # the rounded groove between two layers' edges (open end and sides), radius / the layer [-]
FOLD_DOME = 0.3  # a folded cloth's top rises this much / its layer over its middle (loft, not a flat slab) [-]
FOLD_DOME_MAX = 0.12  # ... at most this / the folded stack's height (a folded towel is still twice the sheet) [-]
FOLD_SIDE_LINES = 6  # layers seen as lines along the folded sheet's sides up to this many layers (64 parts) [-]
BORDER_BAND = 0.1  # a towel's woven border band's width / the folded towel's longer side (~6 cm on 70 cm) [-]
BORDER_MARGIN = 0.09  # the band this far in from the towel's end, / the folded towel's longer side [-]
BORDER_PROUD = 0.45  # the band stands proud of the top by this / the layer (a dobby weave, raised) [-]


def _crease(name: str, s: int, z0: float, z1: float, length: float, width: float) -> list[Part]:
    """A crease at the end x = s * length / 2 joining the layers from z0 to z1: the square end cut off and a roll of
    cloth in its place, as high as the layers it joins, its profile rounded nearly to a half round (a short flat at
    its tip: a true half round's tip is missed by the mesher's grid, and the object drawn 2 % too large)."""
    r = (z1 - z0) / 2
    rx = min(r, 0.35 * length)  # (a short thick stack: the roll an oval, no longer than a third of the sheet)
    zc = (z0 + z1) / 2
    xc = s * (length / 2 - rx)
    cut = _op(box(f"{name} cut", (rx + 0.02 * length, 1.2 * width, z1 - z0), (xc + s * (rx / 2 + 0.01 * length), 0,
                                                                              zc)), "subtract")
    edge = CREASE_ROUND * min(r, rx)
    tail = max(0.0, min(edge, 0.8 * length - 2 * rx))  # (reaching on under the layers: its inner end's rounding
    # hidden, not a notch in the sides where the roll meets them; short of the open end's gaps)
    roll = box(name, (2 * rx + tail, width, z1 - z0), (xc - s * tail / 2, 0, zc), edge=edge, blend=0.05 * r)
    return [cut, roll]


def _border_bands(x0: float, x1: float, width: float, z: float, t: float) -> list[Part]:
    """A folded towel's two woven border bands on its top (from x0 to x1 along x, `width` along y, at height z):
    raised flat stripes across its shorter side, one near each end of its longer side, as a towel is seen on a
    shelf."""
    along_x = width > x1 - x0  # the bands run along the shorter side
    span, long_side = (x1 - x0, width) if along_x else (width, x1 - x0)
    bw = BORDER_BAND * long_side
    proud = BORDER_PROUD * t
    c = 0.5 * (x0 + x1)
    out: list[Part] = []
    for k, s in enumerate((-1.0, 1.0)):
        d = s * (0.5 * long_side - BORDER_MARGIN * long_side - bw / 2)
        at, size = ((c, d, z), (span, bw, 2 * proud)) if along_x else ((c + d, 0.0, z), (bw, 0.96 * span, 2 * proud))
        out.append(box("border" if k == 0 else f"border {k + 1}", size, at, edge=0.3 * proud, blend=0.2 * t))
    return out


FOLD_FLAT = 0.3  # a folded stack at most this high / its smaller side (8 built layers of a blanket stood as a cube
# of grooved foam; a folded blanket or tarp lies low): its layers drawn thinner, its volume less, the density up [-]
FOLD_CELLS = 64  # the draft mesher's cells along the folded stack's longest side [-]
FOLD_LAYER_CELLS = 2.6  # each drawn layer at least this many of them thick (its soft edges still seen apart) [-]
FOLD_SHIFT = 0.022  # each layer shifted up to this / the stack's footprint (folded by hand: not squared up) [-]
FOLD_NARROW = 0.04  # each layer narrower by up to this / its width (folds never quite even) [-]
FOLD_BULGE = 0.03  # the middle layers wider by this / the width (the pile bulging at its middle) [-]
FOLD_YAW = 1.3  # each layer turned up to this about z [deg]
FOLD_LAYER_EDGE = 0.48  # a drawn layer's edges rounded by this / its thickness (soft rolled edges) [-]


def fold_drawn(length: float, width: float, n: int, t: float) -> tuple[int, float]:
    """(layers drawn, each one's thickness) of a folded stack of n built layers t thick on a length x width footprint:
    no higher than FOLD_FLAT of its smaller side, each drawn layer at least FOLD_LAYER_CELLS mesher cells thick
    (fewer, thicker layers drawn when the stack's n would be thinner)."""
    cell = max(length, width) / FOLD_CELLS
    h = min(n * t, max(FOLD_FLAT * min(length, width), 2 * FOLD_LAYER_CELLS * cell))
    m = int(np.clip(np.floor(h / (FOLD_LAYER_CELLS * cell)), 2, n))
    return m, h / m


def _layer_look(i: int, m: int) -> tuple[float, float, float, float, float]:
    """Layer i of m's (shift along x, shift along y, length share, width share, yaw) — fixed wobbles, the same every
    time: layers of a cloth folded by hand, each a little off the one beneath and a little narrower or wider, the
    middle ones bulging."""
    mid = 1.0 - ((2 * i + 1) / m - 1.0) ** 2  # 1 at the stack's middle, ~0 at its top and bottom
    return (FOLD_SHIFT * np.sin(2.3 * i + 0.7), FOLD_SHIFT * np.cos(1.7 * i + 2.1),
            1.0 - 0.5 * FOLD_NARROW * (1 + np.sin(1.3 * i + 0.4)),
            1.0 - 0.5 * FOLD_NARROW * (1 + np.sin(2.9 * i + 1.1)) + FOLD_BULGE * mid, FOLD_YAW * np.sin(3.1 * i + 0.5))


def _folded_layers(length: float, width: float, n: int, t: float, p: SheetParams) -> list[Part]:
    """n layers of a folded sheet along x, soft cloth, drawn low (fold_drawn): each layer its own soft slab, a little
    shifted, turned and narrower or wider than the next (the middle ones bulging), their rounded edges seen apart
    along the sides and the open end; the crease at -x a round roll wrapping the stack (in a letter fold the bottom
    two layers rolled at -x, the top two at +x); the top layer set back from its open edge, its top a little domed; a towel's
    woven border band across the top near each end. A patterned sheet is one tiled block (_folded_block: its tiles
    are its body); cut sheets, paper and a thick pad stay a squared block of their built layers."""
    if p.crisp or p.stiff or p.thickness >= MIN_LAYER:  # cut sheets, paper, a thick foam pad: a squared block
        return _folded_block(length, width, n, t, p)
    m, td = fold_drawn(length, width, n, t)
    if decor_rects(p, length, width):
        return _folded_block(length, width, m, td, p)
    h = m * td
    letter = p.thirds and n == 3 and m == 3  # a letter fold: a crease at each end, an open edge at each
    inset = min(0.06 * length, 2.5 * td)  # the top layer stops short of its open edge: a step seen from above
    parts: list[Part] = []
    runs: list[tuple[float, float, float, float]] = []  # each layer's (x0, x1, y, width)
    for i in range(m):
        sx, sy, ls, ws, yaw = _layer_look(i, m)
        x0, x1 = -length / 2, length / 2
        short = (1.0 - ls) * length + (inset if i == m - 1 else 0.0)  # pulled back from its open end
        if letter and i == 0:
            x1 -= short
        elif letter and i == 2:
            x0 += short
        elif not letter:
            x1 -= short - 0.5 * sx * length * (i < m - 1)
        wi, yi = ws * width, sy * width
        runs.append((x0, x1, yi, wi))
        parts.append(box("body" if i == 0 else f"layer {i + 1}", (x1 - x0, wi, td),
                         (0.5 * (x0 + x1), yi, (i + 0.5) * td), edge=FOLD_LAYER_EDGE * td, rot=(0, 0, yaw),
                         blend=0.06 * td))
    if p.grommets:  # along the top layer's edges, moved with it
        x0, x1, yt, wt = runs[-1]
        parts += [q.model_copy(update={"transform": q.transform.model_copy(update={"translation_m": (
            q.transform.translation_m[0] + 0.5 * (x0 + x1), q.transform.translation_m[1] + yt,
            q.transform.translation_m[2])})}) for q in grommets(p, x1 - x0 - 2 * td, wt, h)]
    x0, x1, yt, wt = runs[-1]
    if letter:  # the top layer's flat run: from its open edge (set back) to the crease at +x
        top_lo, top_hi = x0, x1 - td
    else:  # from the crease's roll to its open edge
        top_lo, top_hi = x0 + min(h / 2, 0.35 * length), x1
    rise = min(FOLD_DOME * td, FOLD_DOME_MAX * h)
    c = rise + 0.5 * td
    parts.append(superellipsoid("loft", (0.45 * (top_hi - top_lo), 0.44 * wt, c),
                                (0.5 * (top_lo + top_hi), yt, h + rise - c), ns=1.0, ew=0.35, blend=0.6 * td))
    creases = [(-1, 0.0, 2 * td), (1, td, h)] if letter else [(-1, 0.0, h)]
    rolls: list[Part] = []
    for k, (s, z0, z1) in enumerate(creases):
        cut, roll = _crease("crease" if k == 0 else f"crease {k + 1}", s, z0, z1, length,
                            (1.0 + 0.5 * FOLD_BULGE) * width)
        parts.append(cut)
        rolls.append(roll)
    parts += rolls
    if p.border:  # a towel's dobby bands: a raised woven stripe across the top near each end of its longer side
        parts += _border_bands(top_lo, top_hi, width, h, td)
    return parts


def _folded_block(length: float, width: float, n: int, t: float, p: SheetParams) -> list[Part]:
    """n layers of a folded sheet with a pattern over its top (one tiled block) along x: the crease at -x a round roll wrapping the stack (and, in a
    letter fold, the bottom two layers rolled at -x, the top two at +x), the open ends' layers cut apart with rounded
    grooves between their edges, the layers seen as lines along the sides, the top layer set back from its open edge
    (a step) and its top a little domed; a towel's woven border band across the top near each end."""
    h = n * t
    e = min(FOLD_SOFT * t, 0.3 * h)
    letter = p.thirds and n == 3  # a letter fold: a crease at each end, an open edge at each
    top_open = -1 if letter else 1
    inset = min(0.06 * length, 2.5 * t)  # the top layer stops short of the open edge: a step seen from above
    extras = 2 * (n - 1) + 4 + 2 + 2 * p.border + (2 * max(p.grommets, 2) if p.grommets else 0)  # (beside the tiles)
    sides = n <= FOLD_SIDE_LINES
    rects = decor_rects(p, length, width)
    if rects:  # tiled through with its pattern (a tile over a ground of the sheet's colour would blend into it)
        parts = tiled_top(rects, length, width, 0.0, h, "body", reserve=extras + 2 * (n - 1) * sides)
    else:
        parts = [box("body", (length, width, h), (0, 0, h / 2), edge=e)]
    if p.grommets:
        parts += [q.model_copy(update={"transform": q.transform.model_copy(update={"translation_m": (
            q.transform.translation_m[0] - top_open * inset / 2, *q.transform.translation_m[1:])})})
            for q in grommets(p, length - inset - 2 * t, width, h)]
    creases = [(-1, 0.0, 2 * t), (1, t, h)] if letter else [(-1, 0.0, h)]
    rolls: list[Part] = []
    for k, (s, z0, z1) in enumerate(creases):
        cut, roll = _crease("crease" if k == 0 else f"crease {k + 1}", s, z0, z1, length, width)
        parts.append(cut)
        rolls.append(roll)
    g = FOLD_NOTCH * t
    gap = min(0.22 * t, FOLD_GAP_MAX * length)
    for i in range(1, n):  # each open edge: a slit between the layers and a rounded groove at its mouth
        s = -1 if (letter and i == 2) else 1
        parts.append(_op(box(f"gap {i}", (0.3 * length, width * 1.2, gap), (s * length / 2, 0, i * t)), "subtract"))
        parts.append(_op(cylinder(f"notch {i}", g, 1.2 * width, (s * length / 2, 0, i * t), rot=(90, 0, 0)),
                         "subtract", 0.2 * g))
    if sides:  # the layers along both sides (a folded cloth's stacked edges; a foam pad has none)
        for i in range(1, n):
            for sy in (-1, 1):
                parts.append(_op(cylinder(f"side line {2 * i - (sy < 0)}", g, 1.2 * length, (0, sy * width / 2, i * t),
                                          rot=(0, 90, 0)), "subtract", 0.2 * g))
    parts.append(_op(box("top edge", (2 * inset, width * 1.2, 1.1 * t), (top_open * length / 2, 0, h - 0.45 * t)),
                     "subtract", 0.1 * t))
    parts += rolls
    if letter:  # the top layer's flat run: from its open edge (set back) to the crease at +x
        top_lo, top_hi = -length / 2 + inset, length / 2 - t
    else:  # from the crease's roll to its open edge
        top_lo, top_hi = -length / 2 + min(h / 2, 0.35 * length), length / 2 - inset
    rise = min(FOLD_DOME * t, FOLD_DOME_MAX * h)
    c = rise + 0.5 * t
    if not rects:  # (a patterned top stays flat: a dome of the ground's colour would cover its pattern)
        parts.append(superellipsoid("loft", (0.45 * (top_hi - top_lo), 0.44 * width, c),
                                    (0.5 * (top_lo + top_hi), 0, h + rise - c), ns=1.0, ew=0.35, blend=0.6 * t))
    if p.border and not rects:  # a towel's dobby bands: a raised woven stripe across the top near each end of its
        # longer side (a striped or printed towel shows its pattern instead)
        parts += _border_bands(top_lo, top_hi, width, h, t)
    return parts


DECOR_MIN = 0.09  # a pattern band at least this / the sheet's drawn footprint wide: the mesher blends a surface's
# colour over 1.5 cells (1/64 of the object at draft), a narrower band is a smear [-]

TILE_DYE = 3  # a pattern patch drawn this many times over, at most (see tiled_top) [-]
TILE_LAP = 0.004  # neighbouring pattern tiles overlap by this / the sheet's footprint [-]
Rect = tuple[str, float, float, float, float]  # a coloured patch: (name, x0, x1, y0, y1)


def _bands(lo: float, hi: float, n: int, share: float, least: float) -> list[tuple[float, float]]:
    """n bands evenly over [lo, hi], each `share` of its pitch wide (at least `least`)."""
    pitch = (hi - lo) / n
    bw = min(max(share * pitch, least), 0.9 * pitch)
    return [(lo + (i + 0.5) * pitch - bw / 2, lo + (i + 0.5) * pitch + bw / 2) for i in range(n)]


def decor_rects(p: SheetParams, length: float, width: float) -> list[Rect]:
    """A sheet's printed or woven pattern over its top (length along x, width along y, centred) as coloured patches
    that do not overlap: stripes across the length (and along it for a check, their crossings 'check'), a hem round
    the edge, a newspaper's headline, text lines and photo, a magazine cover's masthead, photo and cover lines."""
    L, W = length, width
    least = DECOR_MIN * max(L, W)
    out: list[Rect] = []
    x0, x1, y0, y1 = -L / 2, L / 2, -W / 2, W / 2
    if p.hem:
        hw = max(0.06 * min(L, W), least)
        out += [("hem", x0, x1, y1 - hw, y1), ("hem", x0, x1, y0, y0 + hw), ("hem", x0, x0 + hw, y0 + hw, y1 - hw),
                ("hem", x1 - hw, x1, y0 + hw, y1 - hw)]
        x0, x1, y0, y1 = x0 + hw, x1 - hw, y0 + hw, y1 - hw
    if p.stripes and not p.checks:
        out += [("stripe", a, b, y0, y1) for a, b in _bands(x0, x1, p.stripes, 0.4, least)]
    elif p.stripes:  # gingham: bands both ways, their crossings the darkest
        xs = _bands(x0, x1, p.stripes, 0.5, least)
        n_along = int(np.clip(round(p.stripes * (y1 - y0) / (x1 - x0)), 2, p.stripes))  # (at most 7 x 7 tiles)
        ys = _bands(y0, y1, n_along, 0.5, least)
        xcuts = sorted({x0, x1, *[v for ab in xs for v in ab]})
        ycuts = sorted({y0, y1, *[v for ab in ys for v in ab]})
        for xa, xb in zip(xcuts[:-1], xcuts[1:]):
            inx = any(a <= 0.5 * (xa + xb) <= b for a, b in xs)
            for ya, yb in zip(ycuts[:-1], ycuts[1:]):
                iny = any(a <= 0.5 * (ya + yb) <= b for a, b in ys)
                if inx or iny:
                    out.append(("check" if inx and iny else "stripe", xa, xb, ya, yb))
    if p.open_end and p.state == "folded":  # a folded pillowcase: its open end's wide hem band across the top
        out.append(("cuff", x1 - max(0.22 * L, least), x1, y0, y1))
    if p.printed == "newspaper":  # the page's head at +x: the masthead, then three columns of text, a photo
        m = 0.05 * L
        hx = max(0.12 * L, least)
        out.append(("headline", x1 - m - hx, x1 - m, y0 + m, y1 - m))
        top, bot = x1 - 2 * m - hx, x0 + m
        cols = _bands(y0 + m, y1 - m, 3, 0.84, least)
        split = top - 0.45 * (top - bot)  # the photo over the first column's top
        out.append(("photo", split, top, *cols[0]))
        out.append(("text", bot, split - m, *cols[0]))
        out += [("text", bot, top, ya, yb) for ya, yb in cols[1:]]
    if p.printed == "magazine":  # a cover: masthead at +x, the cover photo below it, cover lines beside it
        m = 0.05 * L
        hx = max(0.15 * L, least)
        out.append(("masthead", x1 - m - hx, x1 - m, y0 + m, y1 - m))
        top, bot = x1 - 2 * m - hx, x0 + m
        split = y0 + 0.38 * (y1 - y0)
        out.append(("cover photo", bot, top, split + 0.5 * m, y1 - m))
        for a, b in _bands(bot, top, 3, 0.45, least):
            out.append(("cover line", a, b, y0 + m, split - 0.5 * m))
    return out


def sheet_extras(p: SheetParams) -> int:
    """Parts a flat sheet draws beside its body (fringe, quilting, ribs, zip, grommets, hood, open end, corners)."""
    tassels = 2 * int(np.clip(round(p.width / (3.2 * sheet_layer(p))), 3, 9)) if p.fringe else 0
    return 4 + tassels + 2 * p.quilt + p.ribs + 2 * p.grommets + 8 * (p.curl > 0) + 3


def tiled_top(rects: list[Rect], length: float, width: float, z0: float, z1: float, ground: str,
              reserve: int = 14) -> list[Part]:
    """A layer from z0 to z1 over the whole top (length x width, centred), tiled flush: the coloured patches and,
    between them, `ground` tiles (the sheet's own colour); neighbouring tiles meet side by side, so each patch keeps
    its colour across its middle (a patch standing proud of a ground beneath it would blend into it)."""
    xs = sorted({-length / 2, length / 2, *[r[1] for r in rects], *[r[2] for r in rects]})
    rows: list[tuple[float, float, list[tuple[str, float, float]]]] = []
    for xa, xb in zip(xs[:-1], xs[1:]):
        if xb - xa < 1e-9:
            continue
        mid = 0.5 * (xa + xb)
        cover = sorted((r[3], r[4], r[0]) for r in rects if r[1] <= mid <= r[2])
        row, y = [], -width / 2
        for ya, yb, name in cover:
            if ya > y + 1e-9:
                row.append((ground, y, ya))
            row.append((name, ya, yb))
            y = yb
        if y < width / 2 - 1e-9:
            row.append((ground, y, width / 2))
        if rows and rows[-1][2] == row:
            rows[-1] = (rows[-1][0], xb, row)
        else:
            rows.append((xa, xb, row))
    parts: list[Part] = []
    count: dict[str, int] = {}
    lap = TILE_LAP * max(length, width)  # tiles overlap: flush faces would meet at zero distance, a seam the mesher
    for xa, xb, row in rows:               # splits the sheet along
        for name, ya, yb in row:
            count[name] = count.get(name, 0) + 1
            label = name if count[name] == 1 else f"{name} {count[name]}"
            xa2, xb2 = max(xa - lap, -length / 2), min(xb + lap, length / 2)
            ya2, yb2 = max(ya - lap, -width / 2), min(yb + lap, width / 2)
            parts.append(box(label, (xb2 - xa2, yb2 - ya2, z1 - z0), (0.5 * (xa2 + xb2), 0.5 * (ya2 + yb2),
                                                                       0.5 * (z0 + z1))))
    parts = sorted(parts, key=lambda q: q.name != ground)  # the first ground tile first (the sheet's body)
    # the mesher paints a surface point by every part near it, weighted by nearness, in linear light: a white ground
    # beside a narrow band washes it pink; each patch drawn again in the same place (coincident copies, its colour
    # counted twice or three times over) keeps its own colour across its middle
    patches = [q for q in parts if part_group(q.name) != ground]
    copies = int(np.clip((MAX_PARTS - reserve - len(parts)) // max(len(patches), 1), 0, TILE_DYE - 1))
    for _k in range(copies):
        for q in patches:
            g = part_group(q.name)
            count[g] += 1
            parts.append(q.model_copy(update={"name": f"{g} {count[g]}"}))
    return parts


def grommets(p: SheetParams, length: float, width: float, z: float) -> list[Part]:
    """A tarp's metal eyelets along both long edges of a top at height z, corners included."""
    n = max(p.grommets, 2)
    rg = 0.03 * max(length, width)
    out: list[Part] = []
    for side in (-1, 1):
        for i in range(n):
            x = -length / 2 + 1.6 * rg + i * (length - 3.2 * rg) / (n - 1)
            out.append(torus(f"grommet {len(out) + 1}", rg, 0.45 * rg, (x, side * (width / 2 - 1.6 * rg), z),
                             blend=0.2 * rg))
    return out


def _hood(w: float, t: float) -> list[Part]:
    """A sleeping bag's head end at +x: the hood (a rounded, raised cowl over the end, as wide as the bag) and its
    face opening, a dark oval in the hood's top facing the foot."""
    hx = 0.13
    return [superellipsoid("hood", (hx, 0.5 * w, 0.95 * t), (0.45 - hx, 0, 0.95 * t), ns=0.5, ew=0.6, blend=0.5 * t),
            _op(ellipsoid("face", (0.7 * hx, 0.34 * w, 0.8 * t), (0.45 - 1.05 * hx, 0, 2.0 * t)), "subtract",
                0.2 * t),
            ellipsoid("opening", (0.62 * hx, 0.3 * w, 0.45 * t), (0.45 - 1.05 * hx, 0, 1.05 * t))]


def _open_end(w: float, t: float) -> list[Part]:
    """A pillowcase's open end at +x: the wide hem band across it, standing a little proud, and the mouth cut into
    the end between its two layers."""
    cw = 0.2
    return [box("cuff", (cw, 1.0 * w, 1.25 * t), (0.5 - cw / 2, 0, 0.6 * t), edge=0.4 * t, blend=0.1 * t),
            _op(box("mouth", (0.12, 0.92 * w, 0.35 * t), (0.5, 0, 0.6 * t)), "subtract", 0.05 * t)]


def _turned(parts: list[Part], deg: float) -> list[Part]:
    """Parts turned about z by deg (their translations and rotations)."""
    return rotated_parts(parts, (0.0, 0.0, deg))


def quilting(length: float, width: float, t: float, across: int, along: int) -> list[Part]:
    """Stitched grooves over a puffy layer `t` thick lying on z = 0: `across` baffles across the length (grooves along
    y), `along` across the width (grooves along x), each groove a round channel with soft edges."""
    parts: list[Part] = []
    r = QUILT_DEPTH * t * (0.5 if along else 1.0)  # squares: shallower grooves, the puffs keep their height
    for i in range(1, across):
        x = -length / 2 + length * i / across
        parts.append(_op(cylinder(f"stitch {i}", r, 1.2 * width, (x, 0, t + 0.25 * r), rot=(90, 0, 0)), "subtract",
                         0.35 * r))
    for j in range(1, along):
        y = -width / 2 + width * j / along
        parts.append(_op(cylinder(f"stitch {across + j}", r, 1.2 * length, (0, y, t + 0.25 * r), rot=(0, 90, 0)),
                         "subtract", 0.35 * r))
    return parts


def knit_ribs(length: float, width: float, t: float, n: int) -> list[Part]:
    """n shallow grooves along the length of a strip lying on z = 0 (knit ribbing), stopping short of its ends."""
    g = 0.3 * t
    return [_op(cylinder(f"rib {j}", g, 0.9 * length, (0, -width / 2 + width * j / (n + 1), t + 0.3 * g),
                         rot=(0, 90, 0)), "subtract", 0.3 * g) for j in range(1, n + 1)]


def fringe(length: float, width: float, t: float, at: tuple[float, ...] = (-1.0, 1.0)) -> list[Part]:
    """Tassels beyond the short ends (x = +-length/2) of a strip lying on z = 0, as many as fit its width."""
    n = int(np.clip(round(width / (3.2 * t)), 3, 9))
    tl = min(0.085 * length, 3.2 * width / 2)
    r = 0.5 * t
    parts: list[Part] = []
    for s in at:
        for j in range(n):
            y = -width / 2 + width * (j + 0.5) / n
            a = np.array([s * (length / 2 - 0.3 * tl), y, r])
            b = a + np.array([s * tl, 0.15 * tl * np.sin(2.1 * j + s), 0.0])
            parts.append(limb(f"tassel {len(parts) + 1}", a, b, r, blend=0.2 * r))
    return parts


def _strip_loop(p: SheetParams, t: float) -> list[Part]:
    """A long strip (a scarf) laid on the floor in a loose U: straight arms joined by a bend, fringe at its ends."""
    w = p.width
    rc = 1.1 * w
    arm = 0.5 * (1.0 - np.pi * rc)  # the arms and the half-turn of radius rc make the strip's length
    parts = [box("body", (arm, w, t), (arm / 2, rc, t / 2), edge=p.edge * t / 2),
             box("other arm", (arm, w, t), (arm / 2, -rc, t / 2), edge=p.edge * t / 2)]
    bend = [np.array([rc * np.cos(a), rc * np.sin(a), t / 2]) for a in np.linspace(np.pi / 2, 1.5 * np.pi, 9)]
    parts += _flat_chain("bend", bend, w / 2, t, blend=0.2 * t)  # the half-turn, smooth
    if p.fringe:
        for y in (rc, -rc):
            for q in fringe(arm, w, t, at=(1.0,)):
                tf = q.transform
                x0, y0, z0 = tf.translation_m
                parts.append(q.model_copy(update={"name": f"tassel {len(parts)}", "transform": tf.model_copy(
                    update={"translation_m": (x0 + arm / 2, y0 + y, z0)})}))
    return parts


def roll_radius(p: SheetParams) -> float:
    """Outer radius of the rolled sheet (unit frame): its real cross-section, loosely packed, around its hole."""
    area = 1.0 * p.thickness / p.packing  # the sheet's length x thickness, over the roll's packing
    r = float(np.sqrt(area / (np.pi * (1 - p.core**2))))
    return max(r, 0.04 * p.width)


MIN_TAIL_LAYER = 0.02  # an unrolled tail's drawn thickness, at least this share of the roll's extent [-]


def _rolled(p: SheetParams) -> list[Part]:
    """A roll of length `width` along x: a cylinder with a hole, rings cut into both ends one layer pitch apart, and
    the sheet's free end as a step along the outside."""
    w = p.width
    R = roll_radius(p)
    r0 = p.core * R
    if p.shape == "round":  # a rolled tortilla or pancake: a wrap, tapered at its ends
        return [scaled(cylinder("body", R, w, (0, 0, R), edge=0.6 * R, rot=(0, 90, 0)), (1, 1, 1))]
    puffy = p.quilt > 0  # a quilted sheet (a sleeping bag) rolls up soft: its ends rounded, its baffles round it
    parts = [cylinder("body", R, w, (0, 0, R), edge=ROLL_PUFFY_EDGE * R if puffy else min(0.15 * R, 0.02),
                      rot=(0, 90, 0))]
    layer = float(np.clip(p.thickness, 0.03 * R, 0.12 * R))
    parts.append(box("flap", (w, 0.5 * R, layer), (0, -0.25 * R, 2 * R + layer / 2 - 0.005 * R), edge=0.3 * layer,
                     blend=0.02 * R))
    # rings one sheet layer apart, as many as the mesher can see: a groove at least 2.6 % of the roll's length wide
    g = min(max(0.2 * p.thickness, 0.013 * w), 0.08 * (R - r0))
    rings = int(np.clip(np.floor((R - r0) / (5 * g)) - 1, 1, 5))
    pitch = (R - r0) / (rings + 1)
    depth = min(0.12 * w, 3 * g)
    if p.spiral:  # the spiral instead of the rings, and no hole
        rings, r0 = 0, 0.0
        parts += _spiral_cuts(w, R)
    for i in range(1, rings + 1):
        rad = r0 + pitch * i
        for side, s in (("left", 1), ("right", -1)):
            ring = scaled(torus(f"{side} ring {i}", rad, g, (s * w / 2, 0, R), rot=(0, 90, 0)), (1, 1, depth / g))
            parts.append(_op(ring, "subtract"))
    if r0 > 0:
        parts.append(_op(cylinder("hole", r0, 1.2 * w, (0, 0, R), rot=(0, 90, 0)), "subtract"))
    if puffy:
        parts += _roll_baffles(p, w, R)
    if p.hem or p.fringe:  # a rug rolled up: its border round both ends of the roll, its fringe off the loose end
        parts += _roll_border_fringe(p, w, R, layer)
    if p.straps:
        parts += _roll_straps(w, R)
    if p.tail > 0:  # the free end unrolled off the bottom of the roll, lying flat towards -y
        run = p.tail * 2 * R
        flat = max(layer, MIN_TAIL_LAYER * max(w, run))  # (no thinner than the mesher sees: a half rolled yoga mat's
        parts.append(box("tail", (w, run + 0.5 * R, flat), (0, -0.5 * run, flat / 2), edge=0.3 * flat,  # 6 mm sheet
                         blend=0.05 * R))  # was lost between the voxels)
    if p.bubbles:  # the loose end lying out in front (not a partly unrolled tail), bubbled: a sheet of them reads as
        run = (p.tail or BUBBLE_END) * 2 * R  # bubble wrap, rows round a roll alone as a massage roller
        flat = max(layer, MIN_TAIL_LAYER * max(w, run))
        if p.tail == 0:
            parts.append(box("loose end", (w, run + 0.5 * R, flat), (0, -0.5 * run, flat / 2), edge=0.3 * flat,
                             blend=0.05 * R))
        grid = _bubble_grid(w, run, flat, 36)
        parts += [q.model_copy(update={"transform": q.transform.model_copy(update={"translation_m": (
            q.transform.translation_m[0], q.transform.translation_m[1] - 0.5 * run - 0.1 * R,
            q.transform.translation_m[2])})}) for q in grid]
    if p.bubbles:  # the outer layer's bubbles: staggered rows over the roll's upper half, drawn a little large
        rb = 0.15 * R
        along = max(2, int(0.9 * w / (2.6 * rb)))
        for j, ang in enumerate(np.radians([-70.0, -35.0, 0.0, 35.0, 70.0])):
            for i in range(along):
                x = -0.45 * w + (i + 0.5 * (j % 2)) * 0.9 * w / along
                at = (float(x), float(R * np.sin(ang)), float(R + R * np.cos(ang)))
                parts.append(ellipsoid(f"bubble {len(parts)}", (rb, rb, 0.6 * rb), at,
                                       rot=(float(np.degrees(-ang)), 0, 0), blend=0.3 * rb))
                if len(parts) >= 63:
                    return parts
    return parts


def _roll_border_fringe(p: SheetParams, w: float, R: float, layer: float) -> list[Part]:
    """A rolled sheet's woven border (hem) seen as a band round the roll near each end, and its fringe as tassels
    hanging from the loose end's edge down the roll's side (a rolled rug: the short end with the fringe is outside)."""
    out: list[Part] = []
    if p.hem:
        band = max(0.07 * w, 0.02 * max(w, 2 * R))
        th = max(layer, 0.08 * R)  # (set in from the ends past the rings' or spiral's cut: they stay open)
        for k, sx in enumerate((-1.0, 1.0)):
            x = sx * (w / 2 - 0.06 * w - band / 2)
            out.append(cylinder(f"hem {k + 1}", R + th, band, (x, 0, R), rot=(0, 90, 0), edge=0.3 * th))
    if p.fringe:
        n = int(np.clip(round(w / (0.06 * max(w, 2 * R))), 5, 12))
        r = max(0.5 * layer, 0.012 * max(w, 2 * R))
        tl = 0.55 * R
        for j in range(n):
            x = -0.45 * w + 0.9 * w * j / (n - 1)
            a = np.array([x, -0.5 * R, 2 * R])
            b = np.array([x + 0.08 * tl * np.sin(2.1 * j), -1.0 * R - 0.1 * tl, 2 * R - tl])
            out.append(limb(f"tassel {j + 1}", a, b, r, blend=0.2 * r))
    return out


ROLL_PUFFY_EDGE = 0.3  # a rolled quilted sheet's ends rounded by this / the roll's radius (soft, not a cut tube) [-]
ROLL_BAFFLES = 5  # a rolled quilted sheet's baffle seams drawn round the roll's upper side [-]
STRAP_AT = 0.27  # a rolled sleeping bag's straps this far either side of the roll's middle, / its length [-]
STRAP_WIDE = 0.075  # a strap's width / the roll's length (2.5-4 cm webbing on a ~40-75 cm roll) [-]
STRAP_THICK = 2.2 / 48  # a strap's thickness / the roll's longest side: ~2 mesher cells at draft, to be seen [-]


def _roll_baffles(p: SheetParams, w: float, R: float) -> list[Part]:
    """A rolled quilted sheet's baffle seams: grooves along the roll over its top, one baffle's pitch apart round it
    (the channels between them puff out: a sleeping bag's, not a smooth mat's outside)."""
    step = float(np.clip(np.degrees(1.0 / max(p.quilt, 1) / R), 35.0, 70.0))
    g = max(0.11 * R, 0.03 * max(w, 2 * R))
    out: list[Part] = []
    for k in range(ROLL_BAFFLES):
        a = np.radians(90.0 + (k - (ROLL_BAFFLES - 1) / 2) * step)
        at = (0.0, float((R + 0.25 * g) * np.cos(a)), float(R + (R + 0.25 * g) * np.sin(a)))
        out.append(_op(cylinder(f"baffle {k + 1}", g, 0.86 * w, at, rot=(0, 90, 0)), "subtract", 0.5 * g))
    return out


def _roll_straps(w: float, R: float) -> list[Part]:
    """Two compression straps round a roll (length w along x, radius R, axis at height R), each cinching the roll
    into a shallow waist, its buckle on the top and the strap's loose tail hanging from it."""
    longest = max(w, 2 * R)
    th = STRAP_THICK * longest
    sw = max(STRAP_WIDE * w, 1.6 * th)
    out: list[Part] = []
    for k, sx in enumerate((-1.0, 1.0)):
        x = sx * STRAP_AT * w
        out.append(_op(scaled(torus(f"cinch {k + 1}", R + 0.2 * th, 0.9 * th, (x, 0, R), rot=(0, 90, 0)),
                              (1, 1, 1.3 * sw / (1.8 * th))), "subtract", 0.8 * th))
        out.append(scaled(torus(f"strap {k + 1}", R - 0.35 * th, 0.5 * th, (x, 0, R), rot=(0, 90, 0)),
                          (1, 1, sw / th)))
        a = np.radians(60.0)  # the buckle a little over the top, towards the viewer's side
        at = (x, float(-(R + 0.1 * th) * np.cos(a)), float(R + (R + 0.1 * th) * np.sin(a)))
        out.append(box(f"buckle {k + 1}", (1.35 * sw, 1.2 * sw, 1.1 * th), at, edge=0.3 * th,
                       rot=(90.0 - np.degrees(a), 0, 0), blend=0.2 * th))
    return out


SPIRAL_TURNS = 2.25  # turns of a rolled sheet's spiral drawn at its ends (each groove ~1.5 mesher cells wide) [-]
SPIRAL_STEPS = 10  # straight groove segments per turn [-]


def _spiral_cuts(w: float, R: float) -> list[Part]:
    """A roll's spiral (length `w` along x, radius R, axis at height R) cut into both end faces: a groove following an
    Archimedean spiral from near the axis out to the outer layer, which ends at the roll's top (where the flap is)."""
    pitch = 0.92 * R / SPIRAL_TURNS
    g, depth = 0.42 * pitch, min(0.1 * w, 0.5 * R)
    n = int(SPIRAL_TURNS * SPIRAL_STEPS)
    end = np.pi / 2 + 2 * np.pi * SPIRAL_TURNS  # the outer end at the top
    parts: list[Part] = []
    for side, s in (("left", 1.0), ("right", -1.0)):
        for k in range(n):
            th0, th1 = end - 2 * np.pi * SPIRAL_TURNS * (1 - k / n), end - 2 * np.pi * SPIRAL_TURNS * (1 - (k + 1) / n)
            pts = [(0.06 * R + pitch * (th - end + 2 * np.pi * SPIRAL_TURNS) / (2 * np.pi)) * np.array(
                [np.cos(th), np.sin(th)]) for th in (th0, th1)]
            mid, d = 0.5 * (pts[0] + pts[1]), pts[1] - pts[0]
            seg = float(np.linalg.norm(d)) + 0.8 * g
            phi = float(np.degrees(np.arctan2(d[1], d[0])))
            parts.append(_op(box(f"{side} spiral {k + 1}", (2 * depth, seg, g), (s * w / 2, float(mid[0]), R + float(mid[1])),
                                 rot=(phi, 0, 0)), "subtract"))
    return parts


BUBBLE_END = 0.5  # a roll of bubble wrap's loose end lying out in front, / the roll's diameter [-]
BUBBLE_PITCH = 0.11  # bubble wrap's bubbles drawn this far apart, / the drawn sheet's longer side [-]


def _bubble_grid(length: float, width: float, t: float, most: int) -> list[Part]:
    """Bubble wrap's air bubbles over a sheet's top (length along x, width along y, top at t): staggered rows of domes,
    drawn larger than real (10 mm) so the mesher sees them; at most `most` of them."""
    pitch = BUBBLE_PITCH * max(length, width)
    nx, ny = max(int(length / pitch), 2), max(int(width / pitch), 2)
    while nx * ny > most and nx > 2:
        nx, ny = nx - 1, max(int(ny * (nx - 1) / nx), 2)
    rb = 0.36 * min(length / nx, width / ny)
    parts: list[Part] = []
    for j in range(ny):
        for i in range(nx):
            x = -length / 2 + (i + 0.5 + 0.25 * (1 if j % 2 else -1)) * length / nx
            y = -width / 2 + (j + 0.5) * width / ny
            parts.append(ellipsoid(f"bubble {len(parts) + 1}", (rb, rb, max(0.55 * rb, 0.6 * t)), (x, y, t),
                                   blend=0.15 * rb))
    return parts


# ---------------------------------------------------------------------------------------------------------- pouches
class PouchParams(Model):
    """A filled pouch or bag: IV fluid bag, ice pack, gel pack, bean bag, hand warmer, drink pouch, sandbag."""

    width: float = Field(default=0.6, gt=0.2, le=1.0, description="width / length [-]")
    fill: float = Field(default=0.6, ge=0.0, le=1.0, description="how full: 0 an empty, flat bag; 1 a round pillow [-]")
    seam: float = Field(default=0.04, ge=0.0, le=0.15, description="width of the sealed or sewn border / length [-]")
    squareness: float = Field(default=0.35, gt=0.1, le=1.0, description="1 an oval pouch, small a square one [-]")
    port: Literal["none", "iv", "cap", "spout", "tied", "straw", "hose", "knot"] = Field(
        default="none", description="iv: two ports at the front and a hanger hole; cap: a screw neck; spout: one tube; "
        "tied: a sack's neck gathered and tied, its cloth flaring past the tie; straw: a drinking straw pushed in "
        "through the top seam, standing out past it at an angle; hose: a hydration bladder's screw cap on its top "
        "and a drinking tube out of its bottom end, lying in a loose curve, its bite valve at the end; knot: a bin "
        "bag's neck twisted into a knot, its two drawstring ears splayed out of it")
    channels: int = Field(default=0, ge=0, le=8, description="stitched channels across a quilted pad (an ankle "
                          "weight) [-]")
    strap: float = Field(default=0.0, ge=0.0, le=1.5, description="a flat strap from the pad's +x end (velcro, a "
                         "ring at its end) / length [-]")
    piece: tuple[float, float, float] = Field(default=(0.0, 0.0, 0.0), description="goods seen through a clear "
                                              "bag ('a bag of marshmallows'): one piece's extents / length; 0: none")
    piece_shape: Literal["ball", "cylinder", "block", "shred"] = Field(default="ball", description="the pieces' "
                                                                       "form; shred: thin ruffled leaf shreds tumbled "
                                                                       "every way (shredded lettuce, salad)")
    label: bool = Field(default=False, description="a printed label on its top (a sack of rice, a bag of dog food): "
                        "what tells a pack of goods from a pillow")
    handle: bool = Field(default=False, description="a webbing carry handle across the top, sewn at both ends (a "
                         "stage sandbag)")
    upright: bool = Field(default=False, description="standing on its closed end, the port (a tied neck) up: a full "
                          "bin bag, lumpy with what is in it")
    crimp: bool = Field(default=False, description="a pillow pack (a bag of crisps, frozen peas, rice, pet food, "
                        "compost): no border seam, its two short ends heat-sealed into flat fins with crimp ridges "
                        "across them, the filled body gathering into them")
    emblem: Literal["none", "paw", "bone", "fish", "sprout", "bowl", "drop", "pad", "piece", "chip", "fruit",
                    "wheat", "cat", "bottle", "diaper"] = Field(
        default="none", description="a simple raised picture of the contents on the label (#38), what tells a pack "
        "of dog food from one of flour: paw (cat litter, pet food), bone (dog food, treats), fish (cat food), sprout "
        "(soil, compost, mulch, fertilizer, seed), bowl (rice, grain), drop (milk, juice, liquid soap), pad (pads, "
        "diapers), piece (a window onto the goods: the piece shape in `piece`, candy), chip (a crisp), fruit (an "
        "apple with its leaf: juice, baby food), wheat (an ear of wheat: flour), cat (a cat's head with its pointed ears: "
        "cat litter), bottle (a milk bottle: milk), diaper (one diaper laid open: a pack of diapers)")
    lid: bool = Field(default=False, description="a wipes pack's plastic flip lid on its top: an oval frame round a "
                      "raised lid with a finger tab (the label then lies beside it)")
    grip: bool = Field(default=False, description="a carry flap sealed on at the -x end with a handle slot cut "
                       "through it (a pack of diapers, of toilet rolls)")
    stand: bool = Field(default=False, description="standing on its bottom end, its label facing out (a stand-up "
                        "pouch with a round gusset base and a zip line under its top seam; a bag of crisps on a "
                        "shelf)")
    form: Literal["pouch", "laundry", "mesh", "sack", "deli"] = Field(
        default="pouch", description="laundry: a soft drawstring sack standing full of clothes, bulging, its neck "
        "cinched by a cord with a toggle, a sleeve hanging out; mesh: a bulging net sack lying on its side (a net bag "
        "of onions, a mesh sack of mussels, a hay net, a mesh grain bag): what it holds packed in it (`contents`), a "
        "lattice of net cords over it (`mesh_cell`), gathered into a clip at each end or a drawstring neck; sack: a "
        "paper sack of flour or sugar standing "
        "on its flat bottom, a brick with its top folded down flat, gusset creases down its sides, its printed label "
        "facing out; deli: a flat clear tray of sliced deli meat, the slices folded and shingled along it, the sealed "
        "film's flange round its rim")
    contents: Literal["pieces", "tufts", "mash"] = Field(
        default="pieces", description="what a mesh sack holds, seen through its net: pieces (its goods one by one, "
        "`piece`: onions, mussels, potatoes; plain lumps when `piece` is 0), tufts (a stuffed mass of hay or straw, "
        "strands poking out through the cords; a drawstring neck), mash (a bulging mass of wet grain or mash in "
        "small lumps; a drawstring neck)")
    mesh_cell: float = Field(default=0.16, ge=0.05, le=0.3, description="a mesh sack's cord spacing / its length, "
                             "drawn coarser than real so the draft mesher sees its cords: 0.16 a produce net, 0.15 a "
                             "hay net, 0.1 a fine mesh grain bag [-]")


LABEL_SIZE = (0.46, 0.62)  # a pack's printed label over its top: / length, / width [-]


def pouch(p: PouchParams) -> list[Part]:
    """Length 1 along x, lying flat; ports at +x."""
    w = p.width
    s = p.seam
    h = max(MIN_LAYER * 1.6, p.fill * 0.42 * w)
    if p.upright:  # a full bag standing: as deep as it is wide, its weight spreading it
        h = max(h, 0.8 * p.fill * w)
    if max(p.piece) > 0:  # a bag of goods is as deep as they are thick: they bulge its film, not stand on a tray
        h = max(h, BAG_DEPTH_OVER_PIECE * sorted(p.piece)[0])
    st = MIN_LAYER
    if p.form == "laundry":
        return _laundry_sack(p)
    if p.form == "mesh":
        return net_sack(p)
    if p.form == "sack":
        return _paper_sack(p, h)
    if p.form == "deli":
        return _deli_pack(p)
    if p.crimp and p.port == "none":  # (a bag with a port or a tie is sealed round its border)
        out = _pillow_pack(p, h) + (bagged_pieces(p, h) if max(p.piece) > 0 else [])
        if p.emblem != "none" and p.label:
            out += emblem_parts(p.emblem, h + 0.5 * st, p.piece)
        return _stood(out) if p.stand else out
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
    elif p.port == "tied":  # the cloth gathered from the body's end into the tie, then flaring open
        r0 = 0.8 * min(h, w) / 2
        parts.append(tapered("neck", (0.3, 0, h / 2), (0.62, 0, h / 2), r0, 0.06, blend=0.08))
        parts.append(torus("tie", 0.065, 0.025, (0.62, 0, h / 2), rot=(0, 90, 0), blend=0.005))
        parts.append(cone("ruffle", 0.06, 0.14, 0.14, (0.71, 0, h / 2), edge=0.015, rot=(0, 90, 0), blend=0.03))
    elif p.port == "knot":  # the neck gathered into a knot, the two ears of the tie splayed out of it
        r0 = 0.7 * min(h, w) / 2
        parts.append(tapered("neck", (0.3, 0, h / 2), (0.6, 0, h / 2), r0, 0.05, blend=0.08))
        parts.append(ellipsoid("knot", (0.06, 0.07, 0.06), (0.62, 0, h / 2), blend=0.02))
        for side, sy in (("left", -1.0), ("right", 1.0)):
            parts.append(ellipsoid(f"{side} ear", (0.12, 0.05, 0.018), (0.7, sy * 0.09, h / 2), rot=(0, 0, sy * 40),
                                   blend=0.02))
    elif p.port == "straw":  # through the seam near one corner, sticking out a third of the pouch's length
        parts.append(limb("straw", (0.36, 0.22 * w, h / 2), (0.8, 0.3 * w, h / 2 + 0.08), 0.022, blend=0.006))
    elif p.port == "hose":
        parts.append(cylinder("cap", 0.09, 0.05, (0.25, 0, h + 0.02), edge=0.01, blend=0.01))
        r = HOSE_RADIUS
        pts = [np.array([-0.5 - 0.35 * np.sin(0.5 * np.pi * u), 0.45 * w * (1 - np.cos(np.pi * u)) - 0.1 * w, r])
               for u in np.linspace(0.0, 1.0, 7)]
        pts[0] = np.array([-0.5 + s + 0.06, -0.1 * w, r])  # (from inside the body: one piece)
        parts += [limb(f"hose {k + 1}", pts[k], pts[k + 1], r, blend=0.3 * r) for k in range(len(pts) - 1)]
        parts.append(limb("bite valve", pts[-1], pts[-1] + np.array([0.06, 0.02, 0.0]), 1.5 * r, blend=0.3 * r))
    elif p.port == "spout":
        parts.append(limb("spout", (0.42, 0, h / 2), (0.58, 0, h / 2), 0.035, blend=0.02))
        parts.append(cylinder("cap", 0.05, 0.05, (0.6, 0, h / 2), edge=0.01, rot=(0, 90, 0), blend=0.005))
    for i in range(p.channels):  # stitched lines across the pad
        x = -0.5 + s + (1 - 2 * s) * (i + 1) / (p.channels + 1)
        parts.append(_op(scaled(cylinder(f"stitch {i + 1}", 0.035, w * 1.2, (x, 0, h), rot=(90, 0, 0)),
                                 (1, 1, 1)), "subtract", 0.02))
    if p.handle:  # a flat webbing loop arching over the top along the length, its ends sewn down
        hw = 0.16 * w
        R = (h + 0.02) / 2  # the arch's top 0.08 over the body, its lower half hidden inside it
        parts.append(torus("handle", R, 0.035, (0, 0, h + 0.08 - R), rot=(90, 0, 0)))
        for x in (-R, R):
            parts.append(box("handle tab", (0.09, hw, MIN_LAYER), (x, 0, h * 0.98), edge=0.4 * MIN_LAYER, blend=0.01))
    if max(p.piece) > 0:
        parts += bagged_pieces(p, h)
    elif p.label:
        parts.append(_label(w - 2 * s, h))
    if p.emblem != "none" and p.label:
        parts += emblem_parts(p.emblem, h + 0.5 * st, p.piece)
    if p.lid:  # an oval frame on the top, the raised lid in it, its finger tab towards +x
        lw = 0.32 * w
        parts.append(superellipsoid("lid frame", (0.19, lw, 0.02), (0.0, 0.0, h), ns=0.5, ew=1.0, blend=0.02))
        parts.append(superellipsoid("lid", (0.16, 0.84 * lw, 0.03), (0.0, 0.0, h + 0.02), ns=0.4, ew=1.0,
                                    blend=0.005))
        parts.append(box("lid tab", (0.05, 0.3 * lw, 0.03), (0.17, 0.0, h + 0.02), edge=0.01, blend=0.005))
    if p.grip:  # the carry flap beyond the -x end, a slot cut through it
        ft = 2.5 * st
        parts.append(box("grip", (0.16, 0.7 * w, ft), (-0.5 - 0.05, 0, 0.75 * h), edge=0.4 * ft, blend=0.08))
        parts.append(_op(scaled(cylinder("grip slot", 0.04, 4 * ft, (-0.56, 0, 0.75 * h)), (1.0, 3.0, 1.0)),
                         "subtract", 0.005))
    if p.stand and not p.upright:  # a stand-up pouch: a zip line under the top seam, a round gusset base
        parts.append(box("zip line", (0.035, w - 2.4 * s, 0.6 * st), (0.5 - s - 0.08, 0, 0.93 * h), edge=0.25 * st,
                         blend=0.2 * st))
        parts.append(superellipsoid("gusset", (0.16, w / 2 - s, 0.75 * h), (-0.5 + s + 0.14, 0, h / 2), ns=0.6,
                                    ew=0.3, blend=0.15))
        return _stood(parts)
    if p.upright:  # lumps of what is inside pressing out its sides, then stood on its closed end
        for k, (x, a) in enumerate(((-0.25, 20.0), (-0.05, 150.0), (0.12, 260.0), (-0.2, 300.0))):
            ca, sa = np.cos(np.radians(a)), np.sin(np.radians(a))
            parts.append(ellipsoid(f"lump {k + 1}", (0.16, 0.12, 0.12), (x, 0.3 * w * ca, h / 2 + 0.3 * h * sa),
                                   blend=0.06))
        parts = rotated_parts(parts, (0.0, -90.0, 0.0))
        if p.label:  # its printed front turned to face +x, where the renders look from
            parts = rotated_parts(parts, (0.0, 0.0, 180.0))
    if p.strap > 0:
        sw, st = 0.55 * w, 1.6 * MIN_LAYER
        parts.append(box("strap", (p.strap, sw, st), (0.5 + p.strap / 2 - 0.05, 0, st / 2), edge=0.45 * st,
                         blend=0.01))
        parts.append(box("velcro", (0.35 * p.strap, 0.9 * sw, 0.8 * st), (0.5 + 0.55 * p.strap, 0, st * 1.2),
                         edge=0.3 * st, blend=0.003))
        parts.append(scaled(torus("ring", 0.6 * sw / 2 + 0.02, 0.018, (0.5 + p.strap - 0.02, 0, 0.018)), (1, 1, 1)))
    return parts


HOSE_RADIUS = 0.02  # a hydration bladder's drinking tube, / the bladder's length (drawn ~9 mm of 45 cm) [-]
CRIMP_FIN = 0.09  # a pillow pack's sealed end fin / its length [-]
CRIMP_RIDGES = 5  # crimp ridges across each fin [-]


def _pillow_pack(p: PouchParams, h: float) -> list[Part]:
    """A pillow pack lying flat, length 1 along x: the filled body (rounder the fuller it is) gathering at both
    short ends into flat heat-sealed fins as wide as the bag, crimp ridges across each fin, and the printed label
    on its top."""
    w, st, fin = p.width, MIN_LAYER, CRIMP_FIN
    tf = 1.1 * st  # the fin as the mesher sees it (two films and the crimp)
    half = 0.5 - 0.8 * fin  # the body reaches a little into each fin
    parts = [superellipsoid("body", (half, w / 2, h / 2), (0, 0, h / 2), ns=0.5 + 0.4 * p.fill, ew=0.2)]
    for side, sgn in (("left", -1.0), ("right", 1.0)):
        parts.append(box(f"{side} end seal", (fin, w, tf), (sgn * (0.5 - fin / 2), 0, h / 2), edge=0.4 * tf,
                         blend=0.2 * h))
        for k in range(CRIMP_RIDGES):
            x = sgn * (0.5 - fin * (k + 0.6) / (CRIMP_RIDGES + 0.2))
            parts.append(cylinder(f"{side} crimp {k + 1}", 0.68 * tf, 0.97 * w, (x, 0, h / 2), rot=(90, 0, 0)))
    if p.label and max(p.piece) == 0:
        parts.append(_label(w, h))
    return parts


EMBLEM_PROUD = 0.03  # an emblem's raised face over its label / the pack's length (markings flush, ~3 % proud) [-]


def emblem_parts(kind: str, z: float, piece: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> list[Part]:
    """A simple raised picture of a pack's contents on its label (its top face at z), ~0.3 of the pack's length
    across, each part named 'emblem': a paw (pad and four toes), a dog's bone, a fish, a sprout (stem and two
    leaves), a bowl heaped with grain, a drop, a pad, or one of the goods (`piece`) drawn large."""
    t = 2 * EMBLEM_PROUD
    zc = z + EMBLEM_PROUD - t / 2
    out: list[Part] = []

    def flat(part: Part) -> None:
        out.append(part.model_copy(update={"name": f"emblem {len(out) + 1}"}))

    if kind == "paw":
        flat(ellipsoid("pad", (0.075, 0.09, t / 2), (-0.04, 0.0, zc)))
        for k, (x, y) in enumerate(((0.06, -0.11), (0.1, -0.04), (0.1, 0.04), (0.06, 0.11))):
            flat(ellipsoid(f"toe {k}", (0.035, 0.03, t / 2), (x, y, zc), rot=(0, 0, float(-25 * y / 0.11))))
    elif kind == "bone":
        flat(box("shaft", (0.06, 0.24, t), (0.0, 0.0, zc), edge=0.25 * t))
        for x in (-0.04, 0.04):
            for y in (-0.13, 0.13):
                flat(cylinder("knob", 0.042, t, (x, y, zc), edge=0.25 * t))
    elif kind == "fish":
        flat(ellipsoid("body", (0.075, 0.14, t / 2), (0.0, -0.03, zc)))
        flat(box("tail", (0.085, 0.085, t), (0.0, 0.13, zc), edge=0.2 * t, rot=(0, 0, 45)))
    elif kind == "sprout":
        flat(box("stem", (0.16, 0.024, t), (-0.07, 0.0, zc), edge=0.2 * t))
        for sy in (-1.0, 1.0):
            flat(ellipsoid("leaf", (0.05, 0.1, t / 2), (0.04, sy * 0.08, zc), rot=(0, 0, float(sy * 40))))
    elif kind == "bowl":  # a bowl seen from the side (a flat trapezoid), the grain heaped over its rim
        flat(cone("bowl", 0.075, 0.15, 0.12, (-0.04, 0.0, zc), edge=0.01, rot=(0, 90, 0), scale=(t / 0.3, 1, 1)))
        flat(ellipsoid("heap", (0.07, 0.135, t / 2), (0.03, 0.0, zc)))
    elif kind == "drop":
        flat(ellipsoid("drop", (0.09, 0.09, t / 2), (-0.03, 0.0, zc)))
        flat(cone("tip", 0.086, 0.006, 0.17, (0.055, 0.0, zc), rot=(0, 90, 0), scale=(t / 0.172, 1, 1)))
    elif kind == "chip":  # a crisp: a wavy oval, two lobes
        flat(ellipsoid("chip", (0.1, 0.13, t / 2), (0.0, -0.02, zc), rot=(0, 0, 20)))
        flat(ellipsoid("chip lobe", (0.08, 0.09, t / 2), (0.03, 0.08, zc), rot=(0, 0, -15)))
    elif kind == "fruit":  # an apple: the round fruit, its stalk and one leaf
        flat(ellipsoid("apple", (0.11, 0.12, t / 2), (-0.02, 0.0, zc)))
        flat(box("stalk", (0.07, 0.02, t), (0.11, 0.0, zc), edge=0.2 * t))
        flat(ellipsoid("leaf", (0.03, 0.065, t / 2), (0.13, 0.06, zc), rot=(0, 0, 35)))
    elif kind == "wheat":  # an ear of wheat upright (+x up): its stalk, plump grains in pairs slanting up out of it,
        # one at its tip, and the long bristly awns fanning up past the tip (what tells wheat from a shrimp or a leaf)
        flat(box("stalk", (0.13, 0.026, t), (-0.145, 0.0, zc), edge=0.2 * t))
        for k in range(4):
            for sy in (-1.0, 1.0):
                flat(ellipsoid("grain", (0.036, 0.024, t / 2), (-0.06 + 0.042 * k, sy * 0.03, zc),
                               rot=(0, 0, float(sy * 30))))
        flat(ellipsoid("grain", (0.036, 0.022, t / 2), (0.1, 0.0, zc)))
        for a in (-18.0, -6.0, 6.0, 18.0):
            ca, sa = np.cos(np.radians(a)), np.sin(np.radians(a))
            flat(box("awn", (0.14, 0.013, t), (0.1 + 0.07 * ca, 0.025 * np.sign(a) + 0.07 * sa, zc), rot=(0, 0, a)))
    elif kind == "cat":  # a cat's head face on: the round face, two pointed ears at its top (+x), a hollow for each eye
        flat(ellipsoid("face", (0.11, 0.13, t / 2), (-0.02, 0.0, zc)))
        for sy in (-1.0, 1.0):  # (a cone laid along x, flattened, its tip turned out)
            flat(cone("ear", 0.05, 0.006, 0.11, (0.1, sy * 0.075, zc), rot=(0, 90, float(sy * 25)),
                      scale=(t / 0.1, 1, 1)))
        for sy in (-1.0, 1.0):
            flat(_op(ellipsoid("eye", (0.022, 0.03, t), (0.0, sy * 0.05, zc + t)), "subtract", 0.004))
    elif kind == "bottle":  # a milk bottle standing (+x up): its round-shouldered body, the neck, the cap
        flat(superellipsoid("bottle", (0.11, 0.075, t / 2), (-0.06, 0.0, zc), ns=0.3, ew=0.3))
        flat(cone("shoulder", 0.075, 0.04, 0.1, (0.09, 0.0, zc), edge=0.01, rot=(0, 90, 0), scale=(t / 0.15, 1, 1)))
        flat(box("cap", (0.04, 0.1, t), (0.145, 0.0, zc), edge=0.2 * t))
    elif kind == "diaper":  # a diaper laid open (+x its waist): the wide back panel with its tabs, the narrow
        # crotch, the front panel
        flat(box("back", (0.1, 0.22, t), (0.12, 0.0, zc), edge=0.25 * t))
        flat(superellipsoid("crotch", (0.14, 0.06, t / 2), (0.0, 0.0, zc), ns=0.2, ew=1.0))
        flat(box("front", (0.09, 0.2, t), (-0.13, 0.0, zc), edge=0.25 * t))
        for sy in (-1.0, 1.0):
            flat(box("tab", (0.05, 0.04, t), (0.14, sy * 0.125, zc), edge=0.2 * t))
    elif kind == "pad":
        flat(superellipsoid("pad", (0.16, 0.075, t / 2), (0.0, 0.0, zc), ns=0.3, ew=0.9))
    elif kind == "piece" and max(piece) > 0:
        a, b, _c = sorted(piece, reverse=True)
        flat(ellipsoid("piece", (0.13, max(0.05, 0.13 * b / a), t / 2), (0.0, 0.0, zc)))
    return [_spread(q, EMBLEM_SCALE) for q in out]


EMBLEM_SCALE = 1.3  # the emblem drawn over most of its label (a pack's picture fills its front) [-]


def _spread(part: Part, k: float) -> Part:
    """An emblem part k times larger across the label (x, y), as thick."""
    tf = part.transform
    x, y, z = tf.translation_m
    sx, sy, sz = tf.scale
    turned = abs(abs(tf.rotation_deg[1]) - 90.0) < 1.0  # (a cone laid along x: its local x is the world's z)
    scale = (sx, sy * k, sz * k) if turned else (sx * k, sy * k, sz)
    return part.model_copy(update={"transform": tf.model_copy(update={"translation_m": (x * k, y * k, z),
                                                                       "scale": scale})})


def _stood(parts: list[Part]) -> list[Part]:
    """A pack lying flat (length along x, label up) stood on its -x end, its label facing +x (where the renders'
    front view looks: a stand-up pouch showed its blank back, session 45)."""
    return rotated_parts(rotated_parts(parts, (0.0, -90.0, 0.0)), (0.0, 0.0, 180.0))


SACK_FOLD = 0.1  # a paper sack's folded-down top / its height [-]
SACK_FOLD_THICK = 0.45  # the folded top's thickness / the sack's depth [-]


def _paper_sack(p: PouchParams, h: float) -> list[Part]:
    """A paper sack of flour or sugar (length 1 along x its height, width along y, its depth h along z) standing on
    its flat bottom, its printed front facing +x where the renders look: a brick of paper, the top folded down flat
    into a thinner band, a gusset crease down each side, the label and its emblem on the front."""
    w, st = p.width, MIN_LAYER
    fold = SACK_FOLD
    parts = [superellipsoid("body", (0.5 - fold / 2, w / 2, h / 2), (-fold / 2, 0, h / 2), ns=0.12, ew=0.12)]
    parts.append(box("fold", (fold + 0.04, 0.98 * w, SACK_FOLD_THICK * h), (0.5 - fold / 2 - 0.02, 0, 0.62 * h),
                     edge=0.2 * SACK_FOLD_THICK * h, blend=0.04))
    parts.append(box("fold flap", (0.45 * fold, 0.96 * w, 1.2 * st), (0.5 - fold - 0.01, 0, h + 0.2 * st),
                     edge=0.45 * st, blend=0.01))  # the folded-over top's edge, glued down on the front
    for sy in (-1.0, 1.0):  # a gusset's in-fold down each side
        parts.append(_op(cylinder("gusset crease", 0.035 * h / 0.27, 0.8, (-0.08, sy * w / 2, h / 2),
                                  rot=(0, 90, 0)), "subtract", 0.01))
    if p.label:
        parts.append(box("label", (0.5, 0.84 * w, st), (-0.1, 0.0, h), edge=0.45 * st, blend=0.1 * st))
        if p.emblem != "none":
            parts += [q.model_copy(update={"transform": q.transform.model_copy(update={"translation_m": (
                q.transform.translation_m[0] - 0.1, *q.transform.translation_m[1:])})})
                for q in emblem_parts(p.emblem, h + 0.5 * st)]
    return _stood(parts)


DELI_DEPTH = 0.12  # a deli tray's depth / its length (a 20 cm pack of sliced turkey ~2.5 cm deep) [-]
DELI_SLICES = 6  # folded slices shingled along the tray [-]


def _deli_pack(p: PouchParams) -> list[Part]:
    """A flat clear tray of sliced deli meat lying flat (length 1 along x): the shallow tray ('body'), the sealed
    film's flange round its rim ('seam'), the folded slices shingled along it, each leaning on the next, their
    top edges over the rim ('fill N': the meat's colour), and a printed label band across its -x end."""
    w, st = p.width, MIN_LAYER
    d = DELI_DEPTH
    parts = [superellipsoid("body", (0.46, w / 2 - 0.03, d / 2), (0, 0, d / 2), ns=0.2, ew=0.25)]
    parts.append(box("seam", (0.98, w, 1.2 * st), (0, 0, d), edge=0.45 * st, blend=0.2 * st))
    span = 0.56
    for k in range(DELI_SLICES):  # broad thin ovals, each leaning on the next: a row of shingled slice edges
        x = -span / 2 + span * k / (DELI_SLICES - 1) + 0.05
        parts.append(superellipsoid(f"fill {k + 1}", (0.2, 0.42 * w, 1.1 * st), (x, 0.012 * (-1) ** k, d + 0.03),
                                    ns=0.7, ew=0.6, rot=(0, -16, 0), blend=0.15 * st))
    if p.label:
        parts.append(box("label", (0.14, w, 1.4 * st), (-0.42, 0, d + 0.2 * st), edge=0.45 * st, blend=0.2 * st))
    return parts


def _laundry_sack(p: PouchParams) -> list[Part]:
    """A soft laundry sack standing full of clothes (height 1 along z): a bulging body lumpy with what is in it, the
    neck gathered under a cord channel, the drawstring's two ends out of a toggle, a sleeve hanging over the rim."""
    w = p.width
    hb = 0.72
    r = w / 2
    parts = [superellipsoid("body", (r, 0.85 * r, hb / 2), (0, 0, hb / 2), ns=0.7, ew=0.9)]
    for k, a in enumerate((20.0, 110.0, 200.0, 290.0)):
        ca, sa = np.cos(np.radians(a)), np.sin(np.radians(a))
        parts.append(ellipsoid(f"lump {k + 1}", (0.16, 0.14, 0.16), (0.8 * r * ca, 0.7 * r * sa, 0.3 + 0.12 * (k % 2)),
                               blend=0.06))
    parts.append(cone("shoulder", 0.85 * r, 0.3 * r, 0.16, (0, 0, hb - 0.04), blend=0.06, scale=(1, 0.85, 1)))
    parts.append(torus("channel", 0.3 * r, 0.035, (0, 0, hb + 0.1), blend=0.02, scale=(1, 0.85, 1)))
    for i in range(6):
        a = 2 * np.pi * i / 6
        parts.append(ellipsoid(f"ruffle {i + 1}", (0.07, 0.045, 0.1), (0.3 * r * np.cos(a), 0.26 * r * np.sin(a),
                                                                      hb + 0.18),
                               rot=(0, 25, float(np.degrees(a))), blend=0.03))
    top = np.array([0.3 * r, 0.0, hb + 0.1])
    toggle = top + np.array([0.09, 0.0, -0.1])
    parts.append(cylinder("toggle", 0.03, 0.08, tuple(toggle), edge=0.01, blend=0.005))
    for k, dy in enumerate((-0.05, 0.05)):
        end = toggle + np.array([0.05, dy * 2.5, -0.17])
        parts.append(limb(f"cord {k + 1}", top + np.array([0.0, dy * 0.5, 0.0]), toggle, 0.012, blend=0.005))
        parts.append(limb(f"cord end {k + 1}", toggle, end, 0.012, blend=0.005))
    sleeve = [np.array([-0.1 * r, 0.1, hb + 0.22]), np.array([-0.45 * r, 0.3 * r, hb + 0.12]),
              np.array([-0.95 * r, 0.45 * r, hb - 0.12])]
    parts.append(tapered("sleeve", sleeve[0], sleeve[1], 0.06, 0.055, blend=0.02))
    parts.append(tapered("sleeve cuff", sleeve[1], sleeve[2], 0.055, 0.05, blend=0.02))
    return parts


NET_PIECES_MAX = 22  # goods drawn one by one over a mesh sack's seen side (the rest its core's colour); more are
# drawn larger than life, fewer of them, so each keeps two of its own parts within the 64-part budget [-]
NET_PIECE_MAX_SCALE = 2.5  # ... at most this much larger [-]
NET_SEEN_BELOW = 0.2  # goods and lumps are drawn over the sack's side down to this far under its middle (sin of the
# angle; the underside lies on the ground, unseen) [-]
NET_CORD = 0.011  # a net cord's radius / the sack's length (~1.4 draft cells across: a thinner one is not meshed) [-]
NET_TAIL = 0.12  # a clipped net's gathered end beyond the goods / its length [-]
NET_NECK = 0.2  # a drawstring sack's gathered neck, tie and ruffle beyond the goods / its length [-]
NET_LUMPS = {"tufts": 0, "mash": 40}  # small bulges of a mash pressing out between the cords (grain, not buns) [-]
NET_LOOP_CELLS = 1.3  # the cords along the sack are this much further apart than the rings round it (they gather
# into a star at each end: fewer of them) [-]
NET_TUFTS = 46  # wisps of hay over a hay net's mass, criss-crossing every way, poking out through its cords [-]


def _cap_points(n: int, below: float, seed: float) -> np.ndarray:
    """n nearly even unit directions over the sphere's cap z >= -below (a Fibonacci cap) (n, 3)."""
    k = np.arange(n) + 0.5
    z = 1.0 - (1.0 + below) * k / n
    phi = np.pi * (3.0 - np.sqrt(5.0)) * k + seed
    r = np.sqrt(np.clip(1.0 - z * z, 0.0, 1.0))
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


def _frame_euler(normal: np.ndarray, twist: float) -> tuple[float, float, float]:
    """XYZ Euler angles [deg] of a frame whose z is `normal`, its x turned by `twist` [rad] in the tangent plane."""
    n = normal / max(float(np.linalg.norm(normal)), 1e-12)
    ref = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t1 = np.cross(ref, n)
    t1 /= max(float(np.linalg.norm(t1)), 1e-12)
    t2 = np.cross(n, t1)
    x = np.cos(twist) * t1 + np.sin(twist) * t2
    m = np.stack([x, np.cross(n, x), n], axis=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        e = Rotation.from_matrix(m).as_euler("xyz", degrees=True)
    return float(e[0]), float(e[1]), float(e[2])


def _ellipsoid_area(a: float, b: float, c: float) -> float:
    """Knud Thomsen's approximation of an ellipsoid's surface area [unit^2]."""
    q = 1.6075
    return float(4.0 * np.pi * (((a * b) ** q + (a * c) ** q + (b * c) ** q) / 3.0) ** (1.0 / q))


def _net_cords(centre: np.ndarray, semi: np.ndarray, cell: float, r: float) -> list[Part]:
    """A lattice of net cords over an ellipsoid (semi-axes `semi`, its long axis along x): rings round it across
    its length and loops along it through both ends (each loop two cords), `cell` apart at its middle."""
    A, B, C = (float(v) for v in semi)
    parts: list[Part] = []
    rings = max(2, int(round(2.0 * A / cell)) - 1)
    for i in range(rings):
        u = -1.0 + 2.0 * (i + 1) / (rings + 1)
        k = np.sqrt(max(1.0 - u * u, 1e-6))
        bi, ci = B * k, C * k
        R = min(bi, ci)
        parts.append(torus(f"net {len(parts) + 1}", R, r, (float(centre[0] + A * u), float(centre[1]), float(centre[2])),
                           rot=(0.0, 90.0, 0.0), scale=(ci / R, bi / R, 1.0)))
    loops = max(2, int(round(np.pi * (B + C) / (2.0 * NET_LOOP_CELLS * cell))))
    for j in range(loops):
        alpha = 90.0 + 180.0 * j / loops
        ca, sa = np.cos(np.radians(alpha)), np.sin(np.radians(alpha))
        rj = 1.0 / np.sqrt((ca / B) ** 2 + (sa / C) ** 2)
        R = min(A, rj)
        parts.append(torus(f"net {len(parts) + 1}", R, r, tuple(float(v) for v in centre), rot=(alpha, 0.0, 0.0),
                           scale=(A / R, rj / R, 1.0)))
    return parts


def _net_body(p: PouchParams) -> tuple[float, tuple[float, float, float]]:
    """A mesh sack's body: its centre along x and its semi-axes (length 1 along x, its ends' gathered net beyond)."""
    drawstring = p.contents != "pieces"
    B = p.width / 2
    return (-NET_NECK / 2 if drawstring else 0.0), (0.5 - (NET_NECK / 2 if drawstring else NET_TAIL), B,
                                                     (0.8 if drawstring else 0.72) * B)


def net_capacity(p: PouchParams) -> float:
    """What a mesh sack of length 1 holds: its drawn body's volume [unit^3] (goods_words.bag_capacity_m3)."""
    _xc, (A, B, C) = _net_body(p)
    return float(4.0 / 3.0 * np.pi * A * B * C)


def net_sack(p: PouchParams) -> list[Part]:
    """A mesh sack lying on its side (length 1 along x): its core (`body`, what it holds seen between the goods), the
    goods packed over its seen side ('fill N' slots, drawn as the goods by tasks.geometry.pack_pieces; lumps and hay
    wisps for a stuffed mass), a lattice of net cords pressed into them, and its ends gathered into a clip each
    (goods) or a drawstring neck at +x (hay, mash), the drawstring's two ends hanging from it."""
    drawstring = p.contents != "pieces"
    xc, (A, B, C) = _net_body(p)
    a, b, c = sorted(p.piece, reverse=True) if max(p.piece) > 0 else (0.0, 0.0, 0.0)
    parts: list[Part] = []
    centre = np.array([xc, 0.0, C])
    if p.contents == "pieces" and a > 0:
        cap = _ellipsoid_area(A, B, C) * (1.0 + NET_SEEN_BELOW) / 2.0
        real = cap / (1.1 * a * b)
        n = int(np.clip(round(real), 4, NET_PIECES_MAX))
        k = float(np.clip(np.sqrt(real / n), 1.0, NET_PIECE_MAX_SCALE))
        a, b, c = a * k, b * k, c * k
        core = np.array([A, B, C]) - 0.6 * c  # the goods stand out of their core, the gaps between them its colour
        parts.append(ellipsoid("body", tuple(float(v) for v in core), tuple(centre)))
        # under the goods drawn, the sack's lower side filled out to its net (no cage of cords round an empty foot)
        parts.append(ellipsoid("body 2", (float(core[0]), float(core[1] + 0.45 * c), float(core[2])),
                               (float(centre[0]), 0.0, float(centre[2] - 0.3 * c))))
        for i, d in enumerate(_cap_points(n, NET_SEEN_BELOW, 0.4)):
            normal = d / core
            at = centre + core * d + 0.1 * c * normal / np.linalg.norm(normal)
            parts.append(ellipsoid(f"fill {i + 1}", (a / 2, b / 2, c / 2), tuple(float(v) for v in at),
                                   rot=_frame_euler(normal, 2.39996 * i + 0.7)))
        net_semi = core + 0.5 * c  # the cords pressed into the goods' tops (they hold them: one body), the goods
        # bulging between them
    else:
        semi = np.array([A, B, C])
        parts.append(ellipsoid("body", tuple(float(v) for v in semi), tuple(centre)))
        lr = 0.055
        for i, d in enumerate(_cap_points(NET_LUMPS.get(p.contents, 16), NET_SEEN_BELOW, 0.4)):
            at = centre + 0.97 * semi * d  # bulges of the stuffed mass between the cords
            name = "lump" if i % 3 else "clump"  # (a darker one here and there)
            parts.append(ellipsoid(f"{name} {i + 1}", (1.15 * lr, lr, 0.5 * lr), tuple(float(v) for v in at),
                                   rot=_frame_euler(d / semi, 1.7 * i), blend=0.35 * lr))
        net_semi = semi + (0.02 if p.contents == "tufts" else 0.12 * lr)
        if p.contents == "tufts":  # wisps of hay out through the cords every way, lying close along the surface
            for i, d in enumerate(_cap_points(NET_TUFTS, 0.3, 1.1)):
                normal = d / semi
                normal /= np.linalg.norm(normal)
                root = centre + (semi + 0.005) * d
                along = np.cross(normal, [np.cos(1.9 * i), np.sin(1.9 * i), 0.35])
                along /= max(float(np.linalg.norm(along)), 1e-9)
                length = 0.08 + 0.06 * np.sin(3.3 * i) ** 2
                rise = 0.55 if i % 3 == 0 else 0.2  # most lie along the mass, some stick out
                tip = root + length * (0.8 * along + rise * normal)
                tail = root - 0.7 * length * along - 0.01 * normal
                parts.append(limb(f"{'straw' if i % 3 == 1 else 'tuft'} {i + 1}", tuple(float(v) for v in tail),
                                  tuple(float(v) for v in tip), 0.011 if i % 2 else 0.0095, blend=0.004))
    cell = p.mesh_cell
    parts += _net_cords(centre, net_semi, cell, NET_CORD * (1.15 if cell >= 0.14 else 1.0))
    end = float(net_semi[0])
    z = float(centre[2])
    r0 = 0.22 * float(min(net_semi[1], net_semi[2]))
    if drawstring:  # the net gathered into a neck, its drawstring tied round it, the net's ends flaring past it
        x0 = xc + end
        parts.append(tapered("neck", (x0 - 0.1, 0.0, z), (x0 + 0.07, 0.0, z), 1.6 * r0, 0.03, blend=0.05))
        parts.append(torus("tie", 0.035, 0.014, (x0 + 0.06, 0.0, z), rot=(0, 90, 0), blend=0.005))
        parts.append(cone("ruffle", 0.025, 0.06, 0.07, (x0 + 0.1, 0.0, z), edge=0.008, rot=(0, 90, 0), blend=0.02))
        for i, sy in enumerate((-1.0, 1.0)):  # the drawstring's two ends hanging to the ground
            parts.append(limb(f"cord end {i + 1}", (x0 + 0.06, sy * 0.02, z), (x0 + 0.1 + 0.03 * i, sy * 0.09, 0.012),
                              0.011, blend=0.004))
    else:  # both ends of the net gathered into a clip, a tail of net past each
        for side, sx in (("left", -1.0), ("right", 1.0)):
            x0 = xc + sx * (float(parts[0].primitive.radii_m[0]) - 0.02)  # type: ignore[union-attr]  # (from the core)
            x1 = xc + sx * (end + NET_TAIL * 0.5)
            parts.append(tapered(f"{side} net", (x0, 0.0, z), (x1, 0.0, z), r0, 0.02, blend=0.03))
            parts.append(cylinder(f"{side} clip", 0.028, 0.045, (x1, 0.0, z), edge=0.006, rot=(0, 90, 0),
                                  blend=0.004))
            parts.append(cone(f"{side} tail", 0.018, 0.04, 0.045, (x1 + sx * 0.04, 0.0, z), edge=0.006,
                              rot=(0, sx * 90, 0), blend=0.008))
    return parts[:MAX_PARTS]


def _label(width: float, h: float) -> Part:
    """A pack's printed label: a flat panel just proud of the filled top (at h) across `width`, its own colour."""
    st = MIN_LAYER
    return box("label", (LABEL_SIZE[0], LABEL_SIZE[1] * width, st), (0.0, 0.0, h), edge=0.45 * st, blend=0.1 * st)


BAG_DEPTH_OVER_PIECE = 0.9  # a bag of goods' depth over one piece's thickness (the goods press up its film) [-]
MAX_PIECES = 28  # goods drawn pressing through a bag's film; more (rice, peas) are its fill's colour alone [-]


def piece_grid(p: PouchParams) -> tuple[int, int]:
    """(along, across) the pieces bagged_pieces draws over a pouch's top [-]."""
    a, b, _c = sorted(p.piece, reverse=True)
    inner_x, inner_y = 1.0 - 2.2 * p.seam, p.width - 2.2 * p.seam
    return max(1, int(inner_x // (1.05 * a))), max(1, int(inner_y // (1.05 * b)))


PIECE_DRAWN_MAX_SCALE = 2.0  # goods a little too many to draw are drawn up to this much larger, fewer of them [-]


def _countable(p: PouchParams) -> PouchParams:
    """The pouch with its pieces drawn at most PIECE_DRAWN_MAX_SCALE times larger when more than MAX_PIECES of them
    would cover its top (a bag of gummy bears: 64 bears of 2.5 cm on a 25 cm bag drawn as 28 larger ones, still a bag
    of bears; rice or peas, far smaller, stay the fill's colour alone). Only the drawing: the fill's mass is its own."""
    if max(p.piece) <= 0:
        return p
    for k in np.arange(1.0, PIECE_DRAWN_MAX_SCALE + 1e-9, 0.05):
        q = p.model_copy(update={"piece": tuple(float(v * k) for v in p.piece)})
        nx, ny = piece_grid(q)
        if nx * ny <= MAX_PIECES:
            return q
    return p


def bagged_pieces(p: PouchParams, h: float) -> list[Part]:
    """The goods of a clear bag pressing up through its film: pieces in staggered rows over the bag's top, each
    standing half out of the filled body ('a bag of marshmallows', 'a pack of sponges'); none when they are too
    small to tell apart (rice, peas)."""
    p = _countable(p)
    a, b, c = sorted(p.piece, reverse=True)
    a, b = a * 1.05, b * 1.05
    inner_x, inner_y = 1.0 - 2.2 * p.seam, p.width - 2.2 * p.seam
    nx, ny = piece_grid(p)
    if nx * ny > MAX_PIECES or a > inner_x or b > inner_y:
        return []
    ns, ew = {"ball": (1.0, 1.0), "cylinder": (0.2, 1.0), "block": (0.25, 0.25), "shred": (0.7, 0.6)}[p.piece_shape]
    shred = p.piece_shape == "shred"
    out: list[Part] = []
    for j in range(ny):
        for i in range(nx):
            x = -inner_x / 2 + (i + 0.5 + (0.25 if j % 2 else -0.25) * (nx > 1)) * inner_x / nx
            y = -inner_y / 2 + (j + 0.5) * inner_y / ny
            x = float(np.clip(x, -inner_x / 2 + a / 2, inner_x / 2 - a / 2))
            tilt = 9.0 * np.sin(2.7 * i + 1.3 * j)
            if shred:  # a shred of leaf tumbled every way, curled: its edge up here, its face there
                out.append(superellipsoid(f"fill {len(out) + 1}", (a / 2.1, b / 2.1, c / 2), (x, y, h - 0.25 * b),
                                          ns=ns, ew=ew, rot=(4.0 * tilt, 2.5 * tilt, 40.0 * i + 75.0 * j),
                                          blend=0.3 * c))
                continue
            # each sunk in the bag to just under its top, the film drawn over it: bumps in a pillow, not goods on a tray
            out.append(superellipsoid(f"fill {len(out) + 1}", (a / 2.1, b / 2.1, c / 2), (x, y, h - 0.5 * c),
                                      ns=ns, ew=ew, rot=(tilt, 0.6 * tilt, 1.4 * tilt), blend=0.3 * c))
    return out


# -------------------------------------------------------------------------------------------------- hands and feet
class GloveParams(Model):
    """A glove (palm and five fingers) or a mitten (palm, mitt and thumb), lying flat, fingers towards +x."""

    mitten: bool = False
    finger_length: float = Field(default=1.0, gt=0.4, le=1.6, description="middle finger / palm length [-]")
    thickness: float = Field(default=0.12, gt=0.04, le=0.5, description="thickness / palm width [-]")
    cuff: float = Field(default=0.6, ge=0.0, le=2.0, description="cuff length / palm length [-]")
    flare: float = Field(default=1.1, gt=0.8, le=1.6, description="cuff width at its opening / palm width [-]")
    spread: float = Field(default=6.0, ge=0.0, le=20.0, description="angle between fingers [deg]")
    boxing: bool = Field(default=False, description="a boxing glove: a padded fist curled over the palm, the thumb "
                         "pressed to its side, a round cuff with a strap band, lying on its little-finger side")
    padded: bool = Field(default=False, description="a padded sports glove (an ice hockey or lacrosse glove): "
                         "rolls of padding across each finger and the back of the hand, and a rolled edge round the "
                         "gauntlet cuff's opening")
    state: Literal["flat", "inflated"] = Field(default="flat", description="inflated: blown up like a balloon and "
                                                 "tied off (a party trick with a disposable glove): a round palm, "
                                                 "fat fingers spread, the cuff gathered into a knot")


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


def _inflated_glove(p: GloveParams) -> list[Part]:
    """A glove blown up and tied off: the palm a balloon (round in section), the fingers fat teats spread in a fan and
    tilted up a little, the thumb to the side, the cuff drawn into a neck with a knot; palm length 0.34 as `glove`."""
    pl, pw = 0.34, 0.36
    r = 0.19  # the palm's half-thickness: blown round
    parts = [ellipsoid("palm", (pl / 2 + 0.02, pw / 2, r), (0, 0, r))]
    fr = pw / 6.4
    for i, (name, share) in enumerate(_FINGERS):
        y = pw / 2 - fr - i * (pw - 2 * fr) / 3
        a = np.radians(14.0 * (1.5 - i))
        length = share * p.finger_length * pl * 0.8
        base = np.array([pl / 2 - 0.05, y, r])
        tip = base + length * np.array([np.cos(a), np.sin(a), 0.25])
        parts.append(limb(name, tuple(base), tuple(tip), fr, blend=0.04))
    tb = np.array([-0.02, pw / 2 - 0.03, r])
    ta = np.radians(62.0)
    parts.append(limb("thumb", tuple(tb), tuple(tb + 0.5 * pl * np.array([np.cos(ta), np.sin(ta), 0.2])), 1.15 * fr,
                      blend=0.04))
    neck_end = np.array([-pl / 2 - 0.12, 0.0, 0.7 * r])
    parts.append(limb("cuff", (-pl / 2 + 0.04, 0.0, r), tuple(neck_end), 0.05, blend=0.05))
    parts.append(ellipsoid("knot", (0.035, 0.03, 0.03), tuple(neck_end + np.array([-0.02, 0.0, 0.0])), blend=0.015))
    return parts


def _boxing_glove() -> list[Part]:
    """A boxing glove lying on its little-finger side, the fist towards +x, the thumb up: length ~1 (a 12 oz glove
    is ~31 cm long, its fist ~15 cm across the knuckles and ~13 cm deep, its cuff ~11 x 9 cm)."""
    fist = superellipsoid("body", (0.31, 0.21, 0.24), (0.66, 0.0, 0.25), ns=0.8, ew=0.8, rot=(0, 12, 0))
    curl = ellipsoid("finger roll", (0.16, 0.18, 0.14), (0.86, 0.0, 0.17), blend=0.08)  # the fingers curled under
    palm = ellipsoid("palm", (0.22, 0.17, 0.16), (0.52, 0.0, 0.18), blend=0.08)
    thumb = limb("thumb", (0.40, -0.07, 0.43), (0.74, -0.06, 0.47), 0.085, blend=0.025)  # on the palm's edge
    wrist = superellipsoid("wrist", (0.22, 0.16, 0.17), (0.24, 0.0, 0.19), ns=0.45, ew=0.9, blend=0.06)
    strap = superellipsoid("cuff", (0.08, 0.172, 0.182), (0.17, 0.0, 0.19), ns=0.3, ew=0.9)
    return [fist, curl, palm, thumb, wrist, strap]


def glove(p: GloveParams) -> list[Part]:
    """Palm length 0.34, width 0.3 (the glove's parts in proportion); lying palm down."""
    if p.boxing:
        return _boxing_glove()
    if p.state == "inflated":
        return _inflated_glove(p)
    pl, pw = 0.34, 0.3
    t = p.thickness * pw
    z = t / 2
    parts = [superellipsoid("palm", (pl / 2, pw / 2, t / 2), (0, 0, z), ns=0.6, ew=0.45)]
    fr = pw / 8.6
    if p.mitten:
        ml = 0.8 * p.finger_length * pl
        parts.append(superellipsoid("finger pocket", (ml / 2 + 0.03, pw / 2, t / 2), (pl / 2 + ml / 2 - 0.05, 0, z), ns=0.7,
                                    ew=0.9, blend=0.04))
    else:
        for i, (name, share) in enumerate(_FINGERS):
            y = pw / 2 - fr - i * (pw - 2 * fr) / 3
            a = np.radians(p.spread * (1.5 - i))
            length = share * p.finger_length * pl * 0.85
            base = np.array([pl / 2 - 0.03, y, z])
            tip = base + length * np.array([np.cos(a), np.sin(a), 0.0])
            parts.append(_flat_limb(name, base, tip, fr, t, blend=0.02))
            if p.padded:  # two padded rolls across the finger's back
                for k, at in enumerate((0.35, 0.72)):
                    c = base + at * (tip - base) + np.array([0.0, 0.0, 0.12 * t])
                    parts.append(ellipsoid(f"{name} roll {k + 1}", (0.13 * length, 1.15 * fr, 0.5 * t),
                                           tuple(float(v) for v in c), rot=(0, 0, float(np.degrees(a))), blend=0.01))
    if p.padded and not p.mitten:  # the back of the hand: two padded bars across it
        for k, x in enumerate((-0.07, 0.06)):
            parts.append(superellipsoid(f"back roll {k + 1}", (0.05, 0.46 * pw, 0.3 * t), (x, 0, 1.05 * t), ns=0.5,
                                        ew=0.5, blend=0.01))
    ta = np.radians(40 + p.spread)
    tb = np.array([-0.05, pw / 2 - 0.02, z])
    parts.append(_flat_limb("thumb", tb, tb + 0.6 * pl * np.array([np.cos(ta), np.sin(ta), 0.0]),
                            (1.7 if p.mitten else 1.1) * fr, t, blend=0.03))
    if p.cuff > 0:
        cl = p.cuff * pl
        c = cone("cuff", pw / 2, pw / 2 * p.flare, cl + 0.04, (-pl / 2 - cl / 2 + 0.02, 0, z), edge=0.2 * t,
                 blend=0.03, rot=(0, -90, 0))
        parts.append(scaled(c, (min(1.0, t / pw), 1, 1)))
        if p.padded:  # the gauntlet's opening: a rolled edge across it
            x = -pl / 2 - cl + 0.03
            half = pw / 2 * p.flare
            parts.append(_flat_limb("cuff roll", np.array([x, -half, z]), np.array([x, half, z]), 0.6 * t,
                                    1.15 * t, blend=0.01))
    return parts


class SockParams(Model):
    """A sock lying flat on its side: the leg tube down to the heel, the foot along x to the toe (an L)."""

    leg_length: float = Field(default=0.9, ge=0.15, le=3.0, description="leg / foot length [-]")
    width: float = Field(default=0.33, gt=0.15, le=0.6, description="flat width / foot length [-]")
    thickness: float = Field(default=0.1, gt=0.03, le=0.5, description="thickness / foot length [-]")
    angle: float = Field(default=100.0, ge=90.0, le=150.0, description="angle between leg and foot [deg]")
    cuff: bool = Field(default=True, description="a ribbed band at the opening")
    state: Literal["flat", "rolled"] = Field(default="flat", description="flat, or rolled up into a sock ball (the "
                                             "cuff turned over it)")
    pair: bool = Field(default=False, description="two socks: side by side, or rolled together into one ball")
    standing: bool = Field(default=False, description="a boot standing on its sole (a rubber boot, a wellington): "
                           "the leg upright, a tread sole under the foot and heel, its opening a dark hollow at the "
                           "top")


def sock(p: SockParams) -> list[Part]:
    """Foot length 1 along x (heel at the origin); the leg rises towards +y. Rolled: a ball of the sock's (or the
    pair's) volume, the turned-over cuff a ribbed band round it."""
    if p.state == "rolled":
        return _sock_ball(p)
    if p.pair:
        one = sock(p.model_copy(update={"pair": False}))  # the second over the first, shifted (one body)
        dy, dz = 0.5 * p.width, 0.85 * p.thickness
        other = [q.model_copy(update={"name": f"other {q.name}", "transform": q.transform.model_copy(update={
            "translation_m": (q.transform.translation_m[0] + 0.12, q.transform.translation_m[1] - dy,
                              q.transform.translation_m[2] + dz)})}) for q in one]
        return one + other
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
    if p.standing:  # the L turned up (the leg along +z), a sole under the foot, the opening sunk into the top
        parts = rotated_parts(parts, (90.0, 0.0, 0.0))
        zt = float(top[1])
        xt = float(top[0])
        sole = 0.07
        parts.append(box("sole", (1.0 + 0.1 * r, 1.02 * t, sole), (0.5 - 0.5 * r, -t / 2, -r + sole / 2),
                         edge=0.3 * sole, blend=0.02))
        parts.append(_op(scaled(cylinder("hollow", 0.8 * r, 0.3, (xt, -t / 2, zt + 0.9 * r)), (1.0, 0.75 * t / r / 2
                                                                                              * 2, 1.0)), "subtract",
                         0.02))
        parts.append(scaled(cylinder("opening", 0.78 * r, 0.02, (xt, -t / 2, zt + 0.9 * r - 0.15)),
                            (1.0, 0.75 * t / r, 1.0)))
    return parts


SOCK_BALL_RIBS = 24  # knit ribs round a rolled sock's turned-over cuff [-]


def _sock_ball(p: SockParams) -> list[Part]:
    """A rolled sock (pair): the flat sock's volume as a slightly squashed oval bundle, the turned-over cuff a wide
    ribbed band round its middle with two stripes along its edges (an athletic sock's), the toe tucked inside."""
    # the flat sock is drawn puffier than its two knit layers (~1 cm): rolled tight, the ball holds ~0.45 of that
    flat = 0.45 * p.width * p.thickness * (1.0 + p.leg_length) * 0.85 * (2 if p.pair else 1)
    r = float((flat / (4 / 3 * np.pi * 0.8)) ** (1 / 3))
    zc = 0.84 * r
    parts = [ellipsoid("body", (1.15 * r, 0.95 * r, 0.84 * r), (0, 0, zc))]
    # the turned-over cuff covers the bundle's middle (a narrow band at one end was named a surprise egg's rim and the
    # toe's dark cap an onion's root by blind reviewers, sets 19 and 20), its knit ribs grooves along the roll's axis
    band_x, band_half = 0.1 * r, 0.5 * r
    parts.append(scaled(torus("cuff", 0.9 * r, 0.14 * r, (band_x, 0, zc), rot=(0, 90, 0)),
                        (0.9, 1.0, band_half / (0.14 * r))))
    for i in range(SOCK_BALL_RIBS):
        a = 2 * np.pi * i / SOCK_BALL_RIBS
        y, z = 1.05 * r * np.cos(a), zc + 0.96 * r * np.sin(a)
        parts.append(limb(f"rib {i + 1}", (band_x - 0.8 * band_half, y, z), (band_x + 0.8 * band_half, y, z),
                          0.05 * r).model_copy(update={"operation": "subtract"}))
    for side in (-1.0, 1.0):
        x = band_x + side * 0.62 * band_half
        parts.append(scaled(torus(f"{'left' if side < 0 else 'right'} stripe", 0.9 * r, 0.24 * r, (x, 0, zc),
                                  rot=(0, 90, 0)), (0.9, 1.0, 0.5)))
    return parts


class HatParams(Model):
    """A soft hat: an open dome (a beanie, a bucket or sun hat with a brim, a baby bonnet), opening down."""

    height: float = Field(default=0.85, gt=0.3, le=1.5, description="crown height / crown diameter [-]")
    wall: float = Field(default=0.04, gt=0.0, le=0.2, description="wall thickness / crown diameter [-]")
    cuff: float = Field(default=0.2, ge=0.0, le=0.5, description="folded-up cuff band height / crown diameter [-]")
    brim: float = Field(default=0.0, ge=0.0, le=0.6, description="brim width / crown diameter [-]")
    pompom: bool = False
    ribs: int = Field(default=0, ge=0, le=40, description="knit ribs: vertical grooves round the crown and cuff [-]")
    visor: float = Field(default=0.0, ge=0.0, le=0.9, description="a peak (visor) out of the front of the crown, its "
                         "length / crown diameter (a baseball cap ~0.4-0.6) [-]")


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
    if p.visor > 0:  # a stiffened peak: a flat half-ellipse out of the rim at the front, dipping a little
        parts.append(ellipsoid("visor", (0.5 * p.visor + 0.25, 0.46, 1.5 * w), (R + 0.5 * p.visor - 0.25, 0, 1.5 * w),
                               blend=0.02, rot=(0, 6, 0)))
        parts.append(ellipsoid("button", (0.05, 0.05, 0.03), (0, 0, H), blend=0.01))
    for i in range(p.ribs):  # knit ribs: shallow grooves up the cuff
        a = 2 * np.pi * i / p.ribs
        rr = R + 0.6 * w + 0.004
        parts.append(_op(limb(f"rib {i + 1}", (rr * np.cos(a), rr * np.sin(a), -0.05),
                              (rr * np.cos(a), rr * np.sin(a), p.cuff - 0.03), 0.016), "subtract"))
    if p.cuff > 0:
        parts.append(_op(scaled(torus("cuff edge", R + 0.6 * w + 0.01, 0.012, (0, 0, p.cuff)), (1, 1, 1)),
                         "subtract"))
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
        parts.append(scaled(cylinder("blade", hw / 2, t, (x0 + 0.6 * head_len, 0, z), edge=0.45 * t, blend=0.005),
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
            parts.append(scaled(torus("rim", 0.5 + w, 1.2 * w, (0, 0, h - 0.6 * w)), (1, 1, 0.6))
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


# ------------------------------------------------------------------------------------------------- crumpled heaps
def _rng_angles(n: int, seed: float) -> list[tuple[float, float, float]]:
    """n deterministic (angle, radius share, turn) triples spread over a disc (a golden-angle spiral, jittered)."""
    out = []
    for i in range(n):
        a = i * 2.39996 + seed
        r = np.sqrt((i + 0.5) / n)
        out.append((float(a), float(r), float(np.sin(3.7 * i + seed) * 70.0)))
    return out


def heap(diameter: float, height: float, t: float, seed: float = 0.3, folds: int = 10, flaps: int = 3,
         name: str = "body") -> list[Part]:
    """A crumpled, bunched heap of cloth on the ground: a low, uneven mound crossed by many narrow folds (ridges) of
    different lengths and heights, and a few of the cloth's corners and edges lying out on the floor at uneven
    places; footprint `diameter`, top at about `height`, cloth `t` thick. (Four even flaps round a rounded mound
    with broad folds read as a plush animal lying face down: s30's judges named a crumpled towel a teddy bear.)"""
    R = diameter / 2
    parts = [ellipsoid(name, (0.82 * R, 0.7 * R, 0.64 * height), (0.05 * R, 0.03 * R, 0.05 * height))]
    for i, (a, r, turn) in enumerate(_rng_angles(folds, seed)):
        rho = 0.62 * R * r
        x, y = rho * np.cos(a), rho * np.sin(a)
        top = 0.68 * height * np.sqrt(max(1 - (x / (0.85 * R)) ** 2 - (y / (0.72 * R)) ** 2, 0.05)) + 0.06 * height
        length = (0.45 + 0.35 * abs(np.sin(2.3 * i + seed))) * R
        rad = (0.25 + 0.06 * np.sin(2.7 * i)) * height
        d = np.degrees(a) + 90 + turn
        lean = 25 * np.sin(1.9 * i + seed)
        parts.append(ellipsoid(f"fold {i + 1}", (length / 2, 0.6 * rad, rad), (x, y, top - 0.1 * rad),
                               rot=(float(lean), 0, float(d)), blend=0.7 * rad))
    for i in range(flaps):  # corners and edges out on the floor, at uneven angles and of uneven sizes
        a = seed + 0.8 + i * 2.1 + 0.6 * np.sin(5.0 * i + seed)
        rho = (0.72 + 0.12 * np.sin(3.1 * i)) * R
        size = (0.45 + 0.2 * np.sin(2.3 * i + seed)) * R
        parts.append(box(f"corner {i + 1}", (size, (0.5 + 0.3 * np.cos(1.7 * i)) * size, t),
                         (rho * np.cos(a), rho * np.sin(a), t / 2 + 0.03 * R * (i % 2)), edge=0.45 * t,
                         rot=(0, float(6 * np.sin(1.7 * i)), float(np.degrees(a)) + 25 + 30 * np.sin(i)),
                         blend=0.05 * R))
    parts.append(_op(box("ground", (8, 8, 8), (0, 0, 4)), "intersect"))
    return parts


def _heap_flaps(R: float, height: float, seed: float, tiers: tuple[tuple[float, ...], ...], offset: float
                ) -> Iterator[tuple[int, int, float, float, float, float, float, Rotation]]:
    """Each flap of a heap of cloth: (tier, index, width share, length, angle round the heap, distance out, drop, its
    turn); tiers: (flaps, out from the centre, height, length, width) / the heap's radius R, each tier's flaps turned
    `offset` of a step from the last's and each turned off the radial (overlapping, not a star)."""
    for ti, (n, rho, zs, ln, wd) in enumerate(tiers):
        for i in range(int(n)):
            a = seed + 2 * np.pi * (i + offset * ti) / n + 0.35 * np.sin(3.3 * i + seed)
            length = (ln + 0.15 * np.sin(2.1 * i + seed)) * R
            drop = zs * height
            tilt = float(np.degrees(np.arctan2(drop, 0.8 * length)))
            skew = 28 * np.sin(2.3 * i + 1.7 * seed)
            turn = Rotation.from_euler("z", np.degrees(a) + skew, degrees=True) * Rotation.from_euler(
                "xy", [14 * np.sin(1.3 * i + seed), tilt], degrees=True)
            yield ti, i, float(wd), float(length), float(a), float((rho + 0.08 * np.sin(2.9 * i)) * R), float(drop), turn


def creased_heap(diameter: float, height: float, t: float, seed: float = 0.3) -> list[Part]:
    """A sheet balled up and dropped (a fitted sheet, a towel, a blanket): a low, lopsided mound under the cloth, the
    cloth lying over it in overlapping flaps (their edges seen all round, sloping from the top down to the floor), a
    few narrow folds along the top; no rounded lobes standing up (heap's ridges read as a plush bunny's ears and paws:
    session 38's judges named a balled-up fitted sheet a plush rabbit)."""
    R = diameter / 2
    parts = [ellipsoid("body", (0.62 * R, 0.52 * R, 0.6 * height), (0.05 * R, 0.0, 0.0))]
    tiers = ((6, 0.5, 0.32, 0.85, 0.8), (4, 0.18, 0.6, 0.6, 0.6))  # (flaps, out from the centre, height, size)
    for ti, i, wd, length, a, r_, drop, turn in _heap_flaps(R, height, seed, tiers, 0.37):
        parts.append(box(f"{'corner' if ti == 0 else 'flap'} {i + 1}", (length, (wd + 0.15 * np.cos(1.7 * i)) * R, t),
                         (r_ * np.cos(a), r_ * np.sin(a), drop / 2 + 0.6 * t + 0.1 * height * ti), edge=0.45 * t,
                         rot=tuple(float(e) for e in turn.as_euler("xyz", degrees=True)), blend=0.03 * R))
    for i, (a, r, turn) in enumerate(_rng_angles(5, seed)):  # narrow folds over the top
        rho = 0.3 * R * r
        parts.append(ellipsoid(f"fold {i + 1}", ((0.16 + 0.06 * np.sin(i)) * R, 0.03 * R + 0.5 * t, 0.06 * height),
                               (rho * np.cos(a), rho * np.sin(a), 0.56 * height),
                               rot=(0, 0, float(np.degrees(a) + 90 + turn)), blend=0.04 * R))
    parts.append(_op(box("ground", (8, 8, 8), (0, 0, 4)), "intersect"))
    return parts


QUILTED_HEAP_BAFFLES = 3  # puffy baffle tubes side by side across each flap of a bunched quilted bag [-]


def quilted_heap(diameter: float, height: float, t: float, seed: float = 0.3, zip_: bool = False) -> list[Part]:
    """A quilted bag or duvet bunched up (a sleeping bag in a heap): creased_heap's lopsided mound and overlapping
    flaps, each flap drawn as QUILTED_HEAP_BAFFLES puffy tubes side by side (the down-filled channels between their
    stitch lines), and a zip ('zip') along one flap's edge; a plain creased heap read as a towel (sealed set 32's
    sleeping bag, judged 'a crumpled navy towel')."""
    R = diameter / 2
    parts = [ellipsoid("body", (0.55 * R, 0.45 * R, 0.5 * height), (0.05 * R, 0.0, 0.0))]
    puff = 0.5 * t  # a baffle tube's radius: half the quilted layer (its channels' full height)
    flaps = ((5, 0.5, 0.3, 0.9, 0.55), (3, 0.16, 0.62, 0.65, 0.45))  # (flaps, out, height, length, width) / R
    zipped = False
    for ti, i, wd, length, a, r_, drop, turn in _heap_flaps(R, height, seed, flaps, 0.41):
        centre = np.array([r_ * np.cos(a), r_ * np.sin(a), drop / 2 + puff + 0.1 * height * ti])
        along, across = turn.apply([1.0, 0.0, 0.0]), turn.apply([0.0, 1.0, 0.0])
        width = (wd + 0.1 * np.cos(1.7 * i)) * R
        for k in range(QUILTED_HEAP_BAFFLES):  # the flap's channels, each a puffy tube along it
            off = (k - (QUILTED_HEAP_BAFFLES - 1) / 2) * width / QUILTED_HEAP_BAFFLES
            mid = centre + off * across
            parts.append(limb(f"{'corner' if ti == 0 else 'flap'} {i + 1} baffle {k + 1}",
                              mid - along * (length / 2 - puff), mid + along * (length / 2 - puff), puff,
                              blend=0.1 * puff))
        if zip_ and not zipped and ti == 0:  # the zip along the flap's outer edge, just proud of its tube
            edge = centre + (width / 2 + 0.2 * puff) * across + 0.55 * puff * turn.apply([0.0, 0.0, 1.0])
            parts.append(limb("zip", edge - along * 0.45 * length, edge + along * 0.45 * length, 0.3 * puff))
            zipped = True
    parts.append(_op(box("ground", (8, 8, 8), (0, 0, 4)), "intersect"))
    return parts


CRUMPLE_THIN = 0.0025  # a cloth thinner than this / its flat length (a bed sheet, a tablecloth, a napkin, a silk scarf)
# crumples into many thin, sharp folds with thin edges draped out on the floor [-]
CRUMPLE_SOFT = 0.0038  # a cloth at least this thick / its length and no towel's border (a fleece or wool blanket, a
# throw) bunches into a few thick, soft rolls; between the two (a towel, a tea towel) the creased terry heap [-]
CRUMPLE_CELLS = 64  # the draft mesher's cells along a heap's extent (about 2.2 of its radii) [-]
THIN_FLAP_CELLS = 2.2  # a thin cloth's built flap at least this many of those cells thick [-]
THIN_FOLDS = 12  # a thin cloth's sharp folds running from its heap's top down to the floor (two bars each) [-]
SOFT_ROLLS = 5  # thick soft rolls over a bunched blanket (two segments each) [-]
STRIP_WIDTH = 0.4  # a sheet narrower than this / its length (a scarf, a runner) shows its two ends trailing out [-]


def crumple_class(p: SheetParams) -> Literal["thin", "terry", "soft"]:
    """How a cloth bunches (its thickness / its flat length): 'thin' (a sheet, a tablecloth, a napkin, a silk scarf:
    many thin sharp folds), 'soft' (a blanket, a throw: a few thick soft rolls) or 'terry' (a towel, or anything with
    a towel's woven border: the creased heap of overlapping flaps)."""
    if p.thickness < CRUMPLE_THIN:
        return "thin"
    if p.thickness >= CRUMPLE_SOFT and not p.border:
        return "soft"
    return "terry"


def _ridge_euler(along: np.ndarray, up: np.ndarray, roll: float = 0.0) -> tuple[float, float, float]:
    """Extrinsic xyz Euler angles [deg] of a part whose local x lies along `along`, its local z as near `up` as
    square to it allows, turned `roll` degrees about its own x."""
    x = along / np.linalg.norm(along)
    z = up - np.dot(up, x) * x
    z = z / np.linalg.norm(z)
    frame = np.stack([x, np.cross(z, x), z], axis=1)
    turn = Rotation.from_matrix(frame) * Rotation.from_euler("x", roll, degrees=True)
    return tuple(float(e) for e in turn.as_euler("xyz", degrees=True))  # type: ignore[return-value]


def _flap_decor(p: SheetParams, k: int, centre: np.ndarray, turn: Rotation, length: float, width: float,
                t: float) -> list[Part]:
    """A flap's share of the cloth's pattern, lying on its top: a stripe across it (and one along it for a check), a
    towel's woven border band near its outer end, or a hem band along that end; none for a plain cloth."""
    along, across, up = (turn.apply(v) for v in ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]))
    rot = tuple(float(e) for e in turn.as_euler("xyz", degrees=True))
    lift = centre + 0.35 * t * up
    out: list[Part] = []
    if p.stripes:
        at = lift + (0.12 + 0.12 * np.sin(1.9 * k)) * length * along
        out.append(box(f"stripe {2 * k + 1}", (0.2 * length, 0.96 * width, 0.9 * t), tuple(at), edge=0.3 * t, rot=rot,
                       blend=0.1 * t))
        if p.checks:
            at = lift + 0.18 * np.cos(2.3 * k) * width * across
            out.append(box(f"check {2 * k + 1}", (0.9 * length, 0.2 * width, 0.95 * t), tuple(at), edge=0.3 * t,
                           rot=rot, blend=0.1 * t))
    if p.border or p.hem:
        at = lift + (0.5 - (0.2 if p.border else 0.07)) * length * along
        out.append(box(f"{'border' if p.border else 'hem'} {k + 1}", (0.1 * length, 0.96 * width, 0.9 * t), tuple(at),
                       edge=0.3 * t, rot=rot, blend=0.1 * t))
    return out


def cloth_heap(p: SheetParams, t: float) -> list[Part]:
    """A cloth crumpled and dropped, drawn by how it bunches (crumple_class): a thin cloth as a low mound under many
    thin flaps draped out to the floor, crossed by sharp folds running from its top down to the floor; a blanket as a
    rounder mound under thick soft-edged flaps with a few thick soft rolls over it and rolled edges; a towel as the
    creased heap. Each keeps its pattern (stripes, checks, a border or hem band on its flaps) and its fringe; a strip
    (a scarf) its two ends trailing out of the heap. (One thick creased heap for every cloth: a crumpled bed sheet,
    blanket and tablecloth all read as a towel to blind judges, session 47.)"""
    w = p.width
    d, height = crumpled_size(w)
    seed = 0.3 + 3 * w
    kind = crumple_class(p)
    if kind == "terry" and not (p.stripes or p.border or p.hem or p.fringe) and w >= STRIP_WIDTH:
        return creased_heap(d, height, t, seed=seed)
    R = d / 2
    cell = 2.2 * R / CRUMPLE_CELLS
    if kind == "thin":
        tl = min(t, max(p.thickness, THIN_FLAP_CELLS * cell))
        body = ellipsoid("body", (0.6 * R, 0.5 * R, 0.6 * height), (0.04 * R, 0.0, 0.0))
        tiers = ((7, 0.55, 0.3, 0.9, 0.62), (4, 0.22, 0.36, 0.55, 0.5))
    elif kind == "soft":
        tl = 1.2 * t
        body = ellipsoid("body", (0.62 * R, 0.54 * R, 0.66 * height), (0.04 * R, 0.0, 0.0))
        tiers = ((6, 0.5, 0.32, 0.85, 0.8), (3, 0.18, 0.6, 0.6, 0.6))
    else:
        tl = t
        body = ellipsoid("body", (0.62 * R, 0.52 * R, 0.6 * height), (0.05 * R, 0.0, 0.0))
        tiers = ((6, 0.5, 0.32, 0.85, 0.8), (4, 0.18, 0.6, 0.6, 0.6))
    parts = [body]
    decor: list[Part] = []
    ends: list[tuple[np.ndarray, Rotation, float, float]] = []  # the tier-0 flaps' (centre, turn, length, width)
    flaps: list[tuple[np.ndarray, Rotation, float, float, int]] = []  # every flap's, and its tier
    strip = w < STRIP_WIDTH
    for ti, i, wd, length, a, r_, drop, turn in _heap_flaps(R, height, seed, tiers, 0.37):
        width = (wd + 0.15 * np.cos(1.7 * i)) * R
        if strip and ti == 0 and i < 2:  # a strip's two ends trailing out along the floor
            length, width, drop = 2.2 * R, min(width, 0.9 * w), 0.25 * height
            turn = Rotation.from_euler("z", np.degrees(a), degrees=True) * Rotation.from_euler(
                "y", np.degrees(np.arctan2(drop, length)), degrees=True)
        centre = np.array([r_ * np.cos(a), r_ * np.sin(a), drop / 2 + 0.6 * tl + 0.1 * height * ti])
        if strip and ti == 0 and i < 2:
            centre[:2] = (0.45 * R + 0.5 * length) * np.array([np.cos(a), np.sin(a)])
            centre[2] = drop / 2 + 0.6 * tl
        rot = tuple(float(e) for e in turn.as_euler("xyz", degrees=True))
        parts.append(box(f"{'corner' if ti == 0 else 'flap'} {i + 1}", (length, width, tl), tuple(centre),
                         edge=(0.49 if kind == "soft" else 0.45) * tl, rot=rot, blend=0.03 * R))
        flaps.append((centre, turn, length, width, ti))
        if ti == 0:
            ends.append((centre, turn, length, width))
            decor += _flap_decor(p, i, centre, turn, length, width, tl)
    if kind == "thin":  # many thin, sharp folds: square bars turned 45 deg about their length (a crest up), sunk
        # into the cloth, running from the top down over the mound and the draped flaps to the floor
        for i, (a, r, _) in enumerate(_rng_angles(THIN_FOLDS, seed + 0.5)):
            sq = (0.06 + 0.015 * np.sin(2.3 * i)) * R
            a2 = a + 0.35 * np.sin(1.7 * i + seed)
            a0 = a - 0.3 * np.sin(1.7 * i + seed)  # (the folds start apart, no star at the top)
            pts = [np.array([(0.12 + 0.22 * r) * R * np.cos(a0), (0.12 + 0.22 * r) * R * np.sin(a0),
                             (0.58 - 0.1 * r) * height]),
                   np.array([0.52 * R * np.cos(0.5 * (a + a2)), 0.52 * R * np.sin(0.5 * (a + a2)), 0.4 * height]),
                   np.array([(0.85 + 0.12 * np.sin(2.9 * i)) * R * np.cos(a2),
                             (0.85 + 0.12 * np.sin(2.9 * i)) * R * np.sin(a2), 0.3 * sq])]
            for j in range(2):
                lo, hi = pts[j], pts[j + 1]
                seg = hi - lo
                normal = np.array([-seg[2] * seg[0], -seg[2] * seg[1], float(np.hypot(seg[0], seg[1])) ** 2])
                parts.append(box(f"fold {i + 1}" if j == 0 else f"fold {i + 1} {j + 1}",
                                 (float(np.linalg.norm(seg)) + 0.2 * sq, sq, sq), tuple(0.5 * (lo + hi)),
                                 edge=0.1 * sq, rot=_ridge_euler(seg, normal, 45.0), blend=0.5 * sq))
    elif kind == "soft":  # a few thick soft rolls over the top and down its side, and rolled edges on the floor
        rr = 0.1 * R + 0.4 * tl
        for i, (a, r, _) in enumerate(_rng_angles(SOFT_ROLLS, seed + 0.9)):
            a2 = a + 0.5 * np.sin(1.7 * i + seed)
            top = np.array([0.25 * R * r * np.cos(a), 0.25 * R * r * np.sin(a), 0.62 * height])
            mid = np.array([0.5 * R * np.cos(0.5 * (a + a2)), 0.5 * R * np.sin(0.5 * (a + a2)), 0.42 * height])
            low = np.array([0.85 * R * np.cos(a2), 0.85 * R * np.sin(a2), 0.6 * rr])
            parts += [limb(f"fold {i + 1}", top, mid, rr, blend=0.4 * rr),
                      limb(f"fold {i + 1} 2", mid, low, 0.9 * rr, blend=0.4 * rr)]
        for k, (centre, turn, length, width) in enumerate(ends[:3]):  # a flap's outer edge rolled over
            across = turn.apply([0.0, 1.0, 0.0])
            tip = centre + turn.apply([0.45 * length, 0.0, 0.3 * tl])
            parts.append(limb(f"rolled edge {k + 1}", tip - 0.45 * width * across, tip + 0.45 * width * across,
                              0.8 * tl, blend=0.3 * tl))
    else:  # a towel's narrow folds over the top
        for i, (a, r, turn_deg) in enumerate(_rng_angles(5, seed)):
            rho = 0.3 * R * r
            parts.append(ellipsoid(f"fold {i + 1}", ((0.16 + 0.06 * np.sin(i)) * R, 0.03 * R + 0.5 * tl,
                                                     0.06 * height), (rho * np.cos(a), rho * np.sin(a), 0.56 * height),
                                   rot=(0, 0, float(np.degrees(a) + 90 + turn_deg)), blend=0.04 * R))
    if p.fringe:  # tassels beyond the outer ends of two flaps (a strip's two ends)
        for k, (centre, turn, length, width) in enumerate(ends[:2]):
            along, across = turn.apply([1.0, 0.0, 0.0]), turn.apply([0.0, 1.0, 0.0])
            n = 4
            tlen = min(0.35 * width, 0.2 * length)
            for j in range(n):
                a0 = centre + 0.5 * length * along + (-0.4 + 0.8 * j / (n - 1)) * width * across
                a0[2] = max(a0[2], 0.5 * tl)
                b0 = a0 + tlen * np.array([along[0], along[1], 0.0]) / np.hypot(along[0], along[1])
                b0[2] = 0.5 * tl
                parts.append(limb(f"tassel {n * k + j + 1}", a0, b0, max(0.45 * tl, 0.9 * cell), blend=0.2 * tl))
    room = MAX_PARTS - 1 - len(parts)
    parts += decor[:room]
    parts.append(_op(box("ground", (8, 8, 8), (0, 0, 4)), "intersect"))
    return parts


WAD_FACETS = 22  # planes cutting a paper wad's core into creased facets
WAD_CREASES = 6  # folded ridges standing out of it
WAD_VALLEYS = 8  # creases pressed into it


def wad(diameter: float, seed: float = 0.3, name: str = "body") -> list[Part]:
    """A sheet of paper crumpled in the hand: a lumpy wad `diameter` across, its core cut by WAD_FACETS planes at
    uneven depths into flat facets meeting at sharp creases, WAD_CREASES folded ridges (thin wedges of the sheet)
    standing a little out of it and WAD_VALLEYS creases pressed in. (Fourteen shallow cuts left a round ball and
    its ridges stood out as flaps: blind reviewers named it a ball partly wrapped in paper, sets 19 and 20.)"""
    R = diameter / 2
    zc = 0.8 * R
    parts = [ellipsoid(name, (R, 0.9 * R, 0.8 * R), (0, 0, zc))]
    for i in range(WAD_FACETS):  # each cut: a large box whose face lies 0.7-0.92 R from the centre
        u = np.array([np.cos(i * 2.39996 + seed), np.sin(i * 2.39996 + seed), 1.0 - 2.0 * (i + 0.5) / WAD_FACETS])
        u[:2] *= np.sqrt(max(1.0 - u[2] ** 2, 0.0))
        u /= np.linalg.norm(u)
        reach = float(np.linalg.norm(u * np.array([1.0, 0.9, 0.8])))  # the ellipsoid's radius along u, / R
        depth = (0.81 + 0.11 * np.sin(4.1 * i + seed)) * reach * R
        yaw, pitch = np.degrees(np.arctan2(u[1], u[0])), np.degrees(np.arccos(np.clip(u[2], -1, 1)))
        centre = np.array([0.0, 0.0, zc]) + (depth - 2.0 * R) * u  # the box 4 R deep, its +u face at depth
        parts.append(_op(box(f"facet {i + 1}", (4 * R, 4 * R, 4 * R), tuple(centre), rot=(0.0, float(pitch),
                                                                                            float(yaw))), "intersect"))
    for i in range(WAD_CREASES + WAD_VALLEYS):  # a fold: a thin fin of the sheet square to the surface, standing a
        valley = i >= WAD_CREASES  # little out of it (a crease) or cut into it (a valley)
        u = np.array([np.cos(i * 2.39996 + 1.3 * seed), np.sin(i * 2.39996 + 1.3 * seed), 0.8 * np.sin(2.2 * i + seed)])
        u /= np.linalg.norm(u)
        along = np.cross(u, [np.sin(1.7 * i), np.cos(1.7 * i), 0.5])  # the fold's line, across the surface
        along /= np.linalg.norm(along)
        frame = np.stack([along, np.cross(u, along), u], axis=1)  # local x along the fold, z out of the wad
        euler = Rotation.from_matrix(frame).as_euler("xyz", degrees=True)
        reach = float(np.linalg.norm(u * np.array([1.0, 0.9, 0.8]))) * R
        crease = box(f"{'valley' if valley else 'crease'} {i + 1}",
                     (0.75 * R, (0.08 if valley else 0.05) * R, 0.4 * R),
                     tuple(np.array([0.0, 0.0, zc]) + ((0.86 if valley else 0.68) * reach) * u),
                     rot=tuple(float(e) for e in euler), edge=0.015 * R, blend=0.03 * R)
        parts.append(_op(crease, "subtract") if valley else crease)
    parts.append(_op(box("ground", (8, 8, 8), (0, 0, 4)), "intersect"))
    return parts


def wad_size(area: float) -> float:
    """The diameter of a stiff sheet of `area` (unit frame) crumpled into a wad [-]: about a quarter of the square's
    side (a 21 x 29.7 cm sheet of printer paper balls up to ~6.5 cm across)."""
    return 0.26 * float(np.sqrt(area))


def crumpled_size(area: float) -> tuple[float, float]:
    """(footprint diameter, height) of a crumpled cloth of `area` (unit frame) [-]: a loose heap about half the
    square's side across and under half that high (a 40 x 40 cm cloth bunches to ~20 cm across, ~8 cm high)."""
    side = float(np.sqrt(area))
    return 0.5 * side, 0.22 * side


# ------------------------------------------------------------------------------------------------------- garments
class GarmentParams(Model):
    """A garment: t-shirt, long-sleeved top, sweater, hoodie, jacket, dress, trousers; laid flat (front up), folded,
    crumpled in a heap, or hung on a hanger. Length 1 is the body's (collar to hem) length, along x (collar at +x).
    Laid flat with its sleeves out it is wider than long, so its built layer is `GARMENT_LAYER` of that length."""

    kind: Literal["top", "trousers", "dress", "suit", "apron", "swimsuit"] = Field(
        default="top", description="'suit': a one-piece (a wetsuit, coveralls, a snowsuit, a footed sleepsuit): a top "
        "with legs below its body; 'dress': a fitted bodice on shoulder straps (or sleeves), a waistband and a flared "
        "skirt; 'apron': a bib on a neck loop over a wider skirt panel, waist ties out to the sides, a patch pocket; "
        "'swimsuit': a one-piece swimsuit, its straps, a body narrowing to the waist, high leg openings")
    state: Literal["flat", "folded", "crumpled", "hung"] = "flat"
    sleeves: Literal["none", "short", "long"] = "long"
    hood: bool = False
    pocket: bool = Field(default=False, description="a front (kangaroo) pocket")
    zip: bool = Field(default=False, description="a front zip or button placket (a jacket, a shirt)")
    collar: bool = Field(default=False, description="a shirt collar")
    cuffs: bool = Field(default=True, description="ribbed bands at hem and sleeve ends")
    rumpled: bool = Field(default=False, description="crumpled but spread out (a top or dress dropped on the floor): "
                          "its outline with wrinkles over it, not a heap")
    width: float = Field(default=0.78, gt=0.3, le=1.2, description="body width / length [-]")
    thickness: float = Field(default=0.012, gt=0.0, le=0.1, description="real flat thickness (front and back "
                             "layers) / length [-]")
    robe: bool = Field(default=False, description="a wrap robe (a bathrobe, a dressing gown): a shawl collar "
                       "crossing from the neck to the waist, and a tie belt knotted at the side with its two ends "
                       "hanging")
    coat: bool = Field(default=False, description="a long buttoned coat (a lab coat, a doctor's coat): wide "
                       "notched lapels, a row of buttons down the front, two hip patch pockets and a breast pocket")
    double_breasted: bool = Field(default=False, description="coat: two rows of buttons down the front (a "
                                  "peacoat, a trench coat), not one")
    baffles: int = Field(default=0, ge=0, le=12, description="quilted (down-filled) baffles across the body, and "
                         "along the sleeves in proportion: a puffy layer with stitched grooves (a puffer jacket or "
                         "vest) [-]")
    crease: bool = Field(default=False, description="pressed creases down the middle of each trouser leg (tailored "
                         "trousers, laid flat; not drawn on jeans or sweatpants)")
    motif: Literal["none", "print", "number", "knit", "dots"] = Field(
        default="none", description="what the front shows: 'print' a printed chest graphic (a t-shirt), 'number' a "
        "big number and trim stripes (a sports jersey), 'knit' cable-knit columns (a knitted sweater), 'dots' a "
        "small scattered print (a hospital gown)")


GARMENT_LAYER = 0.045  # a garment's (or a bag's with handles) built layer / its length: MIN_LAYER of its span [-]


def _flat_chain(name: str, pts: list[np.ndarray], r: float, t: float, blend: float) -> list[Part]:
    """Flat capsules along a polyline in the x-y plane (a sleeve, a strap, a handle)."""
    return [_flat_limb(name if i == 0 else f"{name} {i + 1}", pts[i], pts[i + 1], r, t, blend)
            for i in range(len(pts) - 1)]


def _top_flat(p: GarmentParams, t: float) -> list[Part]:
    w = p.width
    z = t / 2
    parts = [superellipsoid("body", (0.5, w / 2, t / 2), (0, 0, z), ns=0.15, ew=0.12)]
    sr = 0.13 if p.sleeves == "long" else 0.15
    for side in (1, -1):
        shoulder = np.array([0.36, side * (w / 2 - 0.06), z])
        if p.sleeves == "long":
            tip = shoulder + np.array([-0.5, side * 0.36, 0.0])  # (ending by the hem they read as trouser legs
            # to blind judges, set 38: a shirt's sleeves end at mid-body)
        elif p.sleeves == "short":
            tip = shoulder + np.array([-0.16, side * 0.2, 0.0])
        else:  # sleeveless (a vest, a gilet): an armhole cut into each side below the shoulder
            parts.append(_op(ellipsoid(f"{'left' if side > 0 else 'right'} armhole", (0.17, 0.09, 3 * t),
                                       (0.22, side * (w / 2 + 0.02), z)), "subtract", 0.02))
            continue
        parts.append(_flat_limb(f"{'left' if side > 0 else 'right'} sleeve", shoulder, tip, sr, t, blend=0.04))
        if p.motif == "number" and p.sleeves == "long":  # a hockey jersey's two bands round the sleeve
            d = (tip - shoulder) / np.linalg.norm(tip - shoulder)
            for k, at in enumerate((0.62, 0.8)):
                c = shoulder + at * (tip - shoulder)
                parts.append(_flat_limb(f"{'left' if side > 0 else 'right'} sleeve stripe {k + 1}", c - 0.03 * d,
                                        c + 0.03 * d, 1.04 * sr, 1.2 * t, blend=0.002))
        if p.cuffs and p.sleeves == "long":
            d = (tip - shoulder) / np.linalg.norm(tip - shoulder)
            parts.append(_flat_limb(f"{'left' if side > 0 else 'right'} cuff", tip - 0.1 * d, tip + 0.02 * d,
                                    0.85 * sr, 1.25 * t, blend=0.005))
    if p.cuffs:
        parts.append(box("hem", (0.08, w * 0.96, 1.25 * t), (-0.46, 0, 0.625 * t), edge=0.5 * t, blend=0.005))
    if p.motif == "number":  # a jersey's big number ('10') on the front, long-sleeved ones a band round the hem
        parts.append(box("number 1", (0.3, 0.05, 1.3 * t), (-0.02, 0.16 * w, 0.65 * t), edge=0.2 * t, blend=0.002))
        parts.append(scaled(torus("number 2", 0.075, 0.024, (-0.02, -0.12 * w, 0.65 * t)), (1.9, 1.0, 1.3 * t / 0.048)))
        if p.sleeves == "long":
            parts.append(box("hem stripe", (0.07, w * 0.98, 1.2 * t), (-0.36, 0, 0.6 * t), edge=0.3 * t, blend=0.002))
    if p.baffles:  # quilted: grooves across the body and the sleeves, the zip and collar laid over them
        parts += quilting(0.92, w + 1.0, t, p.baffles, 0)
    if p.hood:
        parts.append(ellipsoid("hood", (0.24, 0.25, 1.6 * t), (0.6, 0, 0.9 * t), blend=0.03))
        parts.append(scaled(torus("hood rim", 0.15, 0.035, (0.58, 0, 1.9 * t)), (1.0, 1.1, 0.5)))
        parts.append(_op(ellipsoid("hood opening", (0.14, 0.15, 0.8 * t), (0.58, 0, 2.3 * t)), "subtract", 0.01))
        for side in (1, -1):
            a = np.array([0.44, side * 0.05, 1.3 * t])
            parts.append(limb(f"{'left' if side > 0 else 'right'} drawstring", a, a + np.array([-0.24, 0.015 * side,
                                                                                               0]), 0.012,
                              blend=0.005))
    else:
        parts.append(_op(scaled(cylinder("neck", 0.1, 4 * t, (0.52, 0, z)), (0.75, 1, 1)), "subtract", 0.01))
        parts.append(scaled(torus("collar band", 0.105, 0.022, (0.5, 0, 0.7 * t)), (0.78, 1, 0.8)))
    if p.coat:  # a long buttoned coat: wide lapels from the collar, buttons down the front, a breast pocket
        for side in (1, -1):
            parts.append(box(f"{'left' if side > 0 else 'right'} lapel", (0.34, 0.11, 1.8 * t),
                             (0.31, side * 0.08, 1.1 * t), edge=0.4 * t, rot=(0, 0, -side * 18), blend=0.004))
        cols = (0.0,) if not p.double_breasted else (0.075 * w / 0.78, -0.075 * w / 0.78)  # one row or two
        for i, (x, y) in enumerate((x, y) for x in np.linspace(0.12, -0.36, 4) for y in cols):
            parts.append(cylinder(f"button {i + 1}", 0.026, 1.6 * t, (float(x), float(y), 1.2 * t), edge=0.3 * t,
                                  blend=0.002))
        parts.append(superellipsoid("breast pocket", (0.07, 0.08 * w, 0.7 * t), (0.2, -0.28 * w, t), ns=0.2, ew=0.3,
                                    blend=0.004))
    if p.pocket and (p.robe or p.coat):  # two patch pockets, low on either side (a robe's belt ends between)
        for side in (1, -1):
            parts.append(superellipsoid(f"{'left' if side > 0 else 'right'} pocket", (0.1, 0.12 * w, 0.7 * t),
                                        (-0.24, side * 0.3 * w, t), ns=0.2, ew=0.3, blend=0.004))
    elif p.pocket:
        parts.append(superellipsoid("pocket", (0.15, 0.24 * w, 0.3 * t), (-0.2, 0, t), ns=0.2, ew=0.3, blend=0.004))
    if p.zip:  # a zip from hem to collar, its pull at the top
        parts.append(box("zip", (0.9, 0.035, 0.6 * t), (-0.02, 0, t + 0.1 * t), edge=0.1 * t, blend=0.002))
        parts.append(box("zip pull", (0.07, 0.028, 0.5 * t), (0.36, 0.0, t + 0.45 * t), edge=0.15 * t, blend=0.002))
    if p.collar:
        for side in (1, -1):
            parts.append(box(f"{'left' if side > 0 else 'right'} collar", (0.12, 0.12, 0.5 * t),
                             (0.45, side * 0.07, 1.1 * t), edge=0.2 * t, rot=(0, 0, side * 30), blend=0.004))
    if p.robe:
        parts += _robe_wrap(w, t)
    return parts


def _robe_wrap(w: float, t: float) -> list[Part]:
    """A wrap robe's shawl collar (two raised bands crossing from the neck to the waist) and its tie belt (a band
    round the waist, knotted at one side, its two ends hanging down the front)."""
    parts = [_flat_limb(f"{'left' if side > 0 else 'right'} lapel", np.array([0.5, side * 0.1, 1.1 * t]),
                        np.array([0.02, -side * 0.1 * w, 1.1 * t]), 0.08, 2.0 * t, blend=0.01) for side in (1, -1)]
    parts.append(box("belt", (0.07, 1.02 * w, 1.5 * t), (0.0, 0.0, 0.75 * t), edge=0.4 * t, blend=0.005))
    knot = np.array([0.0, 0.12 * w, 1.5 * t])
    parts.append(ellipsoid("belt knot", (0.05, 0.05, 1.1 * t), tuple(float(v) for v in knot), blend=0.01))
    for k, end in enumerate(((-0.44, 0.17 * w), (-0.36, 0.04 * w))):
        parts.append(_flat_limb(f"belt end {k + 1}", knot, np.array([end[0], end[1], 1.2 * t]), 0.035, 1.4 * t,
                                blend=0.01))
    return parts


RISE = 0.3  # the crotch below the waist / the trousers' length [-]


TROUSER_CREASE = 0.006  # a pressed crease's ridge radius / the trousers' length (~7 mm: seen in the renders) [-]


def _trousers_flat(p: GarmentParams, t: float) -> list[Part]:
    """Laid flat, waist at +x: a waistband with belt loops and a button, the seat down to the crotch, two legs
    tapering slightly to square hems with a crotch gap between them widening towards the hems, a fly seam and the
    front pockets' openings; tailored trousers ('crease') a pressed crease down each leg (navy trousers without
    one read as jeans to a blind judge, session 47)."""
    w = p.width
    z = t / 2
    xc = 0.5 - RISE
    parts = [box("body", (RISE, w, t), (0.5 - RISE / 2, 0, z), edge=0.45 * t)]
    gap0, gap1 = 0.04 * w, 0.16 * w  # the crotch gap at the crotch and at the hems
    hem = 0.39 * w  # a leg's width at its hem
    for side, name in ((1, "left"), (-1, "right")):
        top_in, top_out = side * gap0 / 2, side * w / 2
        bot_in, bot_out = side * gap1 / 2, side * (gap1 / 2 + hem)
        a = np.array([xc + 0.04, (top_in + top_out) / 2, z])
        b = np.array([-0.5, (bot_in + bot_out) / 2, z])
        r_top, r_bot = abs(top_out - top_in) / 2, hem / 2
        leg = _flat_frustum(f"{name} leg", a, b, r_top, r_bot, t, blend=0.004)
        parts.append(leg)
        d = (b - a) / np.linalg.norm(b - a)
        parts.append(_flat_frustum(f"{name} hem", b - 0.05 * d, b + 0.004 * d, 1.02 * r_bot, 1.02 * r_bot, 1.35 * t,
                                   blend=0.004))
        parts.append(limb(f"{name} pocket", (0.5 - 0.05, side * 0.3 * w, 1.05 * t), (0.5 - 0.17, side * 0.5 * w,
                                                                                     1.05 * t), 0.012, blend=0.004))
        if p.crease:  # a pressed crease: a sharp ridge down the leg's middle, from below the pocket to the hem
            parts.append(limb(f"{name} crease", a + 0.08 * d + (0, 0, 0.5 * t), b - 0.06 * d + (0, 0, 0.5 * t),
                              TROUSER_CREASE, blend=0.002))
    parts.append(box("waistband", (0.07, w, 1.4 * t), (0.5 - 0.035, 0, 0.7 * t), edge=0.5 * t, blend=0.004))
    for i, y in enumerate(np.linspace(-0.42 * w, 0.42 * w, 5)):
        parts.append(box(f"belt loop {i + 1}", (0.08, 0.025, 0.4 * t), (0.5 - 0.035, y, 1.35 * t), edge=0.2 * t,
                         blend=0.003))
    parts.append(cylinder("button", 0.022, 0.4 * t, (0.5 - 0.035, 0.0, 1.4 * t), edge=0.15 * t, blend=0.003))
    parts.append(limb("fly", (0.5 - 0.07, 0.06 * w, 1.05 * t), (xc + 0.06, 0.06 * w, 1.05 * t), 0.01, blend=0.004))
    parts.append(limb("fly end", (xc + 0.06, 0.06 * w, 1.05 * t), (xc + 0.03, 0.0, 1.05 * t), 0.01, blend=0.004))
    return parts


def _flat_frustum(name: str, a: np.ndarray, b: np.ndarray, ra: float, rb: float, t: float,
                  blend: float = 0.02) -> Part:
    """A flat tapering panel from a (half-width ra) to b (half-width rb) in the x-y plane, `t` thick, square ends."""
    d = b - a
    angle = float(np.degrees(np.arctan2(d[1], d[0])))
    c = cone(name, ra, rb, float(np.linalg.norm(d)), (a + b) / 2, edge=0.3 * t, blend=blend, rot=(0, 90, angle))
    return scaled(c, (t / (2 * max(ra, rb)), 1, 1))


def _dress_flat(p: GarmentParams, t: float) -> list[Part]:
    """A dress laid flat, the neck at +x: a fitted bodice on two shoulder straps (or short or long sleeves), the
    neckline cut between them, a waistband, and the skirt flaring from the waist to a wide hem."""
    w = p.width
    waist = 0.12
    bw = 0.34 * w  # the bodice's half-width
    skirt = 0.5 + waist
    parts = [scaled(cone("body", 0.62 * w, bw, skirt, (waist - skirt / 2, 0, t / 2), rot=(0, 90, 0), edge=0.2 * t),
                    (t / (0.62 * w * 2), 1, 1)),
             superellipsoid("bodice", ((0.46 - waist) / 2, bw, t / 2), ((0.46 + waist) / 2, 0, t / 2), ns=0.2,
                            ew=0.3, blend=0.3 * t),
             box("waistband", (0.05, 2 * bw + 0.02, 1.1 * t), (waist, 0, t / 2), edge=0.3 * t, blend=0.1 * t),
             _op(scaled(cylinder("neck", 0.5 * bw, 4 * t, (0.47, 0, t / 2)), (0.9, 1, 1)), "subtract", 0.2 * t)]
    for side, sy in (("left", -1.0), ("right", 1.0)):
        a = np.array([0.36, sy * 0.72 * bw, t / 2])
        if p.sleeves == "none":
            parts += _flat_chain(f"{side} strap", [a, np.array([0.52, sy * 0.7 * bw, t / 2])], 0.045 * w, t,
                                 blend=0.3 * t)
        else:
            reach = 0.16 if p.sleeves == "short" else 0.5
            start = np.array([0.4, sy * 0.85 * bw, t / 2])
            end = start + np.array([-0.5 * reach, sy * reach * 0.85, 0.0])
            parts += _flat_chain(f"{side} sleeve", [start, end], 0.09 * w, t, blend=0.3 * t)
    return parts


def _apron_flat(p: GarmentParams, t: float) -> list[Part]:
    """An apron laid flat, the neck at +x: the skirt panel (its hem at -x), the narrower bib above it, the neck loop
    from the bib's top corners, the waist ties out from its sides, and a patch pocket on the skirt."""
    w = p.width
    waist = 0.05
    parts = [box("body", (0.5 + waist, w, t), ((waist - 0.5) / 2, 0, t / 2), edge=0.45 * t),
             box("bib", (0.42 - waist + 0.02, 0.62 * w, t), ((0.42 + waist) / 2, 0, t / 2), edge=0.45 * t,
                 blend=0.2 * t)]
    r = 0.3 * w  # the neck loop's half-width
    loop = [np.array([0.41 + 0.17 * np.sin(a), 0.26 * w * np.cos(a), t / 2]) for a in np.linspace(0, np.pi, 7)]
    loop[0][1], loop[-1][1] = 0.26 * w, -0.26 * w
    parts += _flat_chain("neck strap", [np.array([0.4, r * 0.9, t / 2]), *loop[1:-1], np.array([0.4, -r * 0.9, t / 2])],
                         0.025, t, blend=0.2 * t)
    for side, sy in (("left", -1.0), ("right", 1.0)):
        a = np.array([waist, sy * (w / 2 - 0.02), t / 2])
        parts += _flat_chain(f"{side} tie", [a, a + np.array([-0.02, sy * 0.25, 0]), a + np.array([-0.3, sy * 0.36, 0])],
                             0.025, t, blend=0.2 * t)
    if p.pocket:
        parts.append(box("pocket", (0.18, 0.5 * w, 0.5 * t), (-0.2, 0, t), edge=0.2 * t, blend=0.1 * t))
    return parts


def _swimsuit_flat(p: GarmentParams, t: float) -> list[Part]:
    """A one-piece swimsuit laid flat, the neck at +x: the body, narrowing to the waist, its neckline and the high
    leg openings cut away down to the narrow crotch at -x, two shoulder straps."""
    w = p.width
    parts = [superellipsoid("body", (0.36, w / 2, t / 2), (0.06, 0, t / 2), ns=0.2, ew=0.35)]
    bare = p.sleeves == "none"  # (with sleeves: a baby's bodysuit, straight-sided, no straps)
    for side, sy in (("left", -1.0), ("right", 1.0)):
        if bare:
            parts.append(_op(scaled(cylinder(f"{side} waist", 0.2, 4 * t, (0.08, sy * (w / 2 + 0.16), t / 2)),
                                    (1.6, 1, 1)), "subtract", 0.05))
        parts.append(_op(scaled(cylinder(f"{side} leg opening", 0.3, 4 * t, (-0.34, sy * (0.14 * w + 0.3), t / 2)),
                                (1.1, 1, 1)), "subtract", 0.03))
        if bare:
            parts += _flat_chain(f"{side} strap", [np.array([0.35, sy * 0.3 * w, t / 2]),
                                                    np.array([0.5, sy * 0.28 * w, t / 2])], 0.03, t, blend=0.2 * t)
    parts.append(box("crotch", (0.18, 0.16 * w + 0.06, t), (-0.36, 0, t / 2), edge=0.45 * t, blend=0.05))
    parts.append(_op(scaled(cylinder("neck", 0.16 * w + 0.05, 4 * t, (0.45, 0, t / 2)), (0.8, 1, 1)), "subtract",
                     0.03))
    if p.sleeves != "none":  # a baby's bodysuit: sleeves out from the shoulders with trimmed cuffs, the neckline
        # and leg openings trimmed, a heart printed on the chest, snaps across the crotch flap (stub sleeves on a white
        # outline read as a sheepskin rug to blind judges, set 38)
        reach = 0.2 if p.sleeves == "short" else 0.45
        for side, sy in (("left", -1.0), ("right", 1.0)):
            a = np.array([0.36, sy * 0.36 * w, t / 2])
            b = a + np.array([-0.55 * reach, sy * reach, 0.0])
            parts.append(_flat_frustum(f"{side} sleeve", a, b, 0.13, 0.1, t, blend=0.3 * t))
            d = (b - a) / np.linalg.norm(b - a)
            parts.append(_flat_frustum(f"{side} cuff trim", b - 0.035 * d, b + 0.01 * d, 0.105, 0.105, 1.4 * t,
                                       blend=0.002))
            edge = [np.array([-0.45, sy * 0.09, 0.9 * t])]  # the leg opening's edge, from the crotch to the side
            edge += [np.array([-0.34 + 1.04 * 0.33 * np.cos(a), sy * (0.14 * w + 0.3 - 1.04 * 0.3 * np.sin(a)), 0.9 * t])
                     for a in np.radians((90.0, 62.0, 36.0, 14.0))]
            parts += _flat_chain(f"{side} leg trim", edge, 0.014, 0.8 * t, blend=0.002)
        rn = 0.16 * w + 0.05  # the neck cut again (the sleeves reach over it), its trim along the edge
        parts.append(_op(cylinder("neck opening", rn, 4 * t, (0.5, 0, t / 2)), "subtract", 0.03))
        neck = [np.array([0.5 + rn * np.cos(a), rn * np.sin(a), 0.9 * t]) for a in np.radians(
            (80.0, 125.0, 180.0, 235.0, 280.0))]
        parts += _flat_chain("neck trim", neck, 0.016, 0.8 * t, blend=0.002)
        for k, y in enumerate((-0.05, 0.05)):  # a heart on the chest: two lobes and the point below
            parts.append(cylinder(f"heart {k + 1}", 0.062, 0.8 * t, (0.15, y, 1.1 * t), edge=0.1 * t, blend=0.004))
        parts.append(box("heart 3", (0.09, 0.09, 0.8 * t), (0.1, 0.0, 1.1 * t), edge=0.1 * t, rot=(0, 0, 45),
                         blend=0.004))
        for k, y in enumerate((-0.07, 0.0, 0.07)):
            parts.append(cylinder(f"snap {k + 1}", 0.026, 0.6 * t, (-0.42, y, t), edge=0.2 * t, blend=0.1 * t))
    return parts


SUIT_LEG = 0.85  # a one-piece's leg (crotch to ankle) / its body's (collar to crotch) length [-]


def _suit_flat(p: GarmentParams, t: float) -> list[Part]:
    """A one-piece laid flat: the top (sleeves, collar or hood, zip) without its hem band, and two legs from the
    crotch, tapering a little to their ankle cuffs with a gap between them."""
    w = p.width
    z = t / 2
    parts = _top_flat(p.model_copy(update={"cuffs": False}), t)
    for side, name in ((1, "left"), (-1, "right")):
        a = np.array([-0.38, side * 0.25 * w, z])
        b = np.array([-0.45 - SUIT_LEG, side * 0.3 * w, z])
        parts.append(_flat_frustum(f"{name} leg", a, b, 0.24 * w, 0.17 * w, t, blend=0.03))
        if p.cuffs:
            d = (b - a) / np.linalg.norm(b - a)
            parts.append(_flat_frustum(f"{name} ankle cuff", b - 0.08 * d, b + 0.01 * d, 0.18 * w, 0.18 * w, 1.25 * t,
                                       blend=0.004))
    return parts


def _garment_flat(p: GarmentParams, t: float) -> list[Part]:
    if p.kind == "suit":
        return _suit_flat(p, t)
    if p.kind == "trousers":
        return _trousers_flat(p, t)
    if p.kind == "dress":
        return _dress_flat(p, t)
    if p.kind == "apron":
        return _apron_flat(p, t)
    if p.kind == "swimsuit":
        return _swimsuit_flat(p, t)
    return _top_flat(p, t)


def garment(p: GarmentParams) -> list[Part]:
    """Flat: the garment laid out front up (sleeves, hood, pocket, cuffs drawn). Folded: a neat rectangle with the
    collar (or hood) on top. Crumpled: a bunched heap with a sleeve or leg and the hood out of it. Hung: standing in
    the x-z plane on a hanger's hook."""
    t = max(p.thickness, GARMENT_LAYER) * (PUFF if p.baffles else 1.0)
    w = p.width
    if p.state == "flat":
        return _garment_flat(p, t)
    if p.state == "hung":
        parts = _garment_flat(p, t)
        rot = []
        for part in parts:
            tf = part.transform
            x, y, z = tf.translation_m
            rx, ry, rz = tf.rotation_deg
            # lying (x along the body, z up) -> hanging (the collar up): x -> z, z -> -x
            rot.append(part.model_copy(update={"transform": tf.model_copy(update={
                "translation_m": (-z, y, x + 0.5), "rotation_deg": (rx, ry, rz)})}))
        # the rotation of each part about y by -90 deg is applied through a wrapper part order: parts are rebuilt
        # from the flat layout in the x-z plane (thin along x) by swapping their scale and radii axes
        parts = [_swap_xz(q) for q in rot]
        hook_z = 1.0 + 0.2 if not p.hood else 1.25
        parts.append(scaled(torus("hanger", 0.06, 0.012, (0, 0, hook_z + 0.05), rot=(90, 0, 0)), (1, 1, 1)))
        parts.append(limb("hanger bar", (0, -0.38 * w, 0.97), (0, 0.38 * w, 0.97), 0.015, blend=0.005))
        parts.append(limb("hanger neck", (0, 0, 0.97), (0, 0, hook_z), 0.012, blend=0.005))
        return parts
    if p.state == "folded":
        return _garment_folded(p)
    if p.rumpled and p.kind in ("top", "dress"):
        return _rumpled(_garment_flat(p, t), w, t)
    # crumpled: a heap of the body with the sleeves (legs) and the hood out of it
    area = w + (0.5 if p.sleeves == "long" else 0.15 if p.sleeves == "short" else 0.0)
    d, height = 1.3 * crumpled_size(area)[0], 0.22 * float(np.sqrt(area))  # front and back: a fuller heap
    parts = heap(d, height, t, seed=1.3, folds=8, flaps=2)
    ground = parts.pop()
    R = d / 2
    if p.kind == "top":
        # both sleeves out over the floor, flat (a long one trailing, the other bent back), each ending in its cuff
        # (a short sleeve in its hem band); the collar (or a neckline's band) on the heap's top, a shirt's buttons
        # down from it and the body's hem band along the floor; the hood over the heap's edge. (One round sleeve out
        # of a lobed heap read as a bird or a ladle: session 47's crumpled shirt.)
        for k, (a0, bend, ln, out) in enumerate(((0.35, 0.9, 0.42, 0.1), (2.5, -1.1, 0.24, 0.0))):
            if p.sleeves == "none":
                break
            side = "left" if k == 0 else "right"
            ln = ln if p.sleeves == "long" else min(ln, 0.16)
            sr = 0.11 if p.sleeves == "long" else 0.13
            start = np.array([0.55 * R * np.cos(a0), 0.55 * R * np.sin(a0), 0.25 * height])
            mid = np.array([(R + out) * np.cos(a0), (R + out) * np.sin(a0), 0.8 * t])
            a1 = a0 + bend
            end = mid + ln * np.array([np.cos(a1), np.sin(a1), 0])
            end[2] = 0.8 * t
            parts += [_flat_limb(f"{side} sleeve", start, mid, sr, 1.6 * t, 0.04),  # (narrowing to its cuff)
                      _flat_limb(f"{side} sleeve 2", mid, end, 0.75 * sr, 1.4 * t, 0.04)]
            dd = (end - mid) / np.linalg.norm(end - mid)
            band = "cuff" if p.sleeves == "long" else "hem"
            parts.append(box(f"{side} {band}", (0.07, 1.6 * sr, 1.8 * t), tuple(end - 0.02 * dd), edge=0.4 * t,
                             rot=(0, 0, float(np.degrees(np.arctan2(dd[1], dd[0])))), blend=0.004))
        top = np.array([0.05 * R, 0.08 * R, 0.62 * height])
        if not p.hood:  # the neckline on the heap's top: a band round the neck opening, a shirt's collar points
            parts.append(scaled(torus("collar band" if p.collar else "neckline", 0.09, 0.3 * t + 0.012, top,
                                      rot=(12, -8, 20)), (1.2, 1.0, 1.0)))
            parts.append(_op(ellipsoid("neck opening", (0.08, 0.065, 0.05), top + np.array([0.0, 0.0, 0.03]),
                                       rot=(12, -8, 20)), "subtract", 0.01))
            if p.collar:
                for j, sgn in enumerate((-1.0, 1.0)):
                    parts.append(box(f"collar {j + 1}", (0.11, 0.06, 0.5 * t),
                                     tuple(top + np.array([-0.07, sgn * 0.05, 0.02])), edge=0.2 * t,
                                     rot=(sgn * 14.0, -18.0, 20.0 + sgn * 35.0), blend=0.01))
            if p.zip and p.collar:  # a shirt's buttons down its placket from the collar
                for j in range(3):
                    at = top + np.array([-0.14 - 0.09 * j, -0.02 * j, -0.11 * height * (j + 1)])
                    parts.append(cylinder(f"button {j + 1}", 0.016, 0.5 * t, tuple(at), rot=(0, -25, 0),
                                          blend=0.004))
        a_hem = 4.3
        hem_at = np.array([0.62 * R * np.cos(a_hem), 0.62 * R * np.sin(a_hem), 0.3 * height])
        parts.append(box("hem", (0.06, 0.7 * R, 1.2 * t), tuple(hem_at), edge=0.4 * t,
                         rot=(0, 30, float(np.degrees(a_hem))), blend=0.02))
        if p.hood:
            hc = np.array([-0.5 * R, -0.45 * R, 0.6 * height])
            parts.append(ellipsoid("hood", (0.22, 0.18, 0.12), hc, blend=0.03, rot=(0, -15, 35)))
            parts.append(scaled(torus("hood rim", 0.12, 0.03, hc + np.array([-0.06, -0.04, 0.07]), rot=(0, -30, 35)),
                                 (1.25, 1, 1)))
            parts.append(_op(ellipsoid("hood opening", (0.13, 0.1, 0.07), hc + np.array([-0.07, -0.05, 0.1]),
                                       rot=(0, -30, 35)), "subtract", 0.01))
            parts.append(limb("drawstring", hc + np.array([0.08, -0.1, 0.0]), hc + np.array([0.05, -0.42, -0.55 *
                                                                                               height + 0.6 * t]),
                              0.012, blend=0.004))
    elif p.kind == "trousers":
        for k, a0 in enumerate((0.3, 0.75)):
            start = np.array([0.4 * R * np.cos(a0), 0.4 * R * np.sin(a0), 0.4 * height])
            end = start + np.array([0.75 * np.cos(a0), 0.75 * np.sin(a0), 0])
            end[2] = 0.6 * t
            parts += _flat_chain(f"{'left' if k == 0 else 'right'} leg", [start, end], 0.12, 2.2 * t, blend=0.03)
    return parts + [ground]


RUMPLE_RIDGES = ((0.25, 0.12, 35.0, 0.5), (0.0, -0.15, -20.0, 0.6), (-0.25, 0.1, 70.0, 0.45), (-0.3, -0.2, 15.0, 0.4),
                 (0.15, -0.05, -60.0, 0.5), (-0.05, 0.25, 5.0, 0.35), (0.33, -0.28, 50.0, 0.3))  # (x, y/w, deg, length)


def _rumpled(flat: list[Part], w: float, t: float) -> list[Part]:
    """A crumpled top or dress that still shows its outline (a t-shirt dropped on the floor): the flat layout with
    rounded wrinkle ridges across the body and one sleeve's end turned back over it."""
    ridges = [ellipsoid(f"wrinkle {k + 1}", (0.5 * ln, 0.045 + 0.012 * (k % 3), (1.1 + 0.3 * (k % 2)) * t),
                        (x, y * w, 0.6 * t), blend=0.04, rot=(0.0, 0.0, deg))
              for k, (x, y, deg, ln) in enumerate(RUMPLE_RIDGES)]
    bunched = [q.model_copy(update={"transform": q.transform.model_copy(update={"translation_m": (
        q.transform.translation_m[0], q.transform.translation_m[1], q.transform.translation_m[2] + 0.4 * t)})})
        if q.name.startswith("left sleeve") else q for q in flat]
    return [*bunched, *ridges]


def _garment_folded(p: GarmentParams) -> list[Part]:
    """Folded neatly: a rectangle a little longer than wide, 8 layers of the fabric thick (front and back, folded in
    half twice), the ribbed collar (or hood) at the top edge with a neck label inside it, short sleeves folded in as
    flaps at the shoulders with their hems, long sleeves crossed over the front to their ribbed cuffs, the layers'
    edges seen at the folded bottom and the (ribbed) hem band across it; and the front's motif (a chest print, a
    jersey's number, cable-knit columns, a scattered print). A robe shows its shawl collar and tied belt instead
    (_robe_folded), an apron its neck strap, ties and pocket (_apron_folded). (A plain slab with a collar ring read as
    a padded laptop sleeve, a foam tile or a seat cushion to blind judges, set 38; a robe with a t-shirt's collar and
    a sweater's crossed sleeves as a foam packaging insert, an apron as a seat cushion pad, set 39.)"""
    fl, fw = 0.42, 0.62 * p.width
    t = float(np.clip(2 * p.thickness, 0.011, 0.03)) * (PUFF if p.baffles else 1.0)  # one layer (front and back)
    n = 4
    if p.kind == "trousers":
        return _trousers_folded(p, t, n)
    t = min(t, FOLDED_TOP_LAYER * (PUFF if p.baffles else 1.0))  # (a thick knit stacked higher than a fifth of its
    # width was seen from the side only: a block; a shop-folded sweater is ~6 cm high on ~30 cm)
    h = n * t
    parts = [box("body", (fl, fw, h), (0, 0, h / 2), edge=0.9 * t)]  # (soft folded edges, not a crate's)
    if p.robe:
        return parts + _robe_folded(fl, fw, h, t, p.pocket) + _fold_gaps(fl, fw, t, n)
    if p.kind == "apron":
        return parts + _apron_folded(fl, fw, h, t, p.pocket) + _fold_gaps(fl, fw, t, n)
    top, xt = h + 0.3 * t, fl / 2
    if p.motif == "knit":  # cable-knit columns: twisted ropes of slanted stitches along the body
        for k, y in enumerate((-0.3 * fw, 0.0, 0.3 * fw)):
            for j, x in enumerate(np.linspace(-fl / 2 + 0.1, xt - 0.1, 5)):
                parts.append(ellipsoid(f"cable {k + 1} {j + 1}", (0.035, 0.018, 0.5 * t), (float(x), y, h),
                                       rot=(0, 0, 40.0 if j % 2 else -40.0), blend=0.003))
    elif p.motif == "print":  # a printed graphic on the chest: a disc with a ring round it
        parts.append(cylinder("print", 0.075, 0.5 * t, (0.02, 0.0, h + 0.1 * t), edge=0.1 * t, blend=0.002))
        parts.append(scaled(torus("print 2", 0.1, 0.012, (0.02, 0.0, h)), (1.0, 1.0, 0.6)))
    elif p.motif == "number":  # a jersey's big number ('10') across the front
        parts.append(box("number 1", (0.2, 0.05, 1.0 * t), (-0.02, 0.17 * fw, h + 0.3 * t), edge=0.1 * t,
                         blend=0.002))
        parts.append(box("number 2", (0.05, 0.045, 1.0 * t), (0.05, 0.17 * fw - 0.035, h + 0.3 * t),
                         edge=0.1 * t, rot=(0, 0, 35), blend=0.002))
        parts.append(scaled(torus("number 3", 0.07, 0.026, (-0.02, -0.17 * fw, h + 0.2 * t)), (1.4, 1.0, 0.9)))
    elif p.motif == "dots":  # a small scattered print (a hospital gown's; its ties below)
        rng = np.random.default_rng(7)
        for k in range(14):
            x, y = rng.uniform(-fl / 2 + 0.06, xt - 0.07), rng.uniform(-fw / 2 + 0.04, fw / 2 - 0.04)
            parts.append(cylinder(f"dot {k + 1}", 0.02, 0.8 * t, (float(x), float(y), h + 0.2 * t), edge=0.1 * t,
                                  blend=0.002))
    if p.kind in ("top", "suit") and p.sleeves == "long":
        for side in (1, -1):  # a sleeve folded across the front from its shoulder, the two crossing, cuff at the end
            word = "left" if side > 0 else "right"
            a = np.array([xt - 0.07, side * (fw / 2 - 0.06), top])
            b = np.array([-fl / 2 + 0.12, -side * (fw / 2 - 0.1), top + 0.2 * t * side])
            parts.append(_flat_limb(f"{word} sleeve", a, b, 0.058, 1.4 * t, blend=0.006))
            if p.cuffs:
                d = (b - a) / np.linalg.norm(b - a)
                parts.append(_flat_limb(f"{word} cuff", b - 0.06 * d, b + 0.04 * d, 0.054, 1.6 * t, blend=0.003))
                for j in (-1, 0, 1):  # its ribs
                    off = np.array([-d[1], d[0], 0.0]) * 0.03 * j
                    parts.append(_flat_limb(f"{word} cuff rib {j + 2}", b - 0.05 * d + off, b + 0.05 * d + off,
                                            0.008, 2.1 * t, blend=0.002))
    elif p.kind in ("top", "suit") and p.sleeves == "short":
        for side in (1, -1):  # a short sleeve folded in across the shoulder: a flap lying on top, cut to the outline
            word = "left" if side > 0 else "right"
            parts.append(box(f"{word} sleeve", (0.2, 0.34 * fw, 0.9 * t), (xt - 0.09, side * 0.43 * fw, h + 0.35 * t),
                             edge=0.3 * t, rot=(0, 0, side * 35), blend=0.004))
            stripe = "sleeve stripe" if p.motif == "number" else "sleeve hem"
            parts.append(limb(f"{word} {stripe}", (xt - 0.2, side * 0.2 * fw, h + 0.85 * t),
                              (xt - 0.03, side * 0.5 * fw, h + 0.85 * t), 0.014 if p.motif == "number" else 0.007,
                              blend=0.002))
    if p.kind in ("top", "suit") and p.sleeves != "none":
        parts.append(_op(box("outline", (fl, fw, 6 * h), (0, 0, 0)), "intersect"))
    if p.motif == "dots":  # a gown's back ties hanging out at the side, lying on the table
        for k, x in enumerate((0.06, -0.08)):
            a = np.array([x, fw / 2 - 0.02, 0.6 * h])
            bend = a + np.array([-0.05 - 0.03 * k, 0.05, -0.6 * h + 0.012])
            parts.append(limb(f"tie {k + 1}", a, bend, 0.012, blend=0.004))
            parts.append(limb(f"tie {k + 1} end", bend, bend + np.array([0.03, 0.12, 0.0]), 0.012, blend=0.004))
    parts += _fold_gaps(fl, fw, t, n)
    if p.hood:
        parts.append(ellipsoid("hood", (0.13, 0.17, 0.9 * t), (0.12, 0, h + 0.2 * t), blend=0.02))
    elif p.kind in ("top", "suit"):  # the neckline at the top edge: a ribbed band lying on the fabric (a dip cut
        # under it read as a tray's recess), the neck label inside its back
        parts.append(scaled(torus("collar band", 0.1, 0.024, (xt - 0.03, 0, h + 0.2 * t)), (0.8, 1, 1.0)))
        parts.append(box("neck label", (0.035, 0.06, 0.5 * t), (xt - 0.035, 0, h + 0.1 * t), edge=0.1 * t,
                         blend=0.002))
        parts.append(_op(box("collar cut", (0.2, 0.4, 6 * h), (xt + 0.1, 0, 0)), "subtract"))
    if p.cuffs:
        parts.append(box("hem", (0.06, fw, 0.6 * t), (-fl / 2 + 0.04, 0, h + 0.15 * t), edge=0.2 * t, blend=0.003))
        for j, y in enumerate(np.linspace(-0.45 * fw, 0.45 * fw, 10)):  # the ribbed band's ribs
            parts.append(box(f"hem rib {j + 1}", (0.06, 0.012, 0.4 * t), (-fl / 2 + 0.04, float(y), h + 0.5 * t),
                             edge=0.1 * t, blend=0.002))
    else:
        parts.append(limb("hem", (-fl / 2 + 0.04, -0.48 * fw, h), (-fl / 2 + 0.04, 0.48 * fw, h), 0.012, blend=0.004))
    return parts


def _fold_gaps(fl: float, fw: float, t: float, n: int) -> list[Part]:
    """A folded garment's bottom edge (-x): its n layers seen apart."""
    return [_op(box(f"fold gap {i}", (0.12 * fl, fw * 1.2, 0.22 * t), (-fl / 2, 0, i * t)), "subtract")
            for i in range(1, n)]


ROBE_BELT_AT = -0.06  # a folded robe's belt tied round it this far below the middle / its folded length [-]
ROBE_COLLAR_V = 0.36  # a folded robe's shawl collar dips to a V this far down its top / its folded length [-]
ROBE_LAPEL = 0.04  # its lapels this half-wide (unit frame: ~7 cm bands on a robe folded to ~40 cm) [-]
ROBE_KNOT_AT = 0.3  # a folded robe's belt knot this far to one side / its folded width (a robe ties at the side) [-]
GARMENT_STRAP = 0.017  # a folded garment's strap or tie drawn this half-wide (~2 mesher cells wide at draft) [-]


def _robe_folded(fl: float, fw: float, h: float, t: float, pocket: bool) -> list[Part]:
    """A wrap robe folded as a hotel presents it (the sleeves folded behind), on its top: the shawl collar (its roll
    across the neck at the top end and two broad rolled lapels from it crossing in a V down to the waist), the tie
    belt wrapped round the folded robe there, knotted at one side with its two ends hanging down the front, and two
    patch pockets low on either side; a plain turned hem at the folded bottom edge (ribbing read as a sweater)."""
    xt = fl / 2
    xb = ROBE_BELT_AT * fl
    z = h + 0.5 * t
    parts = [_op(ellipsoid("neck", (0.07, 0.2 * fw, 1.2 * t), (xt - 0.02, 0.0, h + 0.2 * t)), "subtract",
                 0.3 * t)]  # (above the collar's V at the top edge: the back of the neck, sunk a little)
    for side, sy in (("left", 1.0), ("right", -1.0)):  # the shawl collar: broad lapels from the top corners down to
        top = np.array([xt - ROBE_LAPEL, sy * (0.5 * fw - ROBE_LAPEL), z])  # a V at the middle, crossing there
        cross = np.array([xt - ROBE_COLLAR_V * fl, -sy * 0.04 * fw, z + (0.5 * t if sy > 0 else 0.0)])
        parts.append(_flat_limb(f"{side} lapel", top, cross, ROBE_LAPEL, 2.4 * t, blend=0.008))
    parts.append(box("belt", (0.06, fw + 2.4 * t, h + 1.2 * t), (xb, 0, (h + 1.2 * t) / 2), edge=1.0 * t,
                     blend=0.004))  # (round the top and sides, not under it: it rests on its back, not on the belt)
    knot = np.array([xb, ROBE_KNOT_AT * fw, h + 1.5 * t])  # (tied at the side: at the middle it read as a bow)
    parts.append(ellipsoid("belt knot", (0.04, 0.036, 1.6 * t), tuple(float(v) for v in knot), blend=0.006))
    for k, dy in enumerate((0.14, -0.02)):
        end = np.array([-fl / 2 + 0.045 + 0.03 * k, (ROBE_KNOT_AT + dy) * fw, h + 0.9 * t])
        parts.append(_flat_limb(f"belt end {k + 1}", knot, end, 0.026, 1.8 * t, blend=0.005))
    if pocket:
        for side, sy in (("left", 1.0), ("right", -1.0)):
            parts.append(superellipsoid(f"{side} pocket", (0.06, 0.15 * fw, 0.8 * t), (-fl / 2 + 0.1, sy * 0.33 * fw,
                                                                                       h + 0.1 * t),
                                        ns=0.2, ew=0.3, blend=0.004))
    parts.append(limb("hem", (-fl / 2 + 0.03, -0.47 * fw, h), (-fl / 2 + 0.03, 0.47 * fw, h), 0.014, blend=0.004))
    return parts


def _apron_folded(fl: float, fw: float, h: float, t: float, pocket: bool) -> list[Part]:
    """A folded apron's own cues: its neck strap lying in a loop over the top end (+x), the two waist ties coming out
    of its sides and lying in loose S-bends on the table, and the patch pocket low on the front, split in two by a
    stitched seam."""
    xt = fl / 2
    z = h + 0.3 * t
    r = GARMENT_STRAP
    loop = [np.array([xt - 0.015 - 0.16 * np.sin(a), 0.24 * fw * np.cos(a), z]) for a in np.linspace(0, np.pi, 7)]
    parts = _flat_chain("neck strap", loop, r, 1.6 * t, blend=0.004)
    for side, sy in (("left", 1.0), ("right", -1.0)):
        out = np.array([0.04, sy * (fw / 2 - 0.01), 0.55 * h])
        down = np.array([0.01, sy * (fw / 2 + 0.045), 0.9 * t])
        parts.append(limb(f"{side} tie", out, down, 0.75 * r, blend=0.004))
        bends = [down, down + np.array([-0.09, sy * 0.03, 0]), down + np.array([-0.19, -sy * 0.005, 0]),
                 down + np.array([-0.27, sy * 0.035, 0])]
        parts += [_flat_limb(f"{side} tie {k + 2}", bends[k], bends[k + 1], r, 1.6 * t, blend=0.004)
                  for k in range(len(bends) - 1)]
    if pocket:
        xp = -fl / 2 + 0.13
        parts.append(box("pocket", (0.14, 0.62 * fw, 1.2 * t), (xp, 0, h + 0.1 * t), edge=0.3 * t, blend=0.003))
        parts.append(limb("pocket seam", (xp - 0.065, 0, h + 0.75 * t), (xp + 0.065, 0, h + 0.75 * t), 0.007,
                          blend=0.002))
    parts.append(limb("hem", (-fl / 2 + 0.03, -0.47 * fw, h), (-fl / 2 + 0.03, 0.47 * fw, h), 0.01, blend=0.004))
    return parts


def _trousers_folded(p: GarmentParams, t: float, n: int) -> list[Part]:
    """Trousers folded as in a shop, front up: a rectangle `n` layers thick with the waistband along its top edge
    (belt loops, the button at its middle), the fly's J-stitch down from it, the two front pockets' scooped openings
    to the sides (a jeans' coin pocket in the right one), and the two legs' turned-up hems side by side at the
    folded bottom edge, the layers seen apart there. (Denim all one colour read as a blue toolbox with a lid, sets 19
    and 20, and the seat up with its back pockets as a foam tile or a hardcover book, set 38: the stitching, button
    and hems carry the entry's colours when it has them.)"""
    fl, fw = 0.36, 0.5 * p.width
    t = TROUSERS_FOLD_LAYER * t
    h = n * t
    top = h + 0.15 * t
    parts = [box("body", (fl, fw, h), (0, 0, h / 2), edge=0.4 * t)]
    xw = fl / 2 - 0.03
    parts.append(box("waistband", (0.055, fw, 0.5 * t), (xw, 0, h + 0.1 * t), edge=0.2 * t, blend=0.003))
    for i, y in enumerate(np.linspace(-0.44 * fw, 0.44 * fw, 5)):
        if abs(y) < 0.05 * fw:
            continue  # (the button's place)
        parts.append(box(f"belt loop {i + 1}", (0.07, 0.02, 0.5 * t), (xw - 0.005, y, h + 0.45 * t), edge=0.2 * t,
                         blend=0.002))
    parts.append(cylinder("button", 0.024, 0.7 * t, (xw, 0.0, h + 0.5 * t), edge=0.15 * t, blend=0.002))
    parts.append(box("patch", (0.04, 0.14 * fw, 0.5 * t), (xw, -0.33 * fw, h + 0.45 * t), edge=0.1 * t,
                     blend=0.002))  # a brand label on the waistband
    ztop, r = h + 0.3 * t, STITCH_RADIUS
    fly = [(xw - 0.035, -0.07 * fw), (xw - 0.15, -0.07 * fw), (xw - 0.185, -0.035 * fw), (xw - 0.19, 0.0)]
    for k in range(3):  # the fly's J-stitch
        parts.append(limb(f"fly stitch {k + 1}", (*fly[k], ztop), (*fly[k + 1], ztop), r, blend=0.001))
    parts.append(limb("centre seam", (xw - 0.19, 0.0, top), (-fl / 2 + 0.07, 0.0, top), 0.006, blend=0.003))
    for side in (1, -1):  # a front pocket's scooped opening: a curve from the waistband down to the side seam
        word = "left" if side > 0 else "right"
        arc = [(xw - 0.03 - 0.12 * (1 - np.cos(a)), side * (0.18 * fw + 0.27 * fw * np.sin(a)))
               for a in np.linspace(0.0, np.pi / 2, 4)]
        for k in range(3):
            (ax, ay), (bx, by) = arc[k], arc[k + 1]
            parts.append(limb(f"{word} pocket edge {k + 1}", (ax, ay, top), (bx, by, top), 0.009, blend=0.002))
            parts.append(limb(f"{word} pocket stitch {k + 1}", (ax - 0.02, ay, ztop), (bx - 0.02, by, ztop), r,
                              blend=0.001))
    coin = [(xw - 0.035, -0.26 * fw), (xw - 0.1, -0.26 * fw), (xw - 0.1, -0.4 * fw), (xw - 0.035, -0.4 * fw)]
    for k in range(3):  # the coin pocket's stitched outline
        parts.append(limb(f"coin pocket stitch {k + 1}", (*coin[k], ztop), (*coin[k + 1], ztop), r, blend=0.001))
    for side in (1, -1):  # the legs' hems, turned up over the folded bottom edge side by side
        word = "left" if side > 0 else "right"
        parts.append(box(f"{word} hem cuff", (0.06, 0.44 * fw, 0.6 * t), (-fl / 2 + 0.035, side * 0.25 * fw,
                                                                            h + 0.2 * t), edge=0.2 * t, blend=0.003))
        parts.append(limb(f"{word} hem stitch", (-fl / 2 + 0.055, side * 0.05 * fw, h + 0.55 * t),
                          (-fl / 2 + 0.055, side * 0.45 * fw, h + 0.55 * t), r, blend=0.001))
    for i in range(1, n):  # the folded bottom edge: the layers seen apart
        parts.append(_op(box(f"fold gap {i}", (0.1 * fl, fw * 1.2, 0.22 * t), (-fl / 2, 0, i * t)), "subtract"))
    return parts


TROUSERS_FOLD_LAYER = 0.45  # a folded trousers' layer / a folded top's (a shop-folded pair of jeans is ~5 cm high,
# under a fifth of its width, so it is seen from above: at 0.6 it was seen from the side only) [-]
FOLDED_TOP_LAYER = 0.016  # a folded top's layer (front and back) at most / its length [-]
STITCH_RADIUS = 0.006  # a stitched seam's bead, drawn wider than thread to be seen (unit frame) [-]


def _swap_xz(part: Part) -> Part:
    """A part of a flat layout (thin along z) stood up in the x-z plane (thin along x): its rotation composed with
    a turn of -90 deg about y, written as XYZ Euler angles."""
    from scipy.spatial.transform import Rotation

    import warnings

    r = Rotation.from_euler("y", -90, degrees=True) * Rotation.from_euler("xyz", part.transform.rotation_deg,
                                                                          degrees=True)
    with warnings.catch_warnings():  # a gimbal-lock case: any of its equal angle sets will do
        warnings.simplefilter("ignore", UserWarning)
        angles = tuple(float(a) for a in r.as_euler("xyz", degrees=True))
    return part.model_copy(update={"transform": part.transform.model_copy(update={"rotation_deg": angles})})


# ------------------------------------------------------------------------------------------------------------ bags
class BagParams(Model):
    """A bag: a tote or shopping bag with two handles, a drawstring pouch (gathered neck, cords), a zip-lock or
    sandwich bag (zip track at its mouth), a backpack-less sack; lying flat, standing, or crumpled; optionally part
    full of a fill (rice, sand, water) that slumps to its bottom. Height 1 (bottom to mouth) along x when lying."""

    kind: Literal["tote", "drawstring", "zip", "sack", "carrier", "backpack", "pouch"] = Field(default="tote", description=(
        "tote; drawstring (a gathered neck and cords); zip; sack; carrier (a film carrying bag: two handle loops cut "
        "from its top, creased film); backpack (a zipped pack: shoulder straps, top handle, front pocket); pouch (a "
        "zipped soft case: a pencil case, a make-up bag, a laptop sleeve: a padded slab with a zip and its pull along "
        "its top edge, `gusset` its depth)"))
    state: Literal["flat", "standing", "crumpled"] = "flat"
    straps: bool = Field(default=False, description="a drawstring bag worn on the back: its cords run down both "
                         "sides to the bottom corners")
    width: float = Field(default=0.9, gt=0.3, le=3.0, description="width / height [-]")
    gusset: float = Field(default=0.0, ge=0.0, le=0.6, description="depth of a standing bag's base / height [-]")
    handle: float = Field(default=0.55, ge=0.0, le=1.2, description="handle loop height above the mouth / height "
                          "(0: none) [-]")
    handle_width: float = Field(default=0.06, gt=0.01, le=0.2, description="strap width / height [-]")
    fill: float = Field(default=0.0, ge=0.0, le=1.0, description="share of the bag's capacity filled [-]")
    thickness: float = Field(default=0.004, gt=0.0, le=0.1, description="real wall (two layers) / height [-]")
    zip_around: bool = Field(default=False, description="pouch: the zip runs along the top edge and down both sides "
                             "(a laptop sleeve's U-shaped zip), its pull lying flat at a top corner, a padded "
                             "border round the edge")


# capacity of a bag filled round, / (height x width x min(height, width)): a 17.7 x 19.5 cm quart zip bag holds
# 0.95 l (US quart), 0.155 x 0.177 x 0.195 x 0.177 m^3
BAG_CAPACITY = 0.155


def bag(p: BagParams) -> list[Part]:
    """Lying flat: the mouth at +x, handles lying flat beyond it; a fill slumps towards -x. Standing: on its base
    (z = 0), mouth up, handles above. Crumpled: a heap with a handle loop out of it."""
    t = max(p.thickness, GARMENT_LAYER if p.handle > 0 and p.kind != "carrier" else 1.5 * MIN_LAYER)
    w = p.width
    if p.kind == "carrier" and p.state != "crumpled":
        return _stand(_carrier(p, t)) if p.state == "standing" else _carrier(p, t)
    if p.kind == "backpack":
        return _backpack(p) if p.state == "standing" else _backpack_flat(p)
    if p.kind == "pouch" and p.state != "crumpled":
        return _stand(_zip_pouch(p)) if p.state == "standing" else _zip_pouch(p)
    if p.kind == "drawstring" and p.straps and p.state != "crumpled":
        return _stand(_drawstring_pack(p, t)) if p.state == "standing" else _drawstring_pack(p, t)
    if p.state == "crumpled" and p.kind == "carrier":
        return _crumpled_film_bag(p, t)
    if p.state == "crumpled":
        d, height = crumpled_size(2 * w)  # its front and back
        heaped = heap(d, height, t, seed=0.7, folds=7, flaps=2)
        ground = heaped.pop()
        if p.handle > 0:
            R = d / 2
            arc = [np.array([0.3 * R + 0.55 * p.handle * np.sin(a) * 0.8, 0.25 * np.cos(a), 0.9 * t + 0.4 * height *
                             np.sin(a) * 0.2]) for a in np.linspace(0, np.pi, 6)]
            arc = [a + np.array([0.45 * R, 0, 0]) for a in arc]
            heaped += _flat_chain("handle", arc, p.handle_width / 2, 1.6 * t, blend=0.02)
        return heaped + [ground]
    if p.kind == "drawstring" and p.state == "standing":
        return _drawstring_standing(p, t)
    standing = p.state == "standing"
    # lying flat (standing: the same layout stood up by the caller's frame swap below)
    fill_h = 0.0
    parts: list[Part] = []
    if p.kind == "drawstring":  # a sack gathered at its neck: the body, the cinched neck, a ruffle beyond it
        parts.append(superellipsoid("body", (0.36, w / 2, t / 2 + 0.04 * (1 + 3 * p.fill)), (-0.14, 0, t / 2 + 0.04 *
                                    (1 + 3 * p.fill)), ns=0.5, ew=0.35))
        parts.append(scaled(cylinder("neck", 0.09 * w + 0.02, 0.08, (0.26, 0, 0.06), rot=(0, 90, 0), edge=0.02),
                             (1, 1, 0.6)))
        for i, yy in enumerate(np.linspace(-0.28 * w, 0.28 * w, 5)):
            parts.append(ellipsoid(f"ruffle {i + 1}", (0.12, 0.075 * w, 0.035), (0.36, yy, 0.045), blend=0.02,
                                   rot=(0, 0, float(25 * np.sin(2.0 * i)))))
        for side in (1, -1):
            a = np.array([0.27, side * 0.05, 0.09])
            b = a + np.array([0.3, side * 0.22, -0.06])
            parts.append(limb(f"{'left' if side > 0 else 'right'} cord", a, b, 0.014, blend=0.01))
            parts.append(ellipsoid(f"{'left' if side > 0 else 'right'} cord end", (0.03, 0.03, 0.03), b, blend=0.01))
        return _stand(parts) if standing else parts
    body_len = 1.0
    if p.fill > 0:  # the fill slumps to the bottom: a pillow over the lower part, the film flat above it
        volume = p.fill * BAG_CAPACITY * min(1.0, w) * w  # the fill's share of the capacity (unit frame)
        length = float(np.clip(0.35 + 0.65 * p.fill, 0.3, 1.0))
        fill_h = float(np.clip(volume / (0.7 * length * 0.94 * w), 2 * t, 0.45 * w))
        parts.append(superellipsoid("fill", (length / 2, 0.47 * w, fill_h / 2), (-0.5 + length / 2, 0, fill_h / 2),
                                    ns=0.45, ew=0.3))
        parts.append(box("body", (body_len, w, t), (0, 0, t / 2), edge=0.45 * t, blend=0.02))
    else:
        parts.append(box("body", (body_len, w, t), (0, 0, t / 2), edge=0.45 * t))
    if p.kind == "zip":
        for i, dx in enumerate((0.0, 0.045)):
            parts.append(box(f"zip track {i + 1}", (0.025, w, 2.2 * t), (0.43 - dx, 0, 1.1 * t), edge=0.45 * t,
                             blend=0.004))
    if p.kind in ("tote", "sack"):
        parts.append(box("hem", (0.06, w, 1.5 * t), (0.47, 0, 0.75 * t), edge=0.5 * t, blend=0.004))
    if p.handle > 0 and p.kind == "tote":
        for k, (yc, zlift) in enumerate(((0.0, 0.0), (0.04, 1.0))):
            span = 0.26 * w
            pts = [np.array([0.5 - 0.06 + p.handle * np.sin(a), yc + span * np.cos(a), t / 2 + zlift * t])
                   for a in np.linspace(0, np.pi, 7)]
            pts[0][0] = pts[-1][0] = 0.38
            parts += _flat_chain("handle" if k == 0 else "back handle", pts, p.handle_width / 2, t, blend=0.015)
    return _stand(parts) if standing else parts


def _zip_pouch(p: BagParams) -> list[Part]:
    """A zipped soft case lying flat, its zipped top edge at +x: a padded slab (depth `gusset`, at least two
    layers), the zip's tape and teeth running along the top near that edge, its slider at one end with the pull tab
    lying out past the case's end."""
    w = p.width
    d = max(p.gusset, 2 * p.thickness, 0.04)
    parts = [superellipsoid("body", (0.5, w / 2, d / 2), (0.0, 0.0, d / 2), ns=0.35, ew=0.2)]
    if p.zip_around:  # a laptop sleeve: a U of zip inboard of three edges, the pull flat at the top corner
        lift = 0.02
        inset = 0.05
        x_top = 0.5 - inset
        run = 1.0 - 2 * inset
        for name, size, at in (("zip tape", (0.045, w - 2 * inset, lift), (x_top, 0.0, d)),
                               ("left zip tape", (run, 0.045, lift), (0.0, -(w / 2 - inset), d)),
                               ("right zip tape", (run, 0.045, lift), (0.0, w / 2 - inset, d))):
            parts.append(box(name, size, at, edge=0.3 * lift, blend=0.01))
        parts.append(box("zip teeth", (0.018, w - 2 * inset - 0.04, 1.6 * lift), (x_top, 0.0, d + 0.3 * lift),
                         edge=0.3 * lift, blend=0.005))
        parts.append(box("zip slider", (0.06, 0.05, 2.2 * lift), (x_top, w / 2 - inset - 0.06, d + 0.5 * lift),
                         edge=0.3 * lift, blend=0.005))
        parts.append(box("zip pull", (0.11, 0.035, 1.2 * lift), (x_top - 0.08, w / 2 - inset - 0.1, d + 0.6 * lift),
                         edge=0.3 * lift, blend=0.005, rot=(0, 0, 30)))
        parts.append(box("patch", (0.12, 0.2, lift), (-0.28, 0.0, d), edge=0.3 * lift, blend=0.01))
        return parts
    x_zip = 0.5 - 0.09 - 0.15 * d  # on the top face, inboard of the rounded edge
    lift = 0.025 + 0.05 * d
    parts.append(box("zip tape", (0.11, 0.92 * w, lift), (x_zip, 0, d - 0.3 * lift), edge=0.3 * lift,
                     blend=0.02))
    parts.append(box("zip teeth", (0.04, 0.9 * w, lift), (x_zip, 0, d + 0.15 * lift), edge=0.3 * lift,
                     blend=0.01))
    y_end = 0.45 * w - 0.04
    parts.append(box("zip slider", (0.09, 0.07, 1.6 * lift), (x_zip, y_end, d + 0.3 * lift), edge=0.3 * lift,
                     blend=0.01))
    parts.append(box("zip pull", (0.06, 0.2, 0.8 * lift), (x_zip, y_end + 0.14, d - 0.1 * lift), edge=0.3 * lift,
                     blend=0.015, rot=(0, 8, 0)))
    return parts


def _crumpled_film_bag(p: BagParams, t: float) -> list[Part]:
    """A crumpled thin-film carrier bag: an irregular mound of bunched film (lumps of different sizes, sharp
    creases between them, not one smooth dome), its mouth open on top as a hollow, the two loop handles out of it."""
    d, height = crumpled_size(2 * p.width)
    R = d / 2
    parts = [ellipsoid("body", (0.78 * R, 0.6 * R, 0.34 * height), (0, 0, 0.05 * height))]
    for i, (a, r, _turn) in enumerate(_rng_angles(7, 0.4)):  # bunched lumps of film
        rho = 0.5 * R * r
        size = (0.3 + 0.1 * np.sin(2.3 * i)) * R
        parts.append(ellipsoid(f"lump {i + 1}", (size, 0.75 * size, (0.45 + 0.2 * np.sin(1.1 * i)) * height),
                               (rho * np.cos(a), 0.8 * rho * np.sin(a), 0.15 * height),
                               rot=(0, float(15 * np.sin(3.1 * i)), float(np.degrees(a))), blend=0.12 * height))
    for i, (a, r, turn) in enumerate(_rng_angles(14, 1.1)):  # creases: thin sharp ridges between the lumps
        rho = 0.6 * R * r
        x, y = rho * np.cos(a), 0.8 * rho * np.sin(a)
        top = 0.5 * height * np.sqrt(max(1 - (x / (0.8 * R)) ** 2 - (y / (0.62 * R)) ** 2, 0.04)) + 0.12 * height
        length = (0.4 + 0.15 * np.sin(1.3 * i)) * R
        rad = (0.13 + 0.04 * np.sin(2.1 * i)) * height
        parts.append(ellipsoid(f"crease {i + 1}", (length / 2, 0.22 * rad, rad), (x, y, top - 0.45 * rad),
                               rot=(float(35 * np.sin(1.7 * i)), 0, float(np.degrees(a) + turn)), blend=0.15 * rad))
    mouth = (0.1 * R, 0.0, 0.62 * height)  # the open mouth: a hollow pressed into the top
    parts.append(_op(ellipsoid("mouth", (0.34 * R, 0.24 * R, 0.32 * height), mouth), "subtract", 0.05 * height))
    for side, y in (("left", -1.0), ("right", 1.0)):  # the handles: flat film loops out of the mouth, fallen aside
        parts.append(torus(f"{side} handle", 0.2 * R, 0.04 * R, (mouth[0] + 0.05 * R, y * 0.26 * R, 0.5 * height),
                           rot=(float(y * 55), 20, 0), blend=0.02 * R))
    parts.append(_op(box("ground", (8, 8, 8), (0, 0, 4)), "intersect"))
    return parts


def _carrier(p: BagParams, t: float) -> list[Part]:
    """A film carrier ('T-shirt') bag lying flat, mouth at +x: the body, two handles rising from its top corners with
    a loop cut through each, the mouth cut down between them, side gusset folds and creases over the film."""
    w = p.width
    hl = float(np.clip(p.handle, 0.2, 0.45))  # the handles' height above the mouth
    x_mouth = 0.5 - hl
    hw = 0.24 * w  # a handle's width
    parts = [box("body", (1.0, w, t), (0, 0, t / 2), edge=0.45 * t)]
    for side in (1, -1):  # the side gussets folded in: a pleat line along each side
        parts.append(limb(f"{'left' if side > 0 else 'right'} gusset", (-0.47, side * (w / 2 - 0.07), t),
                          (x_mouth - 0.02, side * (w / 2 - 0.07), t), 0.2 * t, blend=0.2 * t))
    for i in range(9):  # creases in the film: low ridges every way over the body
        a, rho = 2.4 * i + 0.4, 0.42 * np.sqrt((i + 0.5) / 9)
        at = (-0.5 + 0.5 * (1 - hl) + rho * np.cos(a) * (1 - hl), 0.8 * rho * np.sin(a) * w, t)
        parts.append(ellipsoid(f"crease {i + 1}", (0.11 + 0.04 * np.sin(1.3 * i), 0.2 * t, 0.5 * t), at,
                               rot=(0, 0, float(np.degrees(1.9 * i))), blend=0.3 * t))
    parts.append(_op(scaled(cylinder("mouth", (w - 2 * hw) / 2, 4 * t, (0.5, 0, t / 2)),
                             ((hl + 0.08) / ((w - 2 * hw) / 2), 1, 1)), "subtract", 0.01))
    for side in (1, -1):
        slot = scaled(cylinder(f"{'left' if side > 0 else 'right'} handle hole", 0.2 * hw, 4 * t,
                                (0.5 - 0.45 * hl, side * (w / 2 - 0.5 * hw), t / 2)), (0.3 * hl / (0.2 * hw), 1, 1))
        parts.append(_op(slot, "subtract", 0.005))
    parts.append(box("bottom seam", (0.025, w, 1.2 * t), (-0.5 + 0.03, 0, 0.6 * t), edge=0.4 * t, blend=0.004))
    return parts


def _drawstring_pack(p: BagParams, t: float) -> list[Part]:
    """A drawstring backpack lying flat, mouth at +x: the body narrowing to its cinched top, pleats gathered under the
    casing, the cords out of the casing's ends down both sides in a loose arc to the bottom corners' tabs."""
    w = p.width
    top = 0.6 * w  # the cinched mouth's width
    parts = [box("body", (0.62, w, t), (-0.19, 0, t / 2), edge=0.45 * t)]
    parts.append(_flat_frustum("shoulder", np.array([0.1, 0.0, t / 2]), np.array([0.42, 0.0, t / 2]), w / 2, top / 2,
                               t, blend=0.01))
    parts.append(box("casing", (0.07, top, 1.6 * t), (0.44, 0, 0.8 * t), edge=0.5 * t, blend=0.004))
    for i, y in enumerate(np.linspace(-0.4 * top, 0.4 * top, 6)):  # pleats gathered under the casing
        a = np.array([0.4, y, t])
        b = np.array([0.12, y * w / top, t])
        parts.append(limb(f"pleat {i + 1}", a, b, 0.25 * t, blend=0.2 * t))
    r = 0.35 * t
    for side, name in ((1, "left"), (-1, "right")):
        a0 = np.array([0.45, side * top / 2, 0.8 * t])
        a1 = np.array([-0.47, side * w / 2, 0.8 * t])
        pts = [a0 + (a1 - a0) * u + np.array([0.0, side * 0.16 * np.sin(np.pi * u), 0.0]) for u in np.linspace(0, 1, 7)]
        parts += [limb(f"{name} cord {i + 1}", pts[i], pts[i + 1], r, blend=0.3 * r) for i in range(len(pts) - 1)]
        parts.append(limb(f"{name} cord 9", a0, a0 + np.array([0.09, side * 0.05, 0]), r, blend=0.3 * r))
        parts.append(box(f"{name} tab", (0.07, 0.05, 1.4 * t), (-0.47, side * (w / 2 - 0.01), 0.7 * t), edge=0.4 * t,
                         blend=0.004, rot=(0, 0, side * 40)))
    return parts


def _backpack_flat(p: BagParams) -> list[Part]:
    """A zipped backpack lying on its front, its back up: the padded body, two shoulder straps arching from the top
    down to the bottom corners, the top grab handle, the zip round the top seen at the edge."""
    w = p.width
    d = 0.32  # depth / height
    parts = [superellipsoid("body", (0.5, w / 2, d / 2), (0, 0, d / 2), ns=0.35, ew=0.3)]
    parts.append(superellipsoid("front pocket", (0.28, 0.4 * w, 0.12), (-0.15, 0, 0.08), ns=0.4, ew=0.35,
                                blend=0.03))
    parts.append(box("back panel", (0.8, 0.8 * w, 0.03), (0.02, 0, d + 0.005), edge=0.012, blend=0.02))
    _straps(parts, w, d + 0.02)
    handle = [np.array([0.46 + 0.1 * np.sin(a), 0.09 * np.cos(a), d * 0.85]) for a in np.linspace(0, np.pi, 6)]
    parts += _flat_chain("handle", handle, 0.022, 0.03, blend=0.01)
    zip_arc = [np.array([0.32 + 0.12 * np.sin(a), 0.45 * w * np.cos(a), 0.6 * d]) for a in np.linspace(0, np.pi, 7)]
    parts += [limb("zip" if i == 0 else f"zip {i + 1}", zip_arc[i], zip_arc[i + 1], 0.012, blend=0.004)
              for i in range(len(zip_arc) - 1)]
    return parts


def _straps(parts: list[Part], w: float, z: float) -> None:
    """Two padded shoulder straps over a backpack's back (z up): from the top, apart, to the bottom corners."""
    for side, name in ((1, "left"), (-1, "right")):
        pts = [np.array([0.36 - 0.74 * u, side * (0.12 + 0.22 * u) * w, z + 0.06 * np.sin(np.pi * u)])
               for u in np.linspace(0, 1, 5)]
        parts += _flat_chain(f"{name} strap", pts, 0.055, 0.035, blend=0.015)


def _backpack(p: BagParams) -> list[Part]:
    """A zipped backpack standing: its lying layout stood up, the back at -x, the straps arching off it."""
    return _stand_back(_backpack_flat(p))


def _stand_back(parts: list[Part]) -> list[Part]:
    """A layout lying on its front (top at +x, back up) stood on its bottom: x -> z, z -> -x (its back at -x)."""
    out = []
    for part in rotated_parts(parts, (0.0, -90.0, 0.0)):
        x, y, z = part.transform.translation_m
        out.append(part.model_copy(update={"transform": part.transform.model_copy(update={
            "translation_m": (x, y, z + 0.5)})}))
    return out


def _stand(parts: list[Part]) -> list[Part]:
    """A flat layout (mouth at +x, thin along z) stood on its bottom edge: x -> z (mouth up)."""
    out = []
    for part in parts:
        tf = part.transform
        x, y, z = tf.translation_m
        out.append(_swap_xz(part.model_copy(update={"transform": tf.model_copy(update={
            "translation_m": (-z, y, x + 0.5)})})))
    return out


def _drawstring_standing(p: BagParams, t: float) -> list[Part]:
    """A drawstring pouch standing: a round-bottomed sack, its neck cinched, a ruffled frill above, two cords."""
    w = p.width
    r = w / 2
    hb = 0.62 + 0.1 * p.fill
    parts = [superellipsoid("body", (r, 0.8 * r, hb / 2), (0, 0, hb / 2), ns=0.75, ew=0.85)]
    parts.append(cone("shoulder", 0.75 * r, 0.22 * r + 0.03, 0.22, (0, 0, hb - 0.06), edge=0.02, blend=0.05,
                      scale=(1, 0.85, 1)))
    parts.append(cylinder("neck", 0.22 * r + 0.03, 0.1, (0, 0, hb + 0.02), edge=0.03, blend=0.04))
    for i in range(7):
        a = 2 * np.pi * i / 7
        parts.append(ellipsoid(f"ruffle {i + 1}", (0.12, 0.06, 0.13), (0.12 * np.cos(a), 0.12 * np.sin(a), hb + 0.17),
                               rot=(0, float(np.degrees(0.35)), float(np.degrees(a))), blend=0.03))
    parts.append(_op(cylinder("mouth", 0.06, 0.1, (0, 0, hb + 0.3)), "subtract", 0.01))
    for side in (1, -1):
        top = np.array([0.1 * side, -0.2 * r, hb + 0.02])
        end = np.array([0.28 * side, -0.9 * r, hb - 0.33])
        parts.append(limb(f"{'left' if side > 0 else 'right'} cord", top, end, 0.018, blend=0.01))
        parts.append(ellipsoid(f"{'left' if side > 0 else 'right'} cord end", (0.035, 0.035, 0.045), end, blend=0.01))
    return parts


# ------------------------------------------------------------------------------------------- straps, bands, hoses
class StrapParams(Model):
    """A long flat strip or cord: resistance band, strap, belt, ribbon, tie, hose, cable, skipping rope; straight,
    lying in a loose loop, or coiled. Length 1 is the strip's full length (a closed band's circumference)."""

    state: Literal["straight", "loop", "rolled", "wavy", "bow"] = Field(
        default="straight", description="straight; loop (lying in a loose loop); rolled (coiled); wavy (an open "
        "length dropped on the table in loose S-bends: a feather boa, a garland); bow (tied in a bow: two loops "
        "and two tails out of a knot, a ribbon's)")
    fluff: bool = Field(default=False, description="a fluffy cord (a feather boa): clumps of fluff at uneven tilts "
                        "all along it, as thick as the cord")
    hank: bool = Field(default=False, description="rolled: a long rope coiled in `turns` loops laid one on another "
                       "into a thick ring (a climbing rope's coil), not a flat spiral")
    closed: bool = Field(default=False, description="a closed band (a loop band): laid straight it is doubled")
    width: float = Field(default=0.012, gt=0.0, le=0.3, description="strip width / length [-]")
    thickness: float = Field(default=0.002, gt=0.0, le=0.1, description="strip thickness / length [-]")
    round: bool = Field(default=False, description="a round cord or hose rather than a flat strip")
    bore: float = Field(default=0.0, ge=0.0, lt=1.0, description="a tube's inner over outer diameter (drawn solid; "
                        "its mass is the wall's: tasks.geometry.dims_words) [-]")
    turns: float = Field(default=3.0, ge=1.0, le=60.0, description="turns of a coil (a flat spiral draws at most 8) [-]")
    ends: Literal["none", "handles", "buckle", "ring", "hose", "hooks", "leash", "plug", "coupling", "wrapped"] = Field(
        default="none", description="what the ends carry; hose: an inflatable cuff's (a blood pressure cuff): its "
        "rubber tube and plug out of one face, a hook-and-loop patch; hooks: a J-hook at each end (a bungee cord); "
        "buckle: a metal frame buckle (laid in a loop: the belt buckled, its tip through the buckle); leash: a "
        "handle loop sewn at one end and a snap clip at the other (a dog leash, laid wavy); plug / coupling: a coiled "
        "cord's free end trailing out of the coil to a cable's connector / a hose's threaded coupling; wrapped: a "
        "rope's coil with its free end wound round the coil a few turns and its tail out (a climber's coil)")


def _strip_dims(p: StrapParams, extent: float) -> tuple[float, float]:
    """(built width, built thickness) of the strip: the real ones, no thinner than the mesher sees at this extent."""
    w = max(p.width, 0.045 * extent)
    t = max(p.thickness, 0.028 * extent) if not p.round else w
    return w, min(t, w)


def strap(p: StrapParams) -> list[Part]:
    """Straight: along x. Loop: a loose, uneven closed loop on the ground. Rolled: coiled, a flat spiral of
    `turns`."""
    if p.state == "loop":
        n = 18
        r = 1.0 / (2 * np.pi)
        a = np.linspace(0, 2 * np.pi, n + 1)
        wob = 1 + 0.12 * np.sin(2 * a + 0.5) + 0.06 * np.sin(3 * a + 1.3)
        xy = np.stack([1.25 * r * wob * np.cos(a), 0.8 * r * wob * np.sin(a)], axis=1)
        xy *= 1.0 / np.sum(np.linalg.norm(np.diff(xy, axis=0), axis=1))
        extent = float(np.ptp(xy[:, 0]))
        w, t = _strip_dims(p, extent)
        z = t / 2 if not p.round else w / 2
        pts = [np.array([x, y, z]) for x, y in xy]
        parts = _flat_chain("body", pts, w / 2, t, blend=0.3 * w)
        if p.ends == "buckle":
            parts += _buckle(pts[0], pts[1] - pts[-2], w, t)
    elif p.state == "bow":
        parts = _bow(p)
    elif p.state == "rolled" and coiled_as_hank(p):
        parts = _hank(p)
    elif p.state == "rolled":  # a flat spiral from radius r0 = 0.45 r1 out to r1, its length 1
        turns = min(p.turns, 8.0)
        n = int(min(40, 10 * turns))
        r1 = 1.0 / (np.pi * turns * 1.45)
        r0 = 0.45 * r1
        s_ = np.linspace(0, 1, n + 1)
        ang = 2 * np.pi * turns * s_
        rad = r0 + (r1 - r0) * s_
        xy = np.stack([rad * np.cos(ang), rad * np.sin(ang)], axis=1)
        extent = 2 * r1
        w, t = _strip_dims(p, extent)
        w = min(w, 0.9 * (r1 - r0) / turns) if turns > 1.5 else w
        t = min(t, w) if p.round else t
        z = t / 2 if not p.round else w / 2
        pts = [np.array([x, y, z]) for x, y in xy]
        parts = _flat_chain("body", pts, w / 2, t, blend=0.2 * w)
    elif p.state == "wavy":  # an open length in loose S-bends: 1.5 waves, their amplitude a tenth of the length
        u = np.linspace(0.0, 1.0, WAVY_POINTS)
        xy = np.stack([u, WAVY_AMPLITUDE * np.sin(3 * np.pi * u) * (0.8 + 0.4 * u)], axis=1)
        xy *= 1.0 / np.sum(np.linalg.norm(np.diff(xy, axis=0), axis=1))
        xy -= xy.mean(axis=0)
        w, t = _strip_dims(p, float(np.ptp(xy[:, 0])))
        z = t / 2 if not p.round else w / 2
        pts = [np.array([x, y, z]) for x, y in xy]
        parts = _flat_chain("body", pts, w / 2, t, blend=0.3 * w)
        if p.ends == "leash":
            parts += _leash_ends(pts, w, t)
    else:
        length = 0.5 if p.closed else 1.0
        w, t = _strip_dims(p, length)
        z = t / 2 if not p.round else w / 2
        if p.closed:  # a loop band laid flat: two layers, their ends turned round
            parts = [box("body", (length, w, 2 * t), (0, 0, t), edge=0.95 * t)]
        else:
            parts = [_flat_limb("body", np.array([-length / 2 + w / 2, 0, z]), np.array([length / 2 - w / 2, 0, z]),
                                w / 2, t, blend=0.0)]
        if p.ends == "handles":
            for sgn in (1.0, -1.0):
                parts.append(limb(f"{'left' if sgn > 0 else 'right'} handle", (sgn * length / 2, -0.06, 0.02),
                                  (sgn * length / 2, 0.06, 0.02), 0.02, blend=0.01))
        elif p.ends == "buckle":
            parts.append(box("buckle", (0.04, 1.4 * w, 1.8 * t), (length / 2 - 0.03, 0, 0.9 * t), edge=0.4 * t,
                             blend=0.002))
        elif p.ends == "ring":
            parts.append(scaled(torus("ring", 0.7 * w, 0.12 * w, (length / 2, 0, 0.12 * w)), (1, 1, 1)))
        elif p.ends == "hooks":
            parts += _end_hooks(length, z, w)
        elif p.ends == "hose":  # out of the top face near one end, curving away over the table
            r = 0.012
            pts = [np.array([-0.22 + 0.45 * u - 0.1 * np.sin(np.pi * u), -w / 2 - 0.28 * np.sin(0.5 * np.pi * u),
                             r + t * (1.0 - u) ** 2]) for u in np.linspace(0.0, 1.0, 8)]
            parts += [limb(f"hose {k + 1}", pts[k], pts[k + 1], r, blend=0.3 * r) for k in range(len(pts) - 1)]
            parts.append(limb("hose 0", np.array([-0.22, -0.3 * w, t]), pts[0], r, blend=0.3 * r))
            tip = pts[-1] + np.array([0.04, 0.0, 0.0])
            parts.append(cylinder("plug", 1.8 * r, 0.05, tuple(tip), rot=(0, 90, 0), edge=0.4 * r, blend=0.005))
            parts.append(box("fastener patch", (0.3, 0.8 * w, 0.35 * t), (0.3, 0, t * 1.05), edge=0.15 * t,
                             blend=0.004))
    if p.fluff:
        parts += _fluff(parts)
    return parts


def _bow(p: StrapParams) -> list[Part]:
    """A ribbon tied in a bow lying flat: the knot at the centre, two loops out to the sides (each a flat band round
    a teardrop), two tails hanging down from the knot, their ends cut in a V; the ribbon's length 1 shared among
    them."""
    loop_len, tail_len = 0.34, 0.13
    extent = 2 * loop_len / np.pi + 0.1
    w, t = _strip_dims(p, extent)
    z = t / 2
    parts = [box("body", (1.3 * w, 1.2 * w, 2.2 * t), (0, 0, 1.1 * t), edge=0.45 * t)]  # the knot
    R = loop_len / (2 * np.pi)
    for side, sx in (("left", -1.0), ("right", 1.0)):
        c = np.array([sx * (0.55 * w + R), 0.0])
        pts = [np.array([c[0] + sx * R * np.cos(a), 0.65 * R * np.sin(a), z])
               for a in np.linspace(np.pi + 0.45, 3 * np.pi - 0.45, 9)]
        pts = [np.array([0.0, 0.25 * w * (1 if k == 0 else -1), z]) if k in (0, 8) else q for k, q in enumerate(pts)]
        parts += _flat_chain(f"{side} loop", pts, w / 2, t, blend=0.3 * w)
        a = np.array([0.0, 0.0, z])
        b = np.array([sx * 0.45 * tail_len, -0.9 * tail_len, z])
        parts += _flat_chain(f"{side} tail", [a, b], w / 2, t, blend=0.3 * w)
        parts.append(_op(box(f"{side} tail notch", (0.9 * w, 0.9 * w, 4 * t), tuple(b + np.array([0, -0.35 * w, 0])),
                             rot=(0, 0, 45)), "subtract"))
    return parts


def _buckle(at: np.ndarray, along: np.ndarray, w: float, t: float) -> list[Part]:
    """A belt's frame buckle lying on the strap at `at`, its bar across the strap (the strap running `along`): the
    metal frame (a plate with its window cut), the prong across the window, the strap's tip out past it."""
    d = along / np.linalg.norm(along)
    yaw = float(np.degrees(np.arctan2(d[1], d[0])))
    fl, fw, ft = 1.5 * w, 1.5 * w, 1.4 * t
    c = at + np.array([0.0, 0.0, 0.7 * t])
    return [box("buckle", (fl, fw, ft), tuple(c), edge=0.3 * ft, rot=(0, 0, yaw), blend=0.1 * t),
            _op(box("buckle window", (0.6 * fl, 0.7 * fw, 3 * ft), tuple(c), rot=(0, 0, yaw)), "subtract"),
            box("prong", (0.75 * fl, 0.14 * fw, 0.8 * ft), tuple(c + np.array([0.0, 0.0, 0.1 * t])), edge=0.3 * t,
                rot=(0, 0, yaw)),
            box("keeper", (0.35 * w, 1.2 * w, 1.6 * t), tuple(at - d * 1.3 * fl + np.array([0.0, 0.0, 0.6 * t])),
                edge=0.4 * t, rot=(0, 0, yaw), blend=0.1 * t)]


def _leash_ends(pts: list[np.ndarray], w: float, t: float) -> list[Part]:
    """A leash's ends: the handle, a flat loop of the strap sewn back at the first point, and the metal snap clip
    (a swivel ring and the hook's body) at the last."""
    a, b = pts[0], pts[-1]
    da = (a - pts[1]) / np.linalg.norm(a - pts[1])
    db = (b - pts[-2]) / np.linalg.norm(b - pts[-2])
    R = 0.06
    hc = a + da * R * 0.9
    out = [scaled(torus("handle", R, w / 2, tuple(hc), rot=(0, 0, 0)), (1.0, 0.6, t / w)),
           box("stitching", (1.2 * w, 1.1 * w, 1.2 * t), tuple(a), edge=0.4 * t, blend=0.1 * t,
               rot=(0, 0, float(np.degrees(np.arctan2(da[1], da[0])))))]
    rr = 0.6 * w
    rc = b + db * rr
    out.append(torus("swivel ring", rr, 0.25 * w, tuple(rc), blend=0.1 * t))
    out.append(limb("clip", tuple(rc + db * rr), tuple(rc + db * (rr + 0.07)), 0.45 * w, blend=0.2 * w))
    return out


TAIL_MIN_RADIUS = 0.045  # a coil's trailing end: its radius at least this share of the coil's outer radius [-]
HANK_MIN_TURNS = 4.5  # a round cord coiled in more turns is a hank, not a flat spiral (a hose, a cable) [-]
HANK_PACKING = 0.7  # the cord's share of a coiled hank's ring section [-]
HANK_STRANDS = 14  # loops drawn over the hank's surface [-]


def coiled_as_hank(p: StrapParams) -> bool:
    """A coil drawn loop on loop (a hank), not as a flat spiral: asked for, or a round cord of more than
    HANK_MIN_TURNS turns (hands coil a hose or a cable so)."""
    return p.hank or (p.round and p.turns > HANK_MIN_TURNS)


def _hank(p: StrapParams) -> list[Part]:
    """A rope of length 1 coiled in `turns` loops stacked into one ring lying on the ground: the ring's section holds
    the cord's volume at HANK_PACKING; single loops, a little off round and tilted, are drawn over it (a loop's
    radius at least a quarter of the ring's: a short thick cord, 'halter leads 40cm', made it negative, a crash)."""
    R = 1.0 / (2 * np.pi * p.turns)
    d = max(p.width, 1e-4)
    rb = max(float(np.sqrt(d * d / (4 * HANK_PACKING * 2 * np.pi * R))), 0.6 * d)
    r = max(0.5 * d, 0.3 * rb)  # a strand a third of the section wide: seen as rope, not as a tube's texture
    parts = [torus("body", R, 0.85 * rb, (0, 0, 0.85 * rb))]  # the core the loops lie on
    for i in range(HANK_STRANDS):  # loops side by side and on one another, each off centre the other way (by
        # the golden angle), so along the ring they drift across the coil and cross, as a hand-coiled rope's do
        a = 2.39996 * i
        dr = (i % 3 - 1) * 0.55 * rb
        dz = (0.45 + 0.35 * ((i // 3) % 2)) * rb
        off = 0.45 * rb * np.array([np.cos(a), np.sin(a)])
        parts.append(torus(f"loop {i + 1}", max(R + dr, 0.25 * R), r, (float(off[0]), float(off[1]), rb + dz - r),
                           rot=(2.0 * np.sin(1.7 * i), 2.0 * np.cos(2.3 * i), 0.0)))
    if p.ends in ("plug", "coupling"):
        parts += _coil_end(R, rb, d, p.ends)
    elif p.ends == "wrapped":
        parts += _coil_wraps(R, rb, d)
    return parts


COIL_WRAPS = 3  # turns of a rope's free end round its coil [-]


def _coil_wraps(R: float, rb: float, d: float) -> list[Part]:
    """A rope coil's binding: its free end wound COIL_WRAPS times round the coil's section at one side (rings across
    the ring, each as thick as the cord), then out over the table as a short tail."""
    r = max(d / 2, TAIL_MIN_RADIUS * (R + rb))  # no thinner than the mesher sees at the coil's extent
    zc = 0.9 * rb
    parts = [torus(f"wrap {k + 1}", 1.05 * rb + r, r, (R, (k - (COIL_WRAPS - 1) / 2) * 2.4 * r, zc), rot=(90, 0, 0))
             for k in range(COIL_WRAPS)]
    y_end = (COIL_WRAPS - 1) / 2 * 2.4 * r
    pts = [np.array([R + 1.05 * rb + r, y_end, zc]), np.array([R + rb + 0.2 * R, y_end + 0.25 * R, r]),
           np.array([R + rb + 0.3 * R, y_end + 0.6 * R, r])]
    parts += [limb(f"tail {k + 1}", pts[k], pts[k + 1], r, blend=r) for k in range(2)]
    return parts


def _coil_end(R: float, rb: float, d: float, kind: str) -> list[Part]:
    """A coiled cord's free end: out of the coil's outer edge, curving away over the table, ending in a fitting (a
    cable's connector: a long sleeve three cords thick; a hose's coupling: a short collar half as thick again)."""
    z = d / 2
    pts = [np.array([R + 0.2 * rb, 0.0, rb]), np.array([R + rb + 0.12 * R, -0.3 * R, z]),
           np.array([R + rb + 0.22 * R, -0.7 * R, z])]
    r = max(d / 2, TAIL_MIN_RADIUS * (R + rb))  # no thinner than the mesher sees at the coil's extent
    parts = [limb(f"tail {k + 1}", pts[k], pts[k + 1], r, blend=r) for k in range(2)]
    along = (pts[2] - pts[1]) / np.linalg.norm(pts[2] - pts[1])
    radius, length = (3 * r, 12 * r) if kind == "plug" else (1.6 * r, 3.6 * r)
    start = pts[2] + along * 0.4 * r
    parts.append(limb(kind, start, start + along * length, radius, blend=0.6 * r))
    return parts


WAVY_POINTS = 19  # a wavy length's polyline points [-]
WAVY_AMPLITUDE = 0.1  # its S-bends' amplitude / its length [-]
FLUFF_CLUMPS = 36  # fluff clumps along a fluffy cord (a program holds at most 64 parts) [-]


def _fluff(cord: list[Part]) -> list[Part]:
    """Clumps of fluff along a cord's body segments: flattened ellipsoids as wide as the cord, each at its own tilt
    and a little off the cord's line (deterministic), so the outline is ragged, not a smooth tube."""
    body = [q for q in cord if part_group(q.name) == "body"]
    if len(body) < 2 or body[0].primitive.kind != "capsule":
        return []
    r = float(body[0].primitive.radius_m)
    centres = np.array([q.transform.translation_m for q in body], dtype=np.float64)
    seg = np.linalg.norm(np.diff(centres, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    rng = np.random.default_rng(5)
    out = []
    for i, at in enumerate(np.linspace(0.0, s[-1], min(FLUFF_CLUMPS, 64 - len(cord)))):
        c = np.array([np.interp(at, s, centres[:, k]) for k in range(3)])
        off = rng.normal(0.0, 0.25 * r, 3)
        tilt = rng.uniform(-60.0, 60.0, 3)
        out.append(ellipsoid(f"fluff {i + 1}", (1.5 * r, 1.15 * r, 0.9 * r), c + off, rot=tuple(tilt),
                             blend=0.4 * r))
    return out


HOOK_SIZE = 0.065  # a bungee cord's J-hook: shank length, / the cord's length [-]


def _end_hooks(length: float, z: float, w: float) -> list[Part]:
    """A J-hook at each end of a straight cord, lying on the table: a crimped collar, a straight shank out of it and
    a bend back toward the cord ending in a tip (coated steel, drawn a little thicker than the wire to be seen)."""
    r = max(0.35 * w, 0.006)
    parts: list[Part] = []
    for sgn, word in ((1.0, "right"), (-1.0, "left")):
        end = np.array([sgn * length / 2, 0.0, z])
        parts.append(limb(f"{word} collar", end - [sgn * 0.5 * HOOK_SIZE, 0, 0], end, 0.75 * w, blend=0.2 * w))
        tip = end + [sgn * HOOK_SIZE, 0, 0]
        parts.append(limb(f"{word} hook", end, tip, r, blend=0.3 * r))
        bend = 0.4 * HOOK_SIZE
        a = np.linspace(-0.5 * np.pi, 0.5 * np.pi, 5)
        pts = [tip + np.array([sgn * bend * np.cos(t), bend + bend * np.sin(t), 0.0]) for t in a]
        pts.append(pts[-1] - [sgn * 0.6 * HOOK_SIZE, 0, 0])
        parts += [limb(f"{word} hook {k + 2}", pts[k], pts[k + 1], r, blend=0.3 * r) for k in range(len(pts) - 1)]
    return parts


# ----------------------------------------------------------------------------------------------------- rope toys
class RopeParams(Model):
    """A rope toy or short rope: strands twisted round each other, a knot at each end (or one), frayed tufts beyond
    the knots; each strand (its knots and tuft too) may take its own colour ('strand a', 'strand b' ...)."""

    strands: int = Field(default=3, ge=2, le=4)
    radius: float = Field(default=0.04, gt=0.01, le=0.15, description="rope radius / length [-]")
    knots: int = Field(default=2, ge=0, le=3, description="knots along the rope (ends first) [-]")
    tufts: bool = Field(default=True, description="frayed ends beyond the end knots")
    twist: float = Field(default=2.5, ge=0.5, le=6.0, description="turns of the strands over the rope's length [-]")


def rope(p: RopeParams) -> list[Part]:
    """Length 1 along x, lying on the ground."""
    R = p.radius
    sr = 0.6 * R
    kr = 2.3 * R
    x0, x1 = -0.5 + 0.12, 0.5 - 0.12
    parts: list[Part] = [limb("body", (x0, 0, R), (x1, 0, R), 0.6 * R)]
    n = 8
    for k in range(p.strands):
        ph = 2 * np.pi * k / p.strands
        xs = np.linspace(x0, x1, n + 1)
        pts = [np.array([x, 0.5 * R * np.cos(ph + 2 * np.pi * p.twist * (x - x0)), R + 0.5 * R *
                         np.sin(ph + 2 * np.pi * p.twist * (x - x0))]) for x in xs]
        for i in range(n):
            parts.append(limb(f"strand {'abcd'[k]} {i + 1}", pts[i], pts[i + 1], sr, blend=0.25 * sr))
    at = [x0, x1, 0.0][: p.knots]
    for j, x in enumerate(at):
        for k in range(p.strands):
            ph = 2 * np.pi * k / p.strands + 0.4 * j
            c = np.array([x, 0.45 * kr * np.cos(ph), kr + 0.45 * kr * np.sin(ph) - 0.1 * kr])
            parts.append(ellipsoid(f"strand {'abcd'[k]} {20 + j}", (0.7 * kr, 0.62 * kr, 0.62 * kr), c,
                                   rot=(float(np.degrees(ph)), 0, 20), blend=0.2 * kr))
    if p.tufts:
        for j, (x, s) in enumerate(((x0, -1), (x1, 1))):
            if j >= p.knots:
                break
            for k in range(p.strands):
                ph = 2 * np.pi * k / p.strands
                a = np.array([x + s * 0.45 * kr, 0.3 * kr * np.cos(ph), kr * 0.9 + 0.3 * kr * np.sin(ph)])
                b = a + np.array([s * 0.16, 0.5 * kr * np.cos(ph), 0.35 * kr * np.sin(ph)])
                b[2] = max(b[2], sr * 0.9)
                parts.append(tapered_tuft(f"strand {'abcd'[k]} {30 + j}", a, b, 0.7 * sr))
    return parts


def tapered_tuft(name: str, a: np.ndarray, b: np.ndarray, r: float) -> Part:
    """A frayed tuft: a cone widening from the knot outwards."""
    return tapered(name, a, b, 0.6 * r, 1.3 * r, blend=0.3 * r)


# ----------------------------------------------------------------------------------------------------------- books
class BookParams(Model):
    """A book lying closed: two covers, a page block (its edges striped with page lines), a rounded spine; a soft
    cloth or crinkle book with puffy covers and ribbon tags along its edge."""

    width: float = Field(default=0.75, gt=0.3, le=1.2, description="width / height [-]")
    thickness: float = Field(default=0.12, gt=0.02, le=0.6, description="thickness / height [-]")
    cover: float = Field(default=0.12, gt=0.02, le=0.4, description="one cover's thickness / the book's [-]")
    soft: bool = Field(default=False, description="puffy fabric covers, rounded corners")
    tags: int = Field(default=0, ge=0, le=6, description="ribbon tags along the fore-edge (taggie books) [-]")
    page_lines: int = Field(default=5, ge=0, le=9, description="grooves along the page block's edges [-]")


def book(p: BookParams) -> list[Part]:
    """Height 1 along x, width along y (the spine at -y), lying on its back cover. A hard book: two covers over a page
    block whose edges show page lines. A soft book: its thick fabric pages as separate puffy layers (seen stacked at
    the edges), covers over them, an appliqué patch on the front cover and ribbon tags along the fore-edge."""
    w, T = p.width, p.thickness
    c = max(p.cover * T, MIN_LAYER * 0.8)
    edge = (0.45 if p.soft else 0.2) * c
    pages = T - 2 * c
    if p.soft:
        parts = [superellipsoid("body", (0.5, w / 2, c / 2), (0, 0, c / 2), ns=0.35, ew=0.2)]
        n = max(2, min(p.page_lines, 5))
        pt = pages / n
        for i in range(n):
            parts.append(superellipsoid(f"pages {i + 1}", (0.47, w / 2 - 0.03, 0.42 * pt),
                                        (-0.005 * (i % 2), 0.02 + 0.006 * (i % 2), c + pt * (i + 0.5)), ns=0.3,
                                        ew=0.25, blend=0.1 * pt))
        parts.append(superellipsoid("cover", (0.5, w / 2, c / 2), (0, 0, T - c / 2), ns=0.35, ew=0.2,
                                    blend=0.1 * pt))
        parts.append(scaled(cylinder("spine", T / 2, 1.0, (0, -w / 2 + 0.02, T / 2), edge=0.3 * c, rot=(0, 90, 0),
                                      blend=0.02), (1, 0.4, 1)))
        parts.append(scaled(cylinder("patch", 0.22, 0.25 * c, (0.03, 0.04, T + 0.05 * c), edge=0.1 * c,
                                      blend=0.005), (1, 1, 1)))
    else:
        parts = [box("body", (1.0, w, c), (0, 0, c / 2), edge=edge)]
        parts.append(box("pages", (0.96, w - 0.03, pages + 0.01), (0, 0.01, c + pages / 2), edge=0.1 * c))
        parts.append(box("cover", (1.0, w, c), (0, 0, T - c / 2), edge=edge, blend=0.002))
        parts.append(scaled(cylinder("spine", T / 2, 1.0, (0, -w / 2, T / 2), edge=0.3 * c, rot=(0, 90, 0),
                                      blend=0.01), (1, 0.35, 1)))
        for i in range(p.page_lines):
            z = c + pages * (i + 1) / (p.page_lines + 1)
            g = min(0.012, 0.25 * pages / (p.page_lines + 1))
            parts.append(_op(box(f"page line {i + 1}", (1.2, 0.05, g), (0, w / 2 - 0.01, z)), "subtract"))
            parts.append(_op(box(f"page line {i + 1} end", (0.05, w * 0.9, g), (0.49, 0.03, z)), "subtract"))
    for i in range(p.tags):
        x = -0.33 + 0.66 * i / max(p.tags - 1, 1)
        parts.append(scaled(torus(f"tag {i + 1}", 0.055, 0.022, (x, w / 2 + 0.02, T / 2), rot=(0, 0, 0),
                                   blend=0.01), (0.8, 1.3, 0.6)))
    return parts
