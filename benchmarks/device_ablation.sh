#!/bin/bash
# device: the manipulation ablation on cuda, resumable (call again while the machine is warm); copies records to $OUT
export PYTHONPATH=/var/tmp/site:. PREFECT_HOME=/var/tmp/ph DEFORMSMITH_CACHE=/var/tmp/abl/cache
mkdir -p /var/tmp/abl
LIM=${1:-540}
nvidia-smi --query-gpu=name,memory.used --format=csv,noheader
timeout -s TERM $LIM python3 -m flows.cli.main eval --suite manipulation --ablation manipulation --workers 8 \
  --device cuda --no-videos --out /var/tmp/abl/out --cache /var/tmp/abl/cache --json > /var/tmp/abl/out.json 2>> /var/tmp/abl/err.log
echo "rc=$?"
tail -c 6000 /var/tmp/abl/err.log
mkdir -p $OUT/abl; cp /var/tmp/abl/out.json $OUT/abl/ 2>/dev/null
(cd /var/tmp/abl/out && find . -name "*.json" -size -2M | tar cf $OUT/abl/records.tar -T -) 2>/dev/null
ls -R /var/tmp/abl/out/records 2>/dev/null | head -40
