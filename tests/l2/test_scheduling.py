"""Candidate scheduling (who shares a lock-step rollout), honest simulation-call counts, deterministic results, and
the probe definitions behind 'firm rubber' (contact-layer set in compression, kinetic energy at rest)."""

from __future__ import annotations

import pytest

from contracts.material import Material
from contracts.sim import SimConfig
from tasks.probes.deformable import compress, kinetic_energy_settles, stability
from tasks.probes.rollout import plan_batches, rollouts
from tests.l2.helpers import box_body


def _mat(E: float, nu: float = 0.3, d: float = 5.0) -> Material:
    return Material(youngs_modulus_pa=E, poisson_ratio=nu, damping_rate_per_s=d)


def test_plan_batches_by_schedule() -> None:
    """Batch: one rollout; grouped (= auto): only equal-time-step candidates (same E, nu) share one; sequential: one
    rollout per candidate."""
    body = box_body((0.06, 0.06, 0.04), 6)
    mats = [_mat(1e4), _mat(3e4, d=2.0), _mat(1e4, d=20.0), _mat(1e4, nu=0.45)]
    assert plan_batches(body, mats, SimConfig(), "batch") == [[0, 1, 2, 3]]
    assert plan_batches(body, mats, SimConfig(), "grouped") == [[0, 2], [1], [3]]
    assert plan_batches(body, mats, SimConfig(), "sequential") == [[0], [1], [2], [3]]
    assert plan_batches(body, mats, SimConfig(), "auto") == [[0, 2], [1], [3]]
    assert plan_batches(body, mats[:1], SimConfig(), "batch") == [[0]]
    with pytest.raises(ValueError, match="unknown schedule"):
        plan_batches(body, mats, SimConfig(), "threads")


def test_scheduled_candidates_count_one_call_per_rollout_and_match_their_solo_runs() -> None:
    """Three candidates: sequential = 3 simulation calls, each result identical to that candidate run alone (and on a
    repeat); a lock-step batch = 1 call."""
    body = box_body((0.06, 0.06, 0.04), 5)
    mats = [_mat(1e4), _mat(3e4), _mat(1e4, d=20.0)]
    seq = stability(body, mats, duration_s=0.15, schedule="sequential")
    assert rollouts(plan_batches(body, mats, SimConfig(), "sequential"), seq) == 3
    for m, r in zip(mats, seq):
        alone = stability(body, [m], duration_s=0.15)[0]
        assert r.metrics == alone.metrics and r.sim_calls == 1
    assert [r.metrics for r in stability(body, mats, duration_s=0.15, schedule="sequential")] == [r.metrics for r in seq]
    batch = stability(body, mats, duration_s=0.15, schedule="batch")
    assert rollouts(plan_batches(body, mats, SimConfig(), "batch"), batch) == 1
    grouped = stability(body, mats, duration_s=0.15, schedule="grouped")
    assert rollouts(plan_batches(body, mats, SimConfig(), "grouped"), grouped) == 2


def test_rollouts_side_by_side_match_one_after_another(monkeypatch: pytest.MonkeyPatch) -> None:
    """The sequential schedule's rollouts run two at a time on the CPU (tasks.probes.workers) and give what they give
    one after another (DEFORMSMITH_PROBE_WORKERS=1), in the same order."""
    body = box_body((0.06, 0.06, 0.04), 5)
    mats = [_mat(1e4), _mat(3e4), _mat(1e4, d=20.0)]
    runs = {}
    for workers in ("2", "1"):
        monkeypatch.setenv("DEFORMSMITH_PROBE_WORKERS", workers)
        runs[workers] = [(r.metrics, r.sim_calls) for r in stability(body, mats, duration_s=0.1, schedule="sequential")]
    assert runs["2"] == runs["1"]
    assert len({str(m) for m, _ in runs["1"]}) == 3  # three different candidates, three different results


def test_a_body_at_rest_counts_as_settled_whatever_its_noise_ratio() -> None:
    """Round-off kinetic energy (late ~ peak ~ 2e-9 M g H) is rest, not a failure to decay; real motion is not."""
    M, H = 0.15, 0.085
    mgh = M * 9.81 * H
    assert kinetic_energy_settles(2e-9 * mgh, 2.5e-9 * mgh, M, H)
    assert kinetic_energy_settles(1e-4 * mgh, 1e-2 * mgh, M, H)  # decayed to 1 % of its peak
    assert not kinetic_energy_settles(1e-4 * mgh, 2e-4 * mgh, M, H)  # still moving at half its peak


def test_compression_recovery_of_an_elastic_body_is_not_eaten_by_the_plate_contact() -> None:
    """A lightly damped elastic block released after 10 % compression recovers >= 0.95 of the displacement (the plate's
    contact layer, where the engine pushes particles out without strain, is left out of the heights)."""
    body = box_body((0.1, 0.08, 0.1), 8)  # 4 grid cells tall
    r = compress(body, _mat(1e5, d=1.0), strain=0.1)[0]
    assert r.health.ok
    assert r.metrics["recovery_ratio"] >= 0.95, r.metrics
    assert r.metrics["compression_strain"] > 0.05
