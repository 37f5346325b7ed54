"""Pre-flight checks, run by the commands before any layer: the places a command writes (output parent, cache root),
a generation request's inputs (its image's header; an object the lexicon does not name, under --strict-concept), and
one-line filesystem errors.

Each location must exist or be creatable, be a directory a file can be created in, and have at
least `DEFORMSMITH_MIN_FREE_MB` megabytes free (default 100 MB). `filesystem_error` turns an OSError met anywhere
later (read-only, missing, full) into the InputError the CLI prints as one `error:` line with the path and the cause.
"""

from __future__ import annotations

import errno
import os
import shutil
import tempfile
from collections.abc import Sequence
from pathlib import Path

from cache import CacheMiss, CacheStore, cache_root, content_key
from cache.tempfiles import remove_dead_temporaries
from contracts.errors import CacheError, InputError
from tasks import asset_cache
from tasks.geometry.image_guard import check_image_size

MIN_FREE_MB_DEFAULT = 100.0  # free space a location must have before a run starts [MB]
MIN_FREE_ENV = "DEFORMSMITH_MIN_FREE_MB"
# errors of the place, not of the program: read-only, no permission, missing, full, not a directory
FILESYSTEM_ERRNOS = frozenset({errno.EROFS, errno.EACCES, errno.EPERM, errno.ENOSPC, errno.EDQUOT, errno.ENOENT,
                               errno.ENOTDIR, errno.EISDIR, errno.ENAMETOOLONG, errno.EEXIST, errno.ENOTEMPTY,
                               errno.EIO})
_CAUSES = {errno.EROFS: "read-only file system", errno.EACCES: "permission denied", errno.EPERM: "not permitted",
           errno.ENOSPC: "no space left on the device", errno.EDQUOT: "disk quota exceeded",
           errno.ENOENT: "no such file or directory",
           errno.ENOTDIR: "a part of the path is a file, not a directory", errno.EISDIR: "is a directory",
           errno.ENAMETOOLONG: "file name too long"}


def min_free_bytes() -> int:
    """Free space required in each written location [B]: DEFORMSMITH_MIN_FREE_MB (MB) or 100 MB."""
    raw = os.environ.get(MIN_FREE_ENV, "").strip()
    try:
        mb = float(raw) if raw else MIN_FREE_MB_DEFAULT
    except ValueError:
        raise InputError(f"{MIN_FREE_ENV}={raw!r} is not a number of megabytes") from None
    if mb < 0:
        raise InputError(f"{MIN_FREE_ENV}={raw!r} must not be negative")
    return int(mb * 1e6)


def is_filesystem_error(exc: BaseException) -> bool:
    """An OSError caused by the place written or read (read-only, missing, full ...), not by the program."""
    return isinstance(exc, OSError) and exc.errno in FILESYSTEM_ERRNOS


def filesystem_error(exc: OSError, what: str | None = None) -> InputError:
    """One-line InputError naming the path and the cause of a filesystem OSError."""
    path = exc.filename if exc.filename is not None else "?"
    cause = _CAUSES.get(exc.errno or 0) or exc.strerror or str(exc)
    if exc.filename2 is not None:
        path = f"{path} -> {exc.filename2}"
    return InputError(f"{what + ': ' if what else ''}cannot use {path}: {cause}")


def _existing_ancestor(path: Path) -> Path:
    """The deepest existing path on the way to `path` (itself when it exists)."""
    probe = path
    while not os.path.lexists(probe) and probe != probe.parent:
        probe = probe.parent
    return probe


def check_directory(path: Path, what: str, min_free: int | None = None) -> None:
    """`path` is (or can become) a directory files can be created in, with `min_free` bytes free; else InputError."""
    path = Path(path).expanduser().absolute()
    base = _existing_ancestor(path)
    if not base.is_dir():
        raise InputError(f"{what}: cannot use {path}: {base} is a file, not a directory")
    try:
        fd, name = tempfile.mkstemp(prefix=".deformsmith-probe-", dir=base)
        os.close(fd)
        os.unlink(name)
    except OSError as exc:
        cause = _CAUSES.get(exc.errno or 0) or exc.strerror or str(exc)
        where = "" if base == path else f" (files cannot be created in {base})"
        raise InputError(f"{what}: cannot use {path}{where}: {cause}") from None
    need = min_free_bytes() if min_free is None else min_free
    free = shutil.disk_usage(base).free
    if free < need:
        raise InputError(f"{what}: cannot use {path}: only {free / 1e6:.0f} MB free on its device, "
                         f"{need / 1e6:.0f} MB needed (set {MIN_FREE_ENV} to change)")


