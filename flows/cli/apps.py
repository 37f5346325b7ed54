"""Typer apps shared by the command modules; each module adds its commands here."""

from __future__ import annotations

import json
import sys
from typing import Any, NoReturn

import typer
from rich.console import Console

app = typer.Typer(
    name="deformsmith",
    help="Text, image or mesh -> a deformable asset with tested physics and an executed pick-and-place.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
cache_app = typer.Typer(help="Inspect and maintain the content-addressed result cache.", no_args_is_help=True)
bench_app = typer.Typer(help="Benchmarks that print their figures (use --json).", no_args_is_help=True)
verify_app = typer.Typer(help="Analytic verification suites.", no_args_is_help=True)
app.add_typer(cache_app, name="cache")
app.add_typer(bench_app, name="bench")
app.add_typer(verify_app, name="verify")

console = Console(stderr=True)  # progress and tables go to stderr; --json data goes to stdout


def fail(message: str, code: int = 2) -> NoReturn:
    """Print one clear line on stderr and exit non-zero."""
    sys.stderr.write(f"error: {message}\n")
    raise typer.Exit(code)


def check_device(device: str) -> None:
    """--device is cpu or cuda, and cuda has a GPU that Warp can use: checked before any layer runs."""
    if device not in ("cpu", "cuda"):
        fail(f"--device must be cpu or cuda, got '{device}'")
    if device == "cuda":
        import tasks.mpm  # noqa: F401  (Warp quiet on stdout)
        import warp as wp

        if not wp.is_cuda_available():
            fail("--device cuda: no CUDA device is available to Warp (no NVIDIA GPU or driver); use --device cpu")


def emit_json(data: Any) -> None:
    """Write machine-readable output to stdout."""
    sys.stdout.write(json.dumps(data, indent=2, sort_keys=True, default=str) + "\n")
