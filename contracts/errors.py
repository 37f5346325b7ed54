"""Errors a user sees: one clear line, non-zero exit (the CLI maps them)."""


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
