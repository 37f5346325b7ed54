"""Cross-simulator check and calibration: the search helpers on known responses (fast), L2's measurements on a tet
body, MuJoCo's probes on a small block (fast), and the sponge crosscheck with calibration (slow, real asset)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from tasks.export.calibrate import Knob, fit_both, fit_modulus, fit_rebound
from tasks.export.crosscheck import METRICS, TetKinematics, metric_rows, slice_area_m2
from tests.export.assets import copy_sponge


def test_fit_modulus_secant_converges_in_few_simulations() -> None:
    calls = []

    def measure(e: float) -> float:  # a simulator 30 % too soft and mildly non-linear in E
        calls.append(e)
        return 0.7 * e ** 1.05

    e, m, steps = fit_modulus(measure, 1.0e5, 1.2e5, tol=0.01)
    assert abs(m / 1.2e5 - 1) <= 0.01 and len(calls) <= 3 and len(steps) == len(calls)


def test_fit_modulus_bounds_each_step_when_the_probe_barely_responds() -> None:
    """A probe that hardly moves with E (the rubber ball in Genesis, its heights read off a turning ball: 37.5 kPa
    for a 483 kPa target) must not send E to 1e12 Pa: each trial stays within 4 x of the last, and the closest is kept."""
    from tasks.export.calibrate import MAX_YOUNG_STEP

    tried: list[float] = []

    def measure(e: float) -> float:
        tried.append(e)
        return 37.5e3 * (e / 1.58e6) ** 0.05

    e, m, steps = fit_modulus(measure, 1.58e6, 483e3, first=37.5e3)
    ratios = np.array([tried[0] / 1.58e6] + [b / a for a, b in zip(tried, tried[1:], strict=False)])
    assert len(tried) == 3 and np.all(ratios <= MAX_YOUNG_STEP * (1 + 1e-12)) and max(tried) <= 1.58e6 * 4 ** 3
    assert e == max(tried) and m == pytest.approx(37.5e3 * (e / 1.58e6) ** 0.05)  # the closest to the target


def test_fit_rebound_moves_to_the_second_knob_when_the_first_cannot_reach() -> None:
    """Rebound = f(damping, contact ratio): even undamped the first knob leaves it below the target; the second knob
    (the contact's own damping) must take over."""

    def measure(v: dict[str, float]) -> float:
        return 0.3 * (1 - v["contact"]) / (1 + 100 * v["damping"]) + 0.01

    knobs = [Knob("damping", 1e-3, 1e-6, 1.0), Knob("contact", 1.0, 0.05, 1.0)]
    values, r, steps = fit_rebound(measure, knobs, 0.12, tol=0.05, max_sims=8)
    assert abs(r / 0.12 - 1) <= 0.05 and values["damping"] == pytest.approx(1e-6)
    assert steps[0].measured < 0.12 and len(steps) <= 8


def test_fit_rebound_adds_damping_when_the_simulator_bounces_too_much() -> None:
    def measure(v: dict[str, float]) -> float:
        return 0.6 / (1 + 50 * v["damping"])

    values, r, _ = fit_rebound(measure, [Knob("damping", 1e-3, 1e-6, 1.0)], 0.2, tol=0.05, max_sims=6)
    assert abs(r / 0.2 - 1) <= 0.05 and values["damping"] > 1e-3


def test_fit_rebound_steps_a_costly_knob_by_halvings_before_the_next_knob() -> None:
    """A rubber ball in MuJoCo: its discrete integrator's numerical dissipation leaves too little rebound at the
    exported step (rebound ~ linear in dt, as measured: 0.59 at 0.25 ms, 0.77 at 0.1 ms). The timestep knob comes
    first and moves by halvings (a step 4 x finer costs 4 x the wall time): it must stop at the first halving that
    reaches the target, never try the floor, and leave the damping alone."""
    tried: list[float] = []

    def measure(v: dict[str, float]) -> float:
        tried.append(v["timestep_s"])
        return (0.89 - 1.2e3 * v["timestep_s"]) / (1 + 1e3 * v["damping_s"])

    knobs = [Knob("timestep_s", 2.5e-4, 6.25e-5, 2.5e-4, max_step=2.0), Knob("damping_s", 1e-6, 1e-9, 1e-2)]
    first = measure({"timestep_s": 2.5e-4, "damping_s": 1e-6})
    values, r, steps = fit_rebound(measure, knobs, 0.765, tol=0.05, max_sims=6, first=first)
    assert abs(r / 0.765 - 1) <= 0.05 and values["damping_s"] == 1e-6
    assert min(tried) == pytest.approx(1.25e-4) and len(steps) == 1


def test_fit_both_refits_young_when_the_damping_moves_the_modulus() -> None:
    """A plush toy: the damping that brings its rebound down also stiffens its compression (+30 % here, more than a
    real one): after the rebound fit the modulus must be fitted again, and the rebound kept."""

    def modulus(v: dict[str, float]) -> float:
        return 0.9 * v["young_pa"] * (1 + 0.3 * v["damping_s"] / 1e-2)

    def rebound(v: dict[str, float]) -> float:
        return 0.25 / (1 + (v["damping_s"] / 4e-3) ** 2)

    def knobs(v: dict[str, float]) -> list[Knob]:
        return [Knob("damping_s", v["damping_s"], 1e-6, 4e-2)]

    start = {"young_pa": 1e4, "damping_s": 1e-4}
    one, _ = fit_both(modulus, rebound, knobs, start, 1.3e4, 0.06, rounds=1)
    assert abs(modulus(one) / 1.3e4 - 1) > 0.1  # one pass leaves the modulus off: the case fit_both is for
    values, steps = fit_both(modulus, rebound, knobs, start, 1.3e4, 0.06)
    assert abs(modulus(values) / 1.3e4 - 1) <= 0.1 and abs(rebound(values) / 0.06 - 1) <= 0.1
    assert [s.parameter for s in steps].count("young_pa") >= 2


def test_unrotated_turns_a_body_back_to_its_rest_orientation() -> None:
    """The compression's heights are read along the body's own vertical: a body turned and moved as a whole (a ball
    rolling off after the plate's release) gives its rest heights back."""
    from tasks.export.mujoco_probes import unrotated

    rng = np.random.default_rng(3)
    x0 = rng.normal(size=(40, 3))
    m = rng.uniform(0.5, 2.0, 40)
    a = 1.1
    rot = np.array([[1.0, 0.0, 0.0], [0.0, math.cos(a), -math.sin(a)], [0.0, math.sin(a), math.cos(a)]])
    x = x0 @ rot.T + np.array([0.3, -0.2, 0.5])
    back = unrotated(x, x0, m)
    assert np.allclose(back - back.mean(axis=0), x0 - x0.mean(axis=0), atol=1e-9)
    assert np.allclose(np.ptp(back[:, 2]), np.ptp(x0[:, 2])) and not np.allclose(np.ptp(x[:, 2]), np.ptp(x0[:, 2]))


def test_tet_measures_match_l2_definitions() -> None:
    from tests.export.test_mujoco_export import block_tets

    tet = block_tets()
    kin = TetKinematics(tet.nodes_m, tet.tets, np.ones(len(tet.nodes_m)))
    squashed = tet.nodes_m * np.array([1.0, 1.0, 0.9])
    assert kin.strain_p95(tet.nodes_m) == pytest.approx(0.0, abs=1e-12)
    assert kin.strain_p95(squashed) == pytest.approx(0.1, rel=1e-9)
    assert slice_area_m2(tet.nodes_m, tet.tets, 0.011) == pytest.approx(0.04 * 0.04, rel=1e-9)
    rows = metric_rows({"effective_modulus_pa": 100.0}, {"effective_modulus_pa": 80.0}, {"effective_modulus_pa": 98.0})
    assert set(rows) == set(METRICS) and rows["effective_modulus_pa"].rel_error == pytest.approx(0.2)
    assert rows["effective_modulus_pa"].rel_error_calibrated == pytest.approx(0.02)


def test_mujoco_probes_on_a_block_report_every_metric() -> None:
    """L2's compression and drop in MuJoCo on a 27-node block: every crosscheck metric, finite and plausible (the
    effective modulus of a frictionless prism within a factor 2 of E; a damped block rebounds less than it fell)."""
    pytest.importorskip("mujoco")
    from tasks.export import mujoco as mj
    from tasks.export.mujoco_probes import TetBody, compress, drop
    from tests.export.test_mujoco_export import MATERIAL, block_tets

    tet = block_tets()
    p = mj.flex_params(tet.nodes_m, tet.tets, MATERIAL)
    body = TetBody(tet.nodes_m, tet.tets, MATERIAL.density_kg_per_m3, 0.005, MATERIAL.youngs_modulus_pa)
    c = compress(body, p, 0.1, 0.04 * 0.04)
    d = drop(body, p, 0.25)
    got = {**c, **d}
    for name in METRICS:
        assert math.isfinite(got[name]), name
    assert 0.5e5 < c["effective_modulus_pa"] < 2.0e5 and 0.08 < c["compression_strain"] < 0.13
    assert 0.9 <= c["recovery_ratio"] <= 1.0 and 0.0 <= d["rebound_ratio"] < 1.0


@pytest.mark.slow
def test_sponge_crosscheck_reports_every_metric_and_calibration_reduces_the_residuals(tmp_path: Path) -> None:
    pytest.importorskip("mujoco")
    import shutil

    from flows.crosscheck import crosscheck_asset

    asset = copy_sponge(tmp_path / "sponge")
    shutil.rmtree(asset / "export")
    report = crosscheck_asset(asset, "mujoco", calibrate=True)
    for name, row in report.metrics.items():
        assert row.ours is not None and row.theirs is not None and row.theirs_calibrated is not None, name
    before = max(report.metrics[m].rel_error or 0.0 for m in ("effective_modulus_pa", "rebound_ratio"))
    after = max(report.metrics[m].rel_error_calibrated or 0.0 for m in ("effective_modulus_pa", "rebound_ratio"))
    assert after < before
    assert (asset / "export" / "mujoco" / "sponge_calibrated.xml").is_file() or any(
        (asset / "export" / "mujoco").glob("*_calibrated.xml"))


@pytest.fixture
def grid_sponge(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A copy of the committed sponge meshed by test_export_cmd's stand-in grid mesher (60 nodes)."""
    from tasks.export import inputs as export_inputs
    from tasks.export import registry
    from tests.export.test_export_cmd import grid_tets

    out = copy_sponge(tmp_path / "sponge")
    monkeypatch.setattr(export_inputs, "tetrahedralize", grid_tets)
    monkeypatch.setattr(registry, "MESHER", None, raising=False)
    return out


def test_crosscheck_cli_reports_every_metric_beside_l2(grid_sponge: Path, monkeypatch: pytest.MonkeyPatch,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("mujoco")
    import json

    import sys

    from flows.cli import main as cli_main

    monkeypatch.setattr(sys, "argv", ["deformsmith", "crosscheck", str(grid_sponge), "--sim", "mujoco",
                                      "--no-calibrate"])
    try:
        cli_main.main()
        code = 0
    except SystemExit as exc:
        code = int(exc.code or 0)
    out, err = capsys.readouterr()
    assert code == 0, err
    assert all(name in out for name in METRICS), out  # the table (a result: on stdout): one row each
    report_path = grid_sponge / "export" / "mujoco" / "crosscheck.json"
    report = json.loads(report_path.read_text())
    material = json.loads((grid_sponge / "material.json").read_text())["metrics"]
    assert set(report["metrics"]) == set(METRICS)
    for name, row in report["metrics"].items():
        assert row["ours"] == material[METRICS[name][1]] and math.isfinite(row["theirs"]), name
    assert report["probes"]["strain"] == 0.1 and report["probes"]["height_fraction"] == 0.25
    assert (grid_sponge / "export" / "mujoco" / "kitchen_sponge.xml").is_file()


def test_calibration_runs_each_parameter_set_once_and_records_the_fit(grid_sponge: Path,
                                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    """crosscheck_asset with a stand-in simulator whose damping also stiffens it: the alternating fit must reach
    both of L2's values, never run a probe twice on the same parameters (its rounds re-read them), and report the
    simulations it really ran."""
    import json

    from flows import crosscheck as xc
    from tasks.export.sim_runners import SimRunner
    from tasks.export.calibrate import Knob

    ran: list[tuple[str, tuple]] = []

    def compress(v: dict[str, float]) -> dict[str, float]:
        ran.append(("compress", tuple(sorted(v.items()))))
        return {"effective_modulus_pa": 0.7 * v["young_pa"] * (1 + 20.0 * v["damping_s"]), "recovery_ratio": 1.0}

    def drop(v: dict[str, float]) -> dict[str, float]:
        ran.append(("drop", tuple(sorted(v.items()))))
        return {"rebound_ratio": 0.4 / (1 + (v["damping_s"] / 4e-3) ** 2), "max_impact_strain": 0.02,
                "settle_time_s": 0.2}

    def runner(*_: object) -> SimRunner:
        return SimRunner("mujoco", {"young_pa": 9e4, "damping_s": 1e-4}, compress, drop,
                            lambda v: [Knob("damping_s", v["damping_s"], 1e-7, 0.1)], None)

    monkeypatch.setattr(xc, "sim_runner", runner)
    report = xc.crosscheck_asset(grid_sponge, "mujoco")
    assert report.agrees is True and len(set(ran)) == len(ran) == report.sim_calls
    saved = json.loads((grid_sponge / "export" / "mujoco" / "crosscheck.json").read_text())
    assert saved["calibration"]["sim_calls"] == len(ran) - 2 and saved["calibration"]["parameters"]["damping_s"] > 1e-4


@pytest.mark.parametrize("sim", ["genesis", "bullet"])
def test_crosscheck_cli_refuses_what_it_cannot_run(sim: str, grid_sponge: Path, monkeypatch: pytest.MonkeyPatch,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    """An unknown simulator, or one whose package is missing (genesis-world hidden here): one error line, nothing
    written."""
    import importlib.util

    from tests.export.test_export_cmd import run_cli

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "genesis" else real(name, *a))

    code, err = run_cli(["crosscheck", str(grid_sponge), "--sim", sim], monkeypatch, capsys)
    lines = [line for line in err.splitlines() if line.strip()]
    assert code != 0 and len(lines) == 1 and lines[0].startswith("error:"), err
    assert not (grid_sponge / "export" / "mujoco").exists() and not (grid_sponge / "export" / "genesis").exists()
