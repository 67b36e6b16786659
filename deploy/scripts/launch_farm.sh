#!/usr/bin/env bash
# Starts a whole simulated farm on one DDS domain: every diagnostic service (farm-wide instances), the
# arbiter (and a standby), the farm monitor with its live table on this terminal, then the plant with a
# scenario. Stops everything when the plant ends or on Ctrl-C. A scenario that names a turbine_file (a turbine
# other than the benchmark's) runs every service and the arbiter on that turbine file too: their configurations
# are copied to DIR/deploy/config with turbine_file replaced.
# Usage: launch_farm.sh SCENARIO.yaml [--rate R] [--domain N] [--work DIR] [--standby] [--record]
#                       [--table-period S] [--security DIR] [--http ADDR:PORT]
#   --rate R        plant speed-up (default 1: real time)      --work DIR   logs, farm.sqlite, recording
#   --standby       also a standby arbiter (strength 10)       --record     plant writes DIR/frames.csv.gz
#   --table-period  seconds between live-table refreshes (2)   --security   DDS-Security credentials dir
#   --http          the farm monitor's web page and API there (off; a token file in $WINDFDI_FARM_TOKEN_FILE)
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
bin=${WINDFDI_BIN:-${WINDFDI_BUILD_DIR:-$top/build}/bin}
usage="usage: launch_farm.sh SCENARIO.yaml [--rate R] [--domain N] [--work DIR] [--standby] [--record] [--table-period S] [--security DIR] [--http ADDR:PORT]"
scenario=${1:?$usage}
shift
[ -f "$scenario" ] || { echo "launch_farm: no scenario file $scenario" >&2; exit 2; }
rate=1
work=$top/build/farm
standby=0
record=()
table=2
security=()
http=()
domain=${WINDFDI_DOMAIN:-0}
while [ $# -gt 0 ]; do
  case $1 in
    --rate) rate=$2; shift 2 ;;
    --domain) domain=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --standby) standby=1; shift ;;
    --record) record=(--record "$work/frames.csv.gz" --record-truth); shift ;;
    --table-period) table=$2; shift 2 ;;
    --security) security=(--security "$2"); shift 2 ;;
    --http) http=(--http "$2"); shift 2 ;;
    *) echo "launch_farm: unknown option $1 ($usage)" >&2; exit 2 ;;
  esac
done
export WINDFDI_DOMAIN=$domain
mkdir -p "$work/logs"
pids=()
stop() {
  kill -TERM "${pids[@]}" 2>/dev/null || true
  wait 2>/dev/null || true
}
trap stop EXIT INT TERM

echo "launch_farm: domain $domain, scenario $scenario at ${rate}x, logs in $work/logs"
# The scenario's turbine file, found as the plant finds it (beside the scenario, else under deploy/), is every
# service's and the arbiter's too: without it they would judge another turbine by the benchmark's values.
config_dir=$top/deploy/config
turbine=$(sed -n -E 's/^turbine_file:[[:space:]]*//p' "$scenario" | sed -E 's/[[:space:]]+#.*$//; s/^["'"'"']//; s/["'"'"']$//')
if [ -n "$turbine" ]; then
  case $turbine in
    /*) ;;
    *) if [ -f "$(dirname "$scenario")/$turbine" ]; then turbine=$(dirname "$scenario")/$turbine; else turbine=$top/deploy/$turbine; fi ;;
  esac
  [ -f "$turbine" ] || { echo "launch_farm: $scenario: turbine_file $turbine not found" >&2; exit 2; }
  turbine=$(cd "$(dirname "$turbine")" && pwd)/$(basename "$turbine")
  config_dir=$work/deploy/config
  rm -rf "$work/deploy"
  mkdir -p "$config_dir"
  # The configurations' other relative paths (the observer gains) resolve through links beside the copies.
  for d in "$top"/deploy/*/; do [ "$(basename "$d")" = config ] || ln -s "$d" "$work/deploy/$(basename "$d")"; done
  for f in "$top"/deploy/config/*.yaml; do
    sed -E "s|^turbine_file:.*|turbine_file: $turbine  # the scenario's (launch_farm.sh)|" "$f" >"$config_dir/$(basename "$f")"
  done
  echo "launch_farm: every service and the arbiter on the scenario's turbine file $turbine"
fi
# Every diagnostic service of the registry (services/services.list); a listed one not built is an error.
for service in $(awk '!/^[[:space:]]*(#|$)/ {gsub("_", "-", $1); print $1}' "$top/services/services.list"); do
  exe="$bin/windfdi-$service"
  if [ ! -x "$exe" ]; then echo "launch_farm: $exe not built (build first: deploy/scripts/setup.sh)" >&2; exit 1; fi
  cfg="$config_dir/${service//-/_}.yaml"
  args=("${security[@]}")
  [ -f "$cfg" ] && args+=(--config "$cfg")
  "$exe" "${args[@]}" >"$work/logs/$service.log" 2>&1 &
  pids+=($!)
done
"$bin/windfdi-arbiter" --config "$config_dir/arbiter.yaml" --arbiter-id primary --strength 100 \
  "${security[@]}" >"$work/logs/arbiter.log" 2>&1 &
pids+=($!)
if [ "$standby" = 1 ]; then
  "$bin/windfdi-arbiter" --config "$config_dir/arbiter.yaml" --arbiter-id standby --strength 10 \
    "${security[@]}" >"$work/logs/arbiter-standby.log" 2>&1 &
  pids+=($!)
fi
if [ ${#http[@]} -gt 0 ]; then http+=(--report-scenario "$scenario"); fi
"$bin/windfdi-farm" --db "$work/farm.sqlite" --table-period "$table" "${security[@]}" "${http[@]}" \
  2>"$work/logs/farm.log" &
farm=$!
pids+=($farm)
if [ ${#http[@]} -gt 0 ]; then
  for _ in $(seq 50); do grep -q "API on" "$work/logs/farm.log" 2>/dev/null && break; sleep 0.1; done
  url=$(grep -o "API on [^ ]*" "$work/logs/farm.log" | head -1 | cut -d' ' -f3)
  echo "launch_farm: farm web page ${url:-not started (see $work/logs/farm.log)}"
fi
sleep 2  # the services discover each other before the first frame
"$bin/windfdi-plant" --scenario "$scenario" --rate "$rate" "${record[@]}" --progress 0 "${security[@]}" \
  >"$work/logs/plant.log" 2>&1 || echo "launch_farm: the plant exited with $? (see $work/logs/plant.log)" >&2
sleep 5  # the last reports and configurations reach the farm monitor
kill -TERM "$farm" 2>/dev/null || true
wait "$farm" 2>/dev/null || true
