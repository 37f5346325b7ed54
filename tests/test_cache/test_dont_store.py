"""A cached task whose answer is a stand-in (cache.dont_store) is returned but not stored: the next run asks again."""

from __future__ import annotations

from pathlib import Path

from prefect import flow

from cache import CacheStore, cached_task, dont_store

CALLS: list[str] = []


@cached_task(version=1, name="test.maybe_stand_in")
def answer(question: str, stand_in: bool) -> str:
    CALLS.append(question)
    if stand_in:
        dont_store()
    return f"{'rule' if stand_in else 'llm'}:{question}"


@flow(name="test-dont-store")
def ask(question: str, stand_in: bool) -> str:
    return answer(question, stand_in)


def test_a_stand_in_is_returned_not_stored_and_a_real_answer_is(prefect_api: str, tmp_path: Path,
                                                                 monkeypatch) -> None:  # noqa: ANN001
    monkeypatch.setenv("DEFORMSMITH_CACHE", str(tmp_path / "cache"))
    CALLS.clear()
    assert ask("q1", True) == "rule:q1"
    assert ask("q1", True) == "rule:q1"
    assert CALLS == ["q1", "q1"]  # nothing kept: the second run computed again
    assert ask("q2", False) == "llm:q2"
    assert ask("q2", False) == "llm:q2"
    assert CALLS == ["q1", "q1", "q2"]  # a real answer is kept and reused
    assert len(CacheStore(tmp_path / "cache").verify()) == 0
    dont_store()  # outside a task run: nothing happens
