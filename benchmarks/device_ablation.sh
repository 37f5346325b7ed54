#!/bin/bash
# The manipulation ablation on the GPU machine (cuda, 8 workers), resumable: call it again while the machine is warm
# and finished trials come from the cache; copies the --json output and the records to $OUT.
#   bash benchmarks/device_ablation.sh [SECONDS]     (after deployments/gpu_wheels.py install; see docs/BENCHMARKS.md)
# DEFORMSMITH_WHEEL_SITE: where gpu_wheels installed the packages (default /var/tmp/site, its default);
# ABLATION_DIR: the run's cache, Prefect home and output (default /var/tmp/abl: /var/tmp is what the device keeps
# between calls).
SITE=${DEFORMSMITH_WHEEL_SITE:-/var/tmp/site}
D=${ABLATION_DIR:-/var/tmp/abl}
export PYTHONPATH=$SITE:. PREFECT_HOME=$D/prefect DEFORMSMITH_CACHE=$D/cache
mkdir -p "$D"
LIM=${1:-540}
nvidia-smi --query-gpu=name,memory.used --format=csv,noheader
timeout -s TERM "$LIM" python3 -m flows.cli.main eval --suite manipulation --ablation manipulation --workers 8 \
  --device cuda --no-videos --out "$D/out" --cache "$D/cache" --json > "$D/out.json" 2>> "$D/err.log"
echo "rc=$?"
tail -c 6000 "$D/err.log"
mkdir -p "$OUT/abl"; cp "$D/out.json" "$OUT/abl/" 2>/dev/null
(cd "$D/out" && find . -name "*.json" -size -2M | tar cf "$OUT/abl/records.tar" -T -) 2>/dev/null
ls -R "$D/out/records" 2>/dev/null | head -40
