"""How a batch request's process ended, read from what it left (tasks.batch_requests): its result file, else the
timeout, the batch's interrupt or its exit status with the log's last line; its cache counts from the event log."""

from __future__ import annotations

import json
import signal
from pathlib import Path

from tasks.batch_requests import (
    BatchItem, cache_counts, death_reason, last_log_line, not_started, process_result, slug,
)

ITEM = BatchItem(line=3, name="duck")


def test_a_result_file_is_the_answer(tmp_path: Path) -> None:
    result = tmp_path / "duck.result.json"
    result.write_text(json.dumps({"status": "ok", "reason": None, "asset_dir": "out/duck"}))
    r = process_result(ITEM, 0, 12.34567, result, tmp_path / "duck.log", (5, 7))
    assert (r.status, r.asset_dir, r.wall_s, r.tasks_executed, r.tasks_cached, r.log) == (
        "ok", "out/duck", 12.346, 5, 7, str(tmp_path / "duck.log"))


def test_without_one_the_reason_is_the_timeout_the_interrupt_or_the_death(tmp_path: Path) -> None:
    log = tmp_path / "duck.log"
    log.write_text("loading\n\nValueError: boom\n\n")
    none = tmp_path / "absent.json"
    assert process_result(ITEM, -9, 1.0, none, log, (0, 0), "timed out after 5 s").reason == (
        "timed out after 5 s; last log line: ValueError: boom")
    assert process_result(ITEM, 1, 2.0, none, log, (0, 0), stopping=True).reason == "interrupted after 2.0 s"
    assert process_result(ITEM, -signal.SIGKILL, 1.0, none, log, (0, 0)).reason == (
        "process died from signal SIGKILL; last log line: ValueError: boom")
    assert death_reason(3) == "process exited with code 3 without a result" and death_reason(-200).endswith("200")
    assert last_log_line(tmp_path / "missing.log") == "" and last_log_line(log) == "ValueError: boom"
    assert not_started(ITEM).reason == "interrupted before it started" and not_started(ITEM).attempts == 0


def test_cache_counts_are_one_process_s_from_an_offset(tmp_path: Path) -> None:
    events = tmp_path / "events.jsonl"
    events.write_text(json.dumps({"pid": 1, "outcome": "miss"}) + "\n")
    since = events.stat().st_size
    with events.open("a") as fh:
        for ev in ({"pid": 1, "outcome": "miss"}, {"pid": 1, "outcome": "hit"}, {"pid": 2, "outcome": "miss"}):
            fh.write(json.dumps(ev) + "\n")
        fh.write("{torn\n")
    assert cache_counts(events, 1, since) == (1, 1) and cache_counts(events, 1, 0) == (2, 1)
    assert cache_counts(tmp_path / "none.jsonl", 1, 0) == (0, 0)


def test_slug_names_a_folder() -> None:
    assert slug("A Soft Plush Turtle, 25 cm!") == "a_soft_plush_turtle_25_cm" and slug("!!!") == "asset"
    assert len(slug("x" * 100)) == 48
