"""The particle frames of interaction data as 16-bit fixed point: within the stated error, deterministic, decodable from
the stored attributes alone, and small enough that the default asset's interaction/ stays within 30 MB."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import zarr

from tasks.manipulation import particle_frames as pf
from tasks.manipulation.data import interaction_dir, read_attempt, write_attempt

BUDGET_BYTES = 30e6  # interaction/ of the default asset (the draft plush turtle) ...
ATTEMPTS = 4  # ... which stores four attempts
OTHER_ARRAYS_BYTES = 0.9e6  # per attempt, the arrays other than the particle frames (0.87 MB on disk for the turtle)


def turtle_like(frames: int = 69, particles: int = 5054, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Particle frames shaped like the draft turtle's trial (69 frames of 5054 particles in a 24 x 17 x 8 cm body): a
    lift-and-carry path, a 0.5 rad turn, a 5 % squeeze, and per-frame noise (0.1 mm, 1e-3 in F) at least as rough as
    the simulation's (whose particle frames encode to 4.8 MB, these to ~5.1 MB)."""
    rng = np.random.default_rng(seed)
    rest = rng.uniform(-1.0, 1.0, (particles, 3)) * (0.12, 0.085, 0.04)
    t = np.linspace(0.0, 1.0, frames)
    c, s = np.cos(0.5 * t), np.sin(0.5 * t)
    rot = np.zeros((frames, 3, 3))
    rot[:, 0, 0], rot[:, 0, 1], rot[:, 1, 0], rot[:, 1, 1], rot[:, 2, 2] = c, -s, s, c, 1.0
    f = rot @ (np.eye(3) - 0.05 * np.sin(np.pi * t)[:, None, None] * np.diag([0.0, 1.0, 0.0]))
    path = np.stack([0.2 * t, 0.1 * t, 0.04 + 0.1 * np.sin(np.pi * t)], axis=1)
    x = (path[:, None] + rest @ f.transpose(0, 2, 1)).astype(np.float32)
    x += 1e-4 * rng.standard_normal((frames, particles, 3), dtype=np.float32)
    noise = 1e-3 * rng.standard_normal((frames, particles, 3, 3), dtype=np.float32)
    return x, f[:, None].astype(np.float32) + noise


def stored_bytes(path: Path) -> int:
    return sum(p.stat().st_size for p in path.rglob("*") if p.is_file())


def test_the_default_asset_interaction_data_fits_the_budget(tmp_path: Path) -> None:
    x, f = turtle_like()
    write_attempt(tmp_path / "a", {"particles_x_m": x, "particles_F": f}, {})
    frames = stored_bytes(interaction_dir(tmp_path / "a") / "attempt_000")
    assert frames < (x.nbytes + f.nbytes) / 3  # float32 as before: 16.7 MB (zstd made the turtle's 14.6 MB)
    assert ATTEMPTS * (frames + OTHER_ARRAYS_BYTES) <= BUDGET_BYTES
    back, _ = read_attempt(tmp_path / "a", 0)
    # positions within 4 um (the turtle's 6.7 mm particle spacing / 1700), deformation gradients within 1e-4
    assert np.abs(back["particles_x_m"].astype(np.float64) - x).max() <= 4e-6
    assert np.abs(back["particles_F"].astype(np.float64) - f).max() <= 1e-4


def small_attempt(seed: int = 1) -> dict[str, np.ndarray]:
    x, f = turtle_like(frames=7, particles=300, seed=seed)
    return {"frame_t_s": np.arange(7) / 30.0, "frame_control_index": np.arange(7) * 8, "particles_x_m": x,
            "particles_F": f, "rest_particles_m": x[0].astype(np.float64), "phase": np.arange(7, dtype=np.int8)}


def test_the_particle_frames_round_trip_within_half_a_step_and_the_rest_exactly(tmp_path: Path) -> None:
    arrays = small_attempt()
    write_attempt(tmp_path, arrays, {"labels": {"lifted": 1.0}})
    back, attrs = read_attempt(tmp_path, 0)
    assert attrs["labels"] == {"lifted": 1.0} and set(back) == set(arrays)
    for name in ("frame_t_s", "frame_control_index", "rest_particles_m", "phase"):  # same frames, same times
        assert back[name].dtype == np.asarray(arrays[name]).dtype and np.array_equal(back[name], arrays[name])
    for name in (pf.X, pf.F):
        got, want = back[name], arrays[name]
        assert got.dtype == np.float32 and got.shape == want.shape
        bound = pf.max_error(name, pf.encode(name, want), want)
        err = np.abs(got.astype(np.float64) - want).max()
        assert 0.0 < err <= bound and bound < (4e-6 if name == pf.X else 2e-5)


