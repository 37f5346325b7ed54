"""Expensive deterministic test inputs made once per test run, not once per xdist worker.

CI runs `pytest -n 2 --dist loadfile`: two worker processes, each with its own session fixtures. A session fixture
that files on both workers use (a simulated trial, a built asset) is computed by each. Here the first worker to
finish it leaves it in the run's shared temporary folder (the parent of every worker's basetemp, as pytest-xdist's
documentation shows) and a later worker reads it back. A worker that finds another one still computing computes it
itself rather than waiting (no worse than before). Only for pure functions of their inputs: what is read back is
what the computation returned (pickled: the same arrays and numbers; or the same files).
"""

from __future__ import annotations

import fcntl
import os
import pickle
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

import pytest

T = TypeVar("T")


def _shared_root(factory: pytest.TempPathFactory) -> Path:
    """The folder every worker of this run sees (the controller's basetemp under xdist; this run's own otherwise)."""
    base = factory.getbasetemp()
    root = (base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base) / "worker-share"
    root.mkdir(parents=True, exist_ok=True)
    return root


def shared_value(factory: pytest.TempPathFactory, name: str, make: Callable[[], T]) -> T:
    """`make()`, or the value another worker of this run made under `name`."""
    root = _shared_root(factory)
    done = root / f"{name}.pickle"
    if done.is_file():
        return pickle.loads(done.read_bytes())  # type: ignore[no-any-return]
    with open(root / f"{name}.lock", "w") as lock:
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            return make()  # another worker is making it: make our own rather than wait
        if done.is_file():
            return pickle.loads(done.read_bytes())  # type: ignore[no-any-return]
        value = make()
        part = root / f"{name}.pickle.part"
        part.write_bytes(pickle.dumps(value, protocol=pickle.HIGHEST_PROTOCOL))
        part.replace(done)
        return value


def shared_dir(factory: pytest.TempPathFactory, name: str, make: Callable[[Path], object]) -> Path:
    """A folder `make(folder)` fills (the folder is always named `name`), made once in this run: the path of this
    worker's own copy of it."""
    root = _shared_root(factory)
    done = root / f"{name}.done" / name
    mine = factory.mktemp(name) / name

    def own_copy() -> Path:
        shutil.copytree(done, mine)
        return mine

    if done.is_dir():
        return own_copy()
    with open(root / f"{name}.lock", "w") as lock:
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            make(mine)  # another worker is making it: make our own rather than wait
            return mine
        if done.is_dir():
            return own_copy()
        part = root / f"{name}.part"
        shutil.rmtree(part, ignore_errors=True)
        part.mkdir()
        make(part / name)
        part.replace(done.parent)
        return own_copy()
