#!/bin/bash
# A diagnostic service SIGKILLed and restarted within its 3 s lease, again and again beside a running plant,
# must receive its turbine's frames after every restart (Fast DDS shared-memory ports of dead processes:
# common/dds/participant.cpp). Prints how many restarts never received.
#   restart_loop.sh [--restarts N (25)] [--rate R (20)] [--alive S (1.5)] [--down S (0.8)] [--require]
# --require: exit 1 when a restart never received. WINDFDI_REUSE_PARTICIPANT_ID=1 lets Fast DDS reuse the
# dead process's participant id, as before stop 47 (to measure the difference). The domain, the work directory
# and the clean-up on success and failure (every process stopped, the domain's port files and the dead
# processes' data segments removed) are tests/perf/dds_run.sh's.
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
. "$(dirname "$0")/../perf/dds_run.sh"
for exe in windfdi-plant windfdi-pitch-diag; do
  [ -x "$bin/$exe" ] || { echo "restart_loop.sh: $bin/$exe not built" >&2; exit 2; }
done

"$bin/windfdi-plant" --scenario "$top/deploy/scenarios/hydraulic_leakage.yaml" --rate "$rate" --duration 100000 \
  --progress 0 > "$work/plant.out" 2> "$work/plant.err" &
plant=$!
pids=($plant)
never=0 first=0 marks=""
for i in $(seq 1 "$restarts"); do
  "$bin/windfdi-pitch-diag" --config "$top/deploy/config/pitch_diag.yaml" > /dev/null 2> "$work/diag.err" &
  diag=$!
  pids=($plant $diag)
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
  kill -9 "$diag"; wait "$diag" 2>/dev/null
  pids=($plant)
  sleep "$down"
done
echo "$marks"
echo "restarts that never received their turbine: $never of $restarts (the first: $first; domain $domain, rate ${rate}x, down $down s)"
[ $require = 1 ] && [ $never -gt 0 ] && exit 1
exit 0
