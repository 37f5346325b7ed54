"""Local Prefect runtime: quiet, offline, no per-flow heartbeat; a user's PREFECT_API_URL is respected."""

from __future__ import annotations

import contextlib
import os
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


def uses_remote_server() -> bool:
    """True when the user points Prefect at their own server with PREFECT_API_URL."""
    from prefect.settings import PREFECT_API_URL

    return bool(PREFECT_API_URL.value())


@contextlib.contextmanager
def local_runtime() -> Iterator[None]:
    """Run flows locally without the ~1 s heartbeat join per flow (left on against a user's server)."""
    from prefect.settings import PREFECT_FLOWS_HEARTBEAT_FREQUENCY, temporary_settings

    if uses_remote_server():
        yield
        return
    with temporary_settings({PREFECT_FLOWS_HEARTBEAT_FREQUENCY: None}):
        yield
