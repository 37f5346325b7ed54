"""The `prefect` CLI with one client fix: Prefect 3.8.8's `prefect deploy` posts limit=null to a worker filter that
its own server (FastAPI 0.154) rejects with 422 after the first deployment. Use: `python deployments/prefect_cli.py
deploy ...` exactly like `prefect deploy ...` (every other command is untouched)."""

from __future__ import annotations

from typing import Any

from prefect.client.orchestration._work_pools.client import WorkPoolAsyncClient

_original = WorkPoolAsyncClient.read_workers_for_work_pool


async def _read_workers(self: WorkPoolAsyncClient, work_pool_name: str, worker_filter: Any = None,
                        offset: int | None = None, limit: int | None = None) -> Any:
    """Same call with explicit paging values."""
    return await _original(self, work_pool_name, worker_filter, offset or 0, limit or 200)


WorkPoolAsyncClient.read_workers_for_work_pool = _read_workers  # type: ignore[method-assign]

if __name__ == "__main__":
    from prefect.cli import app

    app()
