"""`cached_task`: a Prefect task keyed by name + explicit version + input content, results in the Zarr store."""

from __future__ import annotations

import asyncio
import functools
import inspect
import os
import shutil
import tempfile
import threading
import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal, TypeVar

from prefect import Task, task
from prefect.cache_policies import CachePolicy
from prefect.context import FlowRunContext, TaskRunContext
from prefect.filesystems import WritableFileSystem
from prefect.serializers import Serializer

from cache import codec
from cache.config import cache_root
from cache.dont_store import take_mark
from cache.hashing import content_key
from cache.locks import FlockLockManager
from cache.runtime import local_runtime
from cache.store import CacheStore
from contracts.errors import CacheError

F = TypeVar("F", bound=Callable[..., Any])
KEY_SCHEMA = "deformsmith.task/1"
SERIALIZER_TYPE = "deformsmith-store"

# ---- per-run bookkeeping (task run id -> key, timings) for the execution log ----------------------


@dataclass
class _Run:
    key: str | None = None
    error: str | None = None
    t0: float = 0.0
    key_s: float = 0.0
    exec_s: float | None = None


_RUNS: dict[Any, _Run] = {}
_RUNS_LOCK = threading.Lock()


def _current_run_id() -> Any:
    ctx = TaskRunContext.get()
    return ctx.task_run.id if ctx and ctx.task_run else None


# ---- in-process handoff between the serializer and the storage block -----------------------------
_HANDOFF: dict[str, Any] = {}
_HANDOFF_LOCK = threading.Lock()
_TOKEN_PREFIX = "deformsmith-handoff:"


def _handoff_put(obj: Any) -> str:
    token = _TOKEN_PREFIX + uuid.uuid4().hex
    with _HANDOFF_LOCK:
        _HANDOFF[token] = obj
    return token


def _handoff_pop(token: str) -> Any:
    with _HANDOFF_LOCK:
        if token not in _HANDOFF:
            raise CacheError("result handoff token not found (serializer and storage must run in one process)")
        return _HANDOFF.pop(token)


class StoreHandoffSerializer(Serializer):
    """Passes the Python object itself to StoreResultStorage (which writes it as a Zarr group)."""

    type: Literal["deformsmith-store"] = "deformsmith-store"

    def dumps(self, obj: Any) -> bytes:
        """Register `obj` for the storage block; the 'bytes' are a one-shot token."""
        return _handoff_put(obj).encode()

    def loads(self, blob: bytes) -> Any:
        """Take back the object that the storage block loaded."""
        return _handoff_pop(blob.decode())


# ---- scratch folders for Path outputs ------------------------------------------------------------
# A task that returns files writes them into `scratch_dir()`. The store copies them into the entry when Prefect
# persists the result (before the call returns); the call then hands back the stored copies, exactly what a hit
# returns, and removes the scratch folder, so nothing is left in the temp directory on a miss either.
_SCRATCH: set[Path] = set()
_RELOCATED: dict[Path, Path] = {}  # scratch file -> its stored copy (set when the entry holding it is intact)
_SCRATCH_LOCK = threading.Lock()


def scratch_dir(prefix: str = "deformsmith-scratch-") -> Path:
    """A new temporary folder for a cached task's file outputs; it goes away once they are safely stored."""
    folder = Path(os.path.abspath(tempfile.mkdtemp(prefix=prefix)))
    with _SCRATCH_LOCK:
        _SCRATCH.add(folder)
    return folder


def _scratch_of(path: Path) -> Path | None:
    """The registered scratch folder holding `path`, if any."""
    p = Path(os.path.abspath(path))
    with _SCRATCH_LOCK:
        return next((d for d in _SCRATCH if p == d or d in p.parents), None)


def _path_pairs(value: Any, stored: Any) -> list[tuple[Path, Path]]:
    """(returned path, stored path) pairs of two value trees of the same shape."""
    if isinstance(value, Path) and isinstance(stored, Path):
        return [(value, stored)]
    if isinstance(value, dict) and isinstance(stored, dict):
        return [pair for k in value if k in stored for pair in _path_pairs(value[k], stored[k])]
    if isinstance(value, (list, tuple)) and isinstance(stored, (list, tuple)) and len(value) == len(stored):
        return [pair for a, b in zip(value, stored) for pair in _path_pairs(a, b)]
    return []


def _has_scratch_path(value: Any) -> bool:
    if isinstance(value, Path):
        return _scratch_of(value) is not None
    if isinstance(value, dict):
        return any(_has_scratch_path(v) for v in value.values())
    if isinstance(value, (list, tuple)):
        return any(_has_scratch_path(v) for v in value)
    return False


