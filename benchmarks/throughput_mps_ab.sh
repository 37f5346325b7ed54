#!/usr/bin/env bash
# Side by side on one machine with two GPUs: the same requests, cold caches, 12 workers per GPU, GPU 0 under CUDA MPS
# (the workers' kernels run concurrently instead of time-sliced) and GPU 1 without. Usage (device machine, wheels
# installed): bash benchmarks/throughput_mps_ab.sh SECONDS LIMIT OUTDIR [WORKDIR] (WORKDIR: the runs, their caches,
# Prefect homes and the MPS pipes; default a new temporary directory)
set -u
SECONDS_RUN=${1:-480}; LIMIT=${2:-40}; OUTDIR=${3:?an output directory}; WORK=${4:-$(mktemp -d)}
R=benchmarks/throughput_requests.jsonl
mkdir -p "$OUTDIR" "$WORK/mps_pipe" "$WORK/mps_log"
CUDA_VISIBLE_DEVICES=0 CUDA_MPS_PIPE_DIRECTORY="$WORK/mps_pipe" CUDA_MPS_LOG_DIRECTORY="$WORK/mps_log" \
  nvidia-cuda-mps-control -d && echo "mps daemon started"
run() {  # NAME GPU [mps]
  local env=(CUDA_VISIBLE_DEVICES="$2" PREFECT_HOME="$WORK/prefect_$1")
  [ "${3:-}" = mps ] && env+=("CUDA_MPS_PIPE_DIRECTORY=$WORK/mps_pipe" "CUDA_MPS_LOG_DIRECTORY=$WORK/mps_log")
  env "${env[@]}" timeout -s INT "$SECONDS_RUN" python3 -m flows.cli.main bench throughput "$R" --gpus 1 \
    --workers-per-gpu 12 --limit "$LIMIT" --out "$WORK/tp_$1" --json > "$OUTDIR/$1.json" 2> "$OUTDIR/$1.err"
  cp "$WORK/tp_$1/throughput_report.json" "$OUTDIR/$1_report.json" 2>/dev/null
}
run mps 0 mps &
run plain 1 &
wait
echo quit | CUDA_MPS_PIPE_DIRECTORY="$WORK/mps_pipe" nvidia-cuda-mps-control
python3 - "$OUTDIR" <<'PY'
import json, sys, pathlib
for name in ("mps", "plain"):
    p = pathlib.Path(sys.argv[1]) / f"{name}_report.json"
    if not p.is_file():
        print(name, "no report"); continue
    r = json.loads(p.read_text())
    keys = ("assets_per_hour", "l3_passed_per_hour", "ok", "failed", "pending", "wall_s", "stage_s_per_asset")
    print(name, {k: r.get(k) for k in keys}, "gpu", r.get("gpu"))
PY
