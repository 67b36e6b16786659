#!/usr/bin/env bash
# The demo: installs what is missing, builds, then runs a simulated farm with several faults on several
# turbines, every diagnostic service, the arbiter and the farm monitor (its live table on this terminal),
# and ends with a table of injected faults against detections and the arbiter's reactions.
# Usage: run_demo.sh [SCENARIO.yaml] (default deploy/scenarios/demo_farm.yaml)
# Environment: WINDFDI_DEMO_RATE (speed-up, default 4), WINDFDI_DOMAIN, WINDFDI_PARTICIPANT_PROFILE.
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
build=${WINDFDI_BUILD_DIR:-$top/build}
"$top/deploy/scripts/setup.sh"
bin=$build/bin
scenario=${1:-$top/deploy/scenarios/demo_farm.yaml}
rate=${WINDFDI_DEMO_RATE:-4}
export WINDFDI_DOMAIN=${WINDFDI_DOMAIN:-$((100 + RANDOM % 100))}
# Loopback discovery works on any machine, with or without multicast.
export WINDFDI_PARTICIPANT_PROFILE=${WINDFDI_PARTICIPANT_PROFILE:-windfdi_participant_loopback}
work=$build/demo
rm -rf "$work"
mkdir -p "$work/logs"
pids=()
cleanup() {
  kill -TERM "${pids[@]}" 2>/dev/null || true
  wait 2>/dev/null || true
}
trap cleanup EXIT INT TERM

echo "demo: domain $WINDFDI_DOMAIN, scenario $scenario at ${rate}x, logs in $work/logs"
for service in blade-load sensor-bias pitch-diag ice-detect; do
  exe="$bin/windfdi-$service"
  if [ ! -x "$exe" ]; then echo "demo: $exe not built yet, skipped"; continue; fi
  cfg="$top/deploy/config/${service//-/_}.yaml"
  args=()
  [ -f "$cfg" ] && args+=(--config "$cfg")
  "$exe" "${args[@]}" >"$work/logs/$service.log" 2>&1 &
  pids+=($!)
done
"$bin/windfdi-arbiter" --config "$top/deploy/config/arbiter.yaml" --arbiter-id primary >"$work/logs/arbiter.log" 2>&1 &
pids+=($!)
"$bin/windfdi-farm" --db "$work/farm.sqlite" --table-period 2 2>"$work/logs/farm.log" &
farm=$!
pids+=($farm)
sleep 2
start=$(date +%s)
"$bin/windfdi-plant" --scenario "$scenario" --rate "$rate" --record "$work/frames.csv.gz" --record-truth \
  --progress 0 >"$work/logs/plant.log" 2>&1
sleep 5  # the last reports and configurations reach the farm monitor
kill -TERM "$farm" 2>/dev/null || true
wait "$farm" 2>/dev/null || true
echo
echo "== injected faults against detections ($(($(date +%s) - start)) s)"
"$bin/windfdi-farm" --db "$work/farm.sqlite" report --scenario "$scenario"
echo "== history: $bin/windfdi-farm --db $work/farm.sqlite history ; recording: $work/frames.csv.gz"
