"""What an asset keeps of L3's trials (#38 item 5: assets a fleet can store).

Every trial's metrics stay in manipulation.json. Its states (interaction/attempt_NNN, ~6-8 MB a trial) and its Rerun
recording (recordings/L3_trial_NN.rrd, ~4-6 MB) stay in the asset only for the trial the asset reports (the adopted
one, else the best failed one: the trial the card, the pick-and-place video and `deformsmith replay` show) unless
`--record all` asks for every trial's. The others are already in the content-addressed cache (each attempt folder is a
cache entry, tasks.manipulation.context.store_attempt_keyed; each recording a file under the cache's recordings/):
their rows say so (`kept_in: "cache"`) and name the entry (`data_key`) and the recording (`recording_in_cache`), and
`deformsmith replay DIR --trial N` reads such a trial from the cache. A trial whose entry the cache does not hold
stays in the asset. The reported trial's particle frames beyond KEPT_FRAMES_BYTES are thinned in time (every s-th
frame, its row's frame_stride; tasks.manipulation.data.thin_frames) when the cache holds them all: a large object's
states (a cat bed: 122 MB) no longer make the asset; `deformsmith replay` reads the full-rate trial from the cache.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

from cache import cache_resolve
from contracts.asset_dir import DEFAULT_KEEP, KEEP_TRIALS, KeepTrials, attempt_path
from contracts.errors import InputError
from contracts.manipulation import ManipulationRecord, TrialRow
from tasks.manipulation.data import INTERACTION, attempt_indices, cached_attempt_folder, thin_frames
from tasks.record.trials import data_location, reported_attempt

_TRIAL_RECORDING = re.compile(r"^L3_trial_\d+\.rrd$")
KEPT_FRAMES_BYTES = 3 * 2**20  # the reported trial's particle frames in a default asset: every s-th frame beyond it
# (a cat bed's frames were 122 MB of a 143 MB asset; 4 MB left it at 25.8 MB with 5.5 MB of frames after compression)


def _in_cache(row: TrialRow) -> bool:
    """The trial's interaction data is an intact entry of the cache (checked by key, digests included)."""
    return cached_attempt_folder(row.data_key) is not None


def keep_trials(asset_dir: Path, record: ManipulationRecord, keep: KeepTrials = DEFAULT_KEEP) -> ManipulationRecord:
    """The record after the asset keeps `keep` of its trials: 'all' changes nothing; 'adopted' removes every other
    trial's interaction folder and recording from the asset, once the cache is seen to hold its data (its row then
    says kept_in 'cache'), and folders or trial recordings no row names (an earlier L3 run's)."""
    if keep not in KEEP_TRIALS:
        raise InputError(f"--record must be one of {', '.join(KEEP_TRIALS)}, got '{keep}'")
    if keep == "all":
        return record
    asset_dir = Path(asset_dir)
    kept = reported_attempt(record)
    rows: list[TrialRow] = []
    for row in record.attempts:
        if row.attempt == kept and row.attempt is not None and row.kept_in == "asset" and _in_cache(row) \
                and (asset_dir / attempt_path(row.attempt)).is_dir():  # the reported trial, within the budget
            stride = thin_frames(asset_dir, row.attempt, KEPT_FRAMES_BYTES)
            rows.append(row.model_copy(update={"frame_stride": stride}) if stride > 1 else row)
            continue
        if row.attempt is None or row.attempt == kept or row.kept_in == "cache" or not _in_cache(row):
            rows.append(row)  # the reported trial, a plan that stored nothing, or data the cache lacks: as it is
            continue
        shutil.rmtree(asset_dir / attempt_path(row.attempt), ignore_errors=True)
        if row.recording:
            (asset_dir / row.recording).unlink(missing_ok=True)
        cached_rrd = row.recording_in_cache if row.recording_in_cache and cache_resolve(
            row.recording_in_cache).is_file() else None
        rows.append(row.model_copy(update={"kept_in": "cache", "recording": None, "recording_in_cache": cached_rrd}))
    named = {r.attempt for r in rows if r.attempt is not None and r.kept_in == "asset"}
    for n in attempt_indices(asset_dir):  # an earlier run's folders (a `manipulate` rerun): no row names them
        if n not in named:
            shutil.rmtree(asset_dir / INTERACTION / f"attempt_{n:03d}", ignore_errors=True)
    recordings = [r.recording for r in rows if r.recording and r.kept_in == "asset"]
    rec_dir = asset_dir / "recordings"
    if rec_dir.is_dir():
        for p in rec_dir.iterdir():
            if _TRIAL_RECORDING.match(p.name) and f"recordings/{p.name}" not in recordings:
                p.unlink(missing_ok=True)
    return record.model_copy(update={"attempts": rows, "recordings": recordings})


__all__ = ["DEFAULT_KEEP", "KEEP_TRIALS", "KeepTrials", "data_location", "keep_trials", "reported_attempt"]
