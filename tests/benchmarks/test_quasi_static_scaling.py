"""`python -m benchmarks.quasi_static_scaling`: its switch turns mass scaling off and back on; a bad --probe is one
clear line, before anything runs."""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner

from benchmarks.quasi_static_scaling import app, unscaled
from tasks.probes import deformable
from tasks.probes.rollout import quasi_static_mass_scale
from tests.l2.helpers import box_body
from tests.l2.test_mass_scaling import RUBBER


def test_unscaled_turns_every_bound_off_and_restores_it() -> None:
    cube = box_body((0.03, 0.03, 0.03), 6, density=1100.0)
    before = (deformable.COMPRESS_QS_PERIOD_S, deformable.STABILITY_QS_PERIOD_S)
    with unscaled():
        assert deformable.compress_qs_period_s(0.015, 0.003) == 0.0
        assert quasi_static_mass_scale(cube, RUBBER, deformable.STABILITY_QS_PERIOD_S) == 1.0
    assert (deformable.COMPRESS_QS_PERIOD_S, deformable.STABILITY_QS_PERIOD_S) == before
    assert quasi_static_mass_scale(cube, RUBBER, deformable.STABILITY_QS_PERIOD_S) > 1.0


def test_an_unknown_probe_is_refused(tmp_path: Path) -> None:
    res = CliRunner().invoke(app, ["--asset", str(tmp_path), "--probe", "drop"])
    assert res.exit_code == 2 and "unknown probe 'drop'" in res.output
