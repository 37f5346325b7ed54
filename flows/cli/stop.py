"""SIGINT (Ctrl-C) and SIGTERM (a scheduler's `timeout`, `kill`): one line on stderr, exit 130 / 143 within ~2 s.

On the first signal the handler says so in one line, silences everything after it (Python's logging, and stderr at
the file-descriptor level: Prefect's crash records, its API client's retries, tracebacks of threads), and raises
KeyboardInterrupt in the main thread: the run unwinds as Ctrl-C always unwound it (a working directory removed by its
`finally`, nothing published, finished tasks in the cache). `main` then ends the process through `leave`. A backstop
thread ends it `BACKSTOP_S` after the signal if the unwinding has not by then (a blocking call, a library retrying a
server that is gone); a second signal ends it at once. Ending it: the child processes (Prefect's local server, batch
requests, evaluation workers) are stopped, this process's own working directories removed, the output flushed,
os._exit (no interpreter teardown, no joins of threads that may never end). The cache is as a kill leaves it: its
entries are written atomically, and what a dead writer left is tidied by the next run or `cache gc`.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
from pathlib import Path
from collections.abc import Callable
from types import FrameType
from typing import NoReturn

from cache.runtime import leave_sigterm_to
from cache.tempfiles import remove_own_working_dirs
from tasks.processes import stop_children

BACKSTOP_S = 1.3  # after the signal, the process ends by this time even if its main thread has not unwound [s]
CHILD_GRACE_S = 0.4  # children get this long to end after SIGTERM (SIGINT for a batch request) before SIGKILL [s]
LINES = {signal.SIGINT: "interrupted", signal.SIGTERM: "stopped by SIGTERM"}
RESUMES = "; finished tasks are cached: the same command resumes from them"


class _State:
    signum: int | None = None
    resumes = False  # a command whose finished tasks are cached (the line says a rerun resumes from them)
    argv: list[str] = []


def install(argv: list[str], resumes: bool) -> Callable[[], None]:
    """Take SIGTERM, and SIGINT unless it is ignored (a background job), in the main thread; returns what puts the
    previous handlers back. `resumes`: the command runs cached tasks. Prefect's flow engine is kept from taking
    SIGTERM over while a flow runs."""
    if threading.current_thread() is not threading.main_thread():
        return lambda: None
    _State.argv, _State.resumes, _State.signum = list(argv), resumes, None
    previous = {sig: signal.getsignal(sig) for sig in (signal.SIGTERM, signal.SIGINT)}
    signal.signal(signal.SIGTERM, _on_signal)
    if previous[signal.SIGINT] is not signal.SIG_IGN:
        signal.signal(signal.SIGINT, _on_signal)

    leave_sigterm_to(_on_signal)

    def restore() -> None:
        for sig, handler in previous.items():
            if handler is not None:
                signal.signal(sig, handler)

    return restore


def stopped() -> int | None:
    """The exit status a stop signal asks for (130, 143), or None when none came."""
    return None if _State.signum is None else 128 + _State.signum


def _on_signal(signum: int, frame: FrameType | None) -> None:
    if _State.signum is not None:  # a second signal: no more waiting
        leave(128 + _State.signum)
    _State.signum = signum
    line = LINES.get(signal.Signals(signum), f"stopped by {signal.Signals(signum).name}")
    _say(line + (RESUMES if _State.resumes else ""))
    _silence()
    threading.Thread(target=_backstop, name="stop-backstop", daemon=True).start()
    raise KeyboardInterrupt


def _say(line: str) -> None:
    """The one line, on a line of its own (a status spinner's line cleared, the cursor it hid shown)."""
    try:
        sys.stderr.flush()
    except (OSError, ValueError):
        pass
    try:
        prefix = "\r\x1b[2K\x1b[?25h" if os.isatty(2) else ""
        os.write(2, (prefix + line + "\n").encode())
    except OSError:
        pass


def _silence() -> None:
    """Nothing more on stderr: logging off, fd 2 onto /dev/null (Python's writes and native ones alike)."""
    import logging

    logging.disable(logging.CRITICAL)
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, 2)
        os.close(null)
    except OSError:
        pass


def _backstop() -> None:
    time.sleep(BACKSTOP_S)
    leave(stopped() or 130)


def leave(code: int) -> NoReturn:
    """End the process now: children stopped, own working directories removed, output flushed, os._exit(code)."""
    try:
        stop_children(CHILD_GRACE_S)
        _remove_own_working_dirs()
    finally:
        flush_and_exit(code)


def flush_and_exit(code: int) -> NoReturn:
    """Flush stdout and stderr (a closed or broken stream is skipped) and end the process with os._exit(code)."""
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    os._exit(code)


def _remove_own_working_dirs() -> None:
    """This process's working directories (cache.tempfiles.remove_own_working_dirs) beside the paths its command line
    names (and in out/, generate's default parent) that its unwinding did not get to remove."""
    places: set[Path] = {Path("out").absolute()}
    for arg in _State.argv[1:]:
        value = arg.split("=", 1)[1] if arg.startswith("--") and "=" in arg else arg
        if value.startswith("-") or not value:
            continue
        path = Path(value).expanduser().absolute()
        places.update((path, path.parent, path / "export"))
    remove_own_working_dirs(places)
