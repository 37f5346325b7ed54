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
    """'sleep N' sleeps; 'crash' dies by SIGKILL; 'stage-fail' raises StageFailure; 'print' prints a line; else
    publishes a marker asset naming the process that ran it."""
    text = request.text or ""
    if text.startswith("sleep"):
        time.sleep(float(text.split()[1]))
    if text == "crash":
        os.kill(os.getpid(), signal.SIGKILL)
    if text == "stage-fail":
        raise StageFailure("L2", "no material passed the gates")
    if text.startswith("print"):
        print(f"output of {text}", flush=True)
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "asset.json").write_text(json.dumps({"request": request.model_dump(mode="json"), "pid": os.getpid()}),
                                        encoding="utf-8")
    return {"asset_dir": str(out_dir)}


RUNS_ENV = "DEFORMSMITH_TEST_RUNS"  # a file each timed_job run appends its request's text to


def timed_job(request: AssetRequest, out_dir: Path, device: str) -> dict[str, Any]:
    """quick_job's behaviours, and a publish that looks like generate's to the throughput benchmark: the run noted in
    $DEFORMSMITH_TEST_RUNS, asset.json with the request, the GPU it was pinned to and L3's verdict ('no-l3' in the
    text: none), 1000 bytes of payload, and generate's per-stage wall times in the summary. 'stubborn' in the text:
    SIGINT is ignored (a request slow to unwind when its batch stops it: SIGKILL ends it)."""
    text = request.text or ""
    if "stubborn" in text:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    runs = os.environ.get(RUNS_ENV)
    if runs:
        with open(runs, "a", encoding="utf-8") as fh:
            fh.write(text + "\n")
    if text == "stage-fail":
        raise StageFailure("L2", "no material passed the gates")
    t0 = time.perf_counter()
    if text.startswith("sleep"):
        time.sleep(float(text.split()[1]))
    out_dir.mkdir(parents=True, exist_ok=True)
    validation = [] if "no-l3" in text else [{"stage": "L3", "passed": "l3-fails" not in text}]
    (out_dir / "asset.json").write_text(json.dumps({
        "request": request.model_dump(mode="json"), "validation": validation,
        "gpu": os.environ.get("CUDA_VISIBLE_DEVICES")}), encoding="utf-8")
    (out_dir / "payload.bin").write_bytes(b"x" * 1000)
    return {"asset_dir": str(out_dir), "wall_time_s": {"L0": 0.01, "L2": time.perf_counter() - t0}}
