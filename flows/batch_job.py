"""Batch requests in a process of their own: one (`python -m flows.batch_job --request F --out DIR --result F`), or
one after another (`--serve`: a worker that reads one order per line on stdin, so that the imports, Warp's kernels and
the Prefect client load once for many assets, and answers each on its stdout once the order's result file is written).

The result file is the only channel back to the batch runner: {"status": "ok"|"failed", "reason", "asset_dir"}.
A process that dies before writing it (a hard crash, a kill) is reported by the runner from its exit status.
SIGINT stops a request as Ctrl-C stops `generate` (its working directory removed), and so does the loss of the batch
that started it (killed, crashed): a request does not run on for a batch that is gone.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import signal
import sys
import traceback
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Any

from contracts.errors import DeformSmithError
from contracts.request import AssetRequest
from tasks.processes import stop_when_orphaned

Job = Callable[[AssetRequest, Path, str], dict[str, Any]]


def generate_job(request: AssetRequest, out_dir: Path, device: str) -> dict[str, Any]:
    """The default job: `generate_asset` for one request; returns a short summary (with generate's wall time per stage,
    which the throughput benchmark reads from the result file)."""
    # lazy: after main() starts the orphan watch (the layers take seconds)
    from flows.generate import TIMINGS, generate_asset

    manifest = generate_asset(request, out_dir, device=device)  # type: ignore[arg-type]
    return {"asset_dir": str(out_dir), "stages": [s.stage for s in manifest.validation], "wall_time_s": dict(TIMINGS)}


def generate_job_requiring_l3(request: AssetRequest, out_dir: Path, device: str) -> dict[str, Any]:
    """`deformsmith batch --require-l3`: `generate_asset`, then RequirementNotMet when L3 did not pass (the request
    fails with L3's reason; its asset is published all the same)."""
    # lazy: after main() starts the orphan watch (importing the layers takes seconds)
    from flows.generate import TIMINGS, generate_asset, require_l3

    manifest = generate_asset(request, out_dir, device=device)  # type: ignore[arg-type]
    require_l3(manifest, out_dir)
    return {"asset_dir": str(out_dir), "stages": [s.stage for s in manifest.validation], "wall_time_s": dict(TIMINGS)}


def generate_job_without_l3(request: AssetRequest, out_dir: Path, device: str) -> dict[str, Any]:
    """`generate_asset` through L2 only (no robot validation): `deformsmith batch --no-l3`."""
    # lazy: after main() starts the orphan watch (the layers take seconds)
    from flows.generate import TIMINGS, generate_asset

    manifest = generate_asset(request, out_dir, device=device, manipulate=False)  # type: ignore[arg-type]
    return {"asset_dir": str(out_dir), "stages": [s.stage for s in manifest.validation], "wall_time_s": dict(TIMINGS)}


def resolve_job(spec: str) -> Job:
    """'module:function' -> the callable."""
    module, _, attr = spec.partition(":")
    if not module or not attr:
        raise ValueError(f"job must be 'module:function', got {spec!r}")
    return getattr(importlib.import_module(module), attr)


def run_request(request: AssetRequest, out_dir: Path, device: str, job: str = "flows.batch_job:generate_job"
                ) -> dict[str, Any]:
    """Run a job; a DeformSmithError or any other exception becomes a 'failed' result with its reason."""
    try:
        summary = resolve_job(job)(request, out_dir, device)
        return {"status": "ok", "reason": None, "asset_dir": str(out_dir), "summary": summary}
    except DeformSmithError as exc:  # a RequirementNotMet names the asset it published anyway
        return {"status": "failed", "reason": f"{type(exc).__name__}: {exc}",
                "asset_dir": getattr(exc, "asset_dir", None)}
    except Exception as exc:  # a bug in one request must not hide the others' results
        tb = traceback.format_exc(limit=3).strip().splitlines()
        return {"status": "failed", "reason": f"{type(exc).__name__}: {exc}", "asset_dir": None, "traceback": tb}


def _write_atomic(path: Path, data: dict[str, Any]) -> None:
    tmp = path.with_name(f".{path.name}.{os.getpid()}")
    tmp.write_text(json.dumps(data, indent=2, default=str) + "\n", encoding="utf-8")
    os.replace(tmp, path)


@contextmanager
def output_to(log: Path) -> Iterator[None]:
    """This process's stdout and stderr (the file descriptors: native libraries' output too) written to `log` while
    the block runs, then restored."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = os.dup(1), os.dup(2)
    try:
        with log.open("w", encoding="utf-8") as fh:
            os.dup2(fh.fileno(), 1)
            os.dup2(fh.fileno(), 2)
            try:
                yield
            finally:
                sys.stdout.flush()
                sys.stderr.flush()
                os.dup2(saved[0], 1)
                os.dup2(saved[1], 2)
    finally:
        os.close(saved[0])
        os.close(saved[1])


def serve(device: str, orders: IO[str], answers: IO[str]) -> int:
    """Run the orders read from `orders`, one JSON object per line ({"name", "request", "out", "result", "log",
    "job"}: files as for one request, the request's output going to "log"), one after another; after each result file
    is written, its name on `answers` as a JSON line. Ends at the end of `orders`, or after a failed request (its answer
    says "retire": what failed may have left this process unfit, a CUDA context after a device error, so a fresh
    worker serves the next)."""
    for line in orders:
        if not line.strip():
            continue
        order = json.loads(line)
        with output_to(Path(order["log"])):
            try:
                request = AssetRequest.model_validate_json(Path(order["request"]).read_text(encoding="utf-8"))
                result = run_request(request, Path(order["out"]), device, order["job"])
            except Exception as exc:  # (an unreadable order: this request fails, the worker serves on)
                result = {"status": "failed", "reason": f"{type(exc).__name__}: {exc}", "asset_dir": None}
            _write_atomic(Path(order["result"]), result)
        retire = result["status"] != "ok"
        answers.write(json.dumps({"done": order["name"], "retire": retire}) + "\n")
        answers.flush()
        if retire:
            break
    return 0


def main(argv: list[str] | None = None) -> int:
    """Entry point of the child process; exit 0 when the request succeeded."""
    # SIGINT is KeyboardInterrupt even when the batch was started with it ignored (nohup, a non-interactive shell)
    signal.signal(signal.SIGINT, signal.default_int_handler)
    ap = argparse.ArgumentParser(prog="python -m flows.batch_job")
    ap.add_argument("--request", type=Path, help="JSON file holding one AssetRequest")
    ap.add_argument("--out", type=Path, help="asset directory to publish")
    ap.add_argument("--result", type=Path, help="where to write the result JSON")
    ap.add_argument("--device", default="cpu")
    ap.add_argument("--job", default="flows.batch_job:generate_job")
    ap.add_argument("--parent-pid", type=int, default=None, help="the batch's PID: stop when it is gone")
    ap.add_argument("--serve", action="store_true", help="run the orders read on stdin, one per line (see serve)")
    ap.add_argument("--log", type=Path, default=None, help="with --serve: the worker's own output, outside orders")
    args = ap.parse_args(argv)
    if not args.serve and None in (args.request, args.out, args.result):
        ap.error("--request, --out and --result are required without --serve")
    stop_when_orphaned(args.parent_pid)
    if args.serve:  # the answers keep the stdout it was given; what is printed outside an order goes to the log
        answers = os.fdopen(os.dup(1), "w", encoding="utf-8")
        if args.log is not None:
            with args.log.open("a", encoding="utf-8") as fh:
                os.dup2(fh.fileno(), 2)
        os.dup2(2, 1)
        return serve(args.device, sys.stdin, answers)
    request = AssetRequest.model_validate_json(args.request.read_text(encoding="utf-8"))
    result = run_request(request, args.out, args.device, args.job)
    _write_atomic(args.result, result)
    return 0 if result["status"] == "ok" else 1


if __name__ == "__main__":
    raise SystemExit(main())
