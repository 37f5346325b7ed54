"""`deformsmith bench l2`'s driver (benchmarks.l2_schedule): what the command imports, and the intent it defaults to."""

from __future__ import annotations

import inspect
import json
from pathlib import Path

from benchmarks.l2_schedule import physical_intent, run_l2_bench


def test_the_default_intent_is_the_one_l1_ran_with(tmp_path: Path) -> None:
    """No physical.json: no intent; else the intent L1 recorded."""
    assert physical_intent(tmp_path) is None
    (tmp_path / "physical.json").write_text(json.dumps({"intent": "a soft foam"}), encoding="utf-8")
    assert physical_intent(tmp_path) == "a soft foam"


def test_the_command_calls_the_driver_with_its_options_in_order() -> None:
    """flows/cli's `bench l2` passes (asset, intent, schedules, probes, device, repeat) positionally."""
    assert list(inspect.signature(run_l2_bench).parameters) == ["asset_dir", "intent", "schedules", "probes", "device",
                                                                  "repeat"]
