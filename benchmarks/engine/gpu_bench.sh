#!/usr/bin/env bash
# GPU figures of the MPM engine (run on the device machine from the repo root; Warp + pydantic on PYTHONPATH).
# Writes one JSON per measurement to ${OUT:-/tmp/mpm_gpu}; BENCHMARKS.md records what it printed.
# KERNEL: optional kernel options (contracts.sim.KernelOptions) for the bench runs, comma-separated name=value.
set -u
OUT=${OUT:-/tmp/mpm_gpu}; mkdir -p "$OUT"
export PYTHONPATH="$PWD:${PYTHONPATH:-}" PYTHONUNBUFFERED=1
kopts=(); IFS=, read -ra kv <<< "${KERNEL:-}"; for o in "${kv[@]}"; do kopts+=(--kernel "$o"); done
ds() { python3 -m benchmarks.mpm_bench "$@"; }  # the MPM benchmark's command line
verify() { python3 -c 'import sys, flows.cli.mpm_cmds; from flows.cli.apps import app; sys.argv[0] = "deformsmith"; app()' verify "$@"; }
nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader | tee "$OUT/gpu.txt"
ds --device cuda --particles 8000 --steps 5000 ${kopts[@]+"${kopts[@]}"} --json > "$OUT/bench_8k.json"; echo "8k rc=$?"
ds --device cuda --particles 1000000 --steps 300 ${kopts[@]+"${kopts[@]}"} --json > "$OUT/bench_1m.json"; echo "1M rc=$?"
ds --device cuda --particles 8000 --steps 2000 --batch 16 ${kopts[@]+"${kopts[@]}"} --json > "$OUT/bench_8k_x16.json"; echo "x16 rc=$?"
ds --device cuda --particles 64000 --steps 1000 ${kopts[@]+"${kopts[@]}"} --json > "$OUT/bench_64k.json"; echo "64k rc=$?"
verify physics --quick --device cuda --json > "$OUT/verify_cuda_quick.json"; echo "verify rc=$?"
python3 -m pytest -q -p no:cacheprovider -m gpu tests/mpm/test_engine.py 2>&1 | tail -2
python3 - "$OUT" <<'PY'
import json, sys, pathlib
out = pathlib.Path(sys.argv[1])
for name in ("bench_8k", "bench_1m", "bench_8k_x16", "bench_64k"):
    p = out / f"{name}.json"
    try:
        d = json.loads(p.read_text())
    except Exception as exc:  # noqa: BLE001
        print(name, "missing", exc); continue
    print(f"{name}: {d['device_name']} particles={d['particles']} batch={d['batch']} us/step={d['us_per_step']:.1f} "
          f"p-steps/s={d['particle_steps_per_s']:.3g} peak={d['peak_memory_bytes']} "
          f"B/particle(engine)={d['engine_bytes_per_particle']:.0f} finite={d['finite']} graph={d['cuda_graph']}")
try:
    v = json.loads((out / "verify_cuda_quick.json").read_text())
    for c in v["cases"]:
        print(f"verify {c['name']}: measured={c['measured']:.5g} expected={c['expected']:.5g} err={c['error']:.3g} pass={c['passed']}")
except Exception as exc:  # noqa: BLE001
    print("verify missing", exc)
PY