def _note_stored(store: CacheStore, key: str, value: Any) -> None:
    """After a put: remember where the value's scratch files now live (read back from the verified entry)."""
    if not _has_scratch_path(value):
        return
    stored, _ = store.load(key)  # verified digests: the copies are intact
    with _SCRATCH_LOCK:
        for src, dst in _path_pairs(value, stored):
            if dst.exists():
                _RELOCATED[Path(os.path.abspath(src))] = dst


def _relocate(value: Any) -> Any:
    """The value with stored scratch files replaced by their stored copies; emptied scratch folders removed."""
    moved: set[Path] = set()
    kept: set[Path] = set()

    def walk(v: Any) -> Any:
        if isinstance(v, Path):
            folder = _scratch_of(v)
            if folder is None:
                return v
            with _SCRATCH_LOCK:
                dst = _RELOCATED.pop(Path(os.path.abspath(v)), None)
            (moved if dst is not None else kept).add(folder)
            return dst if dst is not None else v
        if isinstance(v, dict):
            return {k: walk(x) for k, x in v.items()}
        if isinstance(v, list):
            return [walk(x) for x in v]
        if isinstance(v, tuple):
            return tuple(walk(x) for x in v)
        return v

    out = walk(value)
    for folder in moved - kept:  # every returned file of the folder is in the store
        shutil.rmtree(folder, ignore_errors=True)
        with _SCRATCH_LOCK:
            _SCRATCH.discard(folder)
            for p in [p for p in _RELOCATED if folder in p.parents]:
                _RELOCATED.pop(p)
    return out


_STORES: dict[Path, CacheStore] = {}


def store_for(root: Path | None = None) -> CacheStore:
    """The process-wide CacheStore of a root (default: the resolved cache root)."""
    root = (root or cache_root()).absolute()
    if root not in _STORES:
        _STORES[root] = CacheStore(root)
    return _STORES[root]


class StoreResultStorage(WritableFileSystem):
    """Prefect result storage backed by CacheStore: one verified Zarr group per cache key."""

    _block_type_name = "DeformSmith Cache Store"
    root: str | None = None  # None: the cache root resolved at use (`--cache` / env / user dir)

    def _store(self) -> CacheStore:
        return store_for(Path(self.root) if self.root else None)

    def _resolve_path(self, path: str) -> Path:
        return self._store().root / "entries" / path

    def read_path(self, path: str, _sync: bool | None = None) -> bytes:  # type: ignore[override]  # sync only
        """Prefect record of the entry (verified); raises if missing or corrupt, which Prefect treats as a miss."""
        key = Path(path).name
        value, meta = self._store().load_keep(key)
        metadata = meta.get("prefect_metadata") or {"serializer": {"type": SERIALIZER_TYPE}, "storage_key": path}
        import json

        return json.dumps({"metadata": metadata, "result": _handoff_put(value)}).encode()

    def write_path(self, path: str, content: bytes, _sync: bool | None = None) -> str:  # type: ignore[override]  # sync only
        """Publish the handed-off result under the key atomically."""
        import json

        record = json.loads(content)
        value = _handoff_pop(record["result"])
        if isinstance(value, BaseException):
            # Prefect persists a failed run's exception under a random key; nothing reads it back and the store
            # keeps results only (a failure must not look like an entry), so it is dropped here
            return path
        ctx = TaskRunContext.get()
        if ctx is not None and take_mark(ctx.task_run.id):
            return path  # a stand-in result (cache.dont_store): returned to the caller, never stored
        meta = {"prefect_metadata": record["metadata"]}
        if ctx is not None:
            meta.update(task=ctx.task.name, version=ctx.task.version)
        store = self._store()
        store.put(Path(path).name, value, meta)
        _note_stored(store, Path(path).name, value)
        return path

    async def aread_path(self, path: str) -> bytes:
        """Async form of read_path."""
        return await asyncio.to_thread(self.read_path, path)

    async def awrite_path(self, path: str, content: bytes) -> str:
        """Async form of write_path."""
        return self.write_path(path, content)  # same thread: the handoff and task context live here


@dataclass
class ContentCachePolicy(CachePolicy):
    """Cache key = sha256 of (task name, explicit version, bound inputs by content)."""

    task_name: str = ""
    version: str = ""

    def compute_key(
        self, task_ctx: TaskRunContext, inputs: dict[str, Any], flow_parameters: dict[str, Any], **kwargs: Any
    ) -> str | None:
        """Content key of the inputs; failures are remembered so the task fails loudly instead of uncached."""
        t0 = time.perf_counter()
        run_id = task_ctx.task_run.id if task_ctx and task_ctx.task_run else None
        fn = task_ctx.task.fn if task_ctx else None
        try:
            bound = _bind(fn, inputs)
            key = content_key(KEY_SCHEMA, self.task_name, self.version, bound)
        except Exception as exc:
            with _RUNS_LOCK:
                _RUNS[run_id] = _Run(error=f"{type(exc).__name__}: {exc}", t0=t0)
            raise
        with _RUNS_LOCK:
            _RUNS[run_id] = _Run(key=key, t0=t0, key_s=time.perf_counter() - t0)
        return key


