"""A drop's track (pixels, image y down) reduced to L2's drop metrics: the floor line, the release and the first
impact, the rebound (apex and velocities), the impact strain, the settle time and the recovery.

The phases: the floor is first the object's bottom in its resting frames; when it never rests in view (it rolls on,
toward the camera or out of the picture) the bottom where its first big fall turns (a ball bouncing toward the camera
lands lower in the picture each time: the lowest bottom of all is not the first impact's floor). A frame is on the
floor when its bottom is within contact_tol_px of it; the first run of such frames is the first impact, and the floor
line then the bottom's lowest in it (for an object that never rests, with the impact between two frames, where the
fall's parabola and the rebound's meet). Heights of the rebound are taken from the touchdown (the
centroid when the bottom, in its flight shape, meets the floor line): rebound = rise / fall, both from there. The fall
before it and the flight after it are fitted with parabolas (free flight: constant acceleration): the fall's vertex
is the release (its time and height, also when the release is out of frame), the flight's vertex the apex; their
slopes where the centroid crosses its touchdown height give the speeds in and out.

Settling: the bouncing is over when the centroid stays within contact_tol_px of a straight line through the last
tracked frames (flat for an object at rest; sloped for a ball that rolls on along the floor, toward or away from the
camera: its rolling is not bouncing); the settle time runs from the release to the first frame of that stay
(settle_time: also applied to the simulated bounces sampled at the video's frames).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from contracts.video_fit import VideoMetrics
from tasks.calibrate.track import Track
from tasks.realworld.physics import G_M_PER_S2

REST_FRAMES = 0.1  # the last 10 % of the tracked frames (at least 5) are the resting frames when the object is still
STILL_PX = 1.0  # a centroid within max(1 px, 1 % of the height) of its final place is still
MIN_FIT_FRAMES = 4  # a parabola needs this many frames of flight


CONTACT_FRACTION = 0.03  # a bottom within 3 % of the height of the floor line is on the floor


def contact_tol_px(height_px: float) -> float:
    """A bottom this close to the floor line is on the floor [px] (at least a pixel row and a half)."""
    return max(1.5, CONTACT_FRACTION * height_px)


def impact_amplitude(t: np.ndarray, strain: np.ndarray) -> float:
    """The compression of an impact: the amplitude A of the half sine A sin(pi (t - t0) / tc) on [t0, t0 + tc] (zero
    elsewhere) that fits the strain samples best (least squares; t0 and tc searched on a grid over the samples' span,
    A solved for each): an impact's compression is close to a half sine, and unlike the largest sample the fit is
    not biased up by noise nor by where the frames fall."""
    span = float(t[-1] - t[0])
    if len(t) < 3 or span <= 0:
        return float(np.max(strain)) if len(t) else math.nan
    step = span / max(len(t) - 1, 1)
    t0s = np.linspace(t[0] - step, t[-1], 48)
    tcs = np.linspace(2.0 * step, span + 2.0 * step, 48)
    best, amp = math.inf, math.nan
    for tc in tcs:
        x = (t[None, :] - t0s[:, None]) / tc
        phi = np.where((x >= 0) & (x <= 1), np.sin(np.pi * np.clip(x, 0, 1)), 0.0)
        den = (phi * phi).sum(axis=1)
        a = np.where(den > 0, (phi * strain[None, :]).sum(axis=1) / np.maximum(den, 1e-300), 0.0)
        sse = ((strain[None, :] - a[:, None] * phi) ** 2).sum(axis=1)
        k = int(np.argmin(sse))
        if sse[k] < best:
            best, amp = float(sse[k]), float(a[k])
    return amp


@dataclass
class Parabola:
    """y(t) = a + b t + c t^2 fitted to flight frames."""

    a: float
    b: float
    c: float
    frames: int

    @classmethod
    def fit(cls, t: np.ndarray, y: np.ndarray) -> Parabola | None:
        """Least squares; None with fewer than MIN_FIT_FRAMES frames or no downward acceleration."""
        if len(t) < MIN_FIT_FRAMES:
            return None
        c, b, a = np.polyfit(t, y, 2)
        return cls(float(a), float(b), float(c), len(t)) if c > 0 else None

    def at(self, t: float) -> float:
        return self.a + self.b * t + self.c * t * t

    def slope(self, t: float) -> float:
        return self.b + 2.0 * self.c * t

    @property
    def vertex_t(self) -> float:
        return -self.b / (2.0 * self.c)

    def crossing(self, y: float, later: bool) -> float | None:
        """The time y(t) = y (the later or the earlier root), None if it never gets there."""
        disc = self.b * self.b - 4.0 * self.c * (self.a - y)
        if disc < 0:
            return None
        r = math.sqrt(disc)
        return (-self.b + r) / (2.0 * self.c) if later else (-self.b - r) / (2.0 * self.c)


@dataclass
class DropAnalysis:
    """The phases of the drop in pixels and seconds (see the module docstring); None where the video does not show
    it, with the reason in `why`."""

    floor_y: float
    resting: bool
    rest_cy: float
    rest_height: float | None
    flight_height: float | None
    flight_offset: float  # bottom - centroid in flight [px]
    longest_extent: float  # in the resting frames, else the flight frames [px]
    extent_frames: str
    contact: tuple[int, int] | None = None  # first and last track row of the first impact
    impact_t: float | None = None
    fall: Parabola | None = None
    flight: Parabola | None = None
    release_t: float | None = None
    release_cy: float | None = None
    apex_cy: float | None = None
    left_floor: bool = False
    strain: float | None = None
    strain_noise: float | None = None
    min_height: float | None = None
    settle_t: float | None = None
    settle_tol_px: float | None = None
    bounces: list[dict[str, float]] = field(default_factory=list)
    why: dict[str, str] = field(default_factory=dict)

    impact_frames: int = 0  # frames of the first impact with the bottom on the floor line

    @property
    def drop_px(self) -> float | None:
        """The bottom's fall from release to the floor [px]."""
        return None if self.release_cy is None else self.floor_y - (self.release_cy + self.flight_offset)

    @property
    def rebound_ratio(self) -> float | None:
        if self.release_cy is None:
            return None
        if not self.left_floor:
            return 0.0 if self.contact is not None else None
        if self.apex_cy is None:
            return None
        y_td = self.touchdown_cy
        return max(0.0, y_td - self.apex_cy) / (y_td - self.release_cy)

    @property
    def touchdown_cy(self) -> float:
        """The centroid's image y when the bottom meets the floor line in its flight shape [px]."""
        return self.floor_y - self.flight_offset

    @property
    def restitution(self) -> float | None:
        if self.fall is None or self.flight is None:
            return None
        y_td = self.touchdown_cy
        t_in, t_out = self.fall.crossing(y_td, later=True), self.flight.crossing(y_td, later=False)
        if t_in is None or t_out is None:
            return None
        return abs(self.flight.slope(t_out)) / abs(self.fall.slope(t_in))


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """[first, last] index of each run of True."""
    out, start = [], None
    for i, v in enumerate(mask):
        if v and start is None:
            start = i
        if not v and start is not None:
            out.append((start, i - 1))
            start = None
    if start is not None:
        out.append((start, len(mask) - 1))
    return out


