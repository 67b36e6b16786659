#!/usr/bin/env bash
# Farm capacity: the largest number of turbines at 100 Hz that all services keep up with
# on this machine, with CPU per turbine. For each N: the plant in real time with --block 10 (FARM_BLOCK)
# simulates N turbines (healthy, 8-19 m/s); the five diagnostic services run farm-wide (no --turbine
# filter) with their deploy/config files, plus the arbiter; everything on a private loopback domain.
# system_latency --mode health (tests/perf/system_latency.cpp) reads wt/health over the run and, over the
# window after WARMUP s, decides "keeps up": every service sees all N turbines at >= 97 % of 100 Hz each,
# no new sequence gaps (nothing dropped), lag (age of the newest processed frame) < 0.5 s and not growing
# (< 0.1 s from the first to the last third of the window); the plant itself publishes >= 97 % of real time.
# CPU: utime+stime from /proc/PID/stat over the same window, per process, in % of one core (2 cores = 200 %).
#
# Usage: farm_capacity.sh [SECONDS=30] [N ...=5 10 20 40 80]   (stops at the first N that does not keep up)
# FARM_BLOCK=B: the plant's samples per TurbineFrame (default 10, the plant's own default; 1..32).
# Binaries: $WINDFDI_BIN (default build/bin); system_latency from $SYSTEM_LATENCY_BIN or $WINDFDI_BIN.
set -euo pipefail
. "$(dirname "$0")/dds_run.sh"
meter=${SYSTEM_LATENCY_BIN:-$bin/system_latency}
secs=${1:-30}; shift || true
list=("$@"); [ ${#list[@]} -gt 0 ] || list=(5 10 20 40 80)
warm=10
ticks=$(getconf CLK_TCK)
cpu_of() { awk '{print $14+$15}' "/proc/$1/stat" 2>/dev/null || echo 0; }

echo "farm_capacity: domain $domain, ${secs} s per N (window after ${warm} s), load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
largest=0
for n in "${list[@]}"; do
  {
    echo "duration: $(( secs + 30 ))"; echo "seed: 3"; echo "turbines:"
    for i in $(seq 1 "$n"); do printf '  - {id: T%03d, wind: {mean: %d.0, turbulence_intensity: 0.1}}\n' "$i" $(( 8 + i % 12 )); done
  } > "$work/farm$n.yaml"
  declare -A pid_of=()
  start_services "$top/deploy/config/arbiter.yaml" ".$n"
  "$meter" --mode health --domain "$domain" --turbines "$n" --duration "$(( secs + 2 ))" --warmup "$(( warm + 2 ))" \
    > "$work/health.$n.out" 2>&1 &
  meter_pid=$!; pids+=($meter_pid)
  sleep 2
  "$bin/windfdi-plant" --scenario "$work/farm$n.yaml" --rate realtime --block "${FARM_BLOCK:-10}" --progress 0 --log-level warn \
    > "$work/plant.$n.log" 2>&1 &
  pids+=($!); pid_of[plant]=$!
  sleep "$warm"
  declare -A a=(); for k in "${!pid_of[@]}"; do a[$k]=$(cpu_of "${pid_of[$k]}"); done; ta=$(date +%s.%N)
  sleep $(( secs - warm ))
  declare -A b=(); for k in "${!pid_of[@]}"; do b[$k]=$(cpu_of "${pid_of[$k]}"); done; tb=$(date +%s.%N)
  wait $meter_pid || true
  load=$(cut -d' ' -f1 /proc/loadavg)
  stop_all
  echo "== N=$n turbines at 100 Hz (load average at the end $load)"
  sed 's/^/  /' "$work/health.$n.out"
  total=0
  line="  CPU % of one core (per turbine):"
  for k in plant $services arbiter; do
    c=$(python3 -c "print(round(100*(${b[$k]}-${a[$k]})/$ticks/($tb-$ta),1))")
    total=$(python3 -c "print(round($total+$c,1))")
    line+=" $k $c ($(python3 -c "print(round($c/$n,2))"))"
  done
  svc=$(python3 -c "print(round($total-$(python3 -c "print(round(100*(${b[plant]}-${a[plant]})/$ticks/($tb-$ta),1))"),1))")
  echo "$line"
  echo "  CPU total $total % ($(python3 -c "print(round($total/$n,2))") %/turbine); services+arbiter without the plant $svc % ($(python3 -c "print(round($svc/$n,2))") %/turbine)"
  if grep -q "KEEPS_UP 1" "$work/health.$n.out"; then largest=$n; else echo "  N=$n does not keep up: stopping"; break; fi
  unset pid_of a b
done
echo "farm_capacity: largest N kept up: $largest (of ${list[*]})"
