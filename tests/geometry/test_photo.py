"""Photos: the object is segmented without the room (clutter, door frame, shadow); a named object's program is fitted
to the silhouette, an unknown one reconstructed from it; both match the photo's mask from the camera."""

from __future__ import annotations

import functools
import json
from pathlib import Path

import cv2
import numpy as np
import pytest
from skimage import data

import photo_scenes
from contracts.errors import InputError
from contracts.request import AssetRequest
from helpers import FAST_COACD, run, settings
from tasks.agents.intent import targets_from_intent, targets_from_request
from tasks.geometry import catalogue, image, pipeline, silhouette, sources
from tasks.geometry.meshing import mesh_program
from tasks.render.views import render_view


def _ellipse(shape: tuple[int, int], centre: tuple[int, int], axes: tuple[int, int]) -> np.ndarray:
    m = np.zeros(shape, np.uint8)
    cv2.ellipse(m, centre, axes, 0, 0, 360, 1, -1)
    return m.astype(bool)


def _room(seed: int, clear: np.ndarray | None = None, h: int = 480, w: int = 640) -> np.ndarray:
    """RGB float room: a wall, a wooden floor and clutter on the floor (none within 8 px of `clear`: a differently
    coloured thing pressed against the object is taken as part of it, a known limit)."""
    rng = np.random.default_rng(seed)
    img = np.zeros((h, w, 3))
    img[: int(0.62 * h)] = (205, 195, 170)
    img[int(0.62 * h):] = (150, 110, 75)
    xx = np.arange(w)[None, :]
    img[int(0.62 * h):] *= (0.9 + 0.1 * np.sin(xx / 7.0))[..., None]
    near = np.zeros((h, w), bool) if clear is None else cv2.dilate(clear.astype(np.uint8), np.ones((17, 17))) > 0
    for _ in range(25):
        c = rng.integers(0, 256, 3).astype(float)
        x, y = int(rng.integers(0, w)), int(rng.integers(int(0.55 * h), h))
        x1, y1 = x + int(rng.integers(10, 50)), y + int(rng.integers(8, 30))
        if not near[y : y1 + 1, x : x1 + 1].any():
            cv2.rectangle(img, (x, y), (x1, y1), c.tolist(), -1)
    return img


