"""The goods of a bag drawn as the goods themselves: each piece slot of a pouch ('fill N', a plain lump pressing
through the film) replaced by the piece concept's own hand-written parts, scaled into the slot ('a bag of cashews'
shows crescents, 'a bag of goldfish crackers' orange fish), within the program's part budget (#35)."""

from __future__ import annotations

import functools
import warnings
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from contracts.yaml_io import load_yaml
from contracts.shape import MAX_PARTS, Part, RoundedBox, ShapeProgram, Transform
from tasks.geometry.grammar.parts import part_group, squashed_parts
from tasks.geometry.sdf import program_bounds

PICTURES_FILE = Path(__file__).resolve().parents[2] / "contracts" / "vocab" / "pack_pictures.yaml"
SLOT_KINDS = ("superellipsoid", "ellipsoid")  # how bagged_pieces and the net bag draw a piece slot
PICTURE_ACROSS = 0.6  # the pack's picture of one piece: its longest side / the pack's narrower side [-]
PICTURE_PROUD = 0.06  # the picture's relief / the pack's length (~3 draft cells: a thinner one is not meshed) [-]
PICTURE_SUNK = 0.2  # the share of the picture's relief sunk in its label [-]
LABEL_MARGIN = 1.25  # the label under the picture / the picture's footprint [-]
LABEL_PROUD = 0.03  # the label's face over the film's top / the pack's length (colours are the nearest part's,
# blended over meshing.COLOR_SHARPNESS cells: a flush label would take the film's) [-]
LABEL_THICK = 0.05  # the label's thickness / the pack's length, its face LABEL_PROUD over the film, the rest sunk [-]
LIGHT_LABEL = (0.85, 0.85, 0.82)  # a label under a dark picture (linear RGB)
DARK_LABEL = (0.02, 0.03, 0.12)  # a label under a light one (navy)
PICTURE_MIN_SLOTS = 6  # a pack of fewer, larger goods shows them well enough without a picture [-]
PICTURE_PARTS = 8  # at most this many of the piece's parts in the picture [-]


def _f3(v: np.ndarray) -> tuple[float, float, float]:
    return (float(v[0]), float(v[1]), float(v[2]))


def _part_size(piece: ShapeProgram, p: Part) -> float:
    """A part's rough volume (its primitive's bounding box times its scale) [m^3], to keep the largest parts."""
    lo, hi = program_bounds(piece.model_copy(update={"parts": [p.model_copy(update={"blend_m": 0.0})]}))
    return float(np.prod(np.maximum(hi - lo, 1e-9)))


def piece_parts(piece: ShapeProgram, budget: int) -> list[Part]:
    """The piece's union parts, at most `budget` of them (the largest, in their own order); [] when the piece
    cuts or intersects (its subtract would cut the bag) or nothing fits."""
    if budget < 1 or any(p.operation != "union" for p in piece.parts):
        return []
    keep = sorted(range(len(piece.parts)), key=lambda i: -_part_size(piece, piece.parts[i]))[:budget]
    return [piece.parts[i] for i in sorted(keep)]


def _axes_by_extent(extent: np.ndarray) -> np.ndarray:
    """A proper rotation taking the piece's longest, middle and shortest axes onto x, y and z (as a slot lies)."""
    order = np.argsort(-extent, kind="stable")
    m = np.zeros((3, 3))
    for row, axis in enumerate(order):
        m[row, axis] = 1.0
    if np.linalg.det(m) < 0:
        m[2] *= -1.0
    return m


def _placed(parts: list[Part], centre: np.ndarray, k: float, frame: np.ndarray, at: np.ndarray) -> list[Part]:
    """The piece's parts moved from `centre`, scaled by k, turned by `frame` and put at `at`."""
    out = []
    for q in parts:
        own = Rotation.from_euler("xyz", q.transform.rotation_deg, degrees=True).as_matrix()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # gimbal lock: any equal angle set will do
            euler = Rotation.from_matrix(frame @ own).as_euler("xyz", degrees=True)
        where = frame @ (k * (np.asarray(q.transform.translation_m) - centre)) + at
        out.append(q.model_copy(update={"blend_m": q.blend_m * k, "transform": q.transform.model_copy(update={
            "translation_m": _f3(where), "rotation_deg": _f3(euler),
            "scale": _f3(k * np.asarray(q.transform.scale, dtype=np.float64))})}))
    return out


