"""How a surface looks, by material class: gloss, cloth sheen, a bump at the size of the material's own grain (foam
pores, a crumb, fur, a fabric's creases) and a mottle of its colour (a crust's browning, a fruit's skin), so that L0's
stills read as the material and not as a grey block (#35: tofu and a marshmallow were named soap, a cold pack a
pillow).

    from tasks.render.finish import finish_for, shade_pixels

    finish = finish_for("pu_foam", "foam")                  # Finish(...) by material class, else by category
    rgb = shade_pixels(albedo, normals, points_m, view_axes, finish, pixel_m)

A grain smaller than about two pixels is faded out rather than aliased (a 1 m mattress shows no pores; a 10 cm
sponge does). The bump is solid value noise of the point in metres in the asset frame, so it is the same from
every view and deterministic. Numpy only.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

AMBIENT = 0.36  # light everywhere
KEY = 0.56  # key light over the viewer's shoulder (tasks.render.views.LIGHT)
FILL = 0.14  # fill light from the camera
MIN_GRAIN_PX = 2.0  # a grain below this many pixels fades out
MIN_FADE = 0.3  # ... and one below MIN_FADE x MIN_GRAIN_PX pixels is not drawn


@dataclass(frozen=True)
class Finish:
    """One material's look; lengths in metres, strengths as fractions of the lit colour."""

    gloss: float = 0.0  # strength of the white specular highlight
    shininess: float = 20.0  # Blinn-Phong exponent: higher is a smaller, sharper highlight
    sheen: float = 0.0  # brightening at grazing angles (cloth, fur)
    grain_m: float = 0.0  # size of the bump's features (0: none)
    grain_depth: float = 0.0  # how far the bump tilts the normal
    mottle_m: float = 0.0  # size of the colour's patches (0: none)
    mottle: float = 0.0  # relative colour change across a patch
    lines_m: float = 0.0  # spacing of pale lines across the surface (a fillet's fat lines; 0: none)
    line_share: float = 0.18  # share of the spacing a line covers
    line_tone: float = 0.55  # how far a line's colour goes towards white
    dust: float = 0.0  # a white powder on the upward faces (sugar, flour, starch): how far it whitens them
    dust_m: float = 0.0015  # size of the powder's specks
    mud: float = 0.0  # brown dirt in blotches, thickest low down (a muddy glove, a dirty rag): how far it browns them
    mud_m: float = 0.025  # size of the blotches


MATTE = Finish()
FINISHES: dict[str, Finish] = {
    "pu_foam": Finish(grain_m=0.0012, grain_depth=0.55, mottle_m=0.004, mottle=0.05),
    "slow_rise_foam": Finish(grain_m=0.0010, grain_depth=0.45, mottle_m=0.004, mottle=0.04),
    "sponge": Finish(grain_m=0.0022, grain_depth=0.75, mottle_m=0.005, mottle=0.08),
    "pe_foam": Finish(gloss=0.06, shininess=12.0, grain_m=0.0008, grain_depth=0.30),
    "rubber": Finish(gloss=0.30, shininess=36.0),
    "silicone": Finish(gloss=0.26, shininess=28.0, grain_m=0.0015, grain_depth=0.05),
    "gel": Finish(gloss=0.55, shininess=70.0),
    "inflatable": Finish(gloss=0.45, shininess=55.0),
    "cheese": Finish(gloss=0.06, shininess=10.0, grain_m=0.0015, grain_depth=0.15, mottle_m=0.006, mottle=0.06),
    "bread": Finish(grain_m=0.0025, grain_depth=0.45, mottle_m=0.012, mottle=0.22),
    "plush": Finish(sheen=0.22, grain_m=0.0012, grain_depth=0.65, mottle_m=0.004, mottle=0.06),
    "fruit": Finish(gloss=0.22, shininess=24.0, grain_m=0.0008, grain_depth=0.10, mottle_m=0.010, mottle=0.10),
    "firm_produce": Finish(gloss=0.22, shininess=24.0, grain_m=0.0008, grain_depth=0.10, mottle_m=0.010, mottle=0.10),
    "processed_meat": Finish(gloss=0.3, shininess=30.0, grain_m=0.003, grain_depth=0.15, mottle_m=0.008, mottle=0.12),
    "textile": Finish(sheen=0.14, grain_m=0.012, grain_depth=0.22, mottle_m=0.0009, mottle=0.07),
    "marshmallow": Finish(sheen=0.05, grain_m=0.0010, grain_depth=0.12, mottle_m=0.003, mottle=0.03),
    "dough": Finish(gloss=0.05, shininess=8.0, grain_m=0.004, grain_depth=0.18, mottle_m=0.008, mottle=0.04),
}
LOOKS: dict[str, Finish] = {  # a lexicon entry's own look (its `finish`), where its material class's does not say it
    "fish": Finish(gloss=0.35, shininess=40.0, mottle_m=0.006, mottle=0.05, lines_m=0.011),  # a fillet's fat lines
    "lean_fish": Finish(gloss=0.35, shininess=40.0, mottle_m=0.006, mottle=0.06, lines_m=0.014, line_share=0.1,
                        line_tone=0.25),  # tuna: faint lines
    "rice": Finish(grain_m=0.0022, grain_depth=0.9, mottle_m=0.0025, mottle=0.05),  # cooked grains
    "meat": Finish(gloss=0.3, shininess=30.0, grain_m=0.003, grain_depth=0.15, mottle_m=0.008, mottle=0.12),
    "egg": Finish(gloss=0.08, shininess=10.0, mottle_m=0.006, mottle=0.08),  # cooked egg (an omelette): matte, not gel
    "film": Finish(gloss=0.6, shininess=70.0, sheen=0.05, mottle_m=0.004, mottle=0.04),  # goods seen through a clear
    # film (a blanket in its plastic sleeve, T-shirts in a vacuum bag): the film's glossy highlights over them
    "bloomy": Finish(gloss=0.04, shininess=8.0, grain_m=0.0012, grain_depth=0.3, mottle_m=0.006, mottle=0.07),  # a
    # soft cheese's white mould rind (a brie): matte and velvety, not a gel's gloss
    "wool": Finish(sheen=0.3, grain_m=0.003, grain_depth=0.9, mottle_m=0.008, mottle=0.1),  # wool and fur on the skin
    # or in a clump: crimped locks, no gloss
    "leather": Finish(gloss=0.2, shininess=26.0, grain_m=0.0015, grain_depth=0.1, mottle_m=0.012, mottle=0.06),  # smooth
    # leather goods (a handbag): a soft sheen, a fine pebble, no woven grain
    "foil": Finish(gloss=0.85, shininess=90.0, grain_m=0.005, grain_depth=0.6, mottle_m=0.01, mottle=0.18),  # a metal
    # foil or aluminised film (a space blanket): a mirror's sharp highlights broken by crinkles (it was a grey towel)
}
CATEGORY_MATERIAL = {  # a category's usual class where the material class is not known
    "foam": "pu_foam", "plush_animal": "plush", "plush": "plush", "rubber_toy": "rubber", "fruit": "fruit",
    "vegetable": "fruit", "baked_good": "bread", "textile": "textile", "gel": "gel", "meat": "gel",
    "inflatable": "inflatable", "cheese": "cheese",
}


