"""Local Prefect runtime: quiet, offline, no per-flow heartbeat; a user's PREFECT_API_URL is respected."""

from __future__ import annotations

import atexit
import contextlib
import importlib.util
import os
import socket
import subprocess
import sys
import threading
import time
import urllib.request
from collections.abc import Iterator
from pathlib import Path

import platformdirs

from cache.config import APP_NAME


def default_prefect_home() -> Path:
    """Where Prefect's local state (database, settings) lives unless PREFECT_HOME is set."""
    return Path(platformdirs.user_data_dir(APP_NAME)) / "prefect"


def configure_prefect_env() -> None:
    """Set env defaults Prefect reads at import time (call before `import prefect`; user values win)."""
    if "PREFECT_HOME" not in os.environ:
        home = default_prefect_home()
        with contextlib.suppress(OSError):
            home.mkdir(parents=True, exist_ok=True)  # Prefect itself creates only the last level
        os.environ["PREFECT_HOME"] = str(home)
    os.environ.setdefault("PREFECT_SERVER_ANALYTICS_ENABLED", "false")
    os.environ.setdefault("PREFECT_LOGGING_TO_API_WHEN_MISSING_FLOW", "ignore")  # tasks called outside flows
    # The temporary local server gets 20 s to start by default; on a busy laptop (or CI) that is not enough.
    os.environ.setdefault("PREFECT_SERVER_EPHEMERAL_STARTUP_TIMEOUT_SECONDS", "180")


# the API URL of a local server DeformSmith started for this process or for its parent (a batch or an evaluation
# sharing one server with its workers): flows against it run as locally as against Prefect's own temporary server
LOCAL_API_ENV = "DEFORMSMITH_LOCAL_PREFECT_API"


def uses_remote_server() -> bool:
    """True when the user points Prefect at their own server with PREFECT_API_URL (a local server DeformSmith
    started, named in DEFORMSMITH_LOCAL_PREFECT_API, is not theirs)."""
    from prefect.settings import PREFECT_API_URL

    url = PREFECT_API_URL.value()
    return bool(url) and str(url) != os.environ.get(LOCAL_API_ENV)


def set_env(values: dict[str, str]) -> None:
    """Worker-process initializer: export `values` (before anything imports Prefect in that process)."""
    os.environ.update(values)


def local_api_env(url: str) -> dict[str, str]:
    """Environment for a child process that uses the local server at `url` started here."""
    return {"PREFECT_API_URL": url, LOCAL_API_ENV: url}


def shared_server_env() -> dict[str, str]:
    """Environment for child processes to share this process's prestarted local server (waits for its start); {}
    against a user's server or when none is up (each child then runs as it would alone)."""
    if uses_remote_server():
        return {}
    url = prestarted_api_url()
    return local_api_env(url) if url else {}


HEALTH_POLL_S = 0.05

# The server process runs uvicorn behind a watchdog thread that exits it once its parent is gone: a command killed
# (SIGKILL, a crash) or ending before the server is up must not leave it running, holding the command's stderr open.
# A write that meets SQLite's lock (a subflow's task run created while the task-run recorder writes the events of the
# cached tasks before it: SQLITE_BUSY_SNAPSHOT) is answered 503, which Prefect's client retries after 2 s (2 ** 1, no
# Retry-After): twice per warm `generate`. Here a 503 says Retry-After 0.1 s, three times longer for each other 503
# of the last 5 s (0.1, 0.3, 0.9, 2.7, 8.1 s: a busy database still gets the client's retries spread over ~12 s).
_SERVE = """
import os, runpy, sys, threading, time
parent = os.getppid()
def watch():
    while os.getppid() == parent:
        time.sleep(0.5)
    os._exit(0)
threading.Thread(target=watch, daemon=True).start()
try:
    import prefect.server.api.server as server
    handler, busy = server.custom_internal_exception_handler, []
    async def retry_soon(request, exc):
        response = await handler(request, exc)
        if response.status_code == 503 and "Retry-After" not in response.headers:
            now = time.monotonic()
            busy[:] = [t for t in busy if now - t < 5.0] + [now]
            response.headers["Retry-After"] = f"{0.1 * 3 ** min(len(busy) - 1, 6):.2f}"
        return response
    server.custom_internal_exception_handler = retry_soon
except Exception:
    pass  # another Prefect: its own retry timing
sys.argv = ["uvicorn", *sys.argv[1:]]
runpy.run_module("uvicorn", run_name="__main__")
"""


