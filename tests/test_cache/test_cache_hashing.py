"""Content keys: by value, never by identity; sensitive to everything that changes the content."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from pydantic import BaseModel

from cache import content_key
from contracts.errors import InputError


class M(BaseModel):
    a: float
    b: list[int]


def test_models_hash_by_canonical_content() -> None:
    assert content_key(M(a=1.0, b=[1, 2])) == content_key(M(b=[1, 2], a=1.0))
    assert content_key(M(a=1.0, b=[1, 2])) != content_key(M(a=1.5, b=[1, 2]))


def test_arrays_hash_by_dtype_shape_and_bytes() -> None:
    a = np.arange(12, dtype=np.float32)
    assert content_key(a) == content_key(a.copy())
    assert content_key(a) == content_key(np.asfortranarray(a.reshape(3, 4)).reshape(12))
    assert content_key(a) != content_key(a.reshape(3, 4))
    assert content_key(a) != content_key(a.astype(np.float64))
    b = a.copy()
    b[5] += 1e-6
    assert content_key(a) != content_key(b)


def test_large_arrays_digested_in_parallel_give_the_same_key() -> None:
    big = [np.full((600_000, 3), i, dtype=np.float32) for i in range(3)]
    assert content_key(*big) == content_key(*[x.copy() for x in big])
    assert content_key(*big) != content_key(big[1], big[0], big[2])


def test_containers_and_scalars() -> None:
    assert content_key({"x": 1, "y": 2}) == content_key({"y": 2, "x": 1})
    assert content_key([1, 2]) != content_key((1, 2))
    assert content_key(1) != content_key(1.0) != content_key("1")
    assert content_key(True) != content_key(1)
    assert content_key(None) != content_key("None")
    assert content_key("ab", "c") != content_key("a", "bc")
    assert content_key(np.float32(1.5)) != content_key(np.float64(1.5))


def test_paths_hash_by_content_not_name(tmp_path: Path) -> None:
    f1, f2 = tmp_path / "a.obj", tmp_path / "b.obj"
    f1.write_bytes(b"v 0 0 0\n")
    f2.write_bytes(b"v 0 0 0\n")
    assert content_key(f1) == content_key(f2)
    f2.write_bytes(b"v 0 0 1\n")
    assert content_key(f1) != content_key(f2)
    d = tmp_path / "dir"
    d.mkdir()
    (d / "x.txt").write_text("1")
    k = content_key(d)
    (d / "x.txt").write_text("2")
    assert content_key(d) != k


def test_unhashable_inputs_fail_loudly(tmp_path: Path) -> None:
    with pytest.raises(TypeError):
        content_key(object())
    with pytest.raises(TypeError):
        content_key({1: "int key"})
    with pytest.raises(InputError, match="no such file"):
        content_key(tmp_path / "missing.png")