def _picture(program: ShapeProgram, piece: ShapeProgram) -> tuple[list[Part], np.ndarray, np.ndarray]:
    """The pack's printed picture of its goods: one piece, large, in low relief on the middle of the pack's top (as
    a retail pack shows its contents), and the picture's footprint (lo, hi) in x, y [m]; none without a 'body'."""
    body = next((p for p in program.parts if p.name == "body"), None)
    parts = piece_parts(piece, PICTURE_PARTS)
    if body is None or not parts:
        return [], np.zeros(2), np.zeros(2)
    lo, hi = program_bounds(program.model_copy(update={"parts": [body.model_copy(update={"blend_m": 0.0})]}))
    plo, phi = program_bounds(piece.model_copy(update={"parts": parts}))
    extent = np.maximum(phi - plo, 1e-9)
    ext_sorted = np.sort(extent)[::-1]
    length = float(max(hi[0] - lo[0], hi[1] - lo[1]))
    k = PICTURE_ACROSS * float(min(hi[0] - lo[0], hi[1] - lo[1])) / float(ext_sorted[0])
    flat = min(1.0, PICTURE_PROUD * length / (k * float(ext_sorted[2])))
    drawn = squashed_parts(_placed(parts, (plo + phi) / 2, k, _axes_by_extent(extent), np.zeros(3)), (1.0, 1.0, flat))
    top = hi[2] + LABEL_PROUD * length  # the label's face
    at = np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, top + (0.5 - PICTURE_SUNK) * k * ext_sorted[2] * flat])
    named = [q.model_copy(update={
        "name": "picture" if j == 0 else f"picture {q.name}", "blend_m": 0.0 if j == 0 else q.blend_m,
        "transform": q.transform.model_copy(update={"translation_m": _f3(np.asarray(q.transform.translation_m) + at)})})
        for j, q in enumerate(drawn)]
    half = 0.5 * k * ext_sorted[:2]
    main = np.asarray(named[0].color_rgb)
    light = 0.2126 * main[0] + 0.7152 * main[1] + 0.0722 * main[2] > 0.3
    label = Part(name="picture label", primitive=RoundedBox(size_m=_f3(np.array([
        *(2 * LABEL_MARGIN * half), LABEL_THICK * length])), edge_radius_m=0.45 * LABEL_THICK * length),
        transform=Transform(translation_m=(float(at[0]), float(at[1]), float(top - 0.5 * LABEL_THICK * length))),
        color_rgb=DARK_LABEL if light else LIGHT_LABEL, blend_m=0.1 * LABEL_THICK * length)
    return [label, *named], at[:2] - LABEL_MARGIN * half, at[:2] + LABEL_MARGIN * half


def drawn_pieces(program: ShapeProgram, piece: ShapeProgram, keep_colours: bool = True,
                 picture: bool = True) -> ShapeProgram:
    """`program` with each piece slot ('fill N') replaced by the piece's parts fitted into the slot's box (its
    longest axis along the slot's longest, uniformly scaled, turned as the slot is), and one piece drawn large in
    low relief on the pack's top (its printed picture; the slots under it left out). keep_colours: the piece's own
    colours (unsaid goods); else each piece all in its slot's colour ('pink and white marshmallows'). With no slots
    (goods too small to draw one by one) the picture alone; unchanged when nothing fits within MAX_PARTS. picture:
    False for a net sack (no printed front: its goods are seen through the net)."""
    slots = [i for i, p in enumerate(program.parts)
             if part_group(p.name) == "fill" and p.primitive.kind in SLOT_KINDS and p.operation == "union"]
    if not slots:  # goods too small or too many to draw one by one ('a bag of m&ms'): their picture alone
        return pictured(program, piece) if picture else program
    picture_parts, foot_lo, foot_hi = _picture(program, piece) if picture and len(slots) >= PICTURE_MIN_SLOTS else (
        [], np.zeros(2), np.zeros(2))
    if picture_parts and not keep_colours:
        picture_parts = [picture_parts[0], *(q.model_copy(update={"color_rgb": program.parts[slots[0]].color_rgb})
                                             for q in picture_parts[1:])]
    mid, half = (foot_lo + foot_hi) / 2, (foot_hi - foot_lo) / 2
    covered = {i for i in slots if picture_parts and np.all(np.abs(np.asarray(program.parts[i].transform.translation_m[:2])
                                                             - mid) < half)}
    shown = [i for i in slots if i not in covered]
    if not shown:
        return program
    budget = (MAX_PARTS - (len(program.parts) - len(slots)) - len(picture_parts)) // len(shown)
    parts = piece_parts(piece, budget)
    if not parts:
        return program
    lo, hi = program_bounds(piece.model_copy(update={"parts": parts}))
    centre, extent = (lo + hi) / 2, np.maximum(hi - lo, 1e-9)
    to_slot = _axes_by_extent(extent)
    ext_sorted = np.sort(extent)[::-1]
    out: list[Part] = []
    for i, p in enumerate(program.parts):
        if i in covered:
            continue
        if i not in slots:
            out.append(p)
            continue
        tf = p.transform
        slot_ext = 2.0 * np.asarray(p.primitive.radii_m) * np.asarray(tf.scale)  # type: ignore[union-attr]
        k = float(np.min(np.sort(slot_ext)[::-1] / ext_sorted))
        frame = Rotation.from_euler("xyz", tf.rotation_deg, degrees=True).as_matrix() @ to_slot
        for j, q in enumerate(_placed(parts, centre, k, frame, np.asarray(tf.translation_m, dtype=np.float64))):
            out.append(q.model_copy(update={"name": p.name if j == 0 else f"{p.name} {q.name}",
                                            "color_rgb": q.color_rgb if keep_colours else p.color_rgb,
                                            "blend_m": p.blend_m if j == 0 else q.blend_m}))
    return program.model_copy(update={"parts": out + picture_parts})


@functools.lru_cache(maxsize=1)
def _pictures() -> dict[str, dict[str, str]]:
    return load_yaml(PICTURES_FILE.read_text(encoding="utf-8"))


def picture_of(entry_key: str, fill_key: str | None) -> str | None:
    """The concept a pack of this lexicon entry or fill shows on its front (contracts/vocab/pack_pictures.yaml)."""
    table = _pictures()
    return table["entries"].get(entry_key) or (table["fills"].get(fill_key) if fill_key else None)


def pictured(program: ShapeProgram, piece: ShapeProgram) -> ShapeProgram:
    """A pack with its printed label and emblem replaced by its goods' picture (one piece large on a label); the
    pack unchanged when it has no body or the picture does not fit within MAX_PARTS."""
    kept = [p for p in program.parts if part_group(p.name) not in ("label", "emblem")]
    bare = program.model_copy(update={"parts": kept})
    picture = _picture(bare, piece)[0]
    if not picture or len(kept) + len(picture) > MAX_PARTS:
        return program
    return bare.model_copy(update={"parts": [*kept, *picture]})