def first_impact(tr: Track, floor: float | None, height: float, runs: list[tuple[int, int]]
                 ) -> tuple[int, int] | None:
    """The track rows [first, last] of the first impact: the first run of frames on the floor, or sooner the first
    reversal of a fall of at least half the height that turns near the floor (a fast impact between two frames
    shows no frame on the floor: then that one frame; floor None: anywhere); None when the object never comes down."""
    on = runs[0] if runs else None
    start = 0
    for i in range(1, len(tr.cy) - 1):
        if on is not None and i >= on[0]:
            break
        if tr.cy[i] < tr.cy[start]:
            start = i  # the highest point so far: the fall is measured from there
        falling, rises_next = tr.cy[i] > tr.cy[i - 1], tr.cy[i + 1] < tr.cy[i]
        near = floor is None or tr.bottom[i] >= floor - 0.5 * height
        if falling and rises_next and tr.cy[i] - tr.cy[start] > 0.5 * height and near:
            return i, i
    return on


def settle_time(t: np.ndarray, y: np.ndarray, release_t: float, tol_px: float, tail: int) -> float | None:
    """From `release_t` to the first of the frames from which on the centroid `y` stays within `tol_px` of the
    straight line through the last `tail` frames (see the module docstring); None when even those stray from it
    (still bouncing at the end) or no frame after the release strays (nothing to settle)."""
    tail = min(tail, len(t))
    if tail < 3:
        return None
    b, a = np.polyfit(t[-tail:], y[-tail:], 1)
    off = np.abs(y - (a + b * t)) > tol_px
    if off[-tail:].any():
        return None
    moving = np.flatnonzero(off & (t >= release_t))
    if not len(moving) or moving[-1] + 1 >= len(t):
        return None
    return float(t[moving[-1] + 1] - release_t)


