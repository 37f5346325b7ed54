"""Rerun recordings: one `.rrd` per probe with fixed entity paths and timelines."""

from tasks.record.rerun_recording import (
    COLLIDERS,
    GAUSSIANS,
    HARNESS_LOG,
    METRICS,
    PARTICLES,
    ProbeRecording,
    RecordingSummary,
    read_recording,
    recording_digest,
)

__all__ = ["COLLIDERS", "GAUSSIANS", "HARNESS_LOG", "METRICS", "PARTICLES", "ProbeRecording", "RecordingSummary", "read_recording", "recording_digest"]
