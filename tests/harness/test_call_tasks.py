"""flows.harness.call_tasks and tasks.probes.workers: independent probe tasks side by side on the CPU (Prefect's
thread-pool task runner), results in call order, errors raised, one at a time on CUDA, worker processes sharing the
cores."""

from __future__ import annotations

import threading

import pytest
from prefect import task

from flows.harness import call_tasks, task_states
from tasks.probes.workers import POOL_THREAD_ENVS, PROBE_WORKERS_ENV, child_probe_workers, probe_workers


def test_calls_run_side_by_side_and_come_back_in_order(prefect_api: str) -> None:
    both_in_flight = threading.Barrier(2, timeout=10)  # breaks (fails the test) unless two calls run at once

    @task
    def probe(k: int) -> int:
        if k < 2:
            both_in_flight.wait()
        return k * k

    assert call_tasks([(probe, {"k": k}) for k in range(5)], workers=2, device=None) == [0, 1, 4, 9, 16]
    states = task_states([(probe, {"k": k}) for k in range(3)], workers=2, device=None)
    assert [s.is_completed() for s in states] == [True] * 3 and [s.result() for s in states] == [0, 1, 4]


def test_one_worker_calls_in_order_on_the_callers_thread(prefect_api: str) -> None:
    seen: list[tuple[int, str]] = []

    @task
    def probe(k: int) -> int:
        seen.append((k, threading.current_thread().name))
        return k

    assert call_tasks([(probe, {"k": k}) for k in range(3)], workers=1) == [0, 1, 2]
    assert seen == [(k, threading.current_thread().name) for k in range(3)]


def test_an_error_in_one_call_is_raised_after_the_others_finish(prefect_api: str) -> None:
    done: list[int] = []

    @task
    def probe(k: int) -> int:
        if k == 0:
            raise ValueError("probe 0 failed")
        done.append(k)
        return k

    with pytest.raises(ValueError, match="probe 0 failed"):
        call_tasks([(probe, {"k": k}) for k in range(4)], workers=2, device=None)
    assert sorted(done) == [1, 2, 3]


def test_workers_follow_calls_cores_env_and_device(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(PROBE_WORKERS_ENV, raising=False)
    assert probe_workers(1) == 1
    assert probe_workers(6, "cuda") == 1
    assert 1 <= probe_workers(6) <= 6
    monkeypatch.setenv(PROBE_WORKERS_ENV, "1")
    assert probe_workers(6) == 1
    monkeypatch.setenv(PROBE_WORKERS_ENV, "not a number")
    assert probe_workers(6) == probe_workers(6, "cpu")


def test_worker_processes_share_the_cores_unless_the_user_chose(monkeypatch: pytest.MonkeyPatch) -> None:
    """Each of N workers gets cores / N probe threads and as many OpenMP and BLAS threads (not every core each)."""
    for name in (PROBE_WORKERS_ENV, *POOL_THREAD_ENVS):
        monkeypatch.delenv(name, raising=False)
    one = int(child_probe_workers(1)[PROBE_WORKERS_ENV])
    assert one >= 1
    assert child_probe_workers(10 * one) == {name: "1" for name in (PROBE_WORKERS_ENV, *POOL_THREAD_ENVS)}
    monkeypatch.setenv(PROBE_WORKERS_ENV, "3")
    monkeypatch.setenv("OMP_NUM_THREADS", "2")
    assert child_probe_workers(10 * one) == {"OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def test_eval_worker_processes_get_their_share(monkeypatch: pytest.MonkeyPatch) -> None:
    """flows.evaluate's worker initializer exports the share in each spawned worker process."""
    import multiprocessing as mp
    import os
    from concurrent.futures import ProcessPoolExecutor

    from flows.evaluate import _set_env

    with ProcessPoolExecutor(max_workers=1, mp_context=mp.get_context("spawn"), initializer=_set_env,
                             initargs=({PROBE_WORKERS_ENV: "1"},)) as pool:
        assert pool.submit(os.getenv, PROBE_WORKERS_ENV).result(timeout=120) == "1"
