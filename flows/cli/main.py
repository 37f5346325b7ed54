"""Entry point: collects the command modules and maps user errors to one-line messages."""

from __future__ import annotations

import logging
import sys
from typing import Any, NoReturn

from cache import runtime
from flows.cli import stop

# Nothing heavy at import (cache.runtime and flows.cli.stop are light): main() starts the local Prefect server first,
# then imports the rest.

# The command modules register their commands on the shared apps when imported. A command line names one command:
# only its module is imported (each pulls in its own libraries), so `generate` prints its first line sooner; --help,
# a group (cache, verify) and anything unknown import them all, in this order. (The lab's benchmarks are
# `python -m benchmarks.<name>`, listed in benchmarks/__init__.py; `bench throughput` times the product's own batch
# job, tasks.throughput, and imports none of them.)
COMMAND_MODULES = ("schema_cmds", "physical_cmds", "material_cmds", "generate_cmds", "mpm_cmds", "geometry_cmds",
                   "evidence_cmds", "cache_cmds", "batch_cmds", "manipulate_cmds", "eval_cmds",
                   "card_cmds", "export_cmds", "crosscheck_cmds", "throughput_cmds", "realworld_cmds",
                   "calibrate_cmds")
MODULE_OF: dict[str, str | tuple[str, ...]] = {
             "schema": "schema_cmds", "physical": "physical_cmds", "probe": "material_cmds",
             "material": "material_cmds", "generate": "generate_cmds", "inspect": "generate_cmds",
             "view": "generate_cmds", "geometry": "geometry_cmds", "evidence": "evidence_cmds",
             "batch": "batch_cmds", "manipulate": "manipulate_cmds", "replay": "manipulate_cmds",
             "eval": "eval_cmds", "card": "card_cmds", "export": "export_cmds",
             "crosscheck": "crosscheck_cmds", "bench": ("throughput_cmds", "realworld_cmds"),
             "calibrate": "calibrate_cmds"}


def register_commands(argv: list[str] | None = None) -> None:
    """Import the command module the command line names (all of them when it names none we know)."""
    import importlib

    name = MODULE_OF.get(argv[0]) if argv else None
    for module in ((name,) if isinstance(name, str) else name) or COMMAND_MODULES:
        importlib.import_module(f"flows.cli.{module}")


def __getattr__(name: str) -> Any:
    """`from flows.cli.main import app`: the app with every command registered."""
    if name == "app":
        # lazy: after the Prefect server's prestart (pydantic, typer: ~0.5 s overlap its start)
        from flows.cli.apps import app

        register_commands()
        return app
    raise AttributeError(f"module 'flows.cli.main' has no attribute {name!r}")


# commands that run Prefect flows: their process starts Prefect's local API server first thing, in the background
FLOW_COMMANDS = frozenset({"generate", "geometry", "physical", "material", "manipulate", "probe", "eval", "batch",
                           "bench"})


# flow commands that start the server themselves, once they know they will run flows: `generate` first looks for its
# request's published asset in the cache (tasks.asset_cache), which needs no server
PRESTART_IN_COMMAND = frozenset({"generate"})


def _prestart_for(argv: list[str]) -> None:
    """Prestart the local Prefect server when the command line runs flows (not for --help)."""
    if argv and argv[0] in FLOW_COMMANDS - PRESTART_IN_COMMAND and not {"--help", "-h"} & set(argv):
        runtime.prestart_local_server()


class _UserErrorTracebacks(logging.Filter):
    """Drops Prefect's run-log records that carry a DeformSmithError's traceback: main() reports it as one line (the
    runs' one-line 'Finished in state Failed(...)' records stay)."""

    def filter(self, record: logging.LogRecord) -> bool:
        # lazy: after the Prefect server's prestart (pydantic, typer: ~0.5 s overlap its start)
        from contracts.errors import DeformSmithError
        # lazy: after the Prefect server's prestart (pydantic, typer: ~0.5 s overlap its start)
        from tasks.preflight import is_filesystem_error

        exc = record.exc_info[1] if record.exc_info else None
        return not (exc is not None and (isinstance(exc, DeformSmithError) or is_filesystem_error(exc)))


