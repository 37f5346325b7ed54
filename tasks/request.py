"""A request checked once, at the boundary (the CLI, `generate_asset`, a batch job): what can be refused before any
layer runs is refused there, and what the check derived travels with the request, so no later step checks it again."""

from __future__ import annotations

from dataclasses import dataclass

from contracts.agents import TargetBehaviour
from contracts.request import AssetRequest
from tasks.agents.intent import targets_from_request
from tasks.geometry.catalogue import check_text_size


@dataclass(frozen=True)
class CheckedRequest:
    """A request whose material targets were derived (a rigid material, an object named in an image's file name or a
    bad target override refused) and whose stated size L0 can build."""

    request: AssetRequest
    targets: TargetBehaviour


def checked_request(request: AssetRequest | CheckedRequest) -> CheckedRequest:
    """Check a request once (InputError when it cannot be built); a checked request is returned as it is."""
    if isinstance(request, CheckedRequest):
        return request
    targets = targets_from_request(request)
    check_text_size(request)  # '10 km long' is refused here, not after the Prefect server started
    return CheckedRequest(request, targets)


__all__ = ["CheckedRequest", "checked_request"]