class _Prestart:
    """Prefect's local API server, started on a background thread while the command imports and loads.

    Prefect starts its temporary server at a flow's first API call and waits for it: ~3 s on the 2-core machine, ~9 s
    with a new PREFECT_HOME (the database is created), after ~2 s of importing its server module in the calling
    process. Here the same app (``prefect.server.api.server:create_app`` under uvicorn, as Prefect runs it) starts
    first thing, in a process of its own, so its start overlaps the command's imports; the calling process never
    imports the server module. If it does not come up, flows fall back to Prefect's own temporary server. The server
    stops at exit (``close``, an atexit hook registered before the thread starts), and by itself if the command dies."""

    def __init__(self) -> None:
        self.thread: threading.Thread | None = None
        self.api_url: str | None = None
        self.process: subprocess.Popen | None = None
        self.closed = False
        self.lock = threading.Lock()

    def run(self) -> None:
        for _ in range(3):  # a port taken between choosing and binding: uvicorn exits with code 3
            port = _free_port()
            with self.lock:
                if self.closed:  # the command is exiting: start nothing
                    return
                self.process = _start_server_process(port)
                proc = self.process
            if _wait_healthy(proc, port):
                self.api_url = f"http://127.0.0.1:{port}/api"
                os.environ[LOCAL_API_ENV] = self.api_url  # and for the child processes that will share it
                # the client's first call (its version check), made now: the server's first-request setup runs
                # while this process may still be importing, not after
                threading.Thread(target=_get, args=(f"{self.api_url}/admin/version",), daemon=True).start()
                return
            self._stop(proc)
            with self.lock:
                if self.process is proc:
                    self.process = None

    def close(self) -> None:
        """Stop the server (if one started) and start none after this."""
        with self.lock:
            self.closed = True
            proc, self.process = self.process, None
        if proc is not None:
            self._stop(proc)

    @staticmethod
    def _stop(proc: subprocess.Popen) -> None:
        if proc.poll() is not None:
            return
        proc.terminate()
        try:
            proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


_PRESTART = _Prestart()


def _free_port() -> int:
    with contextlib.closing(socket.socket(socket.AF_INET, socket.SOCK_STREAM)) as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def _start_server_process(port: int) -> subprocess.Popen:
    """Prefect's API server app under uvicorn on 127.0.0.1:`port` (UI off), as Prefect's temporary server runs it."""
    spec = importlib.util.find_spec("prefect")  # locates the package without importing it
    if spec is None or spec.origin is None:
        raise ModuleNotFoundError("prefect")
    app_dir = Path(spec.origin).parent.parent
    env = {**os.environ, "PREFECT_UI_ENABLED": "0", "PREFECT__SERVER_EPHEMERAL": "1", "PREFECT__SERVER_FINAL": "1"}
    args = [sys.executable, "-P", "-c", _SERVE, "--app-dir", str(app_dir), "--factory",
            "prefect.server.api.server:create_app", "--host", "127.0.0.1", "--port", str(port), "--log-level",
            "error", "--lifespan", "on"]
    # stdout stays clean for --json output, and the user's stderr holds only the command's own lines: the server's
    # output (its errors, and the tracebacks uvicorn prints when stopped mid-request) goes to a log in PREFECT_HOME.
    # A session of its own: a signal to the command's process group (Ctrl-C in a terminal, `timeout`) leaves the server
    # up while the command unwinds (its client reports the runs' end to a live server, instead of retrying a dead one),
    # and the command stops it at exit.
    with _server_log() as log:
        return subprocess.Popen(args, env=env, stdout=subprocess.DEVNULL, stderr=log, stdin=subprocess.DEVNULL,
                                start_new_session=True)


SERVER_LOG_NAME = "local-server.log"
SERVER_LOG_MAX_BYTES = 1 << 20


@contextlib.contextmanager
def _server_log() -> Iterator[int]:
    """A file descriptor appending to PREFECT_HOME's server log (the last ~1 MiB kept as `.1`); /dev/null if none opens."""
    path = Path(os.environ.get("PREFECT_HOME", str(default_prefect_home()))) / SERVER_LOG_NAME
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        if path.exists() and path.stat().st_size > SERVER_LOG_MAX_BYTES:
            path.replace(path.with_name(SERVER_LOG_NAME + ".1"))
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o644)
    except OSError:
        fd = os.open(os.devnull, os.O_WRONLY)
    try:
        yield fd
    finally:
        os.close(fd)  # the child holds its own copy


