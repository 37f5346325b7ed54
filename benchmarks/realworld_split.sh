#!/usr/bin/env bash
# `bench realworld` on one GPU in four processes side by side (the set takes ~20 min in one): the rule balls in two
# halves and the measured-modulus foods through L2 (draft), the fruit and bakery masses from the priors alone.
# Usage (device machine, wheels installed): bash benchmarks/realworld_split.sh SECONDS OUTDIR [GPU] [WORKDIR]
# (WORKDIR: the assets, caches and Prefect homes; default a new temporary directory)
set -u
SECONDS_RUN=${1:-500}; OUTDIR=${2:?an output directory}; GPU=${3:-0}; WORK=${4:-$(mktemp -d)}
mkdir -p "$OUTDIR"
part() {  # NAME [options...]
  local name=$1; shift
  CUDA_VISIBLE_DEVICES=$GPU PREFECT_HOME="$WORK/prefect_$name" timeout -s INT "$SECONDS_RUN" \
    python3 -m flows.cli.main bench realworld --out "$WORK/rw_$name" --json "$@" > "$OUTDIR/rw_$name.json" \
    2> "$OUTDIR/rw_$name.err"
}
part balls1 --device cuda --only "tennis ball" --only racquetball --only "table tennis ball" --only basketball \
  --only "soccer ball" --only pickleball &
part balls2 --device cuda --only "padel ball" --only volleyball --only netball --only "squash ball" \
  --only "rugby ball" --only "american football" &
part moduli --device cuda --only marshmallow --only "loaf of bread" --only "slice of bread" \
  --only "block of cheddar cheese" --only "mozzarella cheese" &
part priors --priors-only &
wait
