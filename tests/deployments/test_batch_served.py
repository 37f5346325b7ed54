"""A batch's worker processes serve many requests one after another (flows.batch.ServedWorker): one process per
slot until requests_per_worker, a fresh one after a crash or a timeout, each request's output in its own log."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from contracts.errors import InputError
from flows.batch import run_batch

QUICK = "tests.deployments.jobs:quick_job"
REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(autouse=True)
def _job_importable(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PYTHONPATH", str(REPO))  # (the workers import the test jobs)


def _batch(tmp_path: Path, texts: list[str], **kwargs: object):  # noqa: ANN202
    reqs = tmp_path / "r.jsonl"
    reqs.write_text("".join(json.dumps({"name": f"r{i}", "text": t}) + "\n" for i, t in enumerate(texts)),
                    encoding="utf-8")
    return run_batch(reqs, tmp_path / "out", job=QUICK, **kwargs)  # type: ignore[arg-type]


def _pid(tmp_path: Path, name: str) -> int:
    return json.loads((tmp_path / "out" / name / "asset.json").read_text(encoding="utf-8"))["pid"]


@pytest.mark.usefixtures("prefect_api")
def test_one_worker_serves_its_requests_until_it_is_replaced(tmp_path: Path) -> None:
    report = _batch(tmp_path, ["print a", "print b", "print c", "print d", "print e"], requests_per_worker=2)
    assert (report.ok, report.failed) == (5, 0)
    pids = [_pid(tmp_path, f"r{i}") for i in range(5)]
    assert pids[0] == pids[1] != pids[2] == pids[3] != pids[4]  # two each, then a fresh process
    logs = tmp_path / "out" / "_logs"
    for i, t in enumerate("abcde"):  # each request's output in its own log, none in another's
        text = (logs / f"r{i}.log").read_text(encoding="utf-8")
        assert f"output of print {t}" in text and text.count("output of") == 1


@pytest.mark.usefixtures("prefect_api")
def test_a_crash_a_failure_or_a_timeout_fails_that_request_alone_and_a_fresh_worker_serves_the_next(
        tmp_path: Path) -> None:
    report = _batch(tmp_path, ["fine", "crash", "fine", "stage-fail", "fine", "sleep 30", "fine"], timeout_s=4.0)
    status = {r.name: (r.status, r.reason or "") for r in report.results}
    assert [status[f"r{i}"][0] for i in range(7)] == ["ok", "failed", "ok", "failed", "ok", "failed", "ok"]
    assert "SIGKILL" in status["r1"][1] and "StageFailure" in status["r3"][1]
    assert "timed out after 4 s" in status["r5"][1]
    assert len({_pid(tmp_path, f"r{i}") for i in (0, 2, 4, 6)}) == 4  # (a failed request retires its worker too:
    # what failed may have left the process unfit, a CUDA context after a device error)


def test_requests_per_worker_must_be_positive(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="requests per worker"):
        _batch(tmp_path, ["fine"], requests_per_worker=0)


@pytest.mark.slow  # two real draft generations in one worker against one in its own process: minutes on 2 cores
def test_a_served_asset_equals_the_same_request_from_a_process_of_its_own(tmp_path: Path, prefect_api: str,
                                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    from cache import use_cache_root
    from flows.batch import NO_L3_JOB
    from tasks.record.fingerprint import content_fingerprint

    texts = ["a kitchen sponge 10 x 7 x 3 cm", "a stress ball"]
    reqs = tmp_path / "r.jsonl"
    reqs.write_text("".join(json.dumps({"name": f"r{i}", "text": t, "quality": "draft"}) + "\n"
                            for i, t in enumerate(texts)), encoding="utf-8")
    alone = tmp_path / "alone.jsonl"
    alone.write_text(json.dumps({"name": "r1", "text": texts[1], "quality": "draft"}) + "\n", encoding="utf-8")
    use_cache_root(tmp_path / "cache_served")
    served = run_batch(reqs, tmp_path / "served", job=NO_L3_JOB)  # r1 after r0, in r0's worker
    use_cache_root(tmp_path / "cache_alone")
    own = run_batch(alone, tmp_path / "alone", job=NO_L3_JOB, requests_per_worker=1)
    assert (served.ok, own.ok) == (2, 1), (served.results, own.results)
    assert content_fingerprint(tmp_path / "served" / "r1") == content_fingerprint(tmp_path / "alone" / "r1")
