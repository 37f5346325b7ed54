"""Rerun recordings (one `.rrd` per probe with fixed entity paths and timelines) and the stage tallies that `inspect`
and `evidence` print. The recording names load rerun on first use, so reading records stays quick."""

from __future__ import annotations

from typing import Any

from tasks.record.tally import stage_tallies

_RECORDING_NAMES = ("COLLIDERS", "GAUSSIANS", "HARNESS_LOG", "METRICS", "PARTICLES", "ProbeRecording",
                    "RecordingSummary", "read_recording", "recording_digest")

__all__ = ["COLLIDERS", "GAUSSIANS", "HARNESS_LOG", "METRICS", "PARTICLES", "ProbeRecording", "RecordingSummary",
           "read_recording", "recording_digest", "stage_tallies"]


def __getattr__(name: str) -> Any:
    """Import on first use: tasks.record.rerun_recording imports rerun (~1 s), tasks.record.tally does not."""
    if name in _RECORDING_NAMES:
        # lazy: rerun (1.3 s) only for the recording names; the tallies never load it
        from tasks.record import rerun_recording

        return getattr(rerun_recording, name)
    if name == "stage_tallies":
        return stage_tallies
    raise AttributeError(f"module 'tasks.record' has no attribute {name!r}")
