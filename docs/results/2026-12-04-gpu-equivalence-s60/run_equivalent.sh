#!/usr/bin/env bash
# Session 60 (#38, "each equal by fingerprint to a clean run of the same request"): two cold GPU runs of one request,
# compared by benchmarks.asset_diff --equivalent (the same files, the same decisions with content keys set aside, the
# numbers within rtol 5 % / atol 1e-3 SI) after session 59 found they cannot be equal by bytes.
# usage (device, wheels installed, from the repo root): bash run_equivalent.sh "REQUEST TEXT" NAME
set -u
TEXT=$1; NAME=$2; S=${SCRATCH:-/var/tmp}; SITE=${DEFORMSMITH_WHEEL_SITE:-$S/site}
export PYTHONPATH=$SITE:. PYTHONUNBUFFERED=1
for i in 1 2; do
  t0=$(date +%s)
  WARP_CACHE_PATH=$S/warp_${NAME}_$i PREFECT_HOME=$S/ph_${NAME}_$i DEFORMSMITH_CACHE=$S/cache_${NAME}_$i \
    python3 -m flows.cli.main generate "$TEXT" --device cuda --out $S/rep_${NAME}_$i > $OUT/gen_${NAME}_$i.log 2>&1
  echo "$NAME run $i rc=$? wall_s=$(( $(date +%s) - t0 ))" | tee -a $OUT/summary.txt
done
python3 -m benchmarks.asset_diff $S/rep_${NAME}_1 $S/rep_${NAME}_2 --equivalent --json > $OUT/equivalence_$NAME.json
python3 -m benchmarks.asset_diff $S/rep_${NAME}_1 $S/rep_${NAME}_2 --equivalent | tee -a $OUT/summary.txt
echo "$NAME equivalent rc=${PIPESTATUS[0]}" | tee -a $OUT/summary.txt
