"""Sample every thread's Python stack while a module runs, then print where the time went (a small py-spy).

    python -m benchmarks.sample_profile --out prof.json [--interval-s 0.01] -- flows.cli.main generate --device cuda

cProfile sees one thread and loses its data when the CLI ends with os._exit; Prefect runs tasks in worker threads.
This samples sys._current_frames() from a daemon thread and writes the counts when the process ends, however it
ends (os._exit is wrapped). The report: for each function, the share of samples in which it is on a stack
(inclusive) and at the top (self), over the samples of threads running our code (a frame of flows/, tasks/, cache/
or contracts/ on the stack): idle pool threads and Prefect's services are left out.
"""

from __future__ import annotations

import argparse
import collections
import functools
import json
import os
import runpy
import sys
import threading
import time
from pathlib import Path
from types import FrameType

OURS = tuple(str(Path(__file__).resolve().parent.parent / d) + "/" for d in ("flows", "tasks", "cache", "contracts"))


def _key(frame: FrameType) -> str:
    code = frame.f_code
    return f"{Path(code.co_filename).name}:{code.co_name}"


@functools.cache
def _absolute(filename: str) -> str:
    """A code object's file as an absolute path (modules found through a relative sys.path entry keep it relative)."""
    return os.path.abspath(filename)


class Sampler:
    """Counts, per function, the samples with it on a stack running our code (inclusive) and at its top (self)."""

    def __init__(self, interval_s: float) -> None:
        self.interval_s = interval_s
        self.inclusive: collections.Counter[str] = collections.Counter()
        self.self_: collections.Counter[str] = collections.Counter()
        self.samples = 0
        self.t0 = time.perf_counter()

    def loop(self) -> None:
        me = threading.get_ident()  # the sampler's own thread
        while True:
            time.sleep(self.interval_s)
            for tid, frame in sys._current_frames().items():
                if tid == me:
                    continue
                stack: list[FrameType] = []
                f: FrameType | None = frame
                while f is not None:
                    stack.append(f)
                    f = f.f_back
                if not any(_absolute(s.f_code.co_filename).startswith(OURS) for s in stack):
                    continue
                self.samples += 1
                self.self_[_key(frame)] += 1
                for k in {_key(s) for s in stack}:
                    self.inclusive[k] += 1

    def report(self, top: int = 150) -> dict:
        n = max(self.samples, 1)
        return {"samples": self.samples, "interval_s": self.interval_s,
                "wall_s": round(time.perf_counter() - self.t0, 2),
                "inclusive": [(k, round(v / n, 4)) for k, v in self.inclusive.most_common(top)],
                "self": [(k, round(v / n, 4)) for k, v in self.self_.most_common(top)]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--interval-s", type=float, default=0.01)
    parser.add_argument("module")
    parser.add_argument("args", nargs=argparse.REMAINDER)
    ns = parser.parse_args()
    sampler = Sampler(ns.interval_s)
    real_exit = os._exit

    def dump() -> None:
        ns.out.write_text(json.dumps(sampler.report(), indent=1), encoding="utf-8")

    def exit_after_dump(code: int) -> None:
        dump()
        real_exit(code)

    os._exit = exit_after_dump  # type: ignore[assignment]
    threading.Thread(target=sampler.loop, daemon=True, name="sampler").start()
    sys.argv = [ns.module, *ns.args]
    try:
        runpy.run_module(ns.module, run_name="__main__", alter_sys=True)
    finally:
        dump()


if __name__ == "__main__":
    main()
