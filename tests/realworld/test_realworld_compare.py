"""`bench realworld`'s comparison logic on fixed inputs, its physics (Hertz squeeze, drag) and its CLI's bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from typer.testing import CliRunner

from contracts.errors import InputError
from contracts.realworld import ObjectReport, OurFigures, ValueRange, load_realworld
from flows.cli.main import app
from tasks.realworld.compare import compare, ratio_to_range, select_objects, summarise
from tasks.realworld.impact import impact_metrics
from tasks.realworld.physics import (G_M_PER_S2, damped_impact_speed_m_per_s, damped_rise_height_m, hertz_modulus_pa,
                                     impact_speed_m_per_s, rise_height_m, squeeze_modulus_range,
                                     terminal_speed_m_per_s)

SET = load_realworld()
BY = {o.name: o for o in SET.objects}


def test_ratio_to_the_nearest_end() -> None:
    """1 inside the range, else ours over the nearer end."""
    band = ValueRange(low=10.0, high=20.0)
    assert ratio_to_range(15.0, band) == 1.0
    assert ratio_to_range(5.0, band) == 0.5
    assert ratio_to_range(50.0, band) == 2.5


def test_comparisons_of_a_tennis_ball() -> None:
    """Mass within 2x, the squeeze's equivalent modulus within 2x, the rebound in the rule's band: each judged alone."""
    ours = OurFigures(mass_kg=0.0529, youngs_modulus_pa=5.0e6, poisson_ratio=0.48, rebound_ratio=0.55)
    got = {c.quantity: c for c in compare(BY["tennis ball"], ours)}
    assert got["mass_kg"].passed and got["rebound_ratio"].passed
    assert not got["squeeze_modulus_pa"].passed  # 5 MPa is ~3x the squeeze's 1.1-1.7 MPa
    assert got["squeeze_modulus_pa"].ratio == pytest.approx(5.0e6 / got["squeeze_modulus_pa"].measured.high)
    missed = {c.quantity: c for c in compare(BY["tennis ball"], ours.model_copy(update={"rebound_ratio": 0.40}))}
    assert missed["rebound_ratio"].passed is False


def test_nothing_built_is_not_judged() -> None:
    """A failed build compares nothing: passed is None, not False."""
    got = compare(BY["marshmallow"], OurFigures())
    assert [c.passed for c in got] == [None, None]


def test_summary_counts() -> None:
    """The summary counts objects whose comparisons of a kind all passed."""
    def report(name: str, ours: OurFigures) -> ObjectReport:
        o = BY[name]
        return ObjectReport(name=name, kind=o.kind, expected_concept=o.concept, status="ok", ours=ours,
                            comparisons=compare(o, ours), wall_s=0.0)
    reports = [report("marshmallow", OurFigures(concept="marshmallow", mass_kg=0.007, youngs_modulus_pa=2e4)),
               report("block of cheddar cheese", OurFigures(concept="cheese_block", youngs_modulus_pa=3.35e4)),
               report("basketball", OurFigures(concept="basketball", mass_kg=0.6, rebound_ratio=0.3))]
    s = summarise(reports)
    assert (s.objects, s.concept_matches) == (3, 3)
    assert (s.modulus_measured, s.modulus_within_2x) == (2, 1)
    assert (s.mass_measured, s.mass_within_2x) == (2, 2)
    assert (s.rule_balls, s.rebound_in_band) == (1, 0)


def test_hertz_round_trip_and_the_tennis_squeeze() -> None:
    """The modulus that gives a deformation gives it back; the ITF squeeze is a 1.1-1.7 MPa equivalent solid."""
    e, nu, dia, load = 1.5e6, 0.48, 0.067, 80.07
    e_star = e / (1 - nu ** 2)
    d_each = (9 * load ** 2 / (16 * e_star ** 2 * dia / 2)) ** (1 / 3)
    assert hertz_modulus_pa(load, 2 * d_each, dia, nu) == pytest.approx(e, rel=1e-9)
    squeeze = BY["tennis ball"].squeeze
    assert squeeze is not None
    band = squeeze_modulus_range(squeeze, 0.48)
    assert 1.0e6 < band.low < 1.2e6 and 1.6e6 < band.high < 1.8e6


def test_drag_slows_the_fall_and_the_rise() -> None:
    """In vacuum the closed forms are v = sqrt(2 g h) and h = v^2 / 2g; air takes a few percent off both ways (a tennis
    ball from 2.54 m: terminal speed ~22 m/s, ~5 % of the impact energy)."""
    assert impact_speed_m_per_s(2.54, None) == pytest.approx(math.sqrt(2 * G_M_PER_S2 * 2.54))
    assert rise_height_m(5.0, None) == pytest.approx(25.0 / (2 * G_M_PER_S2))
    vt = terminal_speed_m_per_s(0.058, 0.067)
    assert 19.0 < vt < 24.0
    v = impact_speed_m_per_s(2.54, vt)
    assert 0.93 < v ** 2 / (2 * G_M_PER_S2 * 2.54) < 0.97
    assert rise_height_m(5.0, vt) < rise_height_m(5.0, None)
    assert rise_height_m(5.0, 1e6) == pytest.approx(rise_height_m(5.0, None), rel=1e-6)


def test_impact_metrics_on_a_fixed_series() -> None:
    """A COM that comes in at 4 m/s, touches for 4 ms and leaves at 3 m/s: restitution 0.75."""
    t = np.arange(1, 11) * 1e-3
    vz = np.array([-4.0, -4.0, -2.0, 0.0, 2.0, 3.0, 3.0, 3.0, 3.0, 3.0])
    z = np.full(10, 0.05)  # the COM back at its contact height: no correction
    force = np.array([0, 0, 5, 9, 5, 1, 0, 0, 0, 0], float)
    m = impact_metrics(t, z, vz, force, np.linspace(0, 0.1, 10))
    assert m["restitution"] == pytest.approx(0.75)
    assert m["contact_time_s"] == pytest.approx(4e-3)
    assert m["left_ground"] == 1.0


def test_unknown_objects_are_refused() -> None:
    """--only with a name the set does not hold: InputError naming it; the CLI exits 2 before anything runs."""
    with pytest.raises(InputError, match="unicorn ball"):
        select_objects(SET.objects, ["tennis ball", "unicorn ball"])
    assert [o.name for o in select_objects(SET.objects, ["basketball", "tennis ball"])] == ["tennis ball",
                                                                                          "basketball"]
    assert len(select_objects(SET.objects, None, 3)) == 3
    res = CliRunner().invoke(app, ["bench", "realworld", "--only", "unicorn ball"])
    assert res.exit_code == 2
    assert "unicorn ball" in res.output
    res = CliRunner().invoke(app, ["bench", "realworld", "--limit", "0"])
    assert res.exit_code == 2


def test_the_engine_damping_in_flight() -> None:
    """The fall and rise under the engine's world-frame damping: vacuum at d = 0, below it otherwise, and the fall
    never faster than the terminal speed g / d (checked against a fine explicit integration)."""
    assert damped_impact_speed_m_per_s(2.54, 0.0) == pytest.approx(math.sqrt(2 * G_M_PER_S2 * 2.54))
    assert damped_rise_height_m(5.0, 0.0) == pytest.approx(25.0 / (2 * G_M_PER_S2))
    d, dt, z, v = 2.0, 1e-6, 0.0, 0.0
    while z < 1.0:
        v += dt * (G_M_PER_S2 - d * v)
        z += dt * v
    assert damped_impact_speed_m_per_s(1.0, d) == pytest.approx(v, rel=1e-4)
    z, v = 0.0, 4.0
    while v > 0:
        v -= dt * (G_M_PER_S2 + d * v)
        z += dt * v
    assert damped_rise_height_m(4.0, d) == pytest.approx(z, rel=1e-4)
