"""The Gaussian splatting renderer against analytic cases: the projected footprint, depth-ordered compositing, a
squeezed specimen whose Gaussians follow the particles' F, determinism, view-dependent colour; tiny images."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from contracts.errors import InputError
from tasks.geometry.gaussians import make_gaussians, rest_covariances
from tasks.render import splats
from tasks.render.camera import Camera
from tasks.render.splats import deform_gaussians, render_gaussians
from tasks.render.studio import FLAT_RGB

BG = np.array(FLAT_RGB)


def _alpha_of_black(img: np.ndarray) -> np.ndarray:
    """Coverage of a black splat over the flat background, from the green channel (H, W)."""
    return 1.0 - img[..., 1].astype(np.float64) / np.round(255.0 * BG[1])


def _projected_cov_px(cam: Camera, mean: np.ndarray, cov: np.ndarray) -> np.ndarray:
    """J W Σ Wᵀ Jᵀ + 0.3 I [px²], written out independently of the kernel."""
    rot, eye, f = cam.frame()
    x, y, z = rot @ (mean - eye)
    jac = np.array([[f / z, 0.0, -f * x / z**2], [0.0, f / z, -f * y / z**2]])
    return jac @ rot @ cov @ rot.T @ jac.T + 0.3 * np.eye(2)


def test_isotropic_gaussian_footprint_matches_its_projected_covariance() -> None:
    cam = Camera((0.0, -1.0, 0.0), (0.0, 0.0, 0.0), 40.0, 128, 128)
    sigma_m = 0.08
    img = render_gaussians(cam, np.zeros((1, 3)), np.eye(3)[None] * sigma_m**2, np.zeros((1, 3)), np.array([0.8]),
                           scene="none")
    alpha = _alpha_of_black(img)
    sigma_px = float(np.sqrt(_projected_cov_px(cam, np.zeros(3), np.eye(3) * sigma_m**2)[0, 0]))
    assert 13.5 < sigma_px < 14.5  # f sigma / z with f = 64 / tan 20°, plus the low-pass
    for profile in (alpha[63:65].mean(axis=0), alpha[:, 63:65].mean(axis=1)):  # through the centre, both ways
        peak = profile.max()
        assert peak == pytest.approx(0.8, abs=0.01)
        above = np.nonzero(profile >= 0.5 * peak)[0]
        lo, hi = above[0], above[-1]  # half-maximum crossings, interpolated linearly
        left = lo - (profile[lo] - 0.5 * peak) / (profile[lo] - profile[lo - 1])
        right = hi + (profile[hi] - 0.5 * peak) / (profile[hi] - profile[hi + 1])
        assert (right - left) == pytest.approx(2.0 * np.sqrt(2.0 * np.log(2.0)) * sigma_px, rel=0.05)


def test_anisotropic_off_axis_footprint_has_the_ewa_covariance() -> None:
    cam = Camera((0.0, -1.0, 0.0), (0.0, 0.0, 0.0), 50.0, 160, 160)
    rot = trimesh.transformations.rotation_matrix(0.6, [0.2, 0.5, 1.0])[:3, :3]
    cov = rot @ np.diag([0.07, 0.03, 0.015]) ** 2 @ rot.T
    mean = np.array([0.12, 0.1, -0.08])
    img = render_gaussians(cam, mean[None], cov[None], np.zeros((1, 3)), np.array([0.9]), scene="none")
    alpha = _alpha_of_black(img)
    ys, xs = np.mgrid[0:160, 0:160] + 0.5
    w = alpha.sum()
    mu = np.array([(alpha * xs).sum(), (alpha * ys).sum()]) / w
    d = np.stack([xs - mu[0], ys - mu[1]])
    measured = np.einsum("iyx,jyx,yx->ij", d, d, alpha) / w
    # a 2-D Gaussian cut at Mahalanobis radius 3 keeps E[r²] = 2 - 9 e^-4.5 / (1 - e^-4.5) of its 2
    cut = (2.0 - 9.0 * np.exp(-4.5) / (1.0 - np.exp(-4.5))) / 2.0
    expected = _projected_cov_px(cam, mean, cov) * cut
    rot_cam, eye, f = cam.frame()
    c = rot_cam @ (mean - eye)
    np.testing.assert_allclose(mu, [f * c[0] / c[2] + 80.0, f * c[1] / c[2] + 80.0], atol=0.1)
    ev_m, ev_e = np.linalg.eigvalsh(measured), np.linalg.eigvalsh(expected)
    np.testing.assert_allclose(np.sqrt(ev_m), np.sqrt(ev_e), rtol=0.05)  # widths along both principal axes
    assert ev_e[1] > 2.0 * ev_e[0]  # the case really is anisotropic


@pytest.mark.parametrize("red_nearer", [True, False])
def test_overlapping_gaussians_composite_in_depth_order(red_nearer: bool) -> None:
    cam = Camera((0.0, -1.0, 0.0), (0.0, 0.0, 0.0), 40.0, 65, 65)  # the centre pixel's centre on the axis
    near, far = np.array([0.0, -0.1, 0.0]), np.array([0.0, 0.1, 0.0])
    means = np.stack([near, far] if red_nearer else [far, near])  # red first in the list either way
    covs = np.broadcast_to(np.eye(3) * 0.05**2, (2, 3, 3))
    img = render_gaussians(cam, means, covs, np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]), np.array([0.9, 0.9]),
                           scene="none")
    r, _, b = img[32, 32].astype(int)
    front, back = (r, b) if red_nearer else (b, r)
    # the front colour with alpha 0.9, the back one with 0.9 of the 0.1 left, the background with 0.01
    assert front == pytest.approx(255 * (0.9 + 0.01 * BG[0]), abs=2)
    assert back == pytest.approx(255 * (0.09 + 0.01 * BG[0]), abs=2)


def _box_specimen() -> tuple[trimesh.Trimesh, np.ndarray, float]:
    """A 8 x 8 x 4 cm box of one flat colour, its particles on a 1 cm lattice."""
    mesh = trimesh.creation.box((0.08, 0.08, 0.04))
    mesh.visual.vertex_colors = np.tile([30, 60, 170, 255], (len(mesh.vertices), 1))
    dx = 0.01
    g = np.arange(-3.5, 4.0) * dx
    gz = np.arange(-1.5, 2.0) * dx
    particles = np.stack(np.meshgrid(g, g, gz, indexing="ij"), axis=-1).reshape(-1, 3)
    return mesh, particles, dx


def _silhouette(img: np.ndarray) -> np.ndarray:
    """Pixels the object covers more than half (red channel against the flat background)."""
    cover = (BG[0] * 255.0 - img[..., 0].astype(np.float64)) / (BG[0] * 255.0 - 30.0)
    return cover > 0.5


def _box_silhouette_px(cam: Camera, half_extent: np.ndarray) -> np.ndarray:
    """The exact silhouette of an axis-aligned box centred at the origin: pixels whose ray hits it."""
    rot, eye, f = cam.frame()
    ys, xs = np.mgrid[0:cam.height, 0:cam.width] + 0.5
    d = ((xs - cam.width / 2) / f)[..., None] * rot[0] + ((ys - cam.height / 2) / f)[..., None] * rot[1] + rot[2]
    with np.errstate(divide="ignore"):
        t0 = (-half_extent - eye) / d
        t1 = (half_extent - eye) / d
    near = np.minimum(t0, t1).max(axis=-1)
    far = np.maximum(t0, t1).min(axis=-1)
    return far >= near


def test_squeezed_specimen_silhouette_follows_the_particles_and_has_no_holes() -> None:
    from scipy.ndimage import binary_erosion

    mesh, particles, dx = _box_specimen()
    g = make_gaussians(mesh, particles, dx, 3000, seed=0, dense=False)  # 3000 large ones: F Σ Fᵀ shows
    cov0 = rest_covariances(g["scales_m"], g["rotations_wxyz"])
    F = np.diag([1.3, 1.3, 0.6])
    moved = particles @ F.T
    x, cov = deform_gaussians(g["positions_m"], cov0, g["particle_index"], g["particle_weight"], particles, moved,
                              np.broadcast_to(F, (len(particles), 3, 3)))
    half0 = np.array([0.04, 0.04, 0.02])
    for eye in ((0.05, -0.35, 0.15), (0.0, -0.001, 0.35)):  # oblique and top
        cam = Camera(eye, (0.0, 0.0, 0.0), 30.0, 96, 96)
        rest = _silhouette(render_gaussians(cam, g["positions_m"], cov0, g["colors"], g["opacities"], scene="none"))
        img = render_gaussians(cam, x, cov, g["colors"], g["opacities"], scene="none")
        squeezed = _silhouette(img)
        box0, box1 = _box_silhouette_px(cam, half0), _box_silhouette_px(cam, half0 * np.diag(F))
        # the box's silhouette and a halo of the Gaussians beyond its faces (a few mm: about 1.5 px round 45 px)
        assert 1.0 < rest.sum() / box0.sum() < 1.35 and 1.0 < squeezed.sum() / box1.sum() < 1.35
        # the area changes as the particles' silhouette does (x 1.2 oblique, x 1.6 from the top)
        assert (squeezed.sum() / rest.sum()) == pytest.approx(box1.sum() / box0.sum(), rel=0.05)
        if eye[2] > 0.3:  # from the top, moved centres with rest-shape Gaussians fall short: F Σ Fᵀ matters
            centres_only = _silhouette(render_gaussians(cam, x, cov0, g["colors"], g["opacities"], scene="none"))
            # (0.97: interior blobs no larger than their depth under the surface leave little halo to hide it)
            assert centres_only.sum() / rest.sum() < 0.97 * box1.sum() / box0.sum()
        inner = binary_erosion(box1, iterations=2)
        assert inner.sum() > 300
        # no holes: inside the silhouette the object's colour everywhere, the background's nowhere
        red = img[..., 0].astype(np.float64)[inner]
        assert np.abs(red - 30.0).max() < 0.25 * (BG[0] * 255.0 - 30.0), red.max()


def _random_cloud(seed: int, n: int, centre: tuple[float, float, float], spread_m: float, size_m: float,
                  floor_m2: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """n random Gaussians (means, covariances, colours, opacities) around centre: a reproducible test scene."""
    rng = np.random.default_rng(seed)
    means = rng.normal(0.0, spread_m, (n, 3)) + np.asarray(centre)
    a = rng.normal(0.0, size_m, (n, 3, 3))
    covs = a @ a.transpose(0, 2, 1) + np.eye(3) * floor_m2
    return means, covs, rng.uniform(0, 1, (n, 3)), rng.uniform(0.2, 1.0, n)


def test_cpu_render_is_deterministic_and_independent_of_the_bands(monkeypatch: pytest.MonkeyPatch) -> None:
    means, covs, colors, opac = _random_cloud(3, 400, (0.0, 0.0, 0.08), 0.05, 0.012, 1e-6)
    cam = Camera((0.3, -0.5, 0.35), (0.0, 0.0, 0.06), 40.0, 80, 60)
    one = render_gaussians(cam, means, covs, colors, opac)
    assert one.shape == (60, 80, 3) and one.dtype == np.uint8
    assert render_gaussians(cam, means, covs, colors, opac).tobytes() == one.tobytes()
    monkeypatch.setattr(splats, "CPU_BANDS", 3)
    assert render_gaussians(cam, means, covs, colors, opac).tobytes() == one.tobytes()


def test_studio_draws_a_table_with_a_shadow_under_the_object() -> None:
    cam = Camera((0.0, -0.4, 0.3), (0.0, 0.0, 0.0), 40.0, 96, 72)
    empty = render_gaussians(cam, np.zeros((0, 3)), np.zeros((0, 3, 3)), np.zeros((0, 3)), np.zeros(0))
    assert np.ptp(empty[:, 48].astype(int).sum(axis=-1)) > 30  # not flat: a lit table fading into the backdrop
    xs = np.linspace(-0.03, 0.03, 7)
    means = np.stack(np.meshgrid(xs, xs, [0.02], indexing="ij"), axis=-1).reshape(-1, 3)  # a slab 2 cm up
    covs = np.broadcast_to(np.diag([0.008, 0.008, 0.008]) ** 2, (len(means), 3, 3))
    black = np.zeros((len(means), 3))  # where it leaves the flat background as it is, it darkens < 0.5 / 255
    img = render_gaussians(cam, means, covs, black, np.ones(len(means)))
    flat = render_gaussians(cam, means, covs, black, np.ones(len(means)), scene="none")
    assert np.all(flat[0, 0] == np.round(BG * 255))
    off_object = np.all(flat == np.round(BG * 255), axis=-1)  # pixels no Gaussian reaches
    diff = img.astype(int).sum(axis=-1) - empty.astype(int).sum(axis=-1)
    assert diff[off_object].max() <= 0 and diff[off_object].min() < -60  # the table darkened round the slab


def test_spherical_harmonics_colour_depends_on_the_view() -> None:
    means, covs = np.zeros((1, 3)), np.eye(3)[None] * 0.05**2
    sh = np.zeros((1, 3, 3))
    sh[0, 2] = [0.6, 0.0, 0.0]  # the term -C1 x of degree 1 (x: from the eye to the Gaussian): red seen from +x
    colors = np.full((1, 3), 0.4)
    seen = []
    for eye in ((-1.0, 0.0, 0.0), (1.0, 0.0, 0.0)):
        cam = Camera(eye, (0.0, 0.0, 0.0), 40.0, 32, 32)
        seen.append(render_gaussians(cam, means, covs, colors, np.ones(1), sh_coeffs=sh, scene="none")[16, 16])
        plain = render_gaussians(cam, means, covs, colors, np.ones(1), sh_coeffs=np.zeros((1, 8, 3)), scene="none")
        assert np.array_equal(plain, render_gaussians(cam, means, covs, colors, np.ones(1), scene="none"))
    assert int(seen[1][0]) - int(seen[0][0]) > 100 and abs(int(seen[0][1]) - int(seen[1][1])) <= 1


def test_bad_inputs_are_refused_in_words() -> None:
    cam = Camera((0.0, -1.0, 0.0), (0.0, 0.0, 0.0), 40.0, 16, 16)
    with pytest.raises(InputError, match="covariances"):
        render_gaussians(cam, np.zeros((2, 3)), np.zeros((1, 3, 3)), np.zeros((2, 3)), np.ones(2))
    with pytest.raises(InputError, match="scene"):
        render_gaussians(cam, np.zeros((1, 3)), np.eye(3)[None], np.zeros((1, 3)), np.ones(1), scene="room")
    with pytest.raises(InputError, match="sh_coeffs"):
        render_gaussians(cam, np.zeros((1, 3)), np.eye(3)[None], np.zeros((1, 3)), np.ones(1),
                         sh_coeffs=np.zeros((1, 4, 3)))


def test_tile_ranges_skip_the_placeholder_keys_past_the_last_tile() -> None:
    import warp as wp

    from tasks.render import splat_kernels as k

    tiles = [0, 0, 2, 3, 3, 3, 4, 4]  # tile 4 of 4: placeholders, sorted last
    keys: wp.array = wp.array(np.array(tiles, np.int64) * 2**32 + 7, dtype=wp.int64, device="cpu")
    start, end = wp.zeros(4, dtype=int, device="cpu"), wp.zeros(4, dtype=int, device="cpu")
    wp.launch(k.tile_ranges, dim=len(tiles), inputs=[keys, len(tiles), 4], outputs=[start, end], device="cpu")
    assert start.numpy().tolist() == [0, 0, 2, 3] and end.numpy().tolist() == [2, 0, 3, 6]


@pytest.mark.parametrize("scene", ["studio", "none", "image"])
def test_drawing_only_the_reached_tiles_gives_every_tiles_picture(scene: str, monkeypatch: pytest.MonkeyPatch
                                                                  ) -> None:
    """A small object in a corner of the frame: on the CPU the pixel kernel runs on the tiles its Gaussians (and in
    the studio, its shadow) reach, the rest showing the background (the empty scene, kept per camera, or the given
    picture) unchanged; the picture is byte for byte the one every tile's drawing gives, at 16- and 8-pixel tiles."""
    import warp as wp

    means, covs, colors, opac = _random_cloud(5, 300, (0.09, 0.0, 0.03), 0.01, 0.004, 1e-7)
    cam = Camera((0.0, -0.6, 0.3), (0.0, 0.0, 0.05), 40.0, 192, 128)
    kw: dict = {"scene": scene}
    if scene == "image":  # a picture with its depth: far, but nearer than the object on the frame's right
        depth = np.full((128, 192), 2.0, np.float32)
        depth[:, 122:] = 0.3
        kw = {"background": (np.random.default_rng(6).integers(0, 256, (128, 192, 3), dtype=np.uint8), depth)}
    drawn: list[int] = []
    launch = wp.launch

    def counting(kernel, dim, *args, **kwargs):  # type: ignore[no-untyped-def]
        if kernel.key == "render_pixels":
            drawn.append(int(dim))
        return launch(kernel, dim, *args, **kwargs)

    monkeypatch.setattr(wp, "launch", counting)
    part = [render_gaussians(cam, means, covs, colors, opac, tile_px=t, **kw) for t in (16, 8)]
    part.append(render_gaussians(cam, means, covs, colors, opac, **kw))  # (the empty scene now kept)
    assert 0 < sum(drawn[:1]) < 0.6 * 192 * 128  # the object's tiles (and its shadow's), not the frame's
    monkeypatch.setattr(splats, "_base", lambda *args: None)  # every tile drawn, as a GPU draws them
    drawn.clear()
    every = render_gaussians(cam, means, covs, colors, opac, **kw)
    assert sum(drawn) >= 192 * 128
    assert all(p.tobytes() == every.tobytes() for p in part)
    assert np.any(every != render_gaussians(cam, means[:0], covs[:0], colors[:0], opac[:0], **kw))
