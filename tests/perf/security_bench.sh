#!/usr/bin/env bash
# DDS-Security cost, security off versus on in the same run:
#  1. one-way latency (round trip / 2, p50 and p99) between two processes: tests/perf/security_latency;
#  2. the most turbines windfdi-plant serves at 100 Hz in real time to one reader (windfdi-test-peer listen):
#     N turbines "keep up" when, for every turbine, the reader (stopped SECONDS + 3 s after the plant's start)
#     has the samples up to >= 99 % of SECONDS x 100 (no lag) and lost <= 1 % of the samples after its first
#     one (sequence gaps). Samples before the first one are the discovery/authentication start-up, reported
#     apart ("start-up"): the plant does not wait for readers. N steps through the list, off and on alternately.
# Usage: security_bench.sh [SECONDS=10] ["N1 N2 ..."=default list]
# Environment: WINDFDI_BIN (default build/bin).
set -euo pipefail
top=$(cd "$(dirname "$0")/../.." && pwd)
bin=${WINDFDI_BIN:-$top/build/bin}
secs=${1:-10}
list=${2:-"25 50 100 150 200 300 400"}
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
t0=$(date +%s.%N)
"$top/deploy/security/make_credentials.sh" "$work/sec" --bench >/dev/null
echo "credentials: $(python3 -c "print(round($(date +%s.%N)-$t0,2))") s"
export WINDFDI_PARTICIPANT_PROFILE=windfdi_participant_loopback
unset FASTRTPS_DEFAULT_PROFILES_FILE FASTDDS_ENVIRONMENT_FILE ROS_DISCOVERY_SERVER WINDFDI_QOS_FILE
domain=$(( 150 + $$ % 50 ))

echo "== latency"
"$bin/security_latency" --security "$work/sec" --domain "$domain" --rounds 3 | tee "$work/latency.txt"

echo "== turbines at 100 Hz (plant + one reader, $secs s per point)"
declare -A best=([off]=0 [on]=0) failed=([off]=0 [on]=0)
for n in $list; do
  {
    echo "duration: $secs"; echo "seed: 1"; echo "turbines:"
    for i in $(seq -w 1 "$n"); do echo "  - {id: T$i, wind: {mean: $((8 + 10#$i % 12)), turbulence_intensity: 0.1}}"; done
  } > "$work/farm.yaml"
  for mode in off on; do
    [ "${failed[$mode]}" = 1 ] && continue
    sec_plant=(); sec_reader=()
    if [ $mode = on ]; then sec_plant=(--security "$work/sec"); sec_reader=(--security "$work/sec" --security-role farm); fi
    expect=$(( n * secs * 100 ))
    WINDFDI_DOMAIN=$domain "$bin/windfdi-test-peer" listen --expect "$expect" --timeout $(( secs + 30 )) \
      "${sec_reader[@]}" > "$work/listen.out" 2> "$work/listen.err" &
    lp=$!
    for _ in $(seq 100); do grep -q ready "$work/listen.out" 2>/dev/null && break; sleep 0.1; done
    sleep 1
    WINDFDI_DOMAIN=$domain "$bin/windfdi-plant" --scenario "$work/farm.yaml" --rate realtime --progress 0 \
      --log-level warn "${sec_plant[@]}" 2> "$work/plant.err" &
    pp=$!
    start=$(date +%s.%N)
    # Samples received within SECONDS + 3 s of the plant's start: stop the reader then.
    sleep $(( secs + 3 ))
    kill -TERM $lp 2>/dev/null || true
    wait $lp || true
    wait $pp || true
    read -r ok line < <(tail -1 "$work/listen.out" | python3 -c "
import json, sys
n, per = $n, $secs * 100
try: j = json.load(sys.stdin)
except Exception: j = {}
ids = ['T%0*d' % (len(str(n)), i) for i in range(1, n + 1)]
nxt, first, gaps = j.get('next', {}), j.get('first', {}), j.get('gaps', {})
missing = [i for i in ids if i not in nxt]
lag = min((nxt[i] / per for i in ids if i in nxt), default=0.0)
lost = sum(gaps.get(i, 0) for i in ids) / max(1, sum(nxt[i] - first[i] for i in ids if i in nxt))
startup = max((first[i] / 100.0 for i in ids if i in first), default=float('nan'))
ok = not missing and lag >= 0.99 and lost <= 0.01
print(int(ok), 'received %d samples; %d turbines silent; slowest turbine at %.1f %%; lost %.2f %% after the first sample; start-up %.1f s'
      % (j.get('total', 0), len(missing), 100 * lag, 100 * lost, startup))
" 2>/dev/null || echo "0 no summary from the reader")
    echo "N=$n security $mode: $line -> $([ "$ok" = 1 ] && echo keeps up || echo falls behind)"
    if [ $ok = 1 ]; then best[$mode]=$n; else failed[$mode]=1; fi
  done
  [ "${failed[off]}" = 1 ] && [ "${failed[on]}" = 1 ] && break
done
echo "== summary"
grep '^security_latency:' "$work/latency.txt" || true
ratio=$(python3 -c "print(round(${best[on]}/${best[off]},2) if ${best[off]} else 'n/a')")
echo "security_bench: turbines kept at 100 Hz: off ${best[off]}, on ${best[on]} (ratio $ratio; list: $list)"
