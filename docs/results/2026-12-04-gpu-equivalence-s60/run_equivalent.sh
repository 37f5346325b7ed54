#!/usr/bin/env bash
# Session 60 (#38, "each equal by fingerprint to a clean run of the same request"): two cold GPU runs of one request
# (session 59's run_repeat.sh: each with its own result cache, Prefect home and Warp kernel cache), then compared by
# benchmarks.asset_diff --equivalent (the same files, the same decisions with content keys set aside, the numbers
# within rtol 5 % / atol 1e-3 SI) after session 59 found they cannot be equal by bytes.
# usage (device, wheels installed, from the repo root): bash run_equivalent.sh "REQUEST TEXT" NAME
set -u
NAME=$2; S=${SCRATCH:-/var/tmp}
bash "$(dirname "$0")/../2026-12-04-gpu-repeat-s59/run_repeat.sh" "$@"
export PYTHONPATH=${DEFORMSMITH_WHEEL_SITE:-$S/site}:.
python3 -m benchmarks.asset_diff $S/rep_${NAME}_1 $S/rep_${NAME}_2 --equivalent --json > $OUT/equivalence_$NAME.json
python3 -m benchmarks.asset_diff $S/rep_${NAME}_1 $S/rep_${NAME}_2 --equivalent | tee -a $OUT/summary.txt
echo "$NAME equivalent rc=${PIPESTATUS[0]}" | tee -a $OUT/summary.txt