def still_frames(tr: Track, rows: int) -> np.ndarray:
    """The track rows of the `rows` frames where the centroid moves least (the least motion blur)."""
    return still_frames_of(tr.t_s, tr.cy, rows)


def still_frames_of(t: np.ndarray, y: np.ndarray, rows: int) -> np.ndarray:
    """Indices of the `rows` samples where y(t) changes least."""
    speed = np.abs(np.gradient(y, t)) if len(t) > 1 else np.zeros(len(t))
    return np.argsort(speed, kind="stable")[:max(1, rows)]


def analyse(tr: Track) -> DropAnalysis:
    """The phases of the drop (see the module docstring)."""
    n = len(tr.t_s)
    k = max(5, int(REST_FRAMES * n))
    last_cy = tr.cy[-k:]
    h_est = float(np.median(tr.box_height))
    resting = bool(np.ptp(last_cy) <= max(STILL_PX, 0.01 * h_est) * 2.0 and tr.index[-1] == tr.last_frame)
    tol = contact_tol_px(h_est)
    if resting:
        floor = float(np.median(tr.bottom[-k:]))
    else:  # the floor where the first big fall turns (see the module docstring), else the lowest bottom
        turn = first_impact(tr, None, h_est, [])
        floor = float(tr.bottom[turn[0]]) if turn is not None else float(np.max(tr.bottom))
    on_floor = tr.bottom >= floor - tol
    runs = _runs(on_floor)
    why: dict[str, str] = {}
    offset = float(np.median(tr.bottom - tr.cy))
    rest_cy = float(np.median(last_cy)) if resting else floor - offset
    extent_rows = np.arange(n - k, n) if resting else still_frames(tr, max(3, n // 4))
    longest = float(np.median(np.maximum(tr.box_width, tr.box_height)[extent_rows]))
    d = DropAnalysis(floor, resting, rest_cy, float(np.median(tr.moment_height[-k:])) if resting else None, None,
                     offset, longest, "resting" if resting else "stillest quarter of the tracked", why=why)
    first = first_impact(tr, floor, h_est, runs)
    if first is None or first[0] == 0:
        why["rebound_ratio"] = why["impact_strain"] = ("the video shows no fall onto the floor" if first is None else
                                                       "the object is on the floor in the first tracked frame")
        return d
    c0, c1 = first
    d.contact = (c0, c1)
    d.floor_y = max(floor, float(np.max(tr.bottom[c0:c1 + 1])))  # the floor line: the bottom's lowest at the impact
    d.impact_t = float(tr.t_s[c0])
    d.impact_frames = int(np.count_nonzero(tr.bottom[c0:c1 + 1] >= floor - tol))
    # the fall: the frames before the first impact that move down, back to where the motion starts
    j = c0 - 1
    while j > 0 and tr.cy[j] - tr.cy[j - 1] > 0.05 and tr.consecutive(j):
        j -= 1
    fall_rows = np.arange(j, c0)
    fall_rows = fall_rows[tr.bottom[fall_rows] < floor - tol]
    d.fall = Parabola.fit(tr.t_s[fall_rows], tr.cy[fall_rows])
    if len(fall_rows):
        flight_h = tr.moment_height[fall_rows]
        d.flight_height = float(np.median(flight_h))
        d.flight_offset = float(np.median((tr.bottom - tr.cy)[fall_rows]))
        d.strain_noise = 3.0 * float(np.std(flight_h)) / d.flight_height if len(fall_rows) > 2 else None
    if d.fall is not None:
        d.release_t = max(d.fall.vertex_t, float(tr.t_s[0]) - 1.0)
        d.release_cy = d.fall.at(d.release_t)
    elif len(fall_rows):
        d.release_t, d.release_cy = float(tr.t_s[fall_rows[0]]), float(tr.cy[fall_rows[0]])
        why["restitution_from_velocities"] = "too few frames of the fall for a parabola"
    else:
        why["rebound_ratio"] = "the fall before the first impact is not in the video"
    if not resting and d.release_t is not None:  # the extent in free frames: not held in a hand, least blurred
        free = np.flatnonzero(tr.t_s >= d.release_t)
        if len(free) >= 3:
            sub = free[still_frames_of(tr.t_s[free], tr.cy[free], max(3, len(free) // 4))]
            d.longest_extent = float(np.median(np.maximum(tr.box_width, tr.box_height)[sub]))
            d.extent_frames = "stillest quarter of the post-release"
    # the flight after the first impact
    after = next((r[0] for r in runs if r[0] > c1), n)
    end = c1 + 1  # the flight ends where the centroid, having risen and fallen, stops falling (the next impact)
    while end + 1 < after and tr.cy[end + 1] < tr.cy[end]:
        end += 1
    while end + 1 < after and tr.cy[end + 1] >= tr.cy[end]:
        end += 1
    flight_rows = np.arange(c1 + 1, min(after, end + 1))
    flight_rows = flight_rows[tr.bottom[flight_rows] < floor - tol]
    d.left_floor = len(flight_rows) > 0
    if d.left_floor:
        d.flight = Parabola.fit(tr.t_s[flight_rows], tr.cy[flight_rows])
        top = int(flight_rows[np.argmin(tr.cy[flight_rows])])
        apex_ok = after < n or resting or top != flight_rows[-1]
        if d.flight is not None and flight_rows[0] < top < flight_rows[-1]:
            d.apex_cy = d.flight.at(d.flight.vertex_t)
        elif apex_ok:
            d.apex_cy = float(tr.cy[top])
        else:
            why["rebound_ratio"] = "the apex after the first impact is not in the video"
    # the impact strain: the second-moment height on the floor against the flight height
    if d.flight_height is not None:
        m = max(3, c1 - c0 + 1)  # the impact with as many frames either side (flight: no compression)
        rows = np.arange(max(0, c0 - m), min(n, c1 + 1 + m))
        s = 1.0 - tr.moment_height[rows] / d.flight_height
        d.min_height = float(tr.moment_height[c0:c1 + 1].min())
        strain = impact_amplitude(tr.t_s[rows], s)
        if d.impact_frames < 3:
            why["impact_strain"] = (f"only {d.impact_frames} frame(s) on the floor in the impact: the frame rate is "
                                    "too low to see the compression")
        elif d.strain_noise is not None and strain <= d.strain_noise:
            why["impact_strain"] = (f"the compression ({strain:.3f}) is within the height's noise "
                                    f"({d.strain_noise:.3f})")
        else:
            d.strain = strain
    else:
        why["impact_strain"] = "no flight frames to measure the uncompressed height"
    # an impact between two frames of an object that never rests: the floor line where the two flights meet
    if not resting and d.impact_frames == 0 and d.fall is not None and d.flight is not None:
        meet = _meeting(d.fall, d.flight, float(tr.t_s[c0 - 1]), float(tr.t_s[c1 + 1]) if c1 + 1 < n else d.impact_t)
        if meet is not None and meet + d.flight_offset > d.floor_y:
            d.floor_y = meet + d.flight_offset
    d.bounces = bounce_restitutions(tr, d)
    # settling: from release until the bouncing is over (see the module docstring)
    d.settle_tol_px = tol
    if d.release_t is not None:
        d.settle_t = settle_time(tr.t_s, tr.cy, d.release_t, tol, k)
        if d.settle_t is None:
            why["settle_time_s"] = "the object is still bouncing at the end of the video"
    return d


def bounce_restitutions(tr: Track, d: DropAnalysis, min_frames: int = 4) -> list[dict[str, float]]:
    """The restitution of each impact the video shows, from its timing alone (no scale): an impact is where the
    centroid turns from falling to rising; the flight after impact k lasts T_k, so the speed out is g T_k / 2 and the
    restitution T_k / T_(k-1) (the first impact's: T_1 over twice the fall from the release); a turn after a fall of
    under twice the contact tolerance is jitter. From the first flight shorter than `min_frames` frames on, none (a
    frame's error is too much of it)."""
    if d.contact is None or d.release_t is None or d.impact_t is None:
        return []
    fall_px = 2.0 * contact_tol_px(float(np.median(tr.box_height)))  # a turn after a smaller fall is jitter
    turns = [d.contact[0]]
    for i in range(d.contact[1] + 1, len(tr.cy) - 1):
        if tr.cy[i] >= tr.cy[i - 1] and tr.cy[i] > tr.cy[i + 1] \
                and tr.cy[i] - float(np.min(tr.cy[turns[-1]:i + 1])) > fall_px:
            turns.append(i)
    times = [float(tr.t_s[i]) for i in turns]
    out = []
    before = 2.0 * (times[0] - d.release_t)
    frame = float(np.median(np.diff(tr.t_s))) if len(tr.t_s) > 1 else 1.0 / tr.fps  # repeats left out: wider
    for a, b in zip(times, times[1:]):
        flight = b - a
        if flight < min_frames * frame or before < min_frames * frame:
            break
        out.append({"time_s": a, "speed_in_m_per_s": 0.5 * G_M_PER_S2 * before,
                    "speed_out_m_per_s": 0.5 * G_M_PER_S2 * flight, "restitution": flight / before})
        before = flight
    return out


def _meeting(fall: Parabola, flight: Parabola, t0: float, t1: float) -> float | None:
    """The centroid's image y where the fall's parabola meets the rebound's between t0 and t1 (None: they do not)."""
    c, b, a = fall.c - flight.c, fall.b - flight.b, fall.a - flight.a
    roots = np.roots([c, b, a]) if abs(c) > 1e-12 else (np.array([-a / b]) if abs(b) > 1e-12 else np.array([]))
    real = [float(r.real) for r in np.atleast_1d(roots) if abs(r.imag) < 1e-9 and t0 - 1e-9 <= r.real <= t1 + 1e-9]
    return fall.at(real[0]) if real else None


def video_metrics(d: DropAnalysis, metres_per_px: float) -> VideoMetrics:
    """The analysis in SI units."""
    recovery = None
    if d.rest_height is not None and d.flight_height is not None and d.min_height is not None \
            and d.flight_height - d.min_height > 0 and d.strain is not None:
        recovery = min(1.0, (d.rest_height - d.min_height) / (d.flight_height - d.min_height))
    drop = d.drop_px
    return VideoMetrics(
        release_time_s=d.release_t, first_impact_time_s=d.impact_t,
        drop_height_m=drop * metres_per_px if drop is not None and drop > 0 else None,
        rebound_ratio=d.rebound_ratio, restitution_from_velocities=d.restitution, impact_strain=d.strain,
        impact_frames=d.impact_frames, settle_time_s=d.settle_t,
        settle_tolerance_m=d.settle_tol_px * metres_per_px if d.settle_tol_px is not None else None,
        recovery_ratio=recovery, left_floor=d.left_floor, bounces=d.bounces)


__all__ = ["CONTACT_FRACTION", "DropAnalysis", "Parabola", "analyse", "contact_tol_px", "impact_amplitude", "settle_time",
           "bounce_restitutions", "still_frames", "video_metrics"]