DUSTED = "dusted"  # a look said in the request ('dusted with icing sugar'), joined to the entry's own with '+'
DUST = 0.75
MUDDY = "muddy"  # a look said in the request ('muddy', 'mud-caked', 'dirty'): blotches of mud
MUD = 0.85
MUD_RGB = np.array([0.29, 0.2, 0.11])  # wet soil's brown (0..1, as albedos)


def finish_for(material: str | None, category: str | None = None, look: str | None = None) -> Finish:
    """The entry's own look (LOOKS), else the finish of a material class (contracts/vocab/materials.yaml), else of the
    category's usual class, else MATTE; a look ending '+dusted' (or 'dusted') adds a white powder over its top, one
    with 'muddy' blotches of mud."""
    looks = (look or "").split("+")
    own = next((w for w in looks if w in LOOKS), None)
    if own is not None:
        base = LOOKS[own]
    elif material in FINISHES:
        base = FINISHES[str(material)]
    else:
        base = FINISHES.get(CATEGORY_MATERIAL.get(category or "", ""), MATTE)
    base = replace(base, dust=DUST) if DUSTED in looks else base
    return replace(base, mud=MUD) if MUDDY in looks else base


def with_look(look: str | None, added: str) -> str:
    """An entry's look with another said in the request ('fish' + 'dusted' -> 'fish+dusted')."""
    return added if not look else f"{look}+{added}"


def _hash01(ijk: np.ndarray, seed: int) -> np.ndarray:
    """A deterministic value in [0, 1) per integer lattice point (N, 3)."""
    h = (ijk[:, 0] * 73856093) ^ (ijk[:, 1] * 19349663) ^ (ijk[:, 2] * 83492791) ^ (seed * 2654435761)
    h = (h ^ (h >> 13)) * 1274126177
    h = h ^ (h >> 16)
    return (h & 0xFFFFFF).astype(np.float64) / float(0x1000000)


def value_noise(points: np.ndarray, seed: int = 0) -> np.ndarray:
    """Smooth solid noise in [0, 1) at points (N, 3) given in units of the feature size."""
    p = np.asarray(points, np.float64)
    base = np.floor(p).astype(np.int64)
    f = p - base
    s = f * f * (3.0 - 2.0 * f)  # smoothstep weights
    out = np.zeros(len(p))
    weights = [(1.0 - s[:, k], s[:, k]) for k in range(3)]  # per axis, the low and the high corner's weight
    for corner in range(8):
        d = ((corner >> 2) & 1, (corner >> 1) & 1, corner & 1)
        w = weights[0][d[0]] * weights[1][d[1]] * weights[2][d[2]]  # not np.prod over a last axis of 3: slow
        out += w * _hash01(base + np.array(d), seed)
    return out


