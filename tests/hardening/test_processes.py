"""A process's own housekeeping (tasks.processes, cache.tempfiles, tasks.publish): its children are found and stopped,
a batch's children stop with it, its own working directories go (a dead or another process's stay), and a publish
puts the previous directory back when the rename fails."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from cache.tempfiles import owner_tag, remove_own_working_dirs
from tasks.processes import Children, sigterm_as_interrupt
from tasks.publish import publish_directory, set_aside, working_dir


REPO = Path(__file__).resolve().parents[2]
# in a process of its own: stop_children ends every child of the process it runs in (a test worker's own Prefect
# server among them)
STOP_CHILDREN = """
import subprocess, sys, time
from tasks.processes import child_pids, stop_children
proc = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
found = proc.pid in child_pids()
t0 = time.monotonic()
stop_children(grace_s=2.0)
print(found, proc.pid not in child_pids(), time.monotonic() - t0 < 4)
"""


def test_children_are_found_and_stopped() -> None:
    out = subprocess.run([sys.executable, "-c", STOP_CHILDREN], cwd=REPO, capture_output=True, text=True, timeout=60,
                         env={**os.environ, "PYTHONPATH": str(REPO)})
    assert out.stdout.split() == ["True", "True", "True"], out.stderr


def test_a_stopping_batch_stops_its_children_and_starts_no_more() -> None:
    children = Children()
    proc = children.start([sys.executable, "-c", "import time; time.sleep(60)"])
    assert proc is not None and os.getpgid(proc.pid) == proc.pid  # a session (and group) of its own
    children.stop_all(grace_s=2.0)
    assert proc.wait(timeout=5) != 0  # interrupted
    assert children.start([sys.executable, "-c", "pass"]) is None


def test_sigterm_stops_the_main_thread_as_ctrl_c_does() -> None:
    if threading.current_thread() is not threading.main_thread():
        pytest.skip("signal handlers are the main thread's")
    previous = signal.signal(signal.SIGTERM, signal.SIG_DFL)
    try:
        with pytest.raises(KeyboardInterrupt), sigterm_as_interrupt():
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(5)
        assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL  # put back
    finally:
        signal.signal(signal.SIGTERM, previous)


# a batch's request whose batch died before the request started watching it (the race of a killed batch)
ORPHANED_EARLY = '''
import subprocess, sys, os
child = """
import signal, sys, time
signal.signal(signal.SIGINT, signal.default_int_handler)  # as flows.batch_job (SIGINT may be ignored in the test's)
time.sleep(1.0)  # the parent is gone by now
from tasks.processes import stop_when_orphaned
try:
    stop_when_orphaned(int(sys.argv[1]), poll_s=0.05, grace_s=5.0)
    time.sleep(60)
except KeyboardInterrupt:
    open(sys.argv[2], 'w').write('stopped')
"""
subprocess.Popen([sys.executable, '-c', child, str(os.getpid()), sys.argv[1]], start_new_session=True)
'''


def test_a_request_orphaned_before_it_watches_stops(tmp_path: Path) -> None:
    """The PID the parent passed down is compared, not the adopter's that a late watcher would read as its parent's."""
    flag = tmp_path / "stopped"
    subprocess.run([sys.executable, "-c", ORPHANED_EARLY, str(flag)], cwd=REPO, timeout=60,
                   env={**os.environ, "PYTHONPATH": str(REPO)}, check=True)
    deadline = time.monotonic() + 20.0  # (the child's open() makes the file before its write() fills it)
    while not (flag.is_file() and flag.read_text() == "stopped") and time.monotonic() < deadline:
        time.sleep(0.1)
    assert flag.is_file() and flag.read_text() == "stopped"


def test_only_this_process_working_directories_are_removed(tmp_path: Path) -> None:
    host = socket.gethostname()
    mine = [tmp_path / f".duck.partial-{owner_tag()}abc", tmp_path / f".duck.tmp-{owner_tag()}def"]
    kept = [tmp_path / f".duck.old-{owner_tag()}ghi",  # a set-aside previous asset: the next run's to restore
            tmp_path / f".duck.partial-{host}~1~jkl", tmp_path / f".duck.partial-elsewhere~{os.getpid()}~mno",
            tmp_path / "duck"]
    for d in mine + kept:
        d.mkdir()
    remove_own_working_dirs([tmp_path, tmp_path / "missing"])
    assert not any(d.exists() for d in mine) and all(d.exists() for d in kept)


def test_a_publish_replaces_the_previous_directory_or_puts_it_back(tmp_path: Path) -> None:
    out = tmp_path / "asset"
    out.mkdir()
    (out / "old").write_text("1")
    work = working_dir(out)
    assert work.parent == tmp_path and work.name.startswith(f".asset.partial-{owner_tag()}")
    (work / "new").write_text("2")
    publish_directory(work, out)
    assert (out / "new").exists() and not (out / "old").exists() and not work.exists()
    with pytest.raises(OSError):
        publish_directory(tmp_path / "never-built", out)  # the rename fails: the published directory stays
    assert (out / "new").exists()
    assert set_aside(tmp_path / "nothing") is None