def test_decoding_is_deterministic_and_needs_only_the_stored_attributes(tmp_path: Path) -> None:
    arrays = small_attempt()
    write_attempt(tmp_path / "a", arrays, {})
    write_attempt(tmp_path / "b", arrays, {})
    a, b = (interaction_dir(tmp_path / d) / "attempt_000" for d in "ab")
    files = sorted(p.relative_to(a) for p in a.rglob("*") if p.is_file())
    assert files and all((a / p).read_bytes() == (b / p).read_bytes() for p in files)  # the same bytes stored
    one, two = read_attempt(tmp_path / "a", 0)[0], read_attempt(tmp_path / "b", 0)[0]
    assert all(one[k].tobytes() == two[k].tobytes() for k in one)
    # a plain zarr reader decodes with the formula in the attributes, to the same bits
    g = zarr.open_group(str(a), mode="r")
    q, center = g[pf.X_OFFSET], np.asarray(g[pf.X_CENTER][...])
    assert q.dtype == np.int16 and pf.X not in g
    x = (center[:, None, :] + np.asarray(q[...], np.float64) * q.attrs["step_m"]).astype(np.float32)
    assert x.tobytes() == one[pf.X].tobytes()
    fq = g[pf.F_OFFSET]
    f = (np.eye(3) + np.asarray(fq[...], np.float64) * fq.attrs["step"]).astype(np.float32)
    assert f.tobytes() == one[pf.F].tobytes()


def test_frames_with_a_non_finite_value_and_older_attempts_are_stored_and_read_unchanged(tmp_path: Path) -> None:
    arrays = small_attempt()
    arrays["particles_x_m"][3, 5, 1] = np.nan  # a trial that blew up
    arrays["particles_F"][6, 0, 0, 0] = 1e6
    write_attempt(tmp_path, arrays, {})
    g = zarr.open_group(str(interaction_dir(tmp_path) / "attempt_000"), mode="r")
    assert g[pf.X].dtype == np.float32 and g[pf.F].dtype == np.float32 and pf.X_OFFSET not in g
    back = read_attempt(tmp_path, 0)[0]
    assert np.array_equal(back[pf.X], arrays[pf.X], equal_nan=True) and np.array_equal(back[pf.F], arrays[pf.F])
    # an attempt written before the encoding (float32 frames, zarr's default codecs) reads as it was written
    old = interaction_dir(tmp_path / "old") / "attempt_000"
    og = zarr.open_group(str(old), mode="w")
    og.create_array(pf.X, data=arrays[pf.X])
    assert np.array_equal(read_attempt(tmp_path / "old", 0)[0][pf.X], arrays[pf.X], equal_nan=True)


def test_an_attempts_rest_gaussians_are_stored_at_the_plys_precision(tmp_path: Path) -> None:
    """The rest Gaussians an attempt is drawn with are float32 (as gaussians.ply holds them), half of float64's bytes:
    60k covariances were 2.6 MB of a 21 MB asset."""
    rng = np.random.default_rng(3)
    a = rng.standard_normal((2000, 3, 3)) * 1e-3
    g = {"gaussian_positions_m": rng.uniform(-0.1, 0.1, (2000, 3)), "gaussian_covariances_m2": a @ a.transpose(0, 2, 1),
         "gaussian_colors": rng.uniform(0, 1, (2000, 3))}
    write_attempt(tmp_path / "a", {**small_attempt(), **g}, {})
    stored = zarr.open_group(str(interaction_dir(tmp_path / "a") / "attempt_000"), mode="r")
    back, _ = read_attempt(tmp_path / "a", 0)
    for name, want in g.items():
        assert stored[name].dtype == np.float32
        assert np.allclose(back[name], want, rtol=1e-6, atol=1e-12), name
    assert stored["rest_particles_m"].dtype == np.float64  # the physics' arrays keep theirs