def _stage(img: np.ndarray, obj: np.ndarray, colour: tuple[float, float, float], door_x: int,
           shadow: tuple[tuple[int, int], tuple[int, int]], seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Put a textured object, a cast shadow and a white door frame (top to bottom, touching it) into a room."""
    h, w = obj.shape
    yy, xx = np.mgrid[:h, :w]
    sh = _ellipse((h, w), *shadow) & ~obj
    img[sh] *= 0.55
    img[:, door_x : door_x + 26] = (235, 232, 225)
    img[:, door_x + 26 : door_x + 30] = (120, 115, 110)
    door = np.zeros((h, w), bool)
    door[:, door_x : door_x + 30] = True
    tex = np.asarray(colour) + 25.0 * (np.sin(xx / 6.0) * np.sin(yy / 5.0))[..., None]
    img[obj] = tex[obj]
    img += np.random.default_rng(seed).normal(0, 5, img.shape)
    return cv2.GaussianBlur(img.clip(0, 255).astype(np.uint8), (3, 3), 0), door & ~obj, sh


def _blob_scene() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A blue plush blob (body, head, four feet) in a room, its head against a door frame, its shadow on the floor."""
    h, w = 480, 640
    obj = _ellipse((h, w), (300, 288), (120, 85))
    obj |= _ellipse((h, w), (395, 193), (60, 60))
    for dx in (-80, -30, 40, 85):
        obj |= _ellipse((h, w), (300 + dx, 363), (18, 35))
    img, door, sh = _stage(_room(0), obj, (0.0, 60.0, 150.0), 450, ((410, 388), (170, 30)), 0)
    return img, obj, door, sh


def _fast() -> pipeline.L0Settings:
    """Draft settings at a low marching-cubes resolution (the gates' winding-number checks scale with the faces)."""
    return settings(**FAST_COACD).model_copy(update={"marching_cubes_resolution": 40})


@functools.lru_cache(maxsize=1)
def _coffee_mask() -> np.ndarray:
    """The segmentation of skimage's coffee photo (deterministic; computed once for the tests below)."""
    return image.segment(data.coffee())[0]


@functools.cache
def _photo_segment(file: str) -> tuple[np.ndarray, str]:
    """image.segment of a photo in tests/geometry/photos (deterministic; the mesh test and the mask test below read
    the same photos: each is segmented once per process)."""
    mask, method = image.segment(image.load_image(PHOTOS / file))
    mask.setflags(write=False)
    return mask, method


def _iou(a: np.ndarray, b: np.ndarray) -> float:
    return float((a & b).sum() / (a | b).sum())


def test_clutter_door_frame_and_shadow_are_not_the_object() -> None:
    img, obj, door, shadow = _blob_scene()
    mask, method = image.segment(img)
    assert method.startswith("grabcut")
    assert _iou(mask, obj) > 0.95
    assert (mask & door).sum() < 0.02 * door.sum()  # the border-to-border strip touching the head is cut off
    assert (mask & shadow).sum() < 0.05 * shadow.sum()


def test_real_photo_is_segmented_without_the_table() -> None:
    """skimage's coffee photo: a cup on a saucer on a wooden table (regions marked by eye)."""
    mask = _coffee_mask()
    h, w = mask.shape
    table = np.zeros((h, w), bool)
    table[:, 505:] = table[392:, :] = table[:, :66] = table[:51, :151] = True
    assert (mask & table).sum() < 0.002 * table.sum()
    inner = _ellipse((h, w), (280, 215), (160, 130))  # cup and saucer
    assert (mask & inner).sum() > 0.99 * inner.sum()


def test_real_photo_unknown_object_generic_reconstruction(tmp_path: Path) -> None:
    """Nothing named: thickness from the distance transform; the mesh seen from the camera is the photo's mask."""
    path = tmp_path / "IMG_0042.png"
    cv2.imwrite(str(path), cv2.cvtColor(data.coffee(), cv2.COLOR_RGB2BGR))
    mesh, info, *_, checks = run(AssetRequest(image_path=path, size_hint_m=0.15), _fast())
    assert checks.passed, checks.failed
    assert info.photo is not None and info.photo.method in ("medial-axis inflation", "lathe")
    assert info.entry is None and info.segmentation.startswith("grabcut+saliency")
    mask = _coffee_mask()
    assert silhouette.silhouette_iou(mesh["vertices"], mesh["faces"], info.photo, mask) >= 0.85
    # the visible side carries the photo: reddish-brown crockery, not grey and not the table's dark brown
    fwd = np.asarray(info.photo.camera_forward)
    m = pipeline.arrays_to_mesh(mesh)
    front = m.vertex_normals @ fwd < -0.7
    photo_mean = data.coffee()[mask].mean(axis=0)
    assert np.abs(mesh["colors"][front, :3].mean(axis=0) - photo_mean).max() < 30


def test_real_photo_named_disc_is_fitted_from_above(tmp_path: Path) -> None:
    """'a tortilla': the program's disc fits the saucer's oblique ellipse from the top, per-axis scaled."""
    path = tmp_path / "coffee.png"
    cv2.imwrite(str(path), cv2.cvtColor(data.coffee(), cv2.COLOR_RGB2BGR))
    s = settings().model_copy(update={"marching_cubes_resolution": 48})
    arrays, info = sources.build_mesh(AssetRequest(image_path=path, text="a tortilla 20 cm across"), s)
    photo = info.photo
    assert photo is not None and photo.method == "program fit" and photo.view == "top"
    assert photo.fit_iou >= 0.85  # the program alone, before it is conformed to the mask
    assert silhouette.silhouette_iou(arrays["vertices"], arrays["faces"], photo, _coffee_mask()) >= 0.85
    m = pipeline.arrays_to_mesh(arrays)
    assert m.is_watertight and m.is_winding_consistent


def _cat_photo(tmp_path: Path) -> tuple[Path, np.ndarray, np.ndarray, np.ndarray]:
    """The catalogue cat rendered from the side by the reference renderer (an independent path), stretched 15 %
    in length, textured orange and put into the cluttered room with a door frame and a shadow."""
    cat = mesh_program(catalogue.program_for("plush_cat"), 48)
    side = render_view(cat, "side", 300)
    sil = (side < 250).any(axis=2).astype(np.uint8)
    sil = cv2.resize(sil, (int(300 * 1.15), 300), interpolation=cv2.INTER_NEAREST)
    ys, xs = np.nonzero(sil)
    sil = sil[ys.min() : ys.max() + 1, xs.min() : xs.max() + 1]
    obj = np.zeros((480, 640), bool)
    y0, x0 = 420 - sil.shape[0], 150
    obj[y0 : y0 + sil.shape[0], x0 : x0 + sil.shape[1]] = sil.astype(bool)
    right = x0 + sil.shape[1]
    img, door, sh = _stage(_room(1, obj), obj, (230.0, 130.0, 40.0), right - 2, ((right - 60, 425), (150, 18)), 1)
    path = tmp_path / "plush_cat.png"
    cv2.imwrite(str(path), cv2.cvtColor(img, cv2.COLOR_RGB2BGR))
    return path, obj, door, sh


def test_named_object_is_fitted_to_the_silhouette(tmp_path: Path) -> None:
    """The file name names the cat: its program is fitted (side view, stretched length), the photo's orange is on the
    visible side and the hidden side takes the visible parts' colours, not the catalogue's."""
    path, obj, door, sh = _cat_photo(tmp_path)
    mesh, info, *_, checks = run(AssetRequest(image_path=path, size_hint_m=0.3), _fast())
    assert checks.passed, checks.failed
    photo = info.photo
    assert photo is not None and photo.method == "program fit" and info.entry == "plush_cat"
    assert photo.view == "side" and photo.fit_iou >= 0.85
    assert any("file name" in n for n in info.notes)
    mask, _ = image.segment(image.load_image(path))
    assert _iou(mask, obj) > 0.93 and (mask & door).sum() < 0.02 * door.sum()
    assert silhouette.silhouette_iou(mesh["vertices"], mesh["faces"], photo, mask) >= 0.9
    m = pipeline.arrays_to_mesh(mesh)
    fwd = np.asarray(photo.camera_forward)
    facing = m.vertex_normals @ fwd
    col = mesh["colors"][:, :3].astype(float)
    front, back = col[facing < -0.7], col[facing > 0.7]
    orange = np.array([230.0, 130.0, 40.0])
    assert np.abs(front.mean(axis=0) - orange).max() < 35
    assert np.abs(back.mean(axis=0) - orange).max() < 45  # a plausible back: the cat's own colour
    assert np.percentile(np.abs(back - back.mean(axis=0)).max(axis=1), 90) < 60  # no smeared stripes


@pytest.mark.parametrize("shape", ["vase", "dumbbell"])
def test_generic_reconstruction_has_round_cross_sections(tmp_path: Path, shape: str) -> None:
    """A mirror-symmetric silhouette is lathed; an asymmetric one gets round cross-sections per part (a bar stays a
    bar next to a ball, where inflating to a barrel gives both one thickness)."""
    h, w = 300, 400
    m = np.zeros((h, w), np.uint8)
    if shape == "vase":
        cv2.ellipse(m, (200, 190), (80, 90), 0, 0, 360, 1, -1)
        cv2.rectangle(m, (170, 40), (230, 190), 1, -1)
    else:
        cv2.circle(m, (110, 150), 70, 1, -1)
        cv2.rectangle(m, (110, 135), (330, 165), 1, -1)
        cv2.circle(m, (330, 150), 25, 1, -1)
    rgba = np.zeros((h, w, 4), np.uint8)
    rgba[..., 1] = 180
    rgba[..., 3] = m * 255
    path = tmp_path / f"{shape}_outline.png"  # 'vase.png' names a rigid object, refused (#35)
    cv2.imwrite(str(path), rgba)
    s = settings().model_copy(update={"marching_cubes_resolution": 64})
    arrays, info = sources.build_mesh(AssetRequest(image_path=path, size_hint_m=0.4), s)
    again, _ = sources.build_mesh(AssetRequest(image_path=path, size_hint_m=0.4), s)
    assert all(np.array_equal(arrays[k], again[k]) for k in arrays)  # deterministic (seeded medial-axis ties)
    v = arrays["vertices"]
    x, d = v @ np.asarray(info.photo.camera_right), v @ np.asarray(info.photo.camera_forward)
    if shape == "vase":
        assert info.photo.method == "lathe"
        assert np.ptp(d) == pytest.approx(np.ptp(x), rel=0.06)  # as deep as wide: a solid of revolution
    else:
        assert info.photo.method == "medial-axis inflation"
        cols = m.nonzero()[1]
        px_m = np.ptp(x) / (np.ptp(cols) + 1)  # metres per photo pixel
        u = (x - x.min()) / px_m + cols.min()  # photo column of each vertex

        def depth_px(col: float) -> float:
            return float(np.ptp(d[np.abs(u - col) < 4]) / px_m)

        assert depth_px(110) == pytest.approx(140, rel=0.12)  # the ball: as deep as its 140 px diameter
        assert depth_px(230) == pytest.approx(30, rel=0.35)  # the bar: as deep as its 30 px width
    mesh = pipeline.arrays_to_mesh(arrays)
    assert mesh.is_watertight and mesh.is_winding_consistent


# -- #35: photos keep their upright; revolution or inflation; size and mass from the concept; rigid objects refused --
PHOTOS = Path(__file__).parent / "photos"


def _manifest() -> list[dict]:
    path = PHOTOS / "manifest.json"
    return json.loads(path.read_text(encoding="utf-8")) if path.is_file() else []


def _scene(tmp_path: Path, name: str, file_name: str | None = None) -> Path:
    return photo_scenes.write_scene(name, tmp_path / (file_name or f"{name}.png"))


def _base_radius(v: np.ndarray) -> float:
    """Half the widest extent of the vertices within 1 % of the height above the ground [m]."""
    low = v[v[:, 2] < 0.01 * np.ptp(v[:, 2])]
    return 0.5 * float(np.ptp(low[:, 0]))


def test_standing_bottle_is_a_solid_of_revolution_kept_upright(tmp_path: Path) -> None:
    """No resting-pose step: the photo's vertical is up, the bottle stands on a flat base as wide as its body (a
    'bottle' the lexicon has no template for: a lathe of its silhouette)."""
    path = _scene(tmp_path, "squeeze_bottle", "bottle.png")
    s = _fast().model_copy(update={"marching_cubes_resolution": 64})
    arrays, info = sources.build_mesh(AssetRequest(image_path=path, size_hint_m=0.25), s)
    photo = info.photo
    assert photo is not None and photo.method == "lathe" and photo.view == "front" and not info.reoriented
    assert np.allclose(photo.camera_up, (0, 0, 1), atol=1e-6)
    v = arrays["vertices"]
    ext = np.ptp(v, axis=0)
    assert ext[2] == pytest.approx(0.25, rel=1e-3) and ext[0] == pytest.approx(ext[1], rel=0.05)
    assert ext[0] / ext[2] == pytest.approx(160 / 630, rel=0.1)  # the drawn body's width / height
    assert _base_radius(v) > 0.8 * ext[0] / 2  # a flat base, not the rounded bottom the photo's ellipse gives
    mask = image.segment(image.load_image(path))[0]
    assert silhouette.silhouette_iou(v, arrays["faces"], photo, mask) >= 0.9
    m = pipeline.arrays_to_mesh(arrays)
    assert m.is_watertight and m.is_winding_consistent


def test_a_named_squeeze_bottle_photo_is_fitted_by_its_template_upright(tmp_path: Path) -> None:
    """A photo named as a squeeze bottle: the lexicon's bottle (body, shoulder, neck, cap) fitted to the silhouette,
    standing as in the photo."""
    path = _scene(tmp_path, "squeeze_bottle")
    arrays, info = sources.build_mesh(AssetRequest(image_path=path, size_hint_m=0.25), _fast())
    photo = info.photo
    assert photo is not None and photo.method == "program fit" and photo.entry == "squeeze_bottle"
    assert photo.fit_iou is not None and photo.fit_iou >= 0.85 and not info.reoriented
    assert np.ptp(arrays["vertices"][:, 2]) == pytest.approx(0.25, rel=1e-3)  # standing: its height is the size


def test_pose_stable_is_asked_for(tmp_path: Path) -> None:
    """--pose stable: the most stable resting pose (a tall narrow bottle lies down)."""
    path = _scene(tmp_path, "squeeze_bottle")
    arrays, info = sources.build_mesh(AssetRequest(image_path=path, size_hint_m=0.25, pose="stable"), _fast())
    assert info.reoriented and np.ptp(arrays["vertices"][:, 2]) < 0.5 * 0.25
    assert AssetRequest(text="x").canonical_json() == AssetRequest(text="x", pose="upright").canonical_json()


def test_frontal_figure_is_inflated_with_limbs_front_view_and_a_warned_size(tmp_path: Path) -> None:
    """Nothing named (a camera's file name): a closed inflation, deeper in the body than in the ears, recorded as a
    front view, standing on the ground; no size and no object: a default size with a warning, never silently."""
    path = _scene(tmp_path, "teddy_bear", "IMG_0001.png")
    arrays, info = sources.build_mesh(AssetRequest(image_path=path), _fast())
    photo = info.photo
    assert photo is not None and photo.method == "medial-axis inflation" and photo.view == "front"
    assert any("no size given" in w and "assuming" in w for w in info.warnings)
    v = arrays["vertices"]
    right, fwd = np.asarray(photo.camera_right), np.asarray(photo.camera_forward)
    x, d, z = v @ right, v @ fwd, v[:, 2]
    body = np.ptp(d[(np.abs(x - np.median(x)) < 0.02 * np.ptp(z)) & (np.abs(z - 0.4 * np.ptp(z)) < 0.03 * np.ptp(z))])
    ear = np.ptp(d[z > 0.9 * np.ptp(z)])
    assert body > 2.0 * ear  # limbs keep their own thickness: not one lump
    mask = image.segment(image.load_image(path))[0]
    assert silhouette.silhouette_iou(v, arrays["faces"], photo, mask) >= 0.9
    m = pipeline.arrays_to_mesh(arrays)
    assert m.is_watertight and m.is_winding_consistent and m.volume > 0


def test_named_photo_takes_the_concept_size_and_mass(tmp_path: Path) -> None:
    """'teddy_bear.png' with no size: the lexicon's typical size, the concept (and its typical mass) recorded."""
    path = _scene(tmp_path, "teddy_bear")
    arrays, info = sources.build_mesh(AssetRequest(image_path=path), _fast())
    c = info.concept
    assert c is not None and c.concept == "teddy_bear" and c.typical_size_m is not None
    assert np.ptp(arrays["vertices"], axis=0).max() == pytest.approx(c.typical_size_m, rel=1e-3)
    assert c.typical_mass_range_kg is not None and c.typical_mass_kg is not None
    assert c.typical_mass_range_kg[0] < c.typical_mass_kg < c.typical_mass_range_kg[1]
    assert not any("assuming" in w for w in info.warnings)
    assert info.photo is not None and info.photo.view == "front"  # the teddy faces the camera


@pytest.mark.parametrize(("text", "file_name"), [("a teacup", "photo.png"), (None, "soda_can.png"),
                                                 ("a figurine of a cat", "IMG_7.png"), (None, "glass_vase.png")])
def test_photo_of_a_rigid_object_is_refused_in_one_line(tmp_path: Path, text: str | None, file_name: str) -> None:
    path = _scene(tmp_path, "ball", file_name)
    request = AssetRequest(image_path=path, text=text)
    with pytest.raises(InputError, match="rigid") as exc:
        targets_from_request(request)  # the CLI's check, before any layer
    assert "\n" not in str(exc.value)
    with pytest.raises(InputError, match="rigid"):
        sources.build_mesh(request, _fast())


@pytest.mark.parametrize("text", ["a plush mug", "a foam can cooler", "a squeezable plastic bottle", "a drink bottle", "a silicone cup",
                                  "a ball that can bounce", "a hot water bottle", "a pot holder", "a plastic cup",
                                  "a stress ball shaped like a can", "a bean bag chair", "a teddy bear"])
def test_soft_words_keep_rigid_nouns_allowed(text: str) -> None:
    targets_from_intent(text)


@pytest.mark.parametrize("text", ["a can", "a soda can, 12 cm tall", "a can of beans", "a teacup on a saucer",
                                  "a ceramic mug", "a mug", "a figurine", "a glass bottle", "a spray bottle",
                                  "a wooden chair"])
def test_text_naming_a_rigid_object_is_refused(text: str) -> None:
    with pytest.raises(InputError, match="rigid"):
        targets_from_intent(text)


def test_soft_material_with_a_rigid_file_name_is_allowed(tmp_path: Path) -> None:
    path = _scene(tmp_path, "plastic_cup", "mug.png")
    targets_from_request(AssetRequest(image_path=path, text="a plush toy"))


def test_large_photo_is_reduced_as_it_is_read(tmp_path: Path) -> None:
    """A 12-megapixel phone JPEG (landscape pixels, EXIF orientation 6 = portrait) is decoded reduced and upright,
    and L0 builds from it. (How long it takes beside the small photo is a figure of `benchmarks/photo_bench.py
    --large`, not of a timed test.)"""
    from PIL import Image

    small = _scene(tmp_path, "teddy_bear", "IMG_small.png")
    rgb = photo_scenes.scene_image("teddy_bear", 4032, 3024)  # portrait content
    big = tmp_path / "IMG_big.jpg"
    im = Image.fromarray(np.ascontiguousarray(np.rot90(rgb, 1)))  # stored landscape, as a phone does
    exif = im.getexif()
    exif[0x0112] = 6  # rotate 90 degrees clockwise to display
    im.save(big, quality=90, exif=exif)
    loaded = image.load_image(big)
    assert loaded.shape == (1024, 768, 3)
    truth = cv2.resize(photo_scenes.scene_mask("teddy_bear").astype(np.uint8), (768, 1024)).astype(bool)
    assert _iou(image.segment(loaded)[0], truth) > 0.9  # upright, not on its side
    s = _fast()
    small_mesh, _ = sources.build_mesh(AssetRequest(image_path=small, size_hint_m=0.3), s)
    big_mesh, _ = sources.build_mesh(AssetRequest(image_path=big, size_hint_m=0.3), s)
    # the same teddy at the same size from either photo (the big one is read at the small one's scale)
    extent = [np.ptp(m["vertices"], axis=0) for m in (small_mesh, big_mesh)]
    assert np.allclose(np.sort(extent[1]), np.sort(extent[0]), rtol=0.1), extent


_SOFT = [r for r in _manifest() if r["soft"]]
_RIGID = [r for r in _manifest() if not r["soft"]]
# building a mesh from every soft photo is a sweep (~50 s of one core): the default run builds every fourth, the slow
# run all of them
_SOFT_SAMPLE = {r["file"] for r in _SOFT[::4]}


@pytest.mark.skipif(not _SOFT, reason="no photos in tests/geometry/photos")
@pytest.mark.parametrize("row", [pytest.param(r, id=r["file"], marks=() if r["file"] in _SOFT_SAMPLE else
                                              (pytest.mark.slow,)) for r in _SOFT])
def test_real_photo_of_a_soft_object_matches_its_mask_upright(row: dict, monkeypatch: pytest.MonkeyPatch) -> None:
    """Real photographs (tests/geometry/photos/manifest.json): the mesh seen from the estimated camera is the photo's
    mask (IoU >= 0.85), the photo's up is the mesh's up, its size is stated or the concept's (no silent default)."""
    path = PHOTOS / row["file"]
    segment, (shared, shared_method) = image.segment, _photo_segment(row["file"])

    def segmented_once(img: np.ndarray, seed: int = 0) -> tuple[np.ndarray, str]:
        """image.segment (deterministic): this photo's from _photo_segment, which the mask test below reads too."""
        if seed == 0 and np.array_equal(img, image.load_image(path)):
            return shared.copy(), shared_method
        return segment(img, seed)

    monkeypatch.setattr(sources.image_mod, "segment", segmented_once)
    request = AssetRequest(image_path=path, text=f"a {row['object']}", size_hint_m=row.get("size_m"))
    targets_from_request(request)
    # the draft contract's resolution (64), not _fast's 40: the two cherries hang on stems thinner than a voxel at 40
    # and the mesh keeps one of them (IoU 0.41; 0.94 at 64)
    arrays, info = sources.build_mesh(request, _fast().model_copy(update={"marching_cubes_resolution": 64}))
    photo = info.photo
    assert photo is not None and np.allclose(photo.camera_up, (0, 0, 1), atol=1e-6) and not info.reoriented
    mask = _photo_segment(row["file"])[0]
    assert silhouette.silhouette_iou(arrays["vertices"], arrays["faces"], photo, mask) >= 0.85
    assert pipeline.arrays_to_mesh(arrays).is_watertight
    assert info.concept is not None and info.concept.fallback_level != "generic" or \
        any("no size given" in w for w in info.warnings)


@pytest.mark.skipif(not _RIGID, reason="no photos in tests/geometry/photos")
@pytest.mark.parametrize("row", _RIGID, ids=lambda r: r["file"])
def test_real_photo_of_a_rigid_object_is_refused(row: dict) -> None:
    with pytest.raises(InputError, match="rigid"):
        targets_from_request(AssetRequest(image_path=PHOTOS / row["file"], text=f"a {row['object']}"))


# -- #35 item 5: the mask is the whole object and only it (rough hand labels, tests/geometry/photos/masks.json) --
def _labels() -> dict:
    path = PHOTOS / "masks.json"
    return json.loads(path.read_text(encoding="utf-8")) if path.is_file() else {}


# known failures of the current segmentation (benchmarks/segmentation_sheet.py --labels shows each); strict, so a fix
# that makes one pass must remove it from here
_MASK_KNOWN_BAD = {
    "basketball_depthanything.jpg": "a ball behind the hoop's net: the rim and net strands in front of it are taken "
                                    "with the ball (IoU 0.73)",
}


def _mask_case(row: dict) -> object:
    reason = _MASK_KNOWN_BAD.get(row["file"])
    marks = [pytest.mark.xfail(reason=reason, strict=True)] if reason else []
    return pytest.param(row, id=row["file"], marks=marks)


@pytest.mark.skipif(not _SOFT, reason="no photos in tests/geometry/photos")
@pytest.mark.parametrize("row", [_mask_case(r) for r in _SOFT])
def test_real_photo_mask_is_the_whole_object(row: dict) -> None:
    """Each soft photo's mask against a rough hand label of the object (IoU >= 0.8); a photo with transparency is
    segmented by its own alpha."""
    from benchmarks.segmentation_sheet import label_mask

    mask, method = _photo_segment(row["file"])
    shapes = _labels().get(row["file"])
    if shapes is None:
        assert method == "alpha", f"{row['file']}: no hand label in masks.json and no alpha"
        return
    label = label_mask(shapes, mask.shape)
    assert _iou(mask, label) >= 0.8, f"{row['file']}: mask IoU {_iou(mask, label):.3f} with the hand label"
