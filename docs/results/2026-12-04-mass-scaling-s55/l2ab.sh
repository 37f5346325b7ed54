#!/bin/bash
# L2 alone (deformsmith material) on copies of the L1 tennis ball and turtle: after (working tree) then before (HEAD)
# AB: output folder; AFTER, BEFORE: checkouts of the two commits; ASSETS: folder holding the L1 assets tb/ and turtle/
set -u
. $AFTER/.venv/bin/activate
for obj in tb turtle; do
  for side in after before; do
    src=$AFTER; [ $side = before ] && src=$BEFORE
    d=$AB/$side-$obj; rm -rf $d; mkdir -p $d; cp -r $ASSETS/$obj $d/asset
    cd $src
    export PREFECT_HOME=$d/ph DEFORMSMITH_CACHE=$d/cache PYTHONPATH=$src
    s=$(date +%s.%N)
    python -m flows.cli.main material $d/asset --json > $d/material.json 2> $d/err.log
    rc=$?
    e=$(date +%s.%N)
    echo "$side $obj rc=$rc wall_s=$(python3 -c "print(round($e-$s,2))")" | tee -a $AB/summary.txt
  done
done
