"""Create the server-side automation that marks a Running flow run Crashed when its heartbeats stop (a zombie).

    PREFECT_API_URL=http://SERVER:4200/api python deployments/zombie_automation.py [--within-s 90]

Flow runs send heartbeats only with PREFECT_FLOWS_HEARTBEAT_FREQUENCY set (prefect.yaml sets 30 s, the minimum);
`within` must exceed it. Idempotent: an automation of the same name is replaced.
"""

from __future__ import annotations

import argparse
from datetime import timedelta
from typing import Any

NAME = "deformsmith: crash zombie flow runs"


def create(within_s: float = 90.0) -> str:
    """Create (or replace) the automation; its id."""
    from prefect.automations import Automation
    from prefect.client.schemas.objects import StateType
    from prefect.events.actions import ChangeFlowRunState
    from prefect.events.schemas.automations import EventTrigger, Posture
    from prefect.events.schemas.events import ResourceSpecification

    while (old := _existing()) is not None:
        old.delete()
    automation = Automation(
        name=NAME,
        trigger=EventTrigger(
            after={"prefect.flow-run.heartbeat"},
            expect={"prefect.flow-run.heartbeat", "prefect.flow-run.Completed", "prefect.flow-run.Failed",
                    "prefect.flow-run.Cancelled", "prefect.flow-run.Crashed"},
            match=ResourceSpecification({"prefect.resource.id": ["prefect.flow-run.*"]}),
            for_each={"prefect.resource.id"},
            posture=Posture.Proactive,
            threshold=1,
            within=timedelta(seconds=within_s),
        ),
        actions=[ChangeFlowRunState(state=StateType.CRASHED,
                                    message=f"no heartbeat for {within_s:g} s: marked Crashed (zombie)")],
    ).create()
    return str(automation.id)


def _existing() -> Any:
    """The automation of this name, or None."""
    from prefect.automations import Automation

    try:
        return Automation.read(name=NAME)
    except ValueError:
        return None


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--within-s", type=float, default=90.0, help="silence [s] after which a run counts as a zombie")
    print(create(ap.parse_args().within_s))
