"""`lean_flow`: a Prefect flow whose run parameters go to the API in summary.

Prefect records every flow run's parameters through FastAPI's `jsonable_encoder`, which walks any object it is given:
a probe runner holding a loaded mesh, particles and a trimesh cache costs ~0.5-1 s per subflow run on two cores, for a
JSON blob nobody reads. A lean flow records plain values, paths and pydantic models as JSON (what the UI shows) and
anything else (a callable, a loaded asset, an array) by its type name, as Prefect does for what it cannot encode.
"""

from __future__ import annotations

import enum
from collections.abc import Callable
from pathlib import PurePath
from typing import Any, ParamSpec, TypeVar

from prefect.flows import Flow
from pydantic import BaseModel

P = ParamSpec("P")
R = TypeVar("R")
MAX_ITEMS = 64  # a longer list or dict is recorded by its type name, as an object would be


def parameter_summary(value: Any) -> Any:
    """The JSON a flow run records for one parameter value (see the module docstring)."""
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    if isinstance(value, PurePath):
        return str(value)
    if isinstance(value, enum.Enum):
        return parameter_summary(value.value)
    if isinstance(value, BaseModel):
        try:
            return value.model_dump(mode="json")
        except Exception:  # noqa: BLE001  (a model holding arbitrary types: its name, as Prefect records it)
            return f"<{type(value).__name__}>"
    if isinstance(value, (list, tuple)) and len(value) <= MAX_ITEMS:
        return [parameter_summary(v) for v in value]
    if isinstance(value, dict) and len(value) <= MAX_ITEMS and all(isinstance(k, str) for k in value):
        return {k: parameter_summary(v) for k, v in value.items()}
    return f"<{type(value).__name__}>"


class LeanFlow(Flow[P, R]):
    """A Prefect Flow that records its run parameters with `parameter_summary`."""

    def serialize_parameters(self, parameters: dict[str, Any]) -> dict[str, Any]:
        """Parameters as the API stores them: a summary, never a walk through big objects."""
        return {key: parameter_summary(value) for key, value in parameters.items()}


def lean_flow(name: str, **flow_kwargs: Any) -> Callable[[Callable[P, R]], LeanFlow[P, R]]:
    """Like `prefect.flow(name=..., ...)`, for flows that take big in-memory objects (models, runners, assets)."""

    def decorate(fn: Callable[P, R]) -> LeanFlow[P, R]:
        return LeanFlow(fn=fn, name=name, **flow_kwargs)

    return decorate
