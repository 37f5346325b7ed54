"""Recorded CPU launches replayed without re-packing their arguments.

Warp's ``Launch.launch`` on the CPU builds the kernel's ctypes argument struct field by field on every call (one
``setattr`` per kernel argument, ~26 for the MPM kernels): a few microseconds of Python per launch, which is a large
share of a step at small particle counts (probes, tests). ``PackedCpuLaunch`` builds the struct once and calls the
same compiled entry point with it, so a replay gives the same result bit for bit. Where Warp's internals are not the
expected ones (another Warp version), it falls back to ``Launch.launch``.
"""

from __future__ import annotations

import ctypes
import threading
from collections.abc import Callable
from typing import Any

import warp as wp

from tasks.mpm import cpu_threads, kernels


def _packed_call(cmd: Any) -> Callable[[], None] | None:
    """A no-argument call that runs `cmd`'s forward kernel with a prebuilt argument struct, or None (fall back)."""
    try:
        if not cmd.device.is_cpu or cmd.adjoint or int(cmd.block_dim) > 1:
            return None
        params = list(cmd.params)
        args_spec = cmd.kernel.adj.args
        if len(params) != len(args_spec) + 1:
            return None
        fields = [(a.label, type(p)) for a, p in zip(args_spec, params[1:])]
        struct = type("ArgsStruct", (ctypes.Structure,), {"_fields_": fields})()
        for (name, _), p in zip(fields, params[1:]):
            setattr(struct, name, p)
        forward = cmd.hooks.forward
        bounds = params[0]
        p_bounds, p_args = ctypes.byref(bounds), ctypes.byref(struct)
    except (AttributeError, TypeError):
        return None

    def call() -> None:  # byref keeps the struct and the bounds alive; the struct holds copies of the parameters
        forward(p_bounds, p_args)

    return call


class PackedCpuLaunch:
    """A recorded CPU launch (``wp.launch(..., record_cmd=True)``) whose argument struct is built once."""

    __slots__ = ("cmd", "kernel", "_call")

    def __init__(self, cmd: Any) -> None:
        self.cmd = cmd
        self.kernel = cmd.kernel
        self._call = _packed_call(cmd)

    @property
    def packed(self) -> bool:
        """True when replays skip Warp's per-call packing (False: they go through ``Launch.launch``)."""
        return self._call is not None

    def launch(self) -> None:
        if self._call is None:
            self.cmd.launch()
        else:
            self._call()


def pack_cpu_launches(cmds: list) -> list:
    """`cmds` with every recorded CPU ``wp.Launch`` wrapped (also inside objects holding a ``cmds`` list, such as
    ``cpu_threads.ParallelLaunch``); anything else is returned as it is."""
    out = []
    for c in cmds:
        if isinstance(c, wp.Launch):
            out.append(PackedCpuLaunch(c) if c.device.is_cpu else c)
        elif isinstance(getattr(c, "cmds", None), list):
            c.cmds = pack_cpu_launches(c.cmds)
            out.append(c)
        else:
            out.append(c)
    return out


__all__ = ["PackedCpuLaunch", "pack_cpu_launches"]


_LOAD_LOCK = threading.Lock()
_LOADED = False


def load_cpu_modules() -> None:
    """Load every Warp module the CPU engine launches from (once per process, under a lock).

    Warp loads a module at its first launch, and two threads loading the same module at once can replace the
    executable the other is already running (Warp 1.19's ``Module.load`` holds no lock; a side-by-side L2 run
    segfaulted that way). Call this before rollouts run side by side in threads."""
    global _LOADED
    with _LOAD_LOCK:
        if _LOADED:
            return

        for module in (kernels, cpu_threads, kernels.g2p_p2g_cpu.module, kernels.grid_update_merge_cpu.module):
            wp.load_module(module, device="cpu")
        _LOADED = True
