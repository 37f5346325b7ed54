"""Publish a finished directory in place of another with renames, so readers never see a half-written one.

`generate` builds an asset in a private working directory beside its output (`working_dir`) and publishes it with
one rename (`publish_directory`).

`staged_update(asset)` is how a layer rerun (`deformsmith physical | material | manipulate DIR`) publishes: the layer
writes into a working copy beside the asset (`.NAME.partial-<host>~<pid>~*`: small files copied, the others hard
links, which writers replace and never rewrite), and the copy is swapped in for the asset in one atomic rename
(renameat2 RENAME_EXCHANGE) once the layer ends cleanly. An exception, a SIGKILL or a full disk at any point leaves
the asset as it was or as the layer left it, its files and its evidence together, never a mix.
"""

from __future__ import annotations

import ctypes
import errno
import json
import os
import shutil
import stat
import tempfile
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from cache.tempfiles import dead_partials, owner_tag, remove_paths
from contracts.asset_dir import ASSET_JSON
from contracts.errors import InputError

COPY_BELOW_BYTES = 1 << 20  # files smaller than this are copied into a working copy, larger ones hard-linked [B]
COPIED_SUFFIXES = (".json", ".jsonl")  # documents and evidence: always copied (writers may rewrite them)
_RENAME_EXCHANGE = 2  # linux/fs.h
_AT_FDCWD = -100


def check_out_dir(out_dir: Path) -> None:
    """InputError unless `out_dir` is somewhere an asset may be published: absent, an empty directory, or an earlier
    asset (its asset.json), which the publish replaces."""
    if out_dir.exists() and (not out_dir.is_dir() or (any(out_dir.iterdir()) and not (out_dir / ASSET_JSON).exists())):
        raise InputError(f"{out_dir} exists and is not an asset directory; choose a new or empty directory")


def remove_stale_partials(dest: Path) -> list[Path]:
    """Remove the working directories of `dest` beside it (`.<name>.{partial,tmp,old}-<host>~<pid>~*`) that a process
    of this host left when it died (SIGKILL, power loss); returns those removed."""
    return remove_paths(dead_partials(dest.parent, dest.name))[0]


def working_dir(dest: Path) -> Path:
    """A private working directory beside `dest`, `.<name>.partial-<host>~<pid>~<random>`, so that a dead owner can be
    recognised; those a dead process left for `dest` are removed first (remove_stale_partials)."""
    remove_stale_partials(dest)
    return Path(tempfile.mkdtemp(prefix=f".{dest.name}.partial-{owner_tag()}", dir=dest.parent))


def set_aside(dest: Path) -> Path | None:
    """Move `dest` out of the way, to `previous` in a new `.<name>.old-<owner>` folder beside it (a dead owner's is
    cleared by remove_stale_partials); returns that folder, None when `dest` does not exist."""
    if not dest.exists():
        return None
    aside = Path(tempfile.mkdtemp(prefix=f".{dest.name}.old-{owner_tag()}", dir=dest.parent))
    os.replace(dest, aside / "previous")
    return aside


def replace_directory(finished: Path, dest: Path) -> None:
    """Rename `finished` to `dest` (same filesystem); an existing `dest` is moved aside first, then removed."""
    finished, dest = Path(finished), Path(dest)
    aside = set_aside(dest)
    os.replace(finished, dest)
    if aside is not None:
        shutil.rmtree(aside, ignore_errors=True)


def publish_directory(work: Path, dest: Path) -> None:
    """Publish the finished `work` as `dest`: a previous `dest` is set aside first, so that removing its ~350 files does
    not hold up the rename, and is removed by a thread beside the rest of the run (joined before the process ends);
    when the rename fails, it is put back."""
    previous = set_aside(dest)
    try:
        replace_directory(work, dest)  # (dest is free: a rename)
    except BaseException:
        if previous is not None and not dest.exists():  # the previous directory stays in place
            os.replace(previous / "previous", dest)
            shutil.rmtree(previous, ignore_errors=True)
        raise
    if previous is not None:
        threading.Thread(target=shutil.rmtree, args=(previous,), kwargs={"ignore_errors": True},
                         name="remove-previous-asset").start()


def write_json_atomic(path: Path, record: Any, default: Callable[[Any], Any] | None = str) -> None:
    """Write a JSON record (sorted keys, indented) to a temporary name and rename it into place."""
    write_text_atomic(path, json.dumps(record, indent=2, sort_keys=True, default=default) + "\n")


