"""The flow-run hierarchy as the Prefect UI shows it, read back from the test session's API (the `prefect_api`
fixture): a flow's latest run, the subflow runs a run started, and the flow run each cached task ran in."""

from __future__ import annotations

from typing import Any
from uuid import UUID

from prefect.client.orchestration import get_client
from prefect.client.schemas.filters import (FlowFilter, FlowFilterName, FlowRunFilter, FlowRunFilterId,
                                            FlowRunFilterParentFlowRunId)
from prefect.client.schemas.sorting import FlowRunSort


def latest_run(flow_name: str) -> Any:
    """The newest run of the flow called `flow_name`."""
    with get_client(sync_client=True) as client:
        runs = client.read_flow_runs(flow_filter=FlowFilter(name=FlowFilterName(any_=[flow_name])),
                                     sort=FlowRunSort.EXPECTED_START_TIME_DESC, limit=1)
    assert runs, f"no run of flow {flow_name!r}"
    return runs[0]


def children(flow_run_id: UUID | str) -> list[tuple[str, Any]]:
    """(flow name, run) of each subflow run started by a flow run, in the order they started."""
    with get_client(sync_client=True) as client:
        runs = client.read_flow_runs(flow_run_filter=FlowRunFilter(
            parent_flow_run_id=FlowRunFilterParentFlowRunId(any_=[UUID(str(flow_run_id))])),
            sort=FlowRunSort.EXPECTED_START_TIME_ASC, limit=200)
        return [(client.read_flow(run.flow_id).name, run) for run in runs]


def flow_names(flow_run_ids: list[str]) -> dict[str, str]:
    """Flow run id -> its flow's name."""
    with get_client(sync_client=True) as client:
        runs = client.read_flow_runs(flow_run_filter=FlowRunFilter(id=FlowRunFilterId(
            any_=[UUID(i) for i in set(flow_run_ids)])), limit=200)
        return {str(run.id): client.read_flow(run.flow_id).name for run in runs}
