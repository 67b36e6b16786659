#!/usr/bin/env bash
# The farm web page's data under load: N turbines at 100 Hz (the plant in real time, every diagnostic
# service farm-wide, the arbiter) and the farm monitor with --http on a private loopback domain; after WARMUP
# s, a client asks for the farm view's data (/api/turbines), one turbine's estimates (/api/estimates, the
# last 30 minutes of pitch_diag) and /metrics, REQUESTS times each, one after the other, and prints the
# p50 / p99 / max latency of each in ms, with a static file of the page (/farm.css: no lock, no database) as
# the same run's baseline. The DDS side is watched too: the farm monitor must have stored estimates of every
# turbine (it kept up while being asked). Then the page itself is rendered 3 times in the headless browser the
# tests use, and the tiles it drew are counted.
#
# Usage: farm_http_latency.sh [N=200] [REQUESTS=300] [WARMUP=20]
set -euo pipefail
. "$(dirname "$0")/dds_run.sh"
n=${1:-200}
requests=${2:-300}
warm=${3:-20}

{
  echo "duration: $(( warm + 600 ))"; echo "seed: 3"; echo "turbines:"
  for i in $(seq 1 "$n"); do printf '  - {id: T%03d, wind: {mean: %d.0, turbulence_intensity: 0.1}}\n' "$i" $(( 8 + i % 12 )); done
} > "$work/farm.yaml"
echo "farm_http_latency: $n turbines, domain $domain, load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
start_services "$top/deploy/config/arbiter.yaml"
"$bin/windfdi-farm" --db "$work/farm.sqlite" --table-period 0 --http 0 > "$work/farm.out" 2> "$work/farm.log" &
pids+=($!)
for _ in $(seq 100); do grep -q "API on" "$work/farm.log" 2>/dev/null && break; sleep 0.1; done
url=$(grep -o "API on [^ ]*" "$work/farm.log" | head -1 | cut -d' ' -f3)
[ -n "$url" ] || { echo "farm_http_latency: the farm monitor did not start its web server" >&2; cat "$work/farm.log" >&2; exit 1; }
sleep 2
"$bin/windfdi-plant" --scenario "$work/farm.yaml" --log-level warn > "$work/plant.log" 2>&1 &
pids+=($!)
sleep "$warm"
echo "farm_http_latency: load average after ${warm} s: $(cut -d' ' -f1-3 /proc/loadavg)"
python3 - "$url" "$requests" "$n" <<'EOF'
import json, sys, time, urllib.request
url, requests, n = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
def get(path):
    t0 = time.perf_counter()
    with urllib.request.urlopen(url + path.lstrip("/"), timeout=10) as r:
        body = r.read()
    return (time.perf_counter() - t0) * 1e3, body
since = time.time() - 1800
paths = {"/farm.css (baseline)": "/farm.css", "/api/turbines": "/api/turbines",
         f"/api/estimates (T001 pitch_diag)": f"/api/estimates?turbine=T001&service=pitch_diag&since={since}",
         "/metrics": "/metrics"}
print(f"{'request':<36} {'p50 ms':>8} {'p99 ms':>8} {'max ms':>8} {'bytes':>9}")
for name, path in paths.items():
    times = []
    for _ in range(requests):
        ms, body = get(path)
        times.append(ms)
    times.sort()
    p = lambda q: times[min(len(times) - 1, int(q * len(times)))]
    print(f"{name:<36} {p(0.5):8.2f} {p(0.99):8.2f} {times[-1]:8.2f} {len(body):9d}")
turbines = json.loads(get("/api/turbines")[1])["turbines"]
stored = sum(1 for i in range(1, n + 1) if json.loads(get(f"/api/estimates?turbine=T{i:03d}&service=sensor_bias&limit=1")[1])["estimates"])
print(f"turbines in the farm view: {len(turbines)} of {n}; turbines with stored sensor_bias estimates: {stored} of {n}")
EOF
# The page itself in the headless browser the tests use: the farm view of every turbine, drawn from its data.
browser=$(command -v chromium-headless-shell || command -v chromium || true)
if [ -n "$browser" ]; then
  for run in 1 2 3; do
    start=$(date +%s.%N)
    "$browser" --no-sandbox --disable-gpu --user-data-dir="$work/browser" --virtual-time-budget=1500 --dump-dom \
      "$url" > "$work/dom.html" 2>/dev/null
    end=$(date +%s.%N)
    echo "page in the browser (run $run): $(grep -o 'class="tile"' "$work/dom.html" | wc -l) of $n tiles drawn," \
      "$(awk -v a="$start" -v b="$end" 'BEGIN {printf "%.2f", b - a}') s from start to the rendered DOM (browser start included)"
  done
fi
echo "farm_http_latency: load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
