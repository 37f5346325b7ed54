#!/usr/bin/env bash
# Session 57 (#38, "kernels load once per process and are reused across assets (a worker serves many assets)"):
# `bench throughput` on one H200, cold, --gpus G with K workers per GPU, each worker process serving R requests one
# after another (R=1: a new process per request, as sessions 42-56 measured), stopped after WINDOW_S (SIGINT; the
# report, OUT/throughput_report.json, covers what finished: copied to $OUT).
# usage (device, wheels installed, from the repo root): bash run_tp.sh G WINDOW_S K R
# SCRATCH (default /var/tmp): where the runs write; DEFORMSMITH_WHEEL_SITE as deployments/gpu_wheels.py takes it
set -u
G=$1; W=$2; K=${3:-12}; R=${4:-20}; T=g${G}k${K}r$R
S=${SCRATCH:-/var/tmp}; SITE=${DEFORMSMITH_WHEEL_SITE:-$S/site}
export PYTHONPATH=$SITE:. WARP_CACHE_PATH=$S/warp_$T PYTHONUNBUFFERED=1 PREFECT_HOME=$S/ph_$T
nvidia-smi --query-gpu=index,name,memory.used --format=csv,noheader | tee $OUT/log_$T.txt
nproc | tee -a $OUT/log_$T.txt
t0=$(date +%s)
timeout -k 20 -s INT $W python3 -m flows.cli.main bench throughput benchmarks/throughput_requests.jsonl --gpus $G \
  --workers-per-gpu $K --requests-per-worker $R --out $S/tp_$T --json > $OUT/throughput_$T.json \
  2> $OUT/throughput_err_$T.txt
echo "rc=$? wall_s=$(( $(date +%s) - t0 ))" | tee -a $OUT/log_$T.txt
cp $S/tp_$T/throughput_report.json $OUT/throughput_report_$T.json
cp $S/tp_$T/_throughput/records.jsonl $OUT/records_$T.jsonl
tail -c 20000 $S/tp_$T/_logs/_worker-0.log > $OUT/worker0_log_tail_$T.txt 2>/dev/null || true