def _get(url: str) -> None:
    """GET a local URL, ignoring the answer and any error."""
    opener = urllib.request.build_opener(urllib.request.ProxyHandler({}))  # never through a proxy: it is local
    with contextlib.suppress(OSError), opener.open(url, timeout=30):
        pass


def _wait_healthy(proc: subprocess.Popen, port: int) -> bool:
    """True once the server answers /api/health; False if it exits or misses the startup timeout."""
    timeout = float(os.environ.get("PREFECT_SERVER_EPHEMERAL_STARTUP_TIMEOUT_SECONDS", "180"))
    opener = urllib.request.build_opener(urllib.request.ProxyHandler({}))  # never through a proxy: it is local
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            return False
        try:
            with opener.open(f"http://127.0.0.1:{port}/api/health", timeout=2) as resp:
                if resp.status == 200:
                    return True
        except OSError:
            pass
        time.sleep(HEALTH_POLL_S)
    return False


def prestart_local_server() -> None:
    """Start the local API server in the background, once per process; `local_runtime` points flows at it. Nothing
    starts when PREFECT_API_URL is set (the user's server, or the one a parent batch process shares)."""
    if os.environ.get("PREFECT_API_URL"):
        return
    with _PRESTART.lock:
        if _PRESTART.thread is None and not _PRESTART.closed:
            atexit.register(_PRESTART.close)
            _PRESTART.thread = threading.Thread(target=_safe_run, name="prefect-server-start", daemon=True)
            _PRESTART.thread.start()


def _safe_run() -> None:
    try:
        _PRESTART.run()
    except Exception:  # noqa: BLE001  (flows then start Prefect's own temporary server, as without the prestart)
        _PRESTART.api_url = None


def prestarted_api_url() -> str | None:
    """The prestarted server's API URL once it answers (waits for its start), or None when none was started or
    it did not come up."""
    thread = _PRESTART.thread
    if thread is None:
        return None
    thread.join()
    return _PRESTART.api_url


_CALLER_SIGTERM_HANDLER: object = None


def leave_sigterm_to(handler: object) -> None:
    """While `handler` is the process's SIGTERM handler (the command line's: flows.cli.stop), flows do not install
    Prefect's SIGTERM bridge, which would turn the signal into a crash report per run before the command could stop.
    With any other handler in place (a Prefect worker's run, a test), Prefect's bridge works as it always does."""
    global _CALLER_SIGTERM_HANDLER
    _CALLER_SIGTERM_HANDLER = handler


def _caller_owns_sigterm() -> bool:
    if _CALLER_SIGTERM_HANDLER is None or threading.current_thread() is not threading.main_thread():
        return False
    import signal

    return signal.getsignal(signal.SIGTERM) is _CALLER_SIGTERM_HANDLER


def _route_prefect_sigterm_bridge() -> None:
    """Prefect's flow engine runs each flow inside `capture_sigterm()`: wrapped once, to step aside while the caller
    owns SIGTERM (see leave_sigterm_to)."""
    import prefect.flow_engine as engine

    bridge = engine.capture_sigterm
    if getattr(bridge, "_deformsmith", False):
        return

    @contextlib.contextmanager
    def capture_sigterm() -> Iterator[None]:
        if _caller_owns_sigterm():
            yield
            return
        with bridge():
            yield

    capture_sigterm._deformsmith = True  # type: ignore[attr-defined]
    engine.capture_sigterm = capture_sigterm


@contextlib.contextmanager
def local_runtime() -> Iterator[None]:
    """Run flows locally without the ~1 s heartbeat join per flow (left on against a user's server), against the
    prestarted local server where there is one."""
    from prefect.settings import PREFECT_API_URL, PREFECT_FLOWS_HEARTBEAT_FREQUENCY, temporary_settings

    if _CALLER_SIGTERM_HANDLER is not None:
        _route_prefect_sigterm_bridge()

    if uses_remote_server():
        yield
        return
    settings: dict = {PREFECT_FLOWS_HEARTBEAT_FREQUENCY: None}
    url = prestarted_api_url()
    if url:
        settings[PREFECT_API_URL] = url
    if all(setting.value() == value for setting, value in settings.items()):
        yield  # inside an outer local_runtime (every cached task of a flow): copying the settings costs ~0.1 s
        return
    with temporary_settings(settings):
        yield
