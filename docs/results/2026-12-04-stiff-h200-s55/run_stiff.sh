#!/usr/bin/env bash
# Session 55 (#38 item 4 on the GPU): the draft turtle, a tennis ball and a rubber duck, `generate --device cuda --json`
# (L0-L3, renders, card) one after the other, each cold (its own cache and Prefect home; the summary's timings give
# each stage's wall time), then the tennis ball's quasi-static probes with and without mass scaling side by side
# (benchmarks/quasi_static_scaling.py). usage (device, wheels installed): bash run_stiff.sh DEADLINE_S
set -u
export PYTHONPATH=/var/tmp/site:. WARP_CACHE_PATH=/var/tmp/warp PYTHONUNBUFFERED=1
R=/var/tmp/stiff55; mkdir -p $R; end=$(( $(date +%s) + $1 ))
nvidia-smi --query-gpu=name,memory.used --format=csv,noheader | tee $OUT/log.txt
git log -1 --format='%H %s' >> $OUT/log.txt 2>&1
for obj in turtle tennis duck; do
  case $obj in turtle) text='a soft plush turtle toy, about 25 cm long';; tennis) text='a tennis ball';;
               duck) text='a red rubber duck, 10 cm long';; esac
  left=$(( end - $(date +%s) )); [ $left -lt 30 ] && { echo "$obj skipped" | tee -a $OUT/log.txt; continue; }
  t0=$(date +%s.%N)
  PREFECT_HOME=$R/ph_$obj timeout -k 10 -s INT $left python3 -m flows.cli.main generate "$text" --device cuda \
    --out $R/out_$obj --cache $R/cache_$obj --json > $OUT/generate_$obj.json 2>> $OUT/log.txt; rc=$?
  echo "generate $obj rc=$rc wall_s=$(awk -v a=$t0 -v b=$(date +%s.%N) 'BEGIN{printf "%.1f", b-a}')" | tee -a $OUT/log.txt
done
left=$(( end - $(date +%s) ))
[ $left -gt 60 ] && timeout -s INT $left python3 -m benchmarks.quasi_static_scaling --asset $R/out_tennis --device cuda \
  --json > $OUT/scaling_tennis_cuda.json 2>> $OUT/log.txt; echo "scaling rc=$?" | tee -a $OUT/log.txt