def check_locations(out: Path | None = None, cache: bool = True, out_root: Path | None = None) -> None:
    """Before any layer runs: the output's parent (when `out` is given), the folder `out_root` that holds many
    outputs (batch, eval) and the cache root are usable; then the cache's temporaries of dead processes go."""
    if out_root is not None:
        if Path(out_root).exists() and not Path(out_root).is_dir():
            raise InputError(f"--out: {out_root} is a file, not a directory")
        check_directory(out_root, "--out")
    if out is not None:
        out = Path(out).expanduser().absolute()
        if out.exists() and not out.is_dir():
            raise InputError(f"--out: {out} is a file, not a directory")
        check_directory(out.parent, "--out")
    if cache:
        root = cache_root()
        check_directory(root, "cache root")
        for sub in ("locks", "tmp", "entries", "recordings"):  # a fully cached request still writes its lock files
            if os.path.lexists(root / sub):
                check_directory(root / sub, "cache root", min_free=0)

        from cache import CacheStore  # lazy: cache.store pulls zarr (0.7 s at every CLI start)

        CacheStore(root).init_root()  # marked before any layer runs: a run stopped early leaves a sound cache
        remove_dead_temporaries(root)  # what killed runs left in the cache (their pids are dead)


def check_asset_dir(asset: Path, cache: bool = True) -> None:
    """Before a layer reruns on an asset directory (physical, material, manipulate): files can be created in the
    directory and beside it (its working copy, tasks.publish.staged_update) with free space there; then the cache
    root (check_locations)."""
    asset = Path(asset).expanduser().absolute()
    check_directory(asset, "asset directory", min_free=0)
    check_directory(asset.parent, "asset directory")
    check_locations(cache=cache)


def check_outputs(files: Sequence[Path | None] = (), folders: Sequence[Path | None] = ()) -> None:
    """Before a command writes files or folders named on its command line (replay's --video, --rrd, --frames): the
    folder each file goes into, and each folder, is (or can become) a usable directory."""
    for path, folder in [(f, False) for f in files] + [(f, True) for f in folders]:
        if path is not None:
            path = Path(path).expanduser().absolute()
            if folder and path.exists() and not path.is_dir():
                raise InputError(f"output: {path} is a file, not a directory")
            check_directory(path if folder else path.parent, "output")


def check_request(request, out: Path | None, cache: bool = True) -> None:
    """Every pre-flight check of a generation request: its image's header (decompression bombs) and the locations."""
    if request.image_path is not None and Path(request.image_path).is_file():
        check_image_size(request.image_path)
    check_locations(out, cache=cache)


def concept_line(request, strict: bool) -> str | None:
    """The one line saying that a text request's object is built by analogy (WordNet, a category, a material, a
    generic shape), or None when the lexicon names it; InputError with that line under --strict-concept."""
    if request.mesh_path is not None or not (request.text and request.text.strip()):
        return None
    line = _remembered_concept_line(request.text, request.size_hint_m)
    if line is not None and strict:
        raise InputError(f"--strict-concept: {line}")
    return line


CONCEPT_LINE_VERSION = "1"


def _remembered_concept_line(text: str, size_hint_m: float | None) -> str | None:
    """The analogy line of a text (None: the lexicon names its object), remembered in the result cache by the text, the
    size, the package's code and data and the library versions (tasks.asset_cache): reading the words (spaCy's model,
    the lexicon, WordNet) costs ~3 s of CPU, and a rerun that changed only an option (--record, --no-l3, --intent)
    would pay it again before its first line."""
    key = content_key("preflight.concept_line", CONCEPT_LINE_VERSION, text, size_hint_m, asset_cache.code_fingerprint(),
                      asset_cache.library_versions())
    store = CacheStore(cache_root())
    if store.entry_dir(key).is_dir():
        try:
            kept = store.get(key)
            if isinstance(kept, dict) and (kept.get("line") is None or isinstance(kept.get("line"), str)):
                return kept.get("line")
        except CacheMiss:
            pass
    # lazy: the offline Designer pulls scipy, skimage, trimesh (~2 s at CLI start)
    from tasks.geometry.catalogue import design_from_text

    concept = design_from_text(text, size_hint_m).concept
    line = concept.analogy_line() if concept is not None else None
    if not (store.root / "entries").is_dir():
        return line  # no cache in use yet: a command that keeps none (geometry) or is refused leaves none behind
    try:
        store.put(key, {"line": line}, {"task": "preflight.concept_line"})
    except (OSError, CacheError):
        pass  # not remembered: the next run reads the words again
    return line
