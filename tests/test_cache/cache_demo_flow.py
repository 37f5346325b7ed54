"""A three-stage demonstration flow for the cache proofs (test code, not product code).

Each stage appends its name to the file in $DEMO_COUNTER when it executes, so executions can be counted across
processes. $DEMO_PAUSE_FILE makes the middle stage touch that file and sleep (for the SIGKILL test).
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np
from pydantic import BaseModel, ConfigDict

from cache import cached_task, local_runtime
from prefect import flow


class DemoSummary(BaseModel):
    """Stage-3 output: a pydantic model, to check it comes back as its own class."""

    model_config = ConfigDict(frozen=True)
    n: int
    stiffness: float
    mean_z_m: float
    energy_j: float


def _count(stage: str) -> None:
    path = os.environ.get("DEMO_COUNTER")
    if path:
        fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        try:
            os.write(fd, f"{stage}\n".encode())
        finally:
            os.close(fd)


def executions(path: Path) -> list[str]:
    """Stage names recorded in a counter file, in order."""
    return path.read_text().split() if path.exists() else []


@cached_task(version="1", name="demo.sample")
def sample(n: int, seed: int) -> np.ndarray:
    """Stage 1: particle positions (n, 3) float32."""
    _count("sample")
    return np.random.default_rng(seed).random((n, 3), dtype=np.float32)


@cached_task(version="1", name="demo.deform")
def deform(points: np.ndarray, stiffness: float) -> dict:
    """Stage 2 (the middle stage): a sag that depends on stiffness; pausable for the kill test."""
    _count("deform")
    pause = os.environ.get("DEMO_PAUSE_FILE")
    if pause:
        Path(pause).write_text(str(os.getpid()))
        time.sleep(120)
    sag = (points[:, 0] * (1 - points[:, 0]) / stiffness).astype(np.float32)
    moved = points.copy()
    moved[:, 2] -= sag
    return {"positions": moved, "sag_max_m": float(sag.max()), "shape": tuple(moved.shape)}


@cached_task(version="1", name="demo.summarize")
def summarize(state: dict, stiffness: float) -> DemoSummary:
    """Stage 3: a summary model."""
    _count("summarize")
    pos = state["positions"]
    return DemoSummary(n=int(pos.shape[0]), stiffness=stiffness, mean_z_m=float(pos[:, 2].mean()),
                       energy_j=float(0.5 * stiffness * state["sag_max_m"] ** 2))


@flow(name="demo-three-stage")
def demo_flow(n: int = 2000, seed: int = 0, stiffness: float = 10.0) -> DemoSummary:
    """sample -> deform(stiffness) -> summarize."""
    pts = sample(n, seed)
    state = deform(pts, stiffness)
    return summarize(state, stiffness)


def run(n: int = 2000, seed: int = 0, stiffness: float = 10.0) -> DemoSummary:
    """Run the flow locally (no heartbeat)."""
    with local_runtime():
        return demo_flow(n=n, seed=seed, stiffness=stiffness)


def cli(argv: list[str] | None = None) -> None:
    """Subprocess entry: `stiffness` [n]; prints the summary JSON."""
    args = argv if argv is not None else sys.argv[1:]
    out = run(n=int(args[1]) if len(args) > 1 else 2000, stiffness=float(args[0]))
    print("RESULT " + out.model_dump_json())
