#!/usr/bin/env bash
# Quick look at the CUDA path on the device machine (no before/after): benches, per-kernel profiles, GPU tests.
# Args: kernel option variants (contracts.sim.KernelOptions) to bench at 8k and 16 x 8k, one argument each, options of
# a variant joined by commas, e.g. p2g_parts=3,cuda_block_threads=128 scatter=warp
set -u
variants="$*"
export PYTHONPATH="$PWD:${PYTHONPATH:-}" PYTHONUNBUFFERED=1
ds() { python3 -m benchmarks.mpm_bench "$@"; }  # the MPM benchmark's command line
for args in "8000 5000 1" "8000 2000 16" "1000000 300 1"; do
  set -- $args
  ds --device cuda --particles $1 --steps $2 --batch $3 --json | python3 benchmarks/engine/gpu_summary.py
done
for args in "8000 1" "8000 16" "1000000 1"; do
  set -- $args
  python3 -m benchmarks.engine.gpu_profile --particles $1 --batch $2 --json | python3 benchmarks/engine/gpu_summary.py
done
for var in $variants; do
  for args in "8000 5000 1" "8000 2000 16"; do
    set -- $args
    kopts=(); IFS=, read -ra kv <<< "$var"; for o in "${kv[@]}"; do kopts+=(--kernel "$o"); done
    echo -n "$var: "; ds --device cuda --particles $1 --steps $2 --batch $3 ${kopts[@]+"${kopts[@]}"} --json \
      | python3 benchmarks/engine/gpu_summary.py
  done
done
python3 -m pytest -q -p no:cacheprovider -m gpu tests/mpm 2>&1 | tail -3
