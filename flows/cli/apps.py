"""Typer apps shared by the command modules; each module adds its commands here."""

from __future__ import annotations

import json
import os
import sys
from collections.abc import Iterable
from datetime import datetime
from pathlib import Path
from typing import Any, NoReturn

import typer
from rich.console import Console, JustifyMethod
from rich.style import Style
from rich.text import Text

app = typer.Typer(
    name="deformsmith",
    help="Text, image or mesh -> a deformable asset with tested physics and an executed pick-and-place.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
cache_app = typer.Typer(help="Inspect and maintain the content-addressed result cache.", no_args_is_help=True)
verify_app = typer.Typer(help="Analytic verification suites.", no_args_is_help=True)
bench_app = typer.Typer(help="Measure the real job (the lab's benchmarks: python -m benchmarks.<name>).",
                        no_args_is_help=True)
app.add_typer(cache_app, name="cache")
app.add_typer(verify_app, name="verify")
app.add_typer(bench_app, name="bench")


class ProgressConsole(Console):
    """The stderr console: `log` prints one line, its time first, that only the terminal wraps (rich's own log
    folds a path or a number at the width it assumes, 80 columns in a log file)."""

    def log(self, *objects: Any, sep: str = " ", end: str = "\n", style: str | Style | None = None,
            justify: JustifyMethod | None = None, emoji: bool | None = None, markup: bool | None = None,
            highlight: bool | None = None, log_locals: bool = False, _stack_offset: int = 1) -> None:
        stamp = Text(datetime.now().strftime("[%X]"), style="log.time")
        self.print(stamp, *objects, sep=sep, end=end, style=style, justify=justify, emoji=emoji, markup=markup,
                   highlight=highlight, soft_wrap=True)


# Results go to stdout (`deformsmith inspect DIR > f` holds the table), progress, status lines and warnings to stderr;
# --json data goes to stdout through emit_json. Neither console breaks a line inside a number, a path or a command to
# paste (soft_wrap: a line is as long as it is; only tables are laid out at the console's width). Progress lines carry
# the time, not the source line.
console = ProgressConsole(stderr=True, log_path=False, soft_wrap=True)
results = Console(soft_wrap=True)  # (sys.stdout at each write: a redirect or a test's capture sees it)

_USER_PREFECT_LEVEL = "PREFECT_LOGGING_LEVEL" in os.environ


def prefect_log_level(level: str) -> None:
    """Prefect's log level for this command, unless the user set PREFECT_LOGGING_LEVEL. Prefect reads it once, when
    it first logs, so a command sets it before it runs a flow."""
    if not _USER_PREFECT_LEVEL:
        os.environ["PREFECT_LOGGING_LEVEL"] = level


# Prefect's INFO records (a flow run began, a task ran its cache hook, finished in state Completed: ~45 lines for one
# asset) would drown the progress lines; warnings and errors stay. PREFECT_LOGGING_LEVEL=INFO brings them back.
prefect_log_level("WARNING")


def fail(message: str, code: int = 2) -> NoReturn:
    """Print one clear line on stderr and exit non-zero."""
    sys.stderr.write(f"error: {message}\n")
    raise typer.Exit(code)


def check_device(device: str) -> None:
    """--device is cpu or cuda, and cuda has a GPU that Warp can use: checked before any layer runs."""
    if device not in ("cpu", "cuda"):
        fail(f"--device must be cpu or cuda, got '{device}'")
    if device == "cuda":
        import tasks.mpm  # noqa: F401  (Warp quiet on stdout; lazy: pulls warp, 1.3 s, only for --device cuda)
        import warp as wp

        if not wp.is_cuda_available():
            fail("--device cuda: no CUDA device is available to Warp (no NVIDIA GPU or driver); use --device cpu")


RECORD_CHOICES = ("adopted", "all")  # tasks.manipulation.keep.KEEP_TRIALS (not imported: --help stays quick)
RECORD_HELP = ("what the asset keeps: adopted (the L3 trial L3 adopted, else the one it reports: its states in "
               "interaction/ and its recording; every other trial's states and recording and the L1 and L2 probes' "
               "recordings stay in the cache, named by the records: `deformsmith replay DIR --trial N` and "
               "`deformsmith view DIR` read them there) | all (all of them in the asset, ~10-15 MB a trial)")


def check_record(record: str) -> None:
    """--record is adopted or all."""
    if record not in RECORD_CHOICES:
        fail(f"--record must be {' or '.join(RECORD_CHOICES)}, got '{record}'")


def emit_json(data: Any) -> None:
    """Write machine-readable output to stdout."""
    sys.stdout.write(json.dumps(data, indent=2, sort_keys=True, default=str) + "\n")


def emit_report(data: Any, lines: Iterable[str], path: Path, as_json: bool) -> None:
    """A benchmark's report on stdout: its JSON with --json, else its summary lines and where the report file is."""
    if as_json:
        emit_json(data)
        return
    for line in lines:
        results.print(line, markup=False, highlight=False)
    results.print(f"report: {path}", markup=False, highlight=False)