def _bumped(normals: np.ndarray, points_m: np.ndarray, grain_m: float, depth: float) -> np.ndarray:
    """Normals tilted by the gradient of two octaves of noise at grain_m (finite differences), renormalised."""
    grad = np.zeros_like(normals)
    for octave, weight in ((1.0, 1.0), (2.3, 0.5)):
        q = points_m / (grain_m / octave)
        n0 = value_noise(q, 1)
        h = 0.25
        for axis in range(3):
            step = np.zeros(3)
            step[axis] = h
            grad[:, axis] += weight * (value_noise(q + step, 1) - n0) / h
    tangential = grad - np.einsum("ij,ij->i", grad, normals)[:, None] * normals
    n = normals - depth * tangential
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)


def shade_pixels(albedo: np.ndarray, normals: np.ndarray, points_m: np.ndarray, light: np.ndarray,
                 toward_eye: np.ndarray, finish: Finish, pixel_m: float) -> np.ndarray:
    """Lit colours (N, 3) in 0..1 of pixels with albedo (N, 3), unit normals (N, 3) and points (N, 3) [m], all in one
    frame with the unit light and eye directions; both faces of a surface are lit (meshes may face either way)."""
    n = np.asarray(normals, np.float64)
    n = np.where((n @ toward_eye)[:, None] < 0.0, -n, n)  # the face seen
    colour = np.asarray(albedo, np.float64).copy()
    if finish.grain_m > 0 and finish.grain_depth > 0:
        fade = min(1.0, finish.grain_m / (MIN_GRAIN_PX * pixel_m))
        if fade > MIN_FADE:
            n = _bumped(n, points_m, max(finish.grain_m, MIN_GRAIN_PX * pixel_m), finish.grain_depth * fade)
    fade = 0.0
    if finish.mottle_m > 0 and finish.mottle > 0:
        fade = min(1.0, finish.mottle_m / (MIN_GRAIN_PX * pixel_m))
    if finish.mottle_m > 0 and finish.mottle > 0 and fade > MIN_FADE:
        patch = value_noise(points_m / max(finish.mottle_m, MIN_GRAIN_PX * pixel_m), 2) - 0.5
        colour *= (1.0 + 2.0 * finish.mottle * fade * patch)[:, None]
    if finish.dust > 0:  # powder settles on what faces up, in specks
        up = np.clip(np.asarray(normals, np.float64)[:, 2], 0.0, 1.0) ** 2
        speck = value_noise(points_m / max(finish.dust_m, MIN_GRAIN_PX * pixel_m), 5)
        amount = finish.dust * up * np.clip(0.25 + 1.3 * speck, 0.0, 1.0)
        colour = colour + amount[:, None] * (0.97 - colour)
    if finish.mud > 0:  # blotches of mud, more of it low on the object (a dry patch is left here and there)
        z = np.asarray(points_m, np.float64)[:, 2]
        low = np.clip(1.0 - (z - z.min()) / max(float(np.ptp(z)), 1e-9), 0.0, 1.0) if z.size else z
        size = max(finish.mud_m, MIN_GRAIN_PX * pixel_m)  # two octaves: rounded blotches with ragged edges
        blotch = 0.65 * value_noise(points_m / size, 7) + 0.35 * value_noise(points_m / (0.37 * size), 8)
        amount = finish.mud * np.clip((blotch + 0.3 * low - 0.6) * 3.0, 0.0, 1.0)
        colour = colour + amount[:, None] * (MUD_RGB - colour)
    if finish.lines_m > 0 and finish.lines_m > 3 * pixel_m:  # pale lines across the long axis, a little slanted
        u = (points_m[:, 0] * 0.94 + points_m[:, 1] * 0.34 + 0.2 * points_m[:, 2]) / finish.lines_m
        wobble = 0.25 * (value_noise(points_m / (3 * finish.lines_m), 3) - 0.5)
        phase = np.abs(((u + wobble) % 1.0) - 0.5) * 2.0  # 0 at a line's centre
        on = np.clip((finish.line_share - phase) / max(finish.line_share * 0.4, 1e-6), 0.0, 1.0)
        colour = colour + (finish.line_tone * on)[:, None] * (1.0 - colour)
    n_l = np.clip(n @ light, 0.0, 1.0)
    n_v = np.clip(n @ toward_eye, 0.0, 1.0)
    lit = colour * (AMBIENT + KEY * n_l + FILL * n_v)[:, None]
    if finish.sheen > 0:
        lit += finish.sheen * (1.0 - n_v)[:, None] ** 2 * (0.5 + 0.5 * colour)
    if finish.gloss > 0:
        half = light + toward_eye
        half /= np.linalg.norm(half)
        lit += finish.gloss * (np.clip(n @ half, 0.0, 1.0) ** finish.shininess)[:, None]
    return np.clip(lit, 0.0, 1.0)
