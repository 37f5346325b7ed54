"""Open a recording per probe with an explicit id, log on fixed entity paths, close the file correctly.

Entity-path conventions (viewers and tests rely on them):
  world/object/particles     Points3D, positions [m]
  world/object/gaussians     GaussianSplats3D, centres [m], scales = std-devs [m]
  world/colliders/<name>     Boxes3D / Capsules3D / Mesh3D of a kinematic collider, poses [m]
  metrics/<name_with_unit>   Scalars over sim time
  harness/log                TextLog of the harness's decisions
Timelines: `frame` (sequence) and `sim_time` (duration, seconds).
"""

from __future__ import annotations

import os
import weakref
from dataclasses import dataclass, field
from pathlib import Path
from types import TracebackType
from typing import BinaryIO

import numpy as np
import rerun as rr

PARTICLES = "world/object/particles"
GAUSSIANS = "world/object/gaussians"
COLLIDERS = "world/colliders"
METRICS = "metrics"
HARNESS_LOG = "harness/log"
APP_ID = "deformsmith"
# Rerun's batcher flushes every 200 ms by default: a probe that simulates slower than that writes one chunk per row
# (a 1.7 MB L2 compression recording of 631 chunks). Flushing only when a recording closes (or past 64 MiB) writes a
# few large chunks: the same rows (recording_digest is unchanged) in about half the bytes (#38 item 5).
FLUSH_TICK_S = 24 * 3600.0
FLUSH_BYTES = 64 * 2**20


def _owned(values: np.ndarray, dtype: type) -> np.ndarray:
    """A private copy: Rerun serialises logged arrays later, in the background, so a view of live simulator
    memory (Warp's CPU .numpy() is zero-copy) would be recorded with whatever values it holds by then."""
    return np.array(values, dtype=dtype, copy=True)


def _rgba_u8(colors: np.ndarray | None) -> np.ndarray | None:
    """Colours in [0, 1] floats (N,3|4) or uint8 -> uint8 RGBA-compatible array."""
    if colors is None:
        return None
    c = np.array(colors, copy=True)
    if c.dtype != np.uint8:
        c = np.clip(np.rint(c * 255.0), 0, 255).astype(np.uint8)
    return c


def _remove(path: Path) -> None:
    """Remove a temporary if it is there (a folder that never held it is no error)."""
    try:
        path.unlink()
    except OSError:
        pass


def _write_bytes(fh: BinaryIO, data: bytes) -> None:
    """Write the encoded recording (one place a test can make the disk full)."""
    fh.write(data)


