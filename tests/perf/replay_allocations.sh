#!/usr/bin/env bash
# Heap allocations per sample of every diagnostic service: the plant records SECONDS of a scenario offline,
# each service replays it with a malloc counter preloaded (tests/perf/alloc/count_malloc.c), and the calls
# are divided by the samples. The replay reads its CSV with allocations of its own (about 35 a sample, the
# same for every build), so compare builds, or services against each other, not against zero.
#
# Usage: replay_allocations.sh [SECONDS=900] [SCENARIO=deploy/scenarios/benchmark.yaml]
# Binaries: $WINDFDI_BIN (default build/bin). Needs a C compiler (cc) for the counter.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
bin=${WINDFDI_BIN:-$root/build/bin}
secs=${1:-900}
scenario=${2:-$root/deploy/scenarios/benchmark.yaml}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cc -O2 -shared -fPIC -o "$work/count_malloc.so" "$here/alloc/count_malloc.c" -ldl
"$bin/windfdi-plant" --offline --scenario "$scenario" --duration "$secs" --record "$work/frames.csv.gz" \
  --progress 0 > "$work/plant.log" 2>&1
echo "replay_allocations: $scenario, $secs s"
printf '%-14s %10s %12s %18s\n' service samples mallocs mallocs/sample
for svc in blade-load sensor-bias pitch-diag ice-detect drive-train; do
  env MALLOC_COUNT_FILE="$work/$svc.count" LD_PRELOAD="$work/count_malloc.so" "$bin/windfdi-$svc" \
    --config "$root/deploy/config/${svc//-/_}.yaml" --replay "$work/frames.csv.gz" \
    --estimates "$work/$svc.csv" --events "$work/$svc.jsonl" > "$work/$svc.log" 2>&1
  samples=$(sed -n 's/.*replay of .*: \([0-9]*\) samples,.*/\1/p' "$work/$svc.log")
  mallocs=$(cat "$work/$svc.count")
  printf '%-14s %10d %12d %18.2f\n' "$svc" "$samples" "$mallocs" "$(awk -v m="$mallocs" -v s="$samples" 'BEGIN { print m / s }')"
done