def quiet_user_error_logs() -> None:
    """A user error inside a flow (a mesh with no triangles, a blank photo) ends in its `error:` line, not in two
    tracebacks from Prefect's run loggers and a drain notice from its events worker at exit."""
    for name in ("prefect.flow_runs", "prefect.task_runs"):
        run_logger = logging.getLogger(name)
        if not any(isinstance(f, _UserErrorTracebacks) for f in run_logger.filters):
            run_logger.addFilter(_UserErrorTracebacks())
    logging.getLogger("EventsWorker").setLevel(logging.ERROR)  # "Still processing items" while draining at exit


_OWN_SIGNALS = False  # main() run as the program: flows.cli.stop handles SIGINT and SIGTERM

# flow commands whose process ends without the interpreter's teardown once their work and exit hooks are done
FAST_EXIT_COMMANDS = frozenset({"generate", "geometry", "physical", "material", "manipulate", "probe"})


def _exit_now(code: int) -> NoReturn:
    """End the process as the interpreter would, less its teardown of modules and extensions (~1-1.5 s on two cores
    after a generate run: Warp, Prefect, rerun, zarr): Prefect's services drained first (the threading exit hooks:
    run states and events reach the API), then the exit hooks (the local server stopped, rerun and logging flushed),
    then the output flushed and os._exit."""
    import atexit
    import threading

    shutdown = getattr(threading, "_shutdown", None)  # what Py_FinalizeEx runs first: threading's exit hooks, joins
    if shutdown is not None:
        shutdown()
    atexit._run_exitfuncs()
    stop.flush_and_exit(code)


def main() -> None:
    """Run the CLI; a DeformSmithError becomes one line on stderr and its exit code. A flow command run as the
    program (not a test's stand-in app) ends through _exit_now. Run as the program, SIGINT and SIGTERM end it with one
    line on stderr and exit 130 / 143 (flows.cli.stop)."""
    global _OWN_SIGNALS
    program = _OWN_SIGNALS = "app" not in globals()
    fast = bool(sys.argv[1:2]) and sys.argv[1] in FAST_EXIT_COMMANDS and program
    restore = None
    try:
        if program:  # (inside the try: a signal right after it still ends the command through stop.leave)
            restore = stop.install(sys.argv, resumes=bool(sys.argv[1:2]) and sys.argv[1] in FLOW_COMMANDS)
        _main()
    except BaseException as exc:
        if restore is not None and stop.stopped() is not None:  # unwound after a stop signal: its line is said
            stop.leave(stop.stopped() or 130)
        if not fast or not isinstance(exc, SystemExit):
            if restore is not None:
                restore()  # (main() run in a test's process)
            raise
        if isinstance(exc.code, str):  # sys.exit("message"): printed, exit 1, as Python does
            sys.stderr.write(exc.code + "\n")
        _exit_now(exc.code if isinstance(exc.code, int) else int(exc.code is not None))
    if restore is not None:
        if stop.stopped() is not None:  # a signal that came as the command was ending
            stop.leave(stop.stopped() or 130)
        restore()
    if fast:
        _exit_now(0)


def _main() -> None:
    """The command line's command, with user errors as one line and their exit codes."""
    _prestart_for(sys.argv[1:])  # first: the server's start overlaps the imports below
    # lazy: after the Prefect server's prestart (pydantic, typer: ~0.5 s overlap its start)
    from contracts.errors import DeformSmithError
    # lazy: after the Prefect server's prestart (pydantic, typer: ~0.5 s overlap its start)
    from flows.cli.apps import app
    # lazy: after the Prefect server's prestart (pydantic, typer: ~0.5 s overlap its start)
    from tasks.preflight import filesystem_error, is_filesystem_error

    register_commands(sys.argv[1:])
    quiet_user_error_logs()
    try:
        globals().get("app", app)()  # (tests set a stand-in here)
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
        if exc.code == 130 and not _OWN_SIGNALS:  # Ctrl-C in a test's stand-in (else flows.cli.stop says it)
            resumes = sys.argv[1:2] and sys.argv[1] in FLOW_COMMANDS
            sys.stderr.write("interrupted" + ("; finished tasks are cached: the same command resumes from them\n"
                                              if resumes else "\n"))
        raise


if __name__ == "__main__":
    main()
