"""Per-key advisory file locks (flock): released by the kernel when the holder dies, even on SIGKILL."""

from __future__ import annotations

import asyncio
import contextlib
import fcntl
import os
import threading
import time
from collections.abc import Iterator
from pathlib import Path

from cache.config import cache_root

_POLL_S = 0.02


def lock_path(root: Path, key: str, kind: str) -> Path:
    """Lock file of `key` for one purpose (`task`: one execution per key; `entry`: publishing/removal)."""
    return root / "locks" / key[:2] / f"{key}.{kind}.lock"


def _open(path: Path) -> int:
    path.parent.mkdir(parents=True, exist_ok=True)
    return os.open(path, os.O_RDWR | os.O_CREAT, 0o644)


def acquire_fd(path: Path, timeout: float | None = None, shared: bool = False) -> int | None:
    """Open and flock `path`; blocks (or polls up to `timeout` s); returns the fd or None on timeout."""
    fd = _open(path)
    mode = fcntl.LOCK_SH if shared else fcntl.LOCK_EX
    try:
        if timeout is None:
            fcntl.flock(fd, mode)
            return fd
        deadline = time.monotonic() + timeout
        while True:
            try:
                fcntl.flock(fd, mode | fcntl.LOCK_NB)
                return fd
            except BlockingIOError:
                if time.monotonic() >= deadline:
                    os.close(fd)
                    return None
                time.sleep(_POLL_S)
    except BaseException:
        with contextlib.suppress(OSError):
            os.close(fd)
        raise


def release_fd(fd: int) -> None:
    """Unlock and close a lock fd."""
    try:
        fcntl.flock(fd, fcntl.LOCK_UN)
    finally:
        os.close(fd)


@contextlib.contextmanager
def key_lock(root: Path, key: str, kind: str = "entry") -> Iterator[None]:
    """Hold the exclusive `kind` lock of `key` for the duration of the block."""
    fd = acquire_fd(lock_path(root, key, kind))
    assert fd is not None
    try:
        yield
    finally:
        release_fd(fd)


class FlockLockManager:
    """Prefect LockManager on flock files under `<cache root>/locks` (no stale locks after a crash)."""

    _held: dict[tuple[str, str], tuple[str, int]] = {}  # (root, key) -> (holder, fd), process-wide
    _mutex = threading.Lock()

    def __init__(self, root: str | None = None) -> None:
        self.root = root  # None: resolve the cache root at each call

    def _root(self) -> Path:
        return Path(self.root) if self.root else cache_root()

    def _path(self, key: str) -> Path:
        return lock_path(self._root(), key, "task")

    def _slot(self, key: str) -> tuple[str, str]:
        return (str(self._root()), key)

    def acquire_lock(
        self, key: str, holder: str, acquire_timeout: float | None = None, hold_timeout: float | None = None
    ) -> bool:
        """Take the key's lock for `holder` (re-entrant for the same holder)."""
        slot = self._slot(key)
        with self._mutex:
            held = self._held.get(slot)
            if held and held[0] == holder:
                return True
        fd = acquire_fd(self._path(key), acquire_timeout)
        if fd is None:
            return False
        with self._mutex:
            self._held[slot] = (holder, fd)
        return True

    async def aacquire_lock(
        self, key: str, holder: str, acquire_timeout: float | None = None, hold_timeout: float | None = None
    ) -> bool:
        """Async form of acquire_lock (blocks a worker thread, not the loop)."""
        return await asyncio.to_thread(self.acquire_lock, key, holder, acquire_timeout, hold_timeout)

    def release_lock(self, key: str, holder: str) -> None:
        """Release the key's lock held by `holder`."""
        slot = self._slot(key)
        with self._mutex:
            held = self._held.get(slot)
            if not held or held[0] != holder:
                raise ValueError(f"no lock for transaction with key {key!r} held by {holder!r}")
            del self._held[slot]
        release_fd(held[1])

    def is_locked(self, key: str) -> bool:
        """True when some holder (any process) has the key's lock."""
        path = self._path(key)
        if not path.exists():
            return False
        fd = acquire_fd(path, timeout=0, shared=True)
        if fd is None:
            return True
        release_fd(fd)
        return False

    def is_lock_holder(self, key: str, holder: str) -> bool:
        """True when `holder` in this process has the key's lock."""
        with self._mutex:
            held = self._held.get(self._slot(key))
        return bool(held and held[0] == holder)

    def wait_for_lock(self, key: str, timeout: float | None = None) -> bool:
        """Block until the key's lock is free (or `timeout` s pass)."""
        path = self._path(key)
        if not path.exists():
            return True
        fd = acquire_fd(path, timeout=timeout, shared=True)
        if fd is None:
            return False
        release_fd(fd)
        return True

    async def await_for_lock(self, key: str, timeout: float | None = None) -> bool:
        """Async form of wait_for_lock."""
        return await asyncio.to_thread(self.wait_for_lock, key, timeout)
