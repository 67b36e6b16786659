#!/bin/bash
# A diagnostic service SIGKILLed and restarted within its 3 s lease, again and again beside a running plant,
# must receive its turbine's frames after every restart (Fast DDS shared-memory ports of dead processes:
# common/dds/participant.cpp). Prints how many restarts never received.
#   restart_loop.sh [--restarts N (25)] [--rate R (20)] [--alive S (1.5)] [--down S (0.8)] [--require]
# --require: exit 1 when a restart never received. WINDFDI_REUSE_PARTICIPANT_ID=1 lets Fast DDS reuse the
# dead process's participant id, as before stop 47 (to measure the difference). Uses a private domain (the
# tests' /tmp/windfdi-test-domain-N.lock), stops every process it started and removes that domain's port
# files and the dead processes' data segments (`fastdds shm clean`), on success and on failure.
set -u
restarts=25 rate=20 alive=1.5 down=0.8 require=0
while [ $# -gt 0 ]; do
  case "$1" in
    --restarts) restarts=$2; shift 2 ;;
    --rate) rate=$2; shift 2 ;;
    --alive) alive=$2; shift 2 ;;
    --down) down=$2; shift 2 ;;
    --require) require=1; shift ;;
    *) echo "restart_loop.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
done
here=$(cd "$(dirname "$0")" && pwd)
deploy=$here/../../deploy
bin=${WINDFDI_BUILD_DIR:-$here/../../build}/bin
for exe in windfdi-plant windfdi-pitch-diag; do
  [ -x "$bin/$exe" ] || { echo "restart_loop.sh: $bin/$exe not built" >&2; exit 2; }
done

# A private domain: the first free of the tests' domain locks, held until this script exits.
domain=""
for d in $(seq $((1 + $$ % 200)) 200) $(seq 1 200); do
  exec {lock}>"/tmp/windfdi-test-domain-$d.lock" || continue
  if flock -n "$lock"; then domain=$d; break; fi
  exec {lock}>&-
done
[ -n "$domain" ] || { echo "restart_loop.sh: every test domain is taken" >&2; exit 2; }
work=$(mktemp -d /tmp/windfdi-restart-loop.XXXXXX)
plant="" diag=""
clean_shm() {
  for offset in $(seq 0 249); do
    port=$((7400 + 250 * domain + offset))
    rm -f /dev/shm/fastrtps_port$port /dev/shm/fastrtps_port${port}_el /dev/shm/sem.fastrtps_port${port}_mutex
  done
}
finish() {
  [ -n "$diag" ] && kill -9 "$diag" 2>/dev/null
  [ -n "$plant" ] && { kill "$plant" 2>/dev/null; sleep 0.5; kill -9 "$plant" 2>/dev/null; }
  wait 2>/dev/null
  clean_shm
  # The data segments the killed services left (4 MB each): only those no live process holds.
  command -v fastdds > /dev/null && fastdds shm clean > /dev/null 2>&1
  rm -rf "$work"
}
trap finish EXIT
clean_shm

export WINDFDI_DOMAIN=$domain WINDFDI_PARTICIPANT_PROFILE=windfdi_participant_loopback FASTRTPS_DEFAULT_PROFILES_FILE= \
  FASTDDS_ENVIRONMENT_FILE= ROS_DISCOVERY_SERVER= WINDFDI_QOS_FILE=
"$bin/windfdi-plant" --scenario "$deploy/scenarios/hydraulic_leakage.yaml" --rate "$rate" --duration 100000 \
  --progress 0 > "$work/plant.out" 2> "$work/plant.err" &
plant=$!
never=0 first=0 marks=""
for i in $(seq 1 "$restarts"); do
  "$bin/windfdi-pitch-diag" --config "$deploy/config/pitch_diag.yaml" > /dev/null 2> "$work/diag.err" &
  diag=$!
  seen=0
  for _ in $(seq 1 80); do
    grep -q "diagnosing turbine" "$work/diag.err" && { seen=1; break; }
    sleep 0.1
  done
  if [ $seen = 1 ]; then
    marks="$marks."
  else
    marks="${marks}X"; never=$((never + 1)); [ $first = 0 ] && first=$i
  fi
  sleep "$alive"
  kill -9 "$diag"; wait "$diag" 2>/dev/null; diag=""
  sleep "$down"
done
echo "$marks"
echo "restarts that never received their turbine: $never of $restarts (the first: $first; domain $domain, rate ${rate}x, down $down s)"
[ $require = 1 ] && [ $never -gt 0 ] && exit 1
exit 0
