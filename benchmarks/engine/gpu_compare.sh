#!/usr/bin/env bash
# Before/after of the CUDA kernels on the device machine, back to back in one session: the plain one-thread-per-item
# kernels of kernels.py (KernelOptions cuda_fast=false, "old") and the block-level ones of kernels_cuda.py ("new").
# Run from the repo root with Warp + pydantic on PYTHONPATH. Everything lands in ${OUT}/compare.json (+ log).
set -u
OUT=${OUT:-/tmp/mpm_gpu}; mkdir -p "$OUT"
W=${WORK:-/tmp/mpm_cmp}; rm -rf "$W"; mkdir -p "$W"
export PYTHONPATH="$PWD:${PYTHONPATH:-}" PYTHONUNBUFFERED=1
for mode in old new; do
  fast=true; [ "$mode" = old ] && fast=false
  echo "=== $mode (cuda_fast=$fast)"
  KERNEL="cuda_fast=$fast" OUT="$W/$mode" bash benchmarks/engine/gpu_bench.sh
done
for round in 2; do   # a second round of the latency-bound sizes, alternating, to see run-to-run spread
  for mode in old new; do
    fast=true; [ "$mode" = old ] && fast=false
    for args in "8000 5000 1" "8000 2000 16"; do
      set -- $args
      python3 -m benchmarks.mpm_bench --device cuda --particles $1 --steps $2 --batch $3 --kernel cuda_fast=$fast --json \
        > "$W/$mode/r${round}_bench_$1_x$3.json"
    done
  done
done
for mode in old new; do
  fast=true; [ "$mode" = old ] && fast=false
  for args in "8000 1" "8000 16" "1000000 1"; do
    set -- $args
    python3 -m benchmarks.engine.gpu_profile --particles $1 --batch $2 --steps 60 --kernel cuda_fast=$fast --json \
      > "$W/$mode/profile_$1_x$2.json" || echo "profile $mode $args failed"
  done
done
echo "=== pytest -m gpu tests/mpm (new path)"
python3 -m pytest -q -p no:cacheprovider -m gpu tests/mpm 2>&1 | tail -15
python3 - "$W" "$OUT" <<'PY'
import json, sys, pathlib
w, out = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
res = {}
for mode in ("old", "new"):
    for p in sorted((w / mode).glob("*")):
        try:
            res[f"{mode}/{p.name}"] = json.loads(p.read_text()) if p.suffix == ".json" else p.read_text()
        except Exception as exc:  # noqa: BLE001
            res[f"{mode}/{p.name}"] = f"unreadable: {exc}"
(out / "compare.json").write_text(json.dumps(res, indent=1))
for k, d in res.items():
    if isinstance(d, dict) and "us_per_step" in d:
        print(f"{k}: particles={d['particles']} batch={d['batch']} us/step={d['us_per_step']:.1f} "
              f"p-steps/s={d['particle_steps_per_s']:.3g} B/p={d['engine_bytes_per_particle']:.0f} finite={d['finite']}")
    elif isinstance(d, dict) and "kernels" in d:
        print(f"{k}: kernel us/step={d['kernel_us_per_step']:.1f} " + " ".join(
            f"{n}={v['mean_us']:.1f}x{v['launches']}" for n, v in d["kernels"].items()))
PY
