"""`python -m benchmarks.l3_trial` bundles: the trajectory's closures and splines survive a round trip, also in a
bundle exported when the module was tasks.manipulation.bench_trial."""

from __future__ import annotations

import sys

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from benchmarks import l3_trial
from tasks.robot import trajectory


def _pieces() -> dict[str, object]:
    """An arm path (closure over a scipy spline) and a finger closing (closure over floats), as a Trajectory holds."""
    spline = CubicSpline([0.0, 0.5, 1.0], np.array([[0.0, 0.1], [0.2, 0.3], [0.1, 0.5]]))
    return {"arm": trajectory._path_move(spline, 2.0), "fingers": trajectory._close_fingers(0.08, 0.02, 0.04)}


def _same(a: dict[str, object], b: dict[str, object]) -> None:
    for tau in (0.0, 0.3, 0.77, 1.0):
        for k in ("arm", "fingers"):
            for x, y in zip(a[k](tau), b[k](tau)):  # type: ignore[operator]
                assert np.array_equal(x, y), (k, tau)


def test_bundle_round_trip() -> None:
    """Closures are stored as factory + arguments (no bytecode) and rebuilt to give the same motion."""
    pieces = _pieces()
    data = l3_trial.dump_bundle(pieces)
    assert b"benchmarks.l3_trial" in data
    _same(pieces, l3_trial.load_bundle(data))


def test_bundle_from_the_old_module_path_loads(monkeypatch: pytest.MonkeyPatch) -> None:
    """A bundle naming tasks.manipulation.bench_trial's rebuild functions loads through load_bundle."""
    old = "tasks.manipulation.bench_trial"
    monkeypatch.setitem(sys.modules, old, l3_trial)
    monkeypatch.setattr(l3_trial._rebuild_piece, "__module__", old)
    monkeypatch.setattr(l3_trial._rebuild_ppoly, "__module__", old)
    pieces = _pieces()
    data = l3_trial.dump_bundle(pieces)
    monkeypatch.undo()
    assert old.encode() in data and b"benchmarks.l3_trial" not in data
    _same(pieces, l3_trial.load_bundle(data))
