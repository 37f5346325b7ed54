"""A CUDA graph capture runs with Python's cyclic garbage collector held off: a collection in mid-capture freed a
finished solver's pinned host buffers (cudaFreeHost synchronises with the legacy stream) and the capture failed with
Warp CUDA error 906 ('operation would make the legacy stream depend on a capturing blocking stream', in release_now)
or 901 (two requests of session 40's 1-GPU throughput run, two of the 2-GPU runs before). The failure itself did not
reproduce on demand on an H200 (garbage of device arrays and pinned buffers with the collector's threshold at 1), so
this checks the mechanism on any machine: Warp's capture replaced by a recorder, no automatic collection can start
while the recorded launches run, and the collector is back on afterwards, after a failed launch too."""

from __future__ import annotations

import gc
from types import SimpleNamespace
from typing import Any

import pytest

from tasks.mpm import solver as solver_mod
from tasks.mpm.solver import Solver


class _Capture:
    """Stands in for wp.ScopedCapture: records whether the collector was on while it captured."""

    seen: list[bool] = []
    active = False

    def __init__(self, **_: Any) -> None:
        self.graph = "graph"

    def __enter__(self) -> _Capture:
        _Capture.seen.append(gc.isenabled())
        _Capture.active = True
        return self

    def __exit__(self, *exc: object) -> None:
        _Capture.active = False
        _Capture.seen.append(gc.isenabled())


class _Launch:
    """A recorded launch that allocates (an automatic collection would start here with the threshold at 1)."""

    def __init__(self, fail: bool = False) -> None:
        self.fail = fail
        self.collector_on: list[bool] = []

    def launch(self) -> None:
        self.collector_on.append(gc.isenabled())
        _ = [object() for _ in range(100)]
        if self.fail:
            raise RuntimeError("launch failed")


@pytest.fixture
def recorded_capture(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(solver_mod.wp, "ScopedCapture", _Capture)
    monkeypatch.setattr(solver_mod.wp, "load_module", lambda *a, **k: None)
    _Capture.seen, _Capture.active = [], False


def test_no_collection_can_start_while_a_graph_is_captured(recorded_capture: None) -> None:
    collections: list[int] = []
    callback = lambda phase, info: collections.append(1) if phase == "start" and _Capture.active else None  # noqa: E731
    cmds = [_Launch() for _ in range(5)]
    before = gc.get_threshold()
    gc.callbacks.append(callback)
    try:
        gc.set_threshold(1, 1, 1)
        graph = Solver._capture(SimpleNamespace(device="cuda:0"), cmds)  # type: ignore[arg-type]
    finally:
        gc.callbacks.remove(callback)
        gc.set_threshold(*before)
    assert graph == "graph"
    assert _Capture.seen == [False, False] and not collections  # held off for the whole capture
    assert all(c.collector_on == [False] for c in cmds)
    assert gc.isenabled()


def test_the_collector_is_back_on_after_a_failed_capture(recorded_capture: None) -> None:
    with pytest.raises(RuntimeError, match="launch failed"):
        Solver._capture(SimpleNamespace(device="cuda:0"), [_Launch(), _Launch(fail=True)])  # type: ignore[arg-type]
    assert gc.isenabled()


def test_a_collector_the_caller_turned_off_stays_off(recorded_capture: None) -> None:
    gc.disable()
    try:
        Solver._capture(SimpleNamespace(device="cuda:0"), [_Launch()])  # type: ignore[arg-type]
        assert not gc.isenabled()
    finally:
        gc.enable()
