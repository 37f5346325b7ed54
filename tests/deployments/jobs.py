"""Cheap batch jobs for tests: real child processes, no layer work. The request text picks the behaviour."""

from __future__ import annotations

import json
import os
import signal
import time
from pathlib import Path
from typing import Any

from contracts.errors import StageFailure
from contracts.request import AssetRequest


def quick_job(request: AssetRequest, out_dir: Path, device: str) -> dict[str, Any]:
    """'sleep N' sleeps; 'crash' dies by SIGKILL; 'stage-fail' raises StageFailure; else publishes a marker asset."""
    text = request.text or ""
    if text.startswith("sleep"):
        time.sleep(float(text.split()[1]))
    if text == "crash":
        os.kill(os.getpid(), signal.SIGKILL)
    if text == "stage-fail":
        raise StageFailure("L2", "no material passed the gates")
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "asset.json").write_text(json.dumps({"request": request.model_dump(mode="json")}), encoding="utf-8")
    return {"asset_dir": str(out_dir)}
