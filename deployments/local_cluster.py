"""A Prefect cluster on this machine: server on loopback (SQLite), N process workers, deployments, zombie detection.

    python deployments/local_cluster.py --workers 2                  # up until Ctrl-C, then everything stops
    python deployments/local_cluster.py --workers 2 --batch REQ.jsonl --out DIR   # run one batch, print, stop

Everything lives under --home (Prefect's database, logs); the cache root is --cache. Workers poll the pool's
`generate` queue with `--limit 1` each, so generations spread over workers; one `control` worker runs batch
coordinators. The same steps, spread over hosts, are the multi-machine recipe in deployments/README.md.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parent.parent
PREFECT_FILE = REPO / "deployments" / "prefect.yaml"
POOL = "deformsmith"
GENERATE = "deformsmith-generate/generate"
NIGHTLY = "deformsmith-batch/nightly"
HEARTBEAT_S = 30  # Prefect's minimum flow-run heartbeat interval
ZOMBIE_AFTER_S = 90  # no heartbeat for this long: the automation marks the run Crashed


def free_port() -> int:
    """A free TCP port on 127.0.0.1."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def descendants(pid: int) -> list[int]:
    """Every process below `pid` (children first listed, then theirs), from /proc."""
    out: list[int] = []
    stack = [pid]
    while stack:
        p = stack.pop()
        try:
            kids = []
            for task in Path(f"/proc/{p}/task").iterdir():
                kids += [int(c) for c in (task / "children").read_text().split()]
        except OSError:
            continue
        out += kids
        stack += kids
    return out


def _signal(pids: list[int], sig: int) -> None:
    for pid in pids:
        try:
            os.kill(pid, sig)
        except ProcessLookupError:
            pass


