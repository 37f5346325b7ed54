#!/usr/bin/env bash
# Session 59 (#38, "each equal by fingerprint to a clean run of the same request"): how far two cold runs of the
# same request on one GPU differ. Each run has its own result cache, Prefect home and Warp kernel cache; then
# benchmarks.asset_diff compares the two assets file by file (content fingerprint) and, for JSON files that differ,
# the largest relative difference of their numbers and the other values that differ.
# usage (device, wheels installed, from the repo root): bash run_repeat.sh "REQUEST TEXT" NAME
set -u
TEXT=$1; NAME=$2; S=${SCRATCH:-/var/tmp}; SITE=${DEFORMSMITH_WHEEL_SITE:-$S/site}
export PYTHONPATH=$SITE:. PYTHONUNBUFFERED=1
for i in 1 2; do
  t0=$(date +%s)
  WARP_CACHE_PATH=$S/warp_${NAME}_$i PREFECT_HOME=$S/ph_${NAME}_$i DEFORMSMITH_CACHE=$S/cache_${NAME}_$i \
    python3 -m flows.cli.main generate "$TEXT" --device cuda --out $S/rep_${NAME}_$i > $OUT/gen_${NAME}_$i.log 2>&1
  echo "$NAME run $i rc=$? wall_s=$(( $(date +%s) - t0 ))" | tee -a $OUT/summary.txt
done
python3 -m benchmarks.asset_diff $S/rep_${NAME}_1 $S/rep_${NAME}_2 --json > $OUT/diff_$NAME.json
python3 -m benchmarks.asset_diff $S/rep_${NAME}_1 $S/rep_${NAME}_2 | tee -a $OUT/summary.txt
