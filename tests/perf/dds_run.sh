# Sourced by the DDS benchmarks of tests/perf (bash, set -euo pipefail): the registry's services, the binaries,
# a private loopback domain of its own, a work directory, start_services, and stop_all (every process in `pids`
# stopped, the domain's Fast DDS shared-memory files removed), which also runs on exit (KEEP_WORK=1 keeps the
# logs).
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
# The diagnostic services of the registry, as executable suffixes (blade-load, ...).
services=$(awk '!/^[[:space:]]*(#|$)/ {gsub("_", "-", $1); print $1}' "$top/services/services.list")
bin=${WINDFDI_BIN:-$top/build/bin}
domain=$(( 150 + $$ % 50 ))
export WINDFDI_DOMAIN=$domain WINDFDI_PARTICIPANT_PROFILE=windfdi_participant_loopback
unset FASTRTPS_DEFAULT_PROFILES_FILE ROS_DISCOVERY_SERVER FASTDDS_ENVIRONMENT_FILE WINDFDI_QOS_FILE
work=$(mktemp -d)
pids=()
# Stops every process in `pids` (TERM, then KILL after 1 s) and removes the domain's shared-memory files.
stop_all() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
  sleep 1
  for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null || true; wait "$p" 2>/dev/null || true; done
  pids=()
  for off in $(seq 0 249); do
    port=$(( 7400 + 250 * domain + off ))
    rm -f /dev/shm/fastrtps_port$port /dev/shm/fastrtps_port${port}_el /dev/shm/sem.fastrtps_port${port}_mutex
  done
}
cleanup() { stop_all; [ -n "${KEEP_WORK:-}" ] && echo "logs kept in $work" || rm -rf "$work"; }
# Starts every diagnostic service of the registry farm-wide with its deploy/config file, then the arbiter with
# ARBITER_CONFIG; logs in $work/<name>SUFFIX.log; their PIDs go to `pids` and, by name, to `pid_of`.
declare -A pid_of=()
start_services() {
  local arbiter_config=$1 suffix=${2:-}
  for service in $services; do
    "$bin/windfdi-$service" --config "$top/deploy/config/${service//-/_}.yaml" --log-level warn \
      > "$work/$service$suffix.log" 2>&1 &
    pids+=($!); pid_of[$service]=$!
  done
  "$bin/windfdi-arbiter" --config "$arbiter_config" --log-level warn > "$work/arbiter$suffix.log" 2>&1 &
  pids+=($!); pid_of[arbiter]=$!
}
trap cleanup EXIT
trap 'exit 130' INT TERM
