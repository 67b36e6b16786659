# Sourced by the DDS benchmarks of tests/perf (bash, set -euo pipefail): the registry's services, the binaries,
# a private loopback domain of its own, a work directory, and a cleanup on exit that stops every process in
# `pids` and removes the domain's Fast DDS shared-memory files (KEEP_WORK=1 keeps the logs).
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
# The diagnostic services of the registry, as executable suffixes (blade-load, ...).
services=$(awk '!/^[[:space:]]*(#|$)/ {gsub("_", "-", $1); print $1}' "$top/services/services.list")
bin=${WINDFDI_BIN:-$top/build/bin}
domain=$(( 150 + $$ % 50 ))
export WINDFDI_DOMAIN=$domain WINDFDI_PARTICIPANT_PROFILE=windfdi_participant_loopback
unset FASTRTPS_DEFAULT_PROFILES_FILE ROS_DISCOVERY_SERVER FASTDDS_ENVIRONMENT_FILE WINDFDI_QOS_FILE
work=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
  sleep 1
  for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null || true; wait "$p" 2>/dev/null || true; done
  for off in $(seq 0 249); do
    port=$(( 7400 + 250 * domain + off ))
    rm -f /dev/shm/fastrtps_port$port /dev/shm/fastrtps_port${port}_el /dev/shm/sem.fastrtps_port${port}_mutex
  done
  [ -n "${KEEP_WORK:-}" ] && echo "logs kept in $work" || rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 130' INT TERM
