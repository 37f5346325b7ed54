"""Errors a user sees: one clear line, non-zero exit (the CLI maps them)."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pydantic import ValidationError


class DeformSmithError(Exception):
    """Base of every error that the CLI reports as one line on stderr."""

    exit_code = 1


class InputError(DeformSmithError):
    """The user's input (file, text, option, parameter) is unusable."""

    exit_code = 2


class ContractError(DeformSmithError):
    """A stage contract file or a proposal violates its contract."""

    exit_code = 3


class CacheError(DeformSmithError):
    """The cache store is unreadable or an entry is corrupt."""

    exit_code = 4


class SimulationError(DeformSmithError):
    """A simulation could not run (not: a simulation that ran and failed a gate)."""

    exit_code = 5


class StageFailure(DeformSmithError):
    """A layer ran but produced no valid result (its gates or budget said no); the asset is not published."""

    exit_code = 6

    def __init__(self, stage: str, message: str) -> None:
        super().__init__(f"{stage} failed: {message}")
        self.stage = stage


class RequirementNotMet(DeformSmithError):
    """The asset was published, but a validation the user required (`--require-l3`) did not pass."""

    exit_code = 7

    def __init__(self, stage: str, message: str, asset_dir: str | None = None) -> None:
        where = f" (asset published: {asset_dir})" if asset_dir else ""
        super().__init__(f"{stage} required but not passed: {message}{where}")
        self.stage = stage
        self.asset_dir = asset_dir


def validation_message(exc: ValidationError, names: dict[str, str] | None = None,
                       limit: int | None = None, with_input: bool = False) -> str:
    """One line from a pydantic ValidationError: 'field.path: reason; ...' (pydantic's 'Value error, ' prefix
    dropped; an error of the whole model is its reason alone). `names` renames top-level fields, `limit` keeps the
    first N errors, `with_input` adds ' = <value given>' after each field."""
    parts = []
    for err in exc.errors()[:limit]:
        loc = [str(p) for p in err["loc"]]
        if loc and names and loc[0] in names:
            loc[0] = names[loc[0]]
        given = f" = {err.get('input')}" if with_input else ""
        reason = err["msg"].removeprefix("Value error, ")
        parts.append(f"{'.'.join(loc)}{given}: {reason}" if loc else reason)
    return "; ".join(parts)
