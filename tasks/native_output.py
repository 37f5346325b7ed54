"""Filter what C code prints on the process's stdout / stderr file descriptors (banners, a missing-driver notice),
which Python's own streams never see: everything else is passed on unchanged once the block ends."""

from __future__ import annotations

import ctypes
import os
import sys
import tempfile
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager


def _flush_all() -> None:
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (AttributeError, OSError, ValueError):
            pass
    try:
        ctypes.CDLL(None).fflush(None)  # C stdio buffers (a pipe's stdout is block-buffered)
    except (OSError, AttributeError, TypeError):
        pass


@contextmanager
def _filtered_fd(fd: int, drop: tuple[str, ...], dropped: list[str]) -> Iterator[None]:
    """Capture fd inside the block; afterwards write back every line that contains none of `drop` (the others go to
    `dropped`). Without a usable fd (an embedding host) the block runs unfiltered."""
    try:
        saved = os.dup(fd)
    except OSError:
        yield
        return
    with tempfile.TemporaryFile() as tmp:
        _flush_all()
        os.dup2(tmp.fileno(), fd)
        try:
            yield
        finally:
            _flush_all()
            os.dup2(saved, fd)
            os.close(saved)
            tmp.seek(0)
            kept: list[str] = []
            for line in tmp.read().decode("utf-8", "replace").splitlines(keepends=True):
                (dropped if any(d in line for d in drop) else kept).append(line)
            if kept:
                os.write(fd, "".join(kept).encode("utf-8"))


@contextmanager
def native_output_filtered(drop: tuple[str, ...], fds: tuple[int, ...] = (1, 2)) -> Iterator[list[str]]:
    """Inside the block, lines that C code writes to `fds` and that contain one of `drop` are swallowed (returned in
    the yielded list); every other line, an error included, still reaches its stream after the block."""
    dropped: list[str] = []
    with ExitStack() as stack:
        for fd in fds:
            stack.enter_context(_filtered_fd(fd, drop, dropped))
        yield dropped


CUDA_DRIVER_MISSING = "Could not find or load the NVIDIA CUDA driver"


def init_warp_quietly() -> list[str]:
    """Warp set up for this project and initialised: no banner or module-load lines on stdout (it belongs to --json
    data; warnings and errors stay), and no "Warp CUDA warning: Could not find or load the NVIDIA CUDA driver" on a
    machine without one, which is expected on the CPU (wp.init() probes CUDA from C). Returns the dropped lines;
    anything else Warp prints, an error included, still shows. A `--device cuda` run without a driver is refused in
    words (flows.cli.apps.check_device; Warp itself when it picks the device)."""
    import warp as wp

    if hasattr(wp, "LOG_WARNING"):
        wp.config.log_level = wp.LOG_WARNING
    else:  # a Warp before log levels
        wp.config.quiet = True  # type: ignore[attr-defined]
    with native_output_filtered((CUDA_DRIVER_MISSING,), fds=(2,)) as dropped:
        wp.init()
    return dropped
