#!/usr/bin/env bash
# End-to-end latency of the whole system, in one run on a private loopback domain:
# from the frame that makes a fault decidable to the FaultReport, and to the ControlConfiguration at the
# plant (p50, p99), each as a ratio to raw Fast DDS one-way latency measured in the same run, then the same
# path hop by hop (where the time goes) from every process's WINDFDI_TRACE time stamps.
#
# Set-up: the plant in real time with --block 1 (one sample per TurbineFrame: the lowest-latency deployment)
# simulates N turbines; each turbine's blade-3 strain gauge reads NaN for 2.5 s every PERIOD s (episodes
# staggered across turbines), so blade_load raises sensor_invalid on blade_moment_sensor_3 once the gauge
# has been invalid for invalid_time (1 s): the FaultReport's t is the sample time of that decisive sample.
# All four diagnostic services run farm-wide with their deploy/config files, plus the arbiter with
# clear_hold 1 s (instead of 30 s) so that every episode withdraws and re-applies the IPC fallback and each
# raise yields a new ControlConfiguration. system_latency (tests/perf/system_latency.cpp) subscribes to
# wt/frame, wt/fault and wt/control/config like the services and the plant, takes the publish time of the
# decisive frame from its source time stamp, and measures raw one-way latency (ping/echo, reliable
# sensor_stream QoS) idle before and loaded during the run (the loaded one is the ratios' denominator).
#
# Usage: system_latency.sh [TURBINES=10] [SECONDS=120] [PERIOD=6]
# Binaries: $WINDFDI_BIN (default build/bin); system_latency from $SYSTEM_LATENCY_BIN or $WINDFDI_BIN.
set -euo pipefail
. "$(dirname "$0")/dds_run.sh"
meter=${SYSTEM_LATENCY_BIN:-$bin/system_latency}
n=${1:-10}; secs=${2:-120}; period=${3:-6}

# Scenario: N turbines, episodes of NaN on blade 3 from 15 s on (the services have settled), staggered.
sim=$(( secs + 20 ))
python3 - "$n" "$sim" "$period" > "$work/scenario.yaml" <<'EOF'
import sys
n, sim, period = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3])
print(f"duration: {sim}\nseed: 7\nturbines:")
for i in range(n):
    print(f"  - {{id: T{i+1:03d}, wind: {{mean: {10 + i % 8}.0, turbulence_intensity: 0.1}}}}")
print("faults:")
for i in range(n):
    s = 15.0 + period * i / n
    while s + 3.0 < sim - 5:
        print(f"  - {{turbine: T{i+1:03d}, target: blade_moment_3, type: invalid, start: {s:.2f}, end: {s + 2.5:.2f}}}")
        s += period
EOF
# (The copy's turbine file named absolutely: relative to the work directory it does not exist, and the
# arbiter, exiting on it, left every run since its turbine file came without a configuration to measure.)
sed -e 's/^clear_hold:.*/clear_hold: 1.0/' \
    -e "s|^turbine_file: *\([^ ]*\)|turbine_file: $top/deploy/config/\1|" \
  "$top/deploy/config/arbiter.yaml" > "$work/arbiter.yaml"

# Every process writes its hop time stamps (common/hop_trace.hpp) for the hop-by-hop table at the end.
export WINDFDI_TRACE="$work/trace"
mkdir -p "$WINDFDI_TRACE"
start_services "$work/arbiter.yaml"
"$meter" --mode latency --domain "$domain" --duration "$secs" > "$work/meter.out" 2> "$work/meter.err" &
meter_pid=$!
pids+=($meter_pid)
for _ in $(seq 600); do grep -q READY "$work/meter.out" && break; kill -0 $meter_pid 2>/dev/null || break; sleep 0.1; done
grep -q READY "$work/meter.out" || { cat "$work/meter.out" "$work/meter.err" >&2; echo "system_latency: meter not ready" >&2; exit 1; }
sleep 2  # every reader matched before the first frame
for p in "${pids[@]}"; do
  kill -0 "$p" 2>/dev/null && continue
  tail -n 5 "$work"/*.log >&2
  echo "system_latency: a process ended before the plant started (its log above)" >&2
  exit 1
done
"$bin/windfdi-plant" --scenario "$work/scenario.yaml" --rate realtime --block 1 --progress 0 --log-level warn \
  > "$work/plant.log" 2>&1 &
pids+=($!)
echo "system_latency: $n turbines, --block 1, domain $domain, ${secs} s measured"
rc=0
wait $meter_pid || rc=$?
grep -v READY "$work/meter.out"
echo
echo "Hop by hop (tests/perf/hop_table.py on the processes' WINDFDI_TRACE rows; the first 10 s left out):"
python3 "$(dirname "$0")/hop_table.py" "$WINDFDI_TRACE" --skip 10 || rc=1
[ -s "$work/meter.err" ] && cat "$work/meter.err" >&2
for f in "$work"/*.log; do
  c=$(grep -ciE "samples lost|error" "$f" || true)
  [ "$c" != 0 ] && echo "note: $(basename "$f"): $c lines with 'samples lost' or 'error'"
done
exit $rc
