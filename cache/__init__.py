"""Content-addressed result cache: hashing, a Zarr store, and the Prefect cached-task integration.

Interface (stable; other packages code against it)::

    from cache import cached_task, content_key, CacheStore, cache_root

    @cached_task(version="1")          # name defaults to "<module>.<qualname>"; name="..." overrides
    def build_mesh(program: ShapeProgram, quality: str, seed: int) -> MeshResult: ...

- ``cached_task(version, name=None, **prefect_task_kwargs)`` -> a Prefect task. Cache key = sha256 of (task name,
  explicit version, inputs bound with defaults, by content). A hit is a Prefect state named "Cached" and runs nothing.
  Bump ``version`` whenever the function's code (or anything it calls) changes its output. Works inside flows and
  called directly outside a flow. Key errors (unhashable input) and unstorable outputs fail the task (CacheError/TypeError).
  Two processes on one key: a per-key flock (SERIALIZABLE) gives one execution; the other gets a hit.
- Hashable inputs / storable outputs: pydantic models (canonical JSON + class name), numpy arrays (dtype + shape +
  bytes), ``pathlib.Path`` of an existing file or directory (hashed by content; as an output it is copied into the
  entry and comes back as a path inside the cache, on a miss as on a hit; write such outputs into
  ``scratch_dir(prefix)``, a temporary folder removed once its files are stored), str/int/float/bool/None, numpy
  scalars, and dict (str keys) / list / tuple of these. Outputs come back as the same types (models as their class, tuples as tuples).
- ``content_key(*parts) -> str``: hex sha256 of the parts (same rules as above).
- ``cache_root(cli_value=None) -> Path``: ``--cache`` value > ``$DEFORMSMITH_CACHE`` > user cache dir.
  ``use_cache_root(value)`` also exports it to ``$DEFORMSMITH_CACHE`` (what the CLI's ``--cache`` does).
- ``CacheStore(root)``: ``get(key)`` (value; raises ``CacheMiss``, a KeyError, when missing or corrupt -- a corrupt
  entry is never returned), ``load(key) -> (value, meta)``, ``put(key, value, meta=None) -> bool`` (atomic; False if
  an intact entry was kept), ``contains(key)``, ``remove(key)``, ``keys()``, ``stats()``, ``verify(remove=False) ->
  [Problem(key, reason)]``, ``gc(older_than_s=None, max_bytes=None)``, ``events()``.
- Execution log: ``CacheStore(cache_root()).events()`` -> list of dicts, one per cached-task run, in order:
  ``{"key", "task", "version", "outcome": "hit"|"miss", "wall_s", "key_s", "exec_s", "task_run_id",
  "flow_run_id", "time", "pid"}``. "miss" means the function executed. Tests: read it before/after a run and compare
  the task names of the new "miss" records.

Layout under the root: ``entries/<k[:2]>/<key>/`` (one Zarr v3 group: arrays ``a0, a1, ...`` uncompressed, attributes
``deformsmith`` = value tree with type tags, digests, meta; copied files in ``_files/``), ``tmp/`` (entries being
written; published by rename), ``locks/`` (flock files), ``events.jsonl``, marker file ``DEFORMSMITH_CACHE``.
"""

from typing import Any

from cache.runtime import configure_prefect_env

configure_prefect_env()  # before prefect is imported: local PREFECT_HOME default, analytics off

from cache.config import cache_relative, cache_resolve, cache_root, use_cache_root  # noqa: E402
from cache.dont_store import dont_store  # noqa: E402

_LAZY = {  # heavy imports (prefect ~2.5 s, zarr ~0.4 s, numpy ~0.3 s) only when used, so the CLI starts fast
    "content_key": "cache.hashing",
    "cached_task": "cache.prefect_task",
    "local_runtime": "cache.runtime",
    "CacheMiss": "cache.store",
    "CacheStore": "cache.store",
    "Problem": "cache.store",
    "scratch_dir": "cache.prefect_task",
}


def __getattr__(name: str) -> Any:
    """Import the lazily exported names on first use."""
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'cache' has no attribute {name!r}")


__all__ = [
    "CacheMiss",
    "CacheStore",
    "Problem",
    "cache_root",
    "cached_task",
    "content_key",
    "dont_store",
    "local_runtime",
    "scratch_dir",
    "use_cache_root",
    "cache_relative",
    "cache_resolve",
]
