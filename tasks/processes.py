"""Child processes of this one, and a child's watch on its parent: the command line's stop signal ends every child
(Prefect's local server, batch requests, evaluation workers), a batch runs each request in a process group of its own
and stops them all when it is interrupted, and a request ends itself when its batch is gone. Standard library only."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any


def child_pids() -> list[int]:
    """This process's child processes (Linux /proc; elsewhere those multiprocessing and the prestart know of)."""
    me, found = os.getpid(), []
    try:
        for entry in os.scandir("/proc"):
            if entry.name.isdigit():
                try:
                    with open(f"/proc/{entry.name}/stat", "rb") as fh:
                        stat = fh.read()
                except OSError:
                    continue
                fields = stat[stat.rfind(b")") + 2:].split()  # after "pid (comm) ": state, ppid, ...
                if len(fields) > 1 and int(fields[1]) == me:
                    found.append(int(entry.name))
        return found
    except OSError:
        pass
    import multiprocessing

    found = [p.pid for p in multiprocessing.active_children() if p.pid]
    server = sys.modules.get("cache.runtime")
    proc = getattr(getattr(server, "_PRESTART", None), "process", None)
    return found + ([proc.pid] if proc is not None and proc.poll() is None else [])


def stop_children(grace_s: float) -> None:
    """SIGINT to a child that leads a session of its own (a batch request: it removes its working directory), SIGTERM
    to the others (Prefect's server, workers); SIGKILL to their groups after grace_s. Reaped, so that none holds this
    process's stderr open after it ends."""
    children = child_pids()
    leaders = set()
    for pid in children:
        try:
            if os.getpgid(pid) == pid and os.getsid(pid) == pid:
                leaders.add(pid)
                os.killpg(pid, signal.SIGINT)
            else:
                os.kill(pid, signal.SIGTERM)
        except OSError:
            pass
    left, deadline = set(children), time.monotonic() + grace_s
    while left and time.monotonic() < deadline:
        for pid in list(left):
            try:
                done, _ = os.waitpid(pid, os.WNOHANG)
            except ChildProcessError:
                done = pid  # reaped elsewhere (its Popen object)
            if done:
                left.discard(pid)
        time.sleep(0.02)
    for pid in children:
        try:
            os.killpg(pid, signal.SIGKILL) if pid in leaders else os.kill(pid, signal.SIGKILL)
        except OSError:
            pass


def signal_group(proc: subprocess.Popen[bytes], sig: signal.Signals) -> None:
    """Send `sig` to the process group a child leads (gone or not ours: nothing)."""
    try:
        os.killpg(proc.pid, sig)
    except (ProcessLookupError, PermissionError):
        pass


class Children:
    """The batch's running request processes, so that an interrupted batch stops them (each runs in a session of its
    own, out of reach of the terminal's Ctrl-C) and starts no more."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._procs: set[subprocess.Popen[bytes]] = set()
        self.stopping = threading.Event()

    def start(self, cmd: list[str], **kwargs: Any) -> subprocess.Popen[bytes] | None:
        """Start a child in a new session; None once the batch is stopping."""
        with self._lock:
            if self.stopping.is_set():
                return None
            proc = subprocess.Popen(cmd, start_new_session=True, **kwargs)
            self._procs.add(proc)
            return proc

    def finished(self, proc: subprocess.Popen[bytes]) -> None:
        with self._lock:
            self._procs.discard(proc)

    def stop_all(self, grace_s: float = 10.0) -> None:
        """SIGINT to every child's process group (a request removes its working directory on the way out), SIGKILL
        to what is left after grace_s; no child starts after this."""
        with self._lock:
            self.stopping.set()
            procs = list(self._procs)
        for proc in procs:
            signal_group(proc, signal.SIGINT)
        deadline = time.monotonic() + grace_s
        try:
            for proc in procs:
                try:
                    proc.wait(timeout=max(0.0, deadline - time.monotonic()))
                except subprocess.TimeoutExpired:
                    pass
        finally:
            for proc in procs:
                signal_group(proc, signal.SIGKILL)  # also what the request left running in its group


@contextmanager
def sigterm_as_interrupt() -> Iterator[None]:
    """In the main thread, SIGTERM (a scheduler or `kill` stopping a batch) stops it as Ctrl-C does, so that its
    children, which run in sessions of their own, do not outlive it."""
    if threading.current_thread() is not threading.main_thread() or callable(signal.getsignal(signal.SIGTERM)):
        yield  # (a handler of the caller's own, as the command line's: it stops the batch as Ctrl-C does)
        return

    def interrupt(signum: int, frame: Any) -> None:
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGTERM, interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def stop_when_orphaned(parent: int | None = None, poll_s: float = 0.5, grace_s: float = 10.0) -> None:
    """Once the parent process is gone, interrupt the main thread as Ctrl-C would (directed at it, so that a blocking
    call returns), and exit after grace_s if it has not stopped by then. `parent`: the PID the parent passed down (a
    child reading its own parent's PID would read its adopter's when the parent died before it started watching, and
    never stop); by default the PID of the parent now."""
    parent = os.getppid() if parent is None else parent
    main_thread = threading.main_thread().ident
    assert main_thread is not None

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(poll_s)
        signal.pthread_kill(main_thread, signal.SIGINT)
        time.sleep(grace_s)
        os._exit(130)

    threading.Thread(target=watch, name="orphan-watch", daemon=True).start()
