#!/usr/bin/env bash
# Runs every benchmark of tests/perf (build first with deploy/scripts/setup.sh). Results on stdout.
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
bin=${WINDFDI_BIN:-$top/build/bin}
for b in "$bin"/bench_*; do
  echo "== $(basename "$b")"
  "$b" --benchmark_counters_tabular=true
done
echo "== replay_allocations (heap allocations per sample of every service)"
"$top/tests/perf/replay_allocations.sh" 900
turbine2=$top/deploy/turbine/example_2MW.yaml
turbine3=$top/deploy/turbine/example_3MW_medium_speed.yaml
echo "== pitch_diag_plant, benchmark 4.8 MW turbine"
"$bin/pitch_diag_plant" 3600
echo "== pitch_diag_plant, example 2 MW turbine"
"$bin/pitch_diag_plant" 3600 --turbine "$turbine2" bank
echo "== pitch_diag_slow_swing"
"$bin/pitch_diag_slow_swing" 3 1200
echo "== ice_detect_plant, benchmark 4.8 MW turbine"
"$bin/ice_detect_plant" 3600 3
echo "== ice_detect_plant, example 2 MW turbine"
"$bin/ice_detect_plant" 3600 3 --turbine "$turbine2"
echo "== ice_detect_plant, example 2 MW turbine, the plant's aerodynamic power (no anemometer noise)"
AERO_POWER=1 "$bin/ice_detect_plant" 3600 3 --turbine "$turbine2"
echo "== ice_detect_plant, example medium-speed 3 MW turbine"
"$bin/ice_detect_plant" 3600 3 --turbine "$turbine3"
# The whole system's healthy hours (ten at each of 8, 12, 16 and 20 m/s) and fault delays (ten multi-fault
# scenarios) on the shipped turbines.
healthy=$(mktemp -d)
trap 'rm -rf "$healthy"' EXIT
suite=$top/tests/perf/multi_fault_suite.py
two_mw=(--set blade_load.turbine_file="$turbine2" --set drive_train.turbine_file="$turbine2"
  --set ice_detect.turbine_file="$turbine2" --set sensor_bias.turbine_file="$turbine2"
  --set arbiter.turbine_file="$turbine2" --set pitch_diag.turbine_file="$turbine2"
  --set sensor_bias.drive_train_gains="$top/deploy/sensor_bias/gains_drive_train_observer_2MW.yaml"
  --set blade_load.load_table_file="$top/deploy/turbine/example_2MW_load_table.csv")
# The medium-speed turbine by its turbine file alone: sensor_bias designs its gains and blade_load builds its
# table at start.
medium=(--set blade_load.turbine_file="$turbine3" --set drive_train.turbine_file="$turbine3"
  --set ice_detect.turbine_file="$turbine3" --set sensor_bias.turbine_file="$turbine3"
  --set arbiter.turbine_file="$turbine3" --set pitch_diag.turbine_file="$turbine3")
echo "== healthy hours, benchmark 4.8 MW turbine"
python3 "$suite" generate --healthy --seed 5 --count 10 --out "$healthy/4.8MW" >/dev/null
python3 "$suite" run "$healthy/4.8MW" --mode fast --work "$healthy/w4.8MW" | tail -n 4
echo "== healthy hours, example 2 MW turbine"
python3 "$suite" generate --healthy --seed 5 --count 10 --turbine-file "$turbine2" --out "$healthy/2MW" >/dev/null
python3 "$suite" run "$healthy/2MW" --mode fast --work "$healthy/w2MW" "${two_mw[@]}" | tail -n 6
echo "== healthy hours, example medium-speed 3 MW turbine"
python3 "$suite" generate --healthy --seed 5 --count 10 --turbine-file "$turbine3" --out "$healthy/3MW" >/dev/null
python3 "$suite" run "$healthy/3MW" --mode fast --work "$healthy/w3MW" "${medium[@]}" | tail -n 6
echo "== fault delays (multi-fault suite), benchmark 4.8 MW turbine"
python3 "$suite" generate --seed 6 --count 10 --out "$healthy/f4.8MW" >/dev/null
python3 "$suite" run "$healthy/f4.8MW" --mode fast --work "$healthy/wf4.8MW" | grep -v '^scenario_'
echo "== fault delays (multi-fault suite), example 2 MW turbine"
python3 "$suite" generate --seed 6 --count 10 --turbine-file "$turbine2" --out "$healthy/f2MW" >/dev/null
python3 "$suite" run "$healthy/f2MW" --mode fast --work "$healthy/wf2MW" "${two_mw[@]}" | grep -v '^scenario_'
echo "== fault delays (multi-fault suite), example medium-speed 3 MW turbine"
python3 "$suite" generate --seed 6 --count 10 --turbine-file "$turbine3" --out "$healthy/f3MW" >/dev/null
python3 "$suite" run "$healthy/f3MW" --mode fast --work "$healthy/wf3MW" "${medium[@]}" | grep -v '^scenario_'
# The examples written in stop 61 as turbines nobody had tuned on, by their turbine files alone.
for example in 6MW 1.5MW; do
  file=$top/deploy/turbine/example_$example.yaml
  own=()
  for service in blade_load drive_train ice_detect sensor_bias arbiter pitch_diag; do
    own+=(--set "$service.turbine_file=$file")
  done
  echo "== healthy hours, example $example turbine"
  python3 "$suite" generate --healthy --seed 5 --count 10 --turbine-file "$file" --out "$healthy/$example" >/dev/null
  python3 "$suite" run "$healthy/$example" --mode fast --work "$healthy/w$example" "${own[@]}" | tail -n 6
  echo "== fault delays (multi-fault suite), example $example turbine"
  python3 "$suite" generate --seed 6 --count 10 --turbine-file "$file" --out "$healthy/f$example" >/dev/null
  python3 "$suite" run "$healthy/f$example" --mode fast --work "$healthy/wf$example" "${own[@]}" | grep -v '^scenario_'
done
echo "== drive_train_plant, benchmark 4.8 MW turbine"
"$bin/drive_train_plant" 10 5
echo "== drive_train_plant, example 2 MW turbine"
"$bin/drive_train_plant" 10 5 --turbine "$turbine2"
echo "== drive_train_plant, example medium-speed 3 MW turbine"
"$bin/drive_train_plant" 10 5 --turbine "$turbine3"
echo "== system_latency"
"$top/tests/perf/system_latency.sh" 10 90
echo "== farm_http_latency (the farm web page's data with 200 turbines running)"
"$top/tests/perf/farm_http_latency.sh" 200 300 30
echo "== farm_capacity"
"$top/tests/perf/farm_capacity.sh" 30 10 20 40 80
echo "== farm_shards (one and two service hosts, network namespaces; needs root)"
"$top/tests/perf/farm_shards.sh" 30 30 30 40 50 60 70 80 || echo "farm_shards: skipped or failed"
echo "== ipc_value"
"$bin/ipc_value" 5 3
echo "== plant_farm_cpu"
"$top/tests/perf/plant_farm_cpu.sh" 100 20 3
