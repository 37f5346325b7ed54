"""A throwaway PostgreSQL server for the Prefect server (Debian's `postgresql` package: initdb, pg_ctl).

    with LocalPostgres(Path("/tmp/pg")) as pg:
        LocalCluster(home, cache, extra_env={"PREFECT_API_DATABASE_CONNECTION_URL": pg.url})

The data directory, socket and log live under the given folder (as root: a fresh folder in the temp dir that the
`postgres` user can reach, removed on exit); the server listens on 127.0.0.1 at a free port and
is stopped (fast shutdown) on exit. Run as root, PostgreSQL's own binaries refuse to start, so they run as the
`postgres` system user (which must then exist); otherwise as the current user.
"""

from __future__ import annotations

import os
import pwd
import shutil
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any

from local_cluster import free_port  # type: ignore[import-not-found]

DATABASE = "prefect"


def _pg_bin(name: str) -> str:
    """Path of a PostgreSQL server binary (PATH first, then Debian's versioned folders)."""
    found = shutil.which(name)
    if found:
        return found
    for folder in sorted(Path("/usr/lib/postgresql").glob("*/bin"), reverse=True):
        if (folder / name).is_file():
            return str(folder / name)
    raise FileNotFoundError(f"PostgreSQL's {name} not found: install Debian's 'postgresql' package")


class LocalPostgres:
    """initdb + pg_ctl start on a free loopback port; `.url` is the asyncpg URL Prefect takes."""

    def __init__(self, root: Path, port: int | None = None) -> None:
        self.root = Path(root).absolute()
        self._as_user: list[str] = []
        self._own_root = False
        if os.geteuid() == 0:
            pwd.getpwnam("postgres")  # KeyError when the system user is missing
            self._as_user = ["runuser", "-u", "postgres", "--"]
            # the postgres user may not traverse root's folders (pytest's tmp is 0700): a folder of its own in /tmp
            self.root, self._own_root = Path(tempfile.mkdtemp(prefix="deformsmith-pg-")), True
        self.data, self.log = self.root / "data", self.root / "postgres.log"
        self.port = port or free_port()
        self.url = f"postgresql+asyncpg://prefect@127.0.0.1:{self.port}/{DATABASE}"

    def _run(self, *args: str, timeout_s: float = 120) -> str:
        proc = subprocess.run([*self._as_user, *args], capture_output=True, text=True, timeout=timeout_s)
        if proc.returncode != 0:
            raise RuntimeError(f"{' '.join(args)} failed ({proc.returncode}):\n{proc.stdout}\n{proc.stderr}")
        return proc.stdout

    def start(self) -> None:
        """A fresh cluster with trust authentication on loopback, a `prefect` role and database."""
        self.root.mkdir(parents=True, exist_ok=True)
        if self._as_user:
            shutil.chown(self.root, "postgres")
        self._run(_pg_bin("initdb"), "-D", str(self.data), "-U", "prefect", "--auth=trust", "-E", "UTF8")
        opts = f"-c listen_addresses=127.0.0.1 -p {self.port} -c unix_socket_directories={self.root} " \
               "-c max_connections=200 -c fsync=off"
        self._run(_pg_bin("pg_ctl"), "-D", str(self.data), "-l", str(self.log), "-o", opts, "-w", "-t", "60", "start")
        deadline = time.monotonic() + 60
        while True:
            try:
                self._run(_pg_bin("createdb"), "-h", "127.0.0.1", "-p", str(self.port), "-U", "prefect", DATABASE)
                return
            except RuntimeError:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.5)

    def stop(self) -> None:
        if (self.data / "postmaster.pid").is_file():
            self._run(_pg_bin("pg_ctl"), "-D", str(self.data), "-m", "fast", "-w", "stop", timeout_s=60)
        if self._own_root:
            shutil.rmtree(self.root, ignore_errors=True)

    def __enter__(self) -> LocalPostgres:
        try:
            self.start()
        except BaseException:
            self.stop()
            raise
        return self

    def __exit__(self, *exc: Any) -> None:
        self.stop()
