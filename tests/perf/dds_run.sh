# Sourced by the DDS benchmarks of tests/perf and tests/reliability (bash): the registry's services, the
# binaries, a private loopback domain of its own, a work directory, start_services, and stop_all (every process
# in `pids` stopped, the domain's Fast DDS shared-memory files removed), which also runs on exit with the data
# segments no live process holds (`fastdds shm clean`; KEEP_WORK=1 keeps the logs).
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
# The diagnostic services of the registry, as executable suffixes (blade-load, ...).
services=$(awk '!/^[[:space:]]*(#|$)/ {gsub("_", "-", $1); print $1}' "$top/services/services.list")
bin=${WINDFDI_BIN:-${WINDFDI_BUILD_DIR:-$top/build}/bin}
# The domain: the first free one of the tests' domain locks (/tmp/windfdi-test-domain-N.lock, as private_domain
# in tests/support/process.cpp takes them), held until this shell and every process it started have exited.
# Picked from the pid alone (150 + pid % 50, before stop 48) a benchmark could share a domain with a test
# running beside it and see its plant.
domain=""
for d in $(seq $(( 1 + $$ % 200 )) 200) $(seq 1 200); do
  exec {domain_lock}> "/tmp/windfdi-test-domain-$d.lock" || continue
  if flock -n "$domain_lock"; then domain=$d; break; fi
  exec {domain_lock}>&-
done
[ -n "$domain" ] || { echo "dds_run.sh: every test domain (1-200) is taken" >&2; exit 2; }
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
  remove_domain_shm
}
# The domain's port files (ports 7400 + 250 domain + 0..249; a crashed run's too, so also at the start).
remove_domain_shm() {
  local off port
  for off in $(seq 0 249); do
    port=$(( 7400 + 250 * domain + off ))
    rm -f /dev/shm/fastrtps_port$port /dev/shm/fastrtps_port${port}_el /dev/shm/sem.fastrtps_port${port}_mutex
  done
}
remove_domain_shm
cleanup() {
  stop_all
  # A killed process's data segments (4 MB each) outlive it; only those no live process holds go.
  command -v fastdds > /dev/null && fastdds shm clean > /dev/null 2>&1
  [ -n "${KEEP_WORK:-}" ] && echo "logs kept in $work" || rm -rf "$work"
}
# Starts every diagnostic service of the registry farm-wide with its deploy/config file, then the arbiter with
# ARBITER_CONFIG (and $ARBITER_ARGS, e.g. --shared-memory to compare the arbiter's transports); logs in
# $work/<name>SUFFIX.log; their PIDs go to `pids` and, by name, to `pid_of`.
declare -A pid_of=()
start_services() {
  local arbiter_config=$1 suffix=${2:-}
  for service in $services; do
    "$bin/windfdi-$service" --config "$top/deploy/config/${service//-/_}.yaml" --log-level warn \
      > "$work/$service$suffix.log" 2>&1 &
    pids+=($!); pid_of[$service]=$!
  done
  # ARBITER_ARGS unquoted: one word per option
  "$bin/windfdi-arbiter" --config "$arbiter_config" --log-level warn ${ARBITER_ARGS:-} \
    > "$work/arbiter$suffix.log" 2>&1 &
  pids+=($!); pid_of[arbiter]=$!
}
trap cleanup EXIT
trap 'exit 130' INT TERM
