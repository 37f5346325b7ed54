"""Unusable output or cache locations: one `error:` line naming the path and the cause, exit 2, nothing written.

The tests run as root on CI, where chmod does not stop writes: they use places no one can write to (/proc, /sys), a
path whose parent is a regular file, and a free-space requirement larger than the disk.
"""

from __future__ import annotations

import errno
import os
import subprocess
import sys
from pathlib import Path

import pytest

from contracts.errors import InputError
from flows.cli import main as cli_main
from tasks import preflight

REPO = Path(__file__).resolve().parents[2]


def _cli(*args: str, env: dict[str, str] | None = None, base: dict[str, str] | None = None
         ) -> subprocess.CompletedProcess[str]:
    """The command with `env` over `base` (conftest's `cli_env`: the session's Prefect server) or this process's."""
    return subprocess.run([sys.executable, "-m", "flows.cli.main", *args], cwd=REPO, capture_output=True, text=True,
                          timeout=120, env={**(base or os.environ), **(env or {})})


def _one_error_line(proc: subprocess.CompletedProcess[str]) -> str:
    assert proc.returncode == 2, proc.stderr[-3000:]
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), proc.stderr[-3000:]
    assert "Traceback" not in proc.stderr
    return lines[0]


def _snapshot(root: Path) -> list[str]:
    return sorted(str(p.relative_to(root)) for p in root.rglob("*")) if root.exists() else []


@pytest.mark.parametrize("case", ["out_under_proc", "out_parent_is_file", "cache_not_creatable", "cache_locks_file",
                                  "disk_too_full"])
def test_unusable_location_is_one_error_line(case: str, tmp_path: Path, cache_dir: Path,
                                            cli_env: dict[str, str]) -> None:
    blocker = tmp_path / "plain_file"
    blocker.write_text("not a directory")
    out, env, want = tmp_path / "assets" / "duck", {}, ""
    if case == "out_under_proc":
        out, want = Path("/proc/deformsmith-test/duck"), "--out: cannot use /proc/deformsmith-test"
    elif case == "out_parent_is_file":
        out, want = blocker / "duck", f"{blocker} is a file, not a directory"
    elif case == "cache_not_creatable":
        env["DEFORMSMITH_CACHE"], want = str(blocker / "cache"), "cache root: cannot use"
    elif case == "cache_locks_file":  # the cache exists, but its lock files cannot be made (even a cached request)
        cache_dir.mkdir(parents=True)
        (cache_dir / "locks").write_text("")
        want = f"cache root: cannot use {cache_dir / 'locks'}"
    else:
        env[preflight.MIN_FREE_ENV], want = "1e12", "MB needed"
    before = _snapshot(tmp_path)
    commands = [["generate", "a rubber duck", "--no-l3"]] + ([["geometry", "a rubber duck"]] if case == "out_under_proc"
                                                             or case == "cache_locks_file" else [])
    for command in commands:
        line = _one_error_line(_cli(*command, "--out", str(out), env=env, base=cli_env))
        assert want in line, line
        assert _snapshot(tmp_path) == before  # nothing written, not even a parent directory
        assert not out.exists()


def test_check_directory_accepts_a_new_directory_without_creating_it(tmp_path: Path) -> None:
    target = tmp_path / "a" / "b"
    preflight.check_directory(target, "--out", min_free=0)
    assert list(tmp_path.iterdir()) == []  # the probe file is gone, nothing created
    with pytest.raises(InputError, match=r"--out: cannot use /sys/.*: permission denied|no such file"):
        preflight.check_directory(Path("/sys/deformsmith-test"), "--out", min_free=0)


@pytest.mark.parametrize("code, cause", [(errno.EROFS, "read-only file system"), (errno.ENOSPC, "no space left"),
                                         (errno.EACCES, "permission denied"), (errno.ENOENT, "no such file")])
def test_filesystem_errors_met_later_are_one_line(code: int, cause: str, monkeypatch: pytest.MonkeyPatch,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    """An OSError raised mid-run (a full disk while writing a layer) ends as one line with the path and exit 2."""
    def app() -> None:
        raise OSError(code, os.strerror(code), "/data/assets/.duck.partial-x/geometry.json")

    monkeypatch.setattr(cli_main, "app", app)
    monkeypatch.setattr(sys, "argv", ["deformsmith", "schema"])
    with pytest.raises(SystemExit) as exit_info:
        cli_main.main()
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("error: cannot use /data/assets/.duck.partial-x/geometry.json: ")
    assert cause in err


def test_programming_errors_are_not_disguised(monkeypatch: pytest.MonkeyPatch) -> None:
    def app() -> None:
        raise OSError(errno.EBADF, "Bad file descriptor")

    monkeypatch.setattr(cli_main, "app", app)
    monkeypatch.setattr(sys, "argv", ["deformsmith", "schema"])
    with pytest.raises(OSError):
        cli_main.main()