def _bind(fn: Callable[..., Any] | None, inputs: dict[str, Any]) -> dict[str, Any]:
    """Inputs with defaults applied, so f(x) and f(x, q=<default>) share a key."""
    if fn is None:
        return dict(inputs)
    try:
        sig = inspect.signature(fn)
        bound = sig.bind_partial(**inputs)
        bound.apply_defaults()
        return dict(bound.arguments)
    except TypeError:
        return dict(inputs)


def _check_run(run_id: Any) -> None:
    with _RUNS_LOCK:
        run = _RUNS.get(run_id)
    if run is not None and run.error is not None:
        raise CacheError(f"cannot compute the cache key of the inputs: {run.error}")


def _finish_run(run_id: Any, exec_s: float) -> None:
    with _RUNS_LOCK:
        run = _RUNS.get(run_id)
        if run is not None:
            run.exec_s = exec_s


def _record_cache_event(tsk: Any, task_run: Any, state: Any) -> None:
    """on_completion hook: append hit/miss with key, task, version and wall time to the execution log."""
    with _RUNS_LOCK:
        run = _RUNS.pop(task_run.id, None)
    if run is None or run.key is None:
        return
    store_for().record_event(
        key=run.key,
        task=tsk.name,
        version=tsk.version,
        outcome="hit" if state.name == "Cached" else "miss",
        wall_s=round(time.perf_counter() - run.t0, 6),
        key_s=round(run.key_s, 6),
        exec_s=None if run.exec_s is None else round(run.exec_s, 6),
        task_run_id=str(task_run.id),
        flow_run_id=str(task_run.flow_run_id) if task_run.flow_run_id else None,
    )


class CachedTask(Task):
    """A Prefect Task whose result storage is the content store (kept through `with_options`).

    Called for its result, a miss returns file outputs as their stored copies (as a hit does), and the task's
    scratch folder is removed (see `scratch_dir`).
    """

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        """Run (or reuse) the task; file outputs come back inside the cache."""
        if FlowRunContext.get() is None and TaskRunContext.get() is None:
            # called outside any flow: the same local runtime as the flows (the prestarted server, no heartbeat)
            with local_runtime():
                out = super().__call__(*args, **kwargs)
        else:
            out = super().__call__(*args, **kwargs)
        if kwargs.get("return_state"):
            return out
        if inspect.isawaitable(out):

            async def relocated() -> Any:
                return _relocate(await out)

            return relocated()
        return _relocate(out)

    def with_options(self, *args: Any, **kwargs: Any) -> Any:
        """Like Task.with_options; the copy keeps the store-backed result storage."""
        kwargs["result_storage"] = None
        return _as_cached(super().with_options(*args, **kwargs))


def _as_cached(made: Task) -> Any:
    """Attach the store-backed result storage after construction.

    Prefect's constructor insists that block instances be saved on a server; this one has nothing to save (it
    resolves the cache root at use), so it is set afterwards and `storage_block_id` stays None.
    """
    made.__class__ = CachedTask
    made.result_storage = StoreResultStorage()
    return made


def cached_task(version: str | int, name: str | None = None, **prefect_task_kwargs: Any) -> Callable[[F], Any]:
    """Decorate a function as a Prefect task cached by content (see cache/__init__.py)."""
    version = str(version)

    def decorate(fn: F) -> Any:
        task_name = name or f"{fn.__module__}.{fn.__qualname__}"
        policy = ContentCachePolicy(task_name=task_name, version=version).configure(
            isolation_level="SERIALIZABLE", lock_manager=FlockLockManager()
        )

        if inspect.iscoroutinefunction(fn):

            @functools.wraps(fn)
            async def run_async(*args: Any, **kwargs: Any) -> Any:
                run_id = _current_run_id()
                _check_run(run_id)
                t0 = time.perf_counter()
                out = await fn(*args, **kwargs)
                codec.encode(out)  # unsupported output types fail the task instead of silently not caching
                _finish_run(run_id, time.perf_counter() - t0)
                return out

            body: Callable[..., Any] = run_async
        else:

            @functools.wraps(fn)
            def run_sync(*args: Any, **kwargs: Any) -> Any:
                run_id = _current_run_id()
                _check_run(run_id)
                t0 = time.perf_counter()
                out = fn(*args, **kwargs)
                codec.encode(out)
                _finish_run(run_id, time.perf_counter() - t0)
                return out

            body = run_sync

        hooks = list(prefect_task_kwargs.pop("on_completion", None) or [])
        made = task(
            name=task_name,
            version=version,
            cache_policy=policy,
            persist_result=True,
            result_serializer=StoreHandoffSerializer(),
            on_completion=[_record_cache_event, *hooks],
            **prefect_task_kwargs,
        )(body)
        return _as_cached(made)

    return decorate

