#!/usr/bin/env bash
# CPU of windfdi-plant simulating N turbines at 100 Hz in real time, publishing on DDS to one reader
# that takes every frame (median of R runs). Usage: plant_farm_cpu.sh [N=100] [SECONDS=20] [R=3]
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
bin=${WINDFDI_BIN:-$top/build/bin}
n=${1:-100}; secs=${2:-20}; runs=${3:-3}
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
{
  echo "duration: $secs"; echo "seed: 1"; echo "turbines:"
  for i in $(seq -w 1 "$n"); do echo "  - {id: T$i, wind: {mean: $((8 + 10#$i % 12)), turbulence_intensity: 0.1}}"; done
} > "$work/farm.yaml"
export WINDFDI_DOMAIN=$(( 150 + $$ % 50 )) WINDFDI_PARTICIPANT_PROFILE=windfdi_participant_loopback
ticks=$(getconf CLK_TCK)
results=()
for r in $(seq "$runs"); do
  "$bin/windfdi-test-peer" listen --expect $(( n * secs * 100 )) --timeout $(( secs + 30 )) > "$work/listen.out" 2>&1 &
  lp=$!
  sleep 1
  "$bin/windfdi-plant" --scenario "$work/farm.yaml" --rate realtime --progress 0 --log-level warn &
  pp=$!
  sleep $(( secs / 2 ))
  a=$(awk '{print $14+$15}' /proc/$pp/stat); ta=$(date +%s.%N)
  sleep $(( secs / 4 ))
  b=$(awk '{print $14+$15}' /proc/$pp/stat); tb=$(date +%s.%N)
  wait $pp || true
  wait $lp || true
  cpu=$(python3 -c "print(round(100*($b-$a)/$ticks/($tb-$ta),1))")
  got=$(tail -1 "$work/listen.out" | python3 -c "import json,sys; print(json.load(sys.stdin)['total'])")
  results+=("$cpu")
  echo "run $r: plant CPU ${cpu} % of one core for $n turbines at 100 Hz; reader received $got of $(( n * secs * 100 )) samples"
done
median=$(printf '%s\n' "${results[@]}" | sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
echo "plant_farm_cpu: median ${median} % of one core for $n turbines ($(python3 -c "print(round($median/$n,2))") % per turbine)"