class ProbeRecording:
    """Context manager writing one `.rrd`; the file appears (atomically) only when the block ends cleanly.

    Rerun encodes the recording in memory (a binary stream: a few MB per probe) and this class writes it to
    `<name>.rrd.<pid>.tmp`, then renames it. Rerun's own file writer is not used: on a full disk its thread dies and
    every later flush, disconnect or garbage collection of the stream waits for it forever. A write that fails
    (a full disk, a folder that cannot be written) raises an OSError naming the `.rrd` and leaves no file behind; a
    recording never closed (its rollout raised) has its temporary removed when it is collected."""

    def __init__(self, path: str | os.PathLike[str], recording_id: str, app_id: str = APP_ID) -> None:
        self.path = Path(path)
        self.recording_id = recording_id
        self._tmp = self.path.with_name(self.path.name + f".{os.getpid()}.tmp")
        self._cleanup = weakref.finalize(self, _remove, self._tmp)
        self.rec = rr.RecordingStream(app_id, recording_id=recording_id, batcher_config=rr.ChunkBatcherConfig(
            flush_tick=FLUSH_TICK_S, flush_num_bytes=FLUSH_BYTES))
        self._stream: rr.BinaryStream | None = None
        self._fh: BinaryIO | None = None
        self._time: tuple[int, float] = (0, 0.0)
        # metrics/<name> rows kept until the recording closes, then sent as one column each: one native call per
        # scalar (3 per rollout interval) was ~0.3 ms, ~10 s of a cold generate's CPU; the rows are the same
        self._scalars: dict[str, tuple[list[int], list[float], list[float]]] = {}

    def _failed(self, exc: OSError) -> OSError:
        """A write's OSError naming the recording (its temporary removed)."""
        if self._fh is not None:
            try:
                self._fh.close()  # (flushing what is buffered may meet the full disk again)
            except OSError:
                pass
        _remove(self._tmp)
        return OSError(exc.errno, exc.strerror, str(self.path))

    def __enter__(self) -> ProbeRecording:
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._fh = open(self._tmp, "wb")  # noqa: SIM115 -- closed in __exit__; made now: an unusable folder fails first
        except OSError as exc:
            raise self._failed(exc) from None
        self._stream = self.rec.binary_stream()
        self.set_time(0, 0.0)
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> None:
        assert self._stream is not None and self._fh is not None, "ProbeRecording used outside its `with` block"
        if exc_type is None:
            self._send_scalars()
        data = self._stream.read(flush=True) or b""
        self.rec.disconnect()
        if exc_type is not None:
            self._failed(OSError())
            return
        try:
            _write_bytes(self._fh, data)
            self._fh.close()
            os.replace(self._tmp, self.path)
        except OSError as err:
            raise self._failed(err) from None
        self._cleanup.detach()

    def set_time(self, frame: int, sim_time_s: float) -> None:
        """Move both timelines: frame index and simulated time [s]."""
        self.rec.set_time("frame", sequence=int(frame))
        self.rec.set_time("sim_time", duration=float(sim_time_s))
        self._time = (int(frame), float(sim_time_s))

    def set_sim_time(self, sim_time_s: float) -> None:
        """Move the simulated time alone [s] (the frame stays): curves sampled between recorded frames."""
        self.rec.set_time("sim_time", duration=float(sim_time_s))
        self._time = (self._time[0], float(sim_time_s))

    def _send_scalars(self) -> None:
        """The kept scalars, one column per metric on both timelines (the rows `rec.log` would have written)."""
        for name, (frames, times, values) in self._scalars.items():
            rr.send_columns(f"{METRICS}/{name}", indexes=[rr.TimeColumn("frame", sequence=frames),
                                                          rr.TimeColumn("sim_time", duration=times)],
                            columns=rr.Scalars.columns(scalars=np.asarray(values, np.float64)), recording=self.rec)
        self._scalars.clear()

    def particles(self, positions_m: np.ndarray, colors: np.ndarray | None = None, radius_m: float | None = None) -> None:
        """Log particle positions [m]."""
        self.rec.log(PARTICLES, rr.Points3D(_owned(positions_m, np.float32), colors=_rgba_u8(colors), radii=radius_m))

    def gaussians(
        self, centers_m: np.ndarray, scales_m: np.ndarray, quaternions_xyzw: np.ndarray, colors: np.ndarray | None = None
    ) -> None:
        """Log Gaussian splats: centres [m], std-dev scales [m], rotations as xyzw quaternions."""
        self.rec.log(
            GAUSSIANS,
            rr.GaussianSplats3D(
                _owned(centers_m, np.float32),
                scales=_owned(scales_m, np.float32),
                quaternions=_owned(quaternions_xyzw, np.float32),
                colors=_rgba_u8(colors),
            ),
        )

    def box_collider(self, name: str, center_m: np.ndarray, half_size_m: np.ndarray, quaternion_xyzw: np.ndarray | None = None) -> None:
        """Log a box collider pose."""
        q = None if quaternion_xyzw is None else rr.Quaternion(xyzw=_owned(quaternion_xyzw, np.float32))
        self.rec.log(
            f"{COLLIDERS}/{name}",
            rr.Boxes3D(centers=[_owned(center_m, np.float32)], half_sizes=[_owned(half_size_m, np.float32)],
                       quaternions=None if q is None else [q]),
        )

    def mesh_collider(self, name: str, vertices_m: np.ndarray, faces: np.ndarray, color: np.ndarray | None = None) -> None:
        """Log a collider or robot link as a triangle mesh (vertices already posed, [m])."""
        self.rec.log(
            f"{COLLIDERS}/{name}",
            rr.Mesh3D(vertex_positions=_owned(vertices_m, np.float32), triangle_indices=_owned(faces, np.uint32),
                      albedo_factor=None if color is None else _rgba_u8(np.asarray(color))),
        )

    def scalar(self, name: str, value: float) -> None:
        """Log one scalar under metrics/<name> at the current time (put the unit in the name, e.g.
        'kinetic_energy_j'); written when the recording closes."""
        frames, times, values = self._scalars.setdefault(name, ([], [], []))
        frames.append(self._time[0])
        times.append(self._time[1])
        values.append(float(value))

    def log(self, message: str, level: str = "INFO") -> None:
        """Append a line to the harness log."""
        self.rec.log(HARNESS_LOG, rr.TextLog(message, level=level))


@dataclass
class RecordingSummary:
    """What a `.rrd` holds: recording ids, entity paths and timelines."""

    recording_ids: list[str] = field(default_factory=list)
    entity_paths: set[str] = field(default_factory=set)
    timelines: set[str] = field(default_factory=set)
    rows_per_entity: dict[str, int] = field(default_factory=dict)


def read_recording(path: str | os.PathLike[str]) -> RecordingSummary:
    """Read a `.rrd` back with rerun's RrdReader and summarise it."""
    from rerun.chunk import RrdReader

    reader = RrdReader(str(path))
    summary = RecordingSummary(recording_ids=[e.recording_id for e in reader.recordings()])
    for chunk in reader.stream():
        entity = str(chunk.entity_path)
        if entity.startswith("/__") or "__properties" in entity:
            continue
        summary.entity_paths.add(entity.lstrip("/"))
        summary.timelines.update(chunk.timeline_names)
        summary.rows_per_entity[entity.lstrip("/")] = summary.rows_per_entity.get(entity.lstrip("/"), 0) + chunk.num_rows
    return summary


_RUN_SPECIFIC_COLUMNS = ("rerun.controls.RowId", "log_time", "log_tick")


def _plain(column):
    """Time columns as integer nanoseconds (pyarrow cannot turn nanosecond durations into Python objects)."""
    import pyarrow as pa

    if pa.types.is_duration(column.type) or pa.types.is_timestamp(column.type):
        return column.cast(pa.int64())
    return column


def recording_digest(path: str | os.PathLike[str]) -> str:
    """Digest of what a `.rrd` shows: every row's entity, timelines and data, without the ids and wall-clock times
    that Rerun stamps on each write (so two recordings of the same run compare equal; chunking is irrelevant)."""
    import hashlib

    from rerun.chunk import RrdReader

    rows: list[str] = []
    for chunk in RrdReader(str(path)).stream():
        entity = str(chunk.entity_path)
        if entity.startswith("/__"):
            continue
        batch = chunk.to_record_batch()
        names = [n for n in batch.schema.names if n not in _RUN_SPECIFIC_COLUMNS]
        columns = {n: _plain(batch.column(n)).to_pylist() for n in names}
        for i in range(batch.num_rows):
            row = repr((entity, [(n, columns[n][i]) for n in names]))
            rows.append(hashlib.sha256(row.encode()).hexdigest())
    return hashlib.sha256("".join(sorted(rows)).encode()).hexdigest()
