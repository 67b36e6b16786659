#!/usr/bin/env bash
# Runs every benchmark of tests/perf (build first with deploy/scripts/setup.sh). Results on stdout.
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
bin=${WINDFDI_BIN:-$top/build/bin}
for b in "$bin"/bench_*; do
  echo "== $(basename "$b")"
  "$b" --benchmark_counters_tabular=true
done
echo "== pitch_diag_plant"
"$bin/pitch_diag_plant" 3600
echo "== ice_detect_plant"
"$bin/ice_detect_plant" 3600 3
echo "== drive_train_plant"
"$bin/drive_train_plant" 10 5
echo "== system_latency"
"$top/tests/perf/system_latency.sh" 10 90
echo "== farm_capacity"
"$top/tests/perf/farm_capacity.sh" 30 10 20 40 80
echo "== ipc_value"
"$bin/ipc_value" 5 3
echo "== plant_farm_cpu"
"$top/tests/perf/plant_farm_cpu.sh" 100 20 3
