#!/usr/bin/env bash
# Session 55 (from session 44's): `bench realworld` over the whole set on one H200, one object per process, P processes side by side
# (xargs -P), each `bench realworld --only NAME --device cuda --json`, cold. Re-runnable on a warm machine: an object
# whose report came back is skipped, an unfinished one starts again from its own cache (--out keeps OUT/_cache).
# usage (device, wheels installed): bash run_rw.sh P DEADLINE_S   -> $OUT/reports.tar, $OUT/log.txt
set -u
export PYTHONPATH=/var/tmp/site:. WARP_CACHE_PATH=/var/tmp/warp PYTHONUNBUFFERED=1
R=/var/tmp/rw55; mkdir -p $R/res $R/ph $R/out
if [ "${1:-}" = one ]; then
  name=$2; s=$(echo "$name" | tr ' ' '_'); end=$3
  [ -s $R/res/rw_$s.json ] && exit 0
  left=$(( end - $(date +%s) )); if [ $left -lt 40 ]; then echo "$(date -u +%T) $name skipped (${left} s left)" >> $R/res/runs.txt; exit 0; fi
  t0=$(date +%s.%N); echo "$(date -u +%T) $name start (limit ${left} s)" >> $R/res/runs.txt
  PREFECT_HOME=$R/ph/$s timeout -k 20 -s INT $left python3 -m flows.cli.main bench realworld --only "$name" \
    --device cuda --json --out $R/out/$s > $R/res/rw_$s.part 2> $R/res/err_$s.txt; rc=$?
  [ $rc = 0 ] && mv $R/res/rw_$s.part $R/res/rw_$s.json
  echo "$(date -u +%T) $name rc=$rc wall=$(awk -v a=$t0 -v b=$(date +%s.%N) 'BEGIN{printf "%.1f", b-a}') s" >> $R/res/runs.txt
  exit 0
fi
P=$1; end=$(( $(date +%s) + $2 ))
nvidia-smi --query-gpu=name,memory.used --format=csv,noheader
t0=$(date +%s); echo "$(date -u +%T) call start P=$P deadline $2 s" >> $R/res/runs.txt
grep -v '^#' docs/results/2026-12-04-realworld-h200-s55/objects.txt | xargs -d '\n' -P $P -I{} bash $0 one "{}" $end
echo "$(date -u +%T) call end after $(( $(date +%s) - t0 )) s" >> $R/res/runs.txt
(nvidia-smi --query-gpu=memory.used --format=csv,noheader; uptime) >> $R/res/runs.txt
cp $R/res/runs.txt $OUT/log.txt; (cd $R/res && tar cf $OUT/reports.tar *)
ls $R/res | grep -c '^rw_.*json$'; tail -n 5 $R/res/runs.txt