class LocalCluster:
    """Server + workers as child processes; `with LocalCluster(...) as c:` starts, deploys and stops them."""

    def __init__(self, home: Path, cache: Path, workers: int = 2, port: int | None = None,
                 control_worker: bool = True, extra_env: dict[str, str] | None = None) -> None:
        self.home, self.cache = Path(home).absolute(), Path(cache).absolute()
        self.port = port or free_port()
        self.api_url = f"http://127.0.0.1:{self.port}/api"
        self.n_workers, self.control_worker = workers, control_worker
        self.logs = self.home / "logs"
        self.server: subprocess.Popen[bytes] | None = None
        self.workers: dict[str, subprocess.Popen[bytes]] = {}
        self.env = {k: v for k, v in os.environ.items() if not k.startswith("PREFECT_")}
        self.env.update({
            "PREFECT_HOME": str(self.home / "prefect"), "PREFECT_API_URL": self.api_url,
            "PREFECT_SERVER_ANALYTICS_ENABLED": "false", "PREFECT_FLOWS_HEARTBEAT_FREQUENCY": str(HEARTBEAT_S),
            "PREFECT_WORKER_QUERY_SECONDS": "2", "PREFECT_WORKER_HEARTBEAT_SECONDS": "10",
            "PREFECT_SERVER_LOGGING_LEVEL": "WARNING", "DEFORMSMITH_CACHE": str(self.cache),
            "DEFORMSMITH_ROOT": str(REPO), "PYTHONUNBUFFERED": "1", "PYTHONPATH": str(REPO),
        })
        self.env.update(extra_env or {})

    # ---- lifecycle ------------------------------------------------------------------------------------
    def __enter__(self) -> LocalCluster:
        try:
            self.start()
        except BaseException:
            self.stop()
            raise
        return self

    def __exit__(self, *exc: Any) -> None:
        self.stop()

    def _popen(self, name: str, args: list[str]) -> subprocess.Popen[bytes]:
        self.logs.mkdir(parents=True, exist_ok=True)
        log = open(self.logs / f"{name}.log", "ab")
        return subprocess.Popen([sys.executable, "-m", "prefect", *args], cwd=REPO, env=self.env, stdout=log,
                                stderr=subprocess.STDOUT, start_new_session=True)

    def prefect(self, *args: str, timeout_s: float = 180) -> str:
        """Run a `prefect` CLI command against this cluster; its output (raises on failure)."""
        proc = subprocess.run([sys.executable, "-m", "prefect", *args], cwd=REPO, env=self.env, capture_output=True,
                              text=True, timeout=timeout_s)
        if proc.returncode != 0:
            raise RuntimeError(f"prefect {' '.join(args)} failed ({proc.returncode}):\n{proc.stdout}\n{proc.stderr}")
        return proc.stdout

    def start(self) -> None:
        """Server, work pool, deployments, zombie automation, workers."""
        (self.home / "prefect").mkdir(parents=True, exist_ok=True)
        self.cache.mkdir(parents=True, exist_ok=True)
        self.server = self._popen("server", ["server", "start", "--host", "127.0.0.1", "--port", str(self.port)])
        self.wait_healthy()
        self.prefect("work-pool", "create", POOL, "--type", "process", "--overwrite")
        self.deploy()
        self.create_zombie_automation()
        for i in range(1, self.n_workers + 1):
            self.start_worker(f"gen-{i}")
        if self.control_worker:
            self.start_worker("control", queue="control")

    def wait_healthy(self, timeout_s: float = 180) -> None:
        """Block until the server answers /health."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            if self.server is not None and self.server.poll() is not None:
                raise RuntimeError(f"prefect server exited ({self.server.returncode}); see {self.logs}/server.log")
            try:
                with urllib.request.urlopen(f"{self.api_url}/health", timeout=2) as r:
                    if r.status == 200:
                        return
            except OSError:
                pass
            time.sleep(0.5)
        raise TimeoutError(f"prefect server not healthy after {timeout_s} s")

    def deploy(self) -> None:
        """`prefect deploy --all` with deployments/prefect.yaml (values from this cluster's environment)."""
        proc = subprocess.run([sys.executable, str(REPO / "deployments" / "prefect_cli.py"), "--no-prompt", "deploy",
                               "--all", "--prefect-file", str(PREFECT_FILE)], cwd=REPO, env=self.env,
                              capture_output=True, text=True, timeout=300)
        if proc.returncode != 0:
            raise RuntimeError(f"prefect deploy failed ({proc.returncode}):\n{proc.stdout}\n{proc.stderr}")

    def start_worker(self, name: str, queue: str = "generate", limit: int = 1) -> None:
        """A process worker polling one queue of the pool, `limit` flow runs at a time."""
        self.workers[name] = self._popen(f"worker-{name}", ["worker", "start", "--pool", POOL, "--work-queue", queue,
                                                            "--name", name, "--limit", str(limit), "--type", "process"])

    def kill_worker(self, name: str) -> list[int]:
        """SIGKILL a worker and every process it started, like a host that dies; returns the killed pids."""
        proc = self.workers.pop(name)
        tree = descendants(proc.pid)
        _signal([proc.pid], signal.SIGKILL)  # first the worker, so nobody is left to report its runs
        _signal(tree, signal.SIGKILL)
        proc.wait(timeout=30)
        return [proc.pid, *tree]

    def stop(self) -> None:
        """Stop workers (and their flow runs), then the server: SIGTERM, SIGKILL after a grace period."""
        procs = list(self.workers.values()) + ([self.server] if self.server is not None else [])
        trees = {p.pid: descendants(p.pid) for p in procs}
        for p in procs:
            _signal([p.pid, *trees[p.pid]], signal.SIGTERM)
        deadline = time.monotonic() + 20
        for p in procs:
            try:
                p.wait(timeout=max(0.1, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                pass
        for p in procs:
            _signal([p.pid, *trees[p.pid], *descendants(p.pid)], signal.SIGKILL)
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                pass
        self.workers.clear()
        self.server = None

    # ---- API helpers (in a child, so this process's Prefect settings stay untouched) -----------------------
    def python(self, code: str, timeout_s: float = 120) -> str:
        """Run Python against this cluster's API; stdout."""
        proc = subprocess.run([sys.executable, "-c", code], cwd=REPO, env=self.env, capture_output=True, text=True,
                              timeout=timeout_s)
        if proc.returncode != 0:
            raise RuntimeError(f"cluster helper failed:\n{proc.stdout}\n{proc.stderr}")
        return proc.stdout

    def create_zombie_automation(self) -> None:
        """The server marks a Running flow run Crashed when its heartbeats stop (Prefect's zombie recipe)."""
        proc = subprocess.run([sys.executable, str(REPO / "deployments" / "zombie_automation.py"), "--within-s",
                               str(ZOMBIE_AFTER_S)], cwd=REPO, env=self.env, capture_output=True, text=True, timeout=120)
        if proc.returncode != 0:
            raise RuntimeError(f"zombie automation failed:\n{proc.stdout}\n{proc.stderr}")

    def run_deployment(self, name: str, parameters: dict[str, Any]) -> str:
        """Create a flow run of a deployment now; its id."""
        code = ("import json, sys; from prefect.deployments import run_deployment; "
                f"r = run_deployment({name!r}, parameters=json.loads(sys.argv[1]), timeout=0); print(r.id)")
        proc = subprocess.run([sys.executable, "-c", code, json.dumps(parameters)], cwd=REPO, env=self.env,
                              capture_output=True, text=True, timeout=120)
        if proc.returncode != 0:
            raise RuntimeError(f"run_deployment failed:\n{proc.stderr}")
        return proc.stdout.strip().splitlines()[-1]

    def flow_runs(self) -> list[dict[str, Any]]:
        """Every flow run: id, name, deployment id, state type and name, parent task run id."""
        code = ("import json; from prefect.client.orchestration import get_client\n"
                "from prefect.client.schemas.sorting import FlowRunSort\n"
                "runs = []\n"
                "with get_client(sync_client=True) as c:\n"
                "    while True:\n"
                "        page = c.read_flow_runs(limit=200, offset=len(runs), sort=FlowRunSort.EXPECTED_START_TIME_ASC)\n"
                "        runs += page\n"
                "        if len(page) < 200:\n"
                "            break\n"
                "print(json.dumps([{'id': str(r.id), 'name': r.name, 'deployment_id': str(r.deployment_id),"
                " 'state': r.state.type.value if r.state else None, 'state_name': r.state.name if r.state else None,"
                " 'message': r.state.message if r.state else None, 'parent': str(r.parent_task_run_id),"
                " 'parameters': r.parameters} for r in runs]))")
        return json.loads(self.python(code).strip().splitlines()[-1])  # type: ignore[no-any-return]

    def wait_flow_run(self, run_id: str, timeout_s: float, poll_s: float = 3.0) -> dict[str, Any]:
        """Poll a flow run until it is final (TimeoutError otherwise); its final record."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            run = next((r for r in self.flow_runs() if r["id"] == run_id), None)
            if run and run["state"] in ("COMPLETED", "FAILED", "CRASHED", "CANCELLED"):
                return run
            time.sleep(poll_s)
        raise TimeoutError(f"flow run {run_id} not final after {timeout_s} s")


def main() -> int:
    """CLI: bring a local cluster up (optionally run one batch through the nightly deployment), then stop it."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--home", type=Path, default=None, help="server database + logs (default: a temp dir)")
    ap.add_argument("--cache", type=Path, default=None, help="cache root (default: $DEFORMSMITH_CACHE or <home>/cache)")
    ap.add_argument("--port", type=int, default=None)
    ap.add_argument("--batch", type=Path, default=None, help="run this JSONL through deformsmith-batch/nightly, then stop")
    ap.add_argument("--out", type=Path, default=Path("out/batch"), help="batch output root")
    ap.add_argument("--timeout-s", type=float, default=3600.0)
    ap.add_argument("--postgres", action="store_true",
                    help="the server's database on a throwaway PostgreSQL under <home>/pg (Debian's postgresql) "
                         "instead of SQLite")
    args = ap.parse_args()
    home = args.home or Path(tempfile.mkdtemp(prefix="deformsmith-cluster-"))
    cache = args.cache or Path(os.environ.get("DEFORMSMITH_CACHE") or home / "cache")
    with contextlib.ExitStack() as stack:
        env: dict[str, str] = {}
        if args.postgres:
            from local_postgres import LocalPostgres

            env["PREFECT_API_DATABASE_CONNECTION_URL"] = stack.enter_context(LocalPostgres(home / "pg")).url
        return _serve(args, home, cache, env)


def _serve(args: argparse.Namespace, home: Path, cache: Path, env: dict[str, str]) -> int:
    with LocalCluster(home, cache, workers=args.workers, port=args.port, extra_env=env) as cluster:
        print(f"server {cluster.api_url} (UI: http://127.0.0.1:{cluster.port}); {args.workers} workers; "
              f"cache {cache}; logs {cluster.logs}", flush=True)
        if args.batch is None:
            try:
                while True:
                    time.sleep(3600)
            except KeyboardInterrupt:
                print("stopping", flush=True)
            return 0
        t0 = time.monotonic()
        run_id = cluster.run_deployment(NIGHTLY, {"requests_jsonl": str(args.batch.absolute()),
                                                  "out_root": str(args.out.absolute())})
        run = cluster.wait_flow_run(run_id, args.timeout_s)
        print(f"batch flow run {run_id}: {run['state']} after {time.monotonic() - t0:.1f} s", flush=True)
        report = args.out.absolute() / "batch_report.json"
        if report.is_file():
            print(report.read_text(encoding="utf-8"))
        return 0 if run["state"] == "COMPLETED" else 1


if __name__ == "__main__":
    raise SystemExit(main())
