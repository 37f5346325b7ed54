"""Old-vs-new GPU bench runs in one device call (each run its own process, figures from the bench's --json).

    python3 -m benchmarks.engine.gpu_ab --old _old --plan PLAN [--out DIR]

PLAN is a ';'-separated list of runs ``tag:tree:NAME=V,NAME=V:particles:steps:batch`` (tree: old or new; the NAME=V
part, ``contracts.sim.KernelOptions`` fields passed as ``python -m benchmarks.mpm_bench --kernel NAME=V``, may be empty; a
tree from before KernelOptions took the same switches as DEFORMSMITH_MPM_* environment variables). The old tree is
a ``git archive`` of the old commit extracted into a folder of the repo root (``--old``); new
is the working tree. Prints one line per run and a JSON list of every run's figures to DIR/ab.json.

Example (device machine, repo root, Warp + pydantic on PYTHONPATH; old tree from
``git archive <commit> tasks contracts flows cache benchmarks | tar -x -C _old`` made here and carried):

    python3 -m benchmarks.engine.gpu_ab --out $OUT --plan "o8:old::8000:5000:1;n8:new::8000:5000:1;\
        n16w:new:scatter=warp:8000:2000:16"
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import subprocess
import sys
import time

# a tree from before the benchmark moved to benchmarks/ (#37) runs it as `deformsmith bench mpm`
OLD_CLI = ('import sys, flows.cli.mpm_cmds; from flows.cli.apps import app; sys.argv[0] = "deformsmith"; app()')


def run_one(root: pathlib.Path, options: dict, particles: int, steps: int, batch: int) -> dict:
    """One bench process in `root` with kernel options `options` (name -> value text); the parsed --json (or an error
    record)."""
    e = dict(os.environ)
    e["PYTHONPATH"] = f"{root}:{e.get('PYTHONPATH', '')}"
    bench = ([sys.executable, "-m", "benchmarks.mpm_bench"] if (root / "benchmarks" / "mpm_bench.py").is_file()
             else [sys.executable, "-c", OLD_CLI, "bench", "mpm"])
    cmd = [*bench, "--device", "cuda", "--particles", str(particles), "--steps", str(steps), "--batch", str(batch),
           "--json"]
    for name, value in options.items():
        if name.startswith("DEFORMSMITH_MPM_"):  # an old tree's switch: its environment variable
            e[name] = value
        else:
            cmd += ["--kernel", f"{name}={value}"]
    t = time.time()
    p = subprocess.run(cmd, cwd=root, env=e, capture_output=True, text=True)
    wall = time.time() - t
    try:
        out = p.stdout
        d = json.loads(out[out.index("{"): out.rindex("}") + 1])
    except Exception:  # noqa: BLE001
        return {"error": (p.stderr or p.stdout)[-2000:], "rc": p.returncode, "wall_s": wall}
    d["wall_s"] = wall
    return d


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--old", default="_old")
    ap.add_argument("--plan", required=True)
    ap.add_argument("--out", default=os.environ.get("OUT", "mpm_ab"))
    a = ap.parse_args()
    here = pathlib.Path.cwd()
    roots = {"old": (here / a.old).resolve(), "new": here}
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    res = []
    for item in a.plan.split(";"):
        item = item.strip()
        if not item:
            continue
        tag, tree, envs, n, k, b = item.split(":")
        options = dict(kv.split("=", 1) for kv in envs.split(",") if kv)
        d = run_one(roots[tree], options, int(n), int(k), int(b))
        d.update({"tag": tag, "tree": tree, "kernel": options})
        res.append(d)
        if "error" in d:
            print(f"{tag:24s} {tree} ERROR rc={d['rc']}: {d['error'][-600:]}", flush=True)
        else:
            print(f"{tag:24s} {tree} {envs:28s} n={d['particles']:>8d} B={d['batch']:>2d} "
                  f"us/step={d['us_per_step']:8.2f} "
                  f"p-steps/s={d['particle_steps_per_s']:.3e} B/p={d['engine_bytes_per_particle']:.1f} "
                  f"peak={d['peak_memory_bytes']} finite={d['finite']} health={d['health_ok']} wall={d['wall_s']:.0f}s",
                  flush=True)
        (out / "ab.json").write_text(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
