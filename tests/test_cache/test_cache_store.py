"""CacheStore: round trips, atomic publish, corruption is a miss, verify, gc, events, concurrent writers."""

from __future__ import annotations

import multiprocessing as mp
import os
import time
from pathlib import Path

import numpy as np
import pytest
from pydantic import BaseModel

from cache import CacheMiss, CacheStore, content_key
from cache.codec import encode
from contracts.errors import CacheError


class Part(BaseModel):
    name: str
    mass_kg: float


def _value(tmp_path: Path) -> dict:
    f = tmp_path / "mesh.obj"
    f.write_text("v 0 0 0\n")
    return {
        "pos": np.arange(30, dtype=np.float32).reshape(10, 3),
        "F": np.tile(np.eye(3), (4, 1, 1)),
        "empty": np.zeros((0, 3), dtype=np.int64),
        "part": Part(name="a", mass_kg=0.25),
        "pair": (1, "two", 3.5),
        "nested": [{"x": None, "ok": True}, float("inf")],
        "scalar": np.float32(2.5),
        "file": f,
    }


def _corrupt_first_chunk(store: CacheStore, key: str) -> Path:
    chunk = next(p for p in sorted((store.entry_dir(key) / "a0").rglob("*")) if p.is_file() and p.name != "zarr.json")
    data = bytearray(chunk.read_bytes())
    data[len(data) // 2] ^= 0xFF
    chunk.write_bytes(bytes(data))
    return chunk


def test_round_trip_keeps_types(tmp_path: Path) -> None:
    store = CacheStore(tmp_path / "c")
    value = _value(tmp_path)
    key = content_key("rt")
    assert store.put(key, value, {"task": "t"}) is True
    out = store.get(key)
    np.testing.assert_array_equal(out["pos"], value["pos"])
    assert out["pos"].dtype == np.float32 and out["F"].shape == (4, 3, 3) and out["empty"].shape == (0, 3)
    assert isinstance(out["part"], Part) and out["part"] == value["part"]
    assert out["pair"] == (1, "two", 3.5) and isinstance(out["pair"], tuple)
    assert out["nested"][0] == {"x": None, "ok": True} and out["nested"][1] == float("inf")
    assert out["scalar"] == np.float32(2.5) and out["scalar"].dtype == np.float32
    assert out["file"].read_text() == "v 0 0 0\n" and str(out["file"]).startswith(str(store.root))
    assert store.contains(key) and store.load(key)[1] == {"task": "t"}
    assert store.put(key, value) is False  # an intact entry is kept


def test_missing_key_is_a_miss(tmp_path: Path) -> None:
    with pytest.raises(CacheMiss):
        CacheStore(tmp_path).get(content_key("nothing"))
    with pytest.raises(CacheError):
        CacheStore(tmp_path).get("not-a-key")


def test_unstorable_value_is_rejected_before_writing(tmp_path: Path) -> None:
    with pytest.raises(TypeError):
        encode({"f": lambda: 1})
    store = CacheStore(tmp_path / "c")
    with pytest.raises(TypeError):
        store.put(content_key("x"), object())
    assert store.keys() == [] and list((tmp_path / "c" / "tmp").iterdir()) == []


def test_crash_before_rename_leaves_no_readable_entry(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    store = CacheStore(tmp_path / "c")
    key = content_key("crash")

    def boom(*a: object, **k: object) -> None:
        raise KeyboardInterrupt("crash during publish")

    monkeypatch.setattr(os, "rename", boom)
    with pytest.raises(KeyboardInterrupt):
        store.put(key, {"a": np.ones(1000)})
    monkeypatch.undo()
    assert not store.contains(key)
    with pytest.raises(CacheMiss):
        store.get(key)


def test_corrupt_entry_is_a_miss_reported_by_verify_and_replaced(tmp_path: Path) -> None:
    store = CacheStore(tmp_path / "c")
    good, bad = content_key("good"), content_key("bad")
    store.put(good, {"a": np.ones(100)})
    store.put(bad, {"a": np.arange(100.0)})
    _corrupt_first_chunk(store, bad)
    with pytest.raises(CacheMiss):
        store.get(bad)
    problems = store.verify()
    assert [p.key for p in problems] == [bad] and "digest" in problems[0].reason
    assert store.put(bad, {"a": np.arange(100.0)}) is True  # replaced
    np.testing.assert_array_equal(store.get(bad)["a"], np.arange(100.0))
    assert store.verify() == []


def test_edited_attributes_and_deleted_chunks_are_detected(tmp_path: Path) -> None:
    store = CacheStore(tmp_path / "c")
    k1, k2 = content_key(1), content_key(2)
    store.put(k1, {"mass_kg": 1.0})
    store.put(k2, {"a": np.arange(10.0)})
    zj = store.entry_dir(k1) / "zarr.json"
    zj.write_text(zj.read_text().replace("1.0", "2.0"))
    _corrupt_first_chunk(store, k2).unlink()
    assert {p.key for p in store.verify()} == {k1, k2}
    for k in (k1, k2):
        with pytest.raises(CacheMiss):
            store.get(k)
    store.verify(remove=True)
    assert store.keys() == []


def test_gc_by_age_and_size(tmp_path: Path) -> None:
    store = CacheStore(tmp_path / "c")
    keys = [content_key("gc", i) for i in range(4)]
    for i, k in enumerate(keys):
        store.put(k, {"a": np.zeros(10_000)})
        old = time.time() - (4 - i) * 3600
        os.utime(store.entry_dir(k), (old, old))
    store.get(keys[0])  # a hit refreshes last use
    res = store.gc(older_than_s=2.5 * 3600)
    assert set(res["removed"]) == {keys[1]}
    size = store.stats()["bytes"]
    res = store.gc(max_bytes=int(size * 0.7))
    assert res["removed"] == [keys[2]] and res["remaining_bytes"] <= int(size * 0.7)
    assert set(store.keys()) == {keys[0], keys[3]}


def test_events_log(tmp_path: Path) -> None:
    store = CacheStore(tmp_path / "c")
    store.record_event(key="ab" * 32, task="t", version="1", outcome="miss")
    store.record_event(key="ab" * 32, task="t", version="1", outcome="hit")
    assert [e["outcome"] for e in store.events()] == ["miss", "hit"]
    assert store.stats()["hits"] == 1


def _racing_put(root: str, key: str, barrier: object) -> bool:
    barrier.wait()  # type: ignore[attr-defined]
    return CacheStore(root).put(key, {"F": np.full((200_000, 3, 3), 7, dtype=np.float32)})


def test_concurrent_writers_leave_one_intact_entry(tmp_path: Path) -> None:
    root, key = str(tmp_path / "c"), content_key("race")
    ctx = mp.get_context("spawn")
    barrier = ctx.Manager().Barrier(4)
    with ctx.Pool(4) as pool:
        published = pool.starmap(_racing_put, [(root, key, barrier)] * 4)
    store = CacheStore(root)
    assert sum(published) == 1 and store.keys() == [key] and store.verify() == []
    assert float(store.get(key)["F"].sum()) == 7 * 200_000 * 9


def test_models_with_nan_and_inf_metrics_round_trip(tmp_path: Path) -> None:
    """An undefined metric (NaN) or an unbounded one (inf) is data: stored and returned as such."""
    import math

    from contracts.probes import ProbeResult, ProbeSpec

    from cache import CacheStore

    result = ProbeResult(spec=ProbeSpec(kind="pick_and_place"),
                         metrics={"hold_normal_force_n": math.nan, "settle_time_s": math.inf, "mass_kg": 0.15})
    store = CacheStore(tmp_path)
    store.put("ab" * 32, {"result": result})
    back = store.get("ab" * 32)["result"]
    assert math.isnan(back.metrics["hold_normal_force_n"]) and back.metrics["settle_time_s"] == math.inf
    assert back.metrics["mass_kg"] == 0.15 and store.verify() == []
