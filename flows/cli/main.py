"""Entry point: collects the command modules and maps user errors to one-line messages."""

from __future__ import annotations

import logging
import sys

from contracts.errors import DeformSmithError
from flows.cli.apps import app
from flows.cli.preflight import filesystem_error, is_filesystem_error

# Each module registers its commands on the shared apps when imported.
from flows.cli import schema_cmds  # noqa: E402,F401
from flows.cli import physical_cmds  # noqa: E402,F401
from flows.cli import material_cmds  # noqa: E402,F401
from flows.cli import generate_cmds  # noqa: E402,F401
from flows.cli import mpm_cmds  # noqa: E402,F401
from flows.cli import geometry_cmds  # noqa: E402,F401
from flows.cli import evidence_cmds  # noqa: E402,F401
from flows.cli import cache_cmds  # noqa: E402,F401
from flows.cli import batch_cmds  # noqa: E402,F401
from flows.cli import manipulate_cmds  # noqa: E402,F401
from flows.cli import eval_cmds  # noqa: E402,F401


# commands that run Prefect flows: their process starts Prefect's local API server first thing, in the background
FLOW_COMMANDS = frozenset({"generate", "geometry", "physical", "material", "manipulate", "probe", "eval", "batch"})


def _prestart_for(argv: list[str]) -> None:
    """Prestart the local Prefect server when the command line runs flows (not for --help)."""
    if argv and argv[0] in FLOW_COMMANDS and not {"--help", "-h"} & set(argv):
        from cache.runtime import prestart_local_server

        prestart_local_server()


class _UserErrorTracebacks(logging.Filter):
    """Drops Prefect's run-log records that carry a DeformSmithError's traceback: main() reports it as one line (the
    runs' one-line 'Finished in state Failed(...)' records stay)."""

    def filter(self, record: logging.LogRecord) -> bool:
        exc = record.exc_info[1] if record.exc_info else None
        return not (isinstance(exc, DeformSmithError) or is_filesystem_error(exc))  # type: ignore[arg-type]


def quiet_user_error_logs() -> None:
    """A user error inside a flow (a mesh with no triangles, a blank photo) ends in its `error:` line, not in two
    tracebacks from Prefect's run loggers and a drain notice from its events worker at exit."""
    for name in ("prefect.flow_runs", "prefect.task_runs"):
        run_logger = logging.getLogger(name)
        if not any(isinstance(f, _UserErrorTracebacks) for f in run_logger.filters):
            run_logger.addFilter(_UserErrorTracebacks())
    logging.getLogger("EventsWorker").setLevel(logging.ERROR)  # "Still processing items" while draining at exit


def main() -> None:
    """Run the CLI; a DeformSmithError becomes one line on stderr and its exit code."""
    _prestart_for(sys.argv[1:])
    quiet_user_error_logs()
    try:
        app()
    except DeformSmithError as exc:
        sys.stderr.write(f"error: {exc}\n")
        sys.exit(exc.exit_code)
    except OSError as exc:  # read-only, missing, full: one line naming the path and the cause, exit 2
        if not is_filesystem_error(exc):
            raise
        user = filesystem_error(exc)
        sys.stderr.write(f"error: {user}\n")
        sys.exit(user.exit_code)
    except SystemExit as exc:
        if exc.code == 130:  # Ctrl-C: Typer turns KeyboardInterrupt into a silent exit 130
            resumes = sys.argv[1:2] and sys.argv[1] in FLOW_COMMANDS
            sys.stderr.write("interrupted" + ("; finished tasks are cached: the same command resumes from them\n"
                                              if resumes else "\n"))
        raise


if __name__ == "__main__":
    main()