def write_text_atomic(path: Path, text: str) -> Path:
    """Write a text file under a temporary name and rename it into place (never rewrites the old file's inode)."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        tmp.write_text(text, encoding="utf-8")
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
    return path


def copy_file_atomic(src: Path, dest: Path) -> Path:
    """Copy a file so that `dest` appears only complete, as a new file (a hard link to the old one is not rewritten)."""
    dest = Path(dest)
    dest.parent.mkdir(parents=True, exist_ok=True)
    tmp = dest.with_name(f".{dest.name}.{os.getpid()}.tmp")
    try:
        shutil.copyfile(src, tmp)
        os.replace(tmp, dest)
    finally:
        tmp.unlink(missing_ok=True)
    return dest


def exchange_directories(a: Path, b: Path) -> bool:
    """Swap two directories of one filesystem in one atomic rename (Linux renameat2 RENAME_EXCHANGE); False where
    the system or the filesystem cannot (the caller falls back to two renames); other errors raise OSError."""
    try:
        renameat2 = ctypes.CDLL(None, use_errno=True).renameat2
    except (AttributeError, OSError):
        return False
    renameat2.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    renameat2.restype = ctypes.c_int
    if renameat2(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP):
        return False
    raise OSError(code, os.strerror(code), str(a), None, str(b))


def _copied(path: Path, size: int) -> bool:
    """A file a working copy holds as its own copy (not a hard link)."""
    return size < COPY_BELOW_BYTES or path.suffix in COPIED_SUFFIXES or "evidence" in path.parts


def mirror_tree(src: Path, dest: Path) -> None:
    """Fill the empty directory `dest` with `src`'s tree: small files, documents and evidence copied (with their
    times), other files hard-linked (copied where links are refused), symbolic links as links, modes kept."""
    src, dest = Path(src), Path(dest)
    for root, dirs, files in os.walk(src):
        rel = Path(root).relative_to(src)
        here = dest / rel
        for d in dirs:
            s = Path(root) / d
            if s.is_symlink():
                os.symlink(os.readlink(s), here / d)
            else:
                os.mkdir(here / d)
                os.chmod(here / d, stat.S_IMODE(s.stat().st_mode))
        dirs[:] = [d for d in dirs if not (Path(root) / d).is_symlink()]
        for f in files:
            s, t = Path(root) / f, here / f
            info = s.lstat()
            if stat.S_ISLNK(info.st_mode):
                os.symlink(os.readlink(s), t)
            elif _copied(rel / f, info.st_size):
                shutil.copy2(s, t)
            else:
                try:
                    os.link(s, t)
                except OSError:
                    shutil.copy2(s, t)
    os.chmod(dest, stat.S_IMODE(src.stat().st_mode))


def swap_in(work: Path, dest: Path) -> None:
    """Put the finished working copy `work` in place of `dest`: one atomic exchange (the old tree is then at `work`),
    else two renames (replace_directory)."""
    if not exchange_directories(work, dest):
        aside = Path(tempfile.mkdtemp(prefix=f".{dest.name}.old-{owner_tag()}", dir=dest.parent))
        os.replace(dest, aside / "previous")
        try:
            os.replace(work, dest)
        except BaseException:
            os.replace(aside / "previous", dest)
            os.rmdir(aside)
            raise
        os.replace(aside, work)  # removed with the working copy


@contextmanager
def staged_update(dest: Path) -> Iterator[Path]:
    """A working copy of the directory `dest` to write into; swapped in for `dest` when the block ends cleanly, removed
    (and `dest` untouched) when it raises or the process dies (the next staged update removes a dead one's copy)."""
    shown, dest = Path(dest).absolute(), Path(dest).resolve()  # a link to the directory: the directory is swapped
    work = working_dir(dest)
    try:
        mirror_tree(dest, work)
        yield work
        swap_in(work, dest)
    except OSError as exc:  # name the asset's path, not the working copy's (which is gone)
        raise _in_dest(exc, work, shown) from None
    finally:
        shutil.rmtree(work, ignore_errors=True)


def _in_dest(exc: OSError, work: Path, dest: Path) -> OSError:
    """The same error with paths inside the working copy `work` named inside `dest` instead."""
    names = [exc.filename, exc.filename2]
    moved = [str(dest) + str(n)[len(str(work)):] if n is not None and (str(n) + "/").startswith(str(work) + "/")
             else n for n in names]
    if moved == names or exc.errno is None:
        return exc
    out = type(exc)(exc.errno, exc.strerror, moved[0], None, moved[1])
    out.__traceback__ = exc.__traceback__
    return out
