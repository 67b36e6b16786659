#!/usr/bin/env bash
# Farm shards: how many turbines at 100 Hz one service host carries, and two service hosts sharing the farm
# with --turbine ranges. Hosts are network namespaces on a bridge (UDP only, discovery through a Fast DDS
# discovery server on the farm host): the plant on a turbine host, the four diagnostic services on each
# service host, the discovery server, the arbiter and the meter on the farm host. A host's size is a CPU
# quota: every service host gets QUOTA % of one core (a cgroup), the same for one host or two, so two hosts
# have twice the CPU of one, as two machines would; the turbine and farm hosts are not limited.
# "Keeps up" is farm_capacity.sh's test (system_latency --mode health): every service sees every turbine at
# >= 97 % of 100 Hz, no sequence gap, lag < 0.5 s and not growing, the plant at >= 97 % of real time.
# Each N runs SECONDS (the first 10 s not judged). One host tries each N of the list, two hosts each 2 N;
# each stops at the first N it does not keep up with.
#
# Usage (root: namespaces and cgroups): farm_shards.sh [SECONDS=30] [QUOTA=20] [N ...=30 40 50 ... 150]
set -euo pipefail
. "$(dirname "$0")/dds_run.sh"
meter=${SYSTEM_LATENCY_BIN:-$bin/system_latency}
secs=${1:-30}; quota=${2:-20}; shift 2 || shift $#
list=("$@"); [ ${#list[@]} -gt 0 ] || list=($(seq 30 10 150))
warm=10
if [ "$(id -u)" != 0 ] || ! command -v ip > /dev/null; then echo "farm_shards: needs root and iproute2"; exit 1; fi
cg=""
for root in /sys/fs/cgroup/cpu /sys/fs/cgroup; do
  if [ -e "$root/cpu.cfs_quota_us" ] || [ -e "$root/cgroup.controllers" ]; then cg=$root; break; fi
done
[ -n "$cg" ] || { echo "farm_shards: no cpu cgroup controller under /sys/fs/cgroup"; exit 1; }
[ -x /usr/bin/fast-discovery-server ] || { echo "farm_shards: needs fast-discovery-server (fastdds-tools)"; exit 1; }

id=$(( $$ % 200 ))
prefix=ws$id; net=10.214.$id
hosts=(p s1 s2)
# A cgroup per service host, QUOTA % of one core each (cgroup v1 cpu.cfs_quota_us or v2 cpu.max).
set_quota() {
  mkdir -p "$cg/$prefix$1"
  if [ -e "$cg/$prefix$1/cpu.cfs_quota_us" ]; then
    echo 100000 > "$cg/$prefix$1/cpu.cfs_period_us"; echo $(( quota * 1000 )) > "$cg/$prefix$1/cpu.cfs_quota_us"
  else
    echo "$(( quota * 1000 )) 100000" > "$cg/$prefix$1/cpu.max"
  fi
}
teardown_hosts() {
  ip netns del "${prefix}f" 2>/dev/null || true
  for h in "${hosts[@]}"; do ip netns del "$prefix$h" 2>/dev/null || true; done
  for h in s1 s2; do rmdir "$cg/$prefix$h" 2>/dev/null || true; done
}
trap 'stop_all; teardown_hosts; [ -n "${KEEP_WORK:-}" ] && echo "logs kept in $work" || rm -rf "$work"' EXIT
ip netns add "${prefix}f"
ip -n "${prefix}f" link set lo up
ip -n "${prefix}f" link add br0 type bridge
ip -n "${prefix}f" link set br0 up
ip -n "${prefix}f" addr add "$net.1/24" dev br0
address=2
for h in "${hosts[@]}"; do
  ip netns add "$prefix$h"
  ip -n "$prefix$h" link set lo up
  ip link add "$prefix${h}0" type veth peer name "$prefix${h}1"
  ip link set "$prefix${h}0" netns "$prefix$h"
  ip link set "$prefix${h}1" netns "${prefix}f"
  ip -n "${prefix}f" link set "$prefix${h}1" master br0
  ip -n "${prefix}f" link set "$prefix${h}1" up
  ip -n "$prefix$h" addr add "$net.$address/24" dev "$prefix${h}0"
  ip -n "$prefix$h" link set "$prefix${h}0" up
  address=$(( address + 1 ))
done
for h in s1 s2; do set_quota "$h"; done
export WINDFDI_PARTICIPANT_PROFILE=windfdi_participant_udp ROS_DISCOVERY_SERVER="$net.1:11811"

# on HOST [CGROUP] -- COMMAND...: runs COMMAND in HOST's namespace (and cgroup) in the background, logged.
on() {
  local host=$1 group=$2 log=$3; shift 4
  if [ -n "$group" ]; then
    sh -c 'echo $$ > "$0/cgroup.procs" && exec "$@"' "$cg/$prefix$group" ip netns exec "$prefix$host" "$@" \
      > "$work/$log.log" 2>&1 &
  else
    ip netns exec "$prefix$host" "$@" > "$work/$log.log" 2>&1 &
  fi
  pids+=($!); host_pids[$host]+=" $!"
}
declare -A host_pids=()
cpu_of_host() {  # CPU time (clock ticks) of the processes started on a host
  local sum=0 p
  for p in ${host_pids[$1]:-}; do sum=$(( sum + $(awk '{print $14+$15}' "/proc/$p/stat" 2>/dev/null || echo 0) )); done
  echo $sum
}

rx_of() { ip netns exec "$prefix$1" cat "/sys/class/net/$prefix${1}0/statistics/rx_bytes"; }

# run HOSTS N: the farm of N turbines served by HOSTS (1 or 2) service hosts; prints the meter's verdict.
run() {
  local hosts_used=$1 n=$2 share=$(( $2 / $1 ))
  {
    echo "duration: $(( secs + 30 ))"; echo "seed: 3"; echo "turbines:"
    for i in $(seq 1 "$n"); do printf '  - {id: T%03d, wind: {mean: %d.0, turbulence_intensity: 0.1}}\n' "$i" $(( 8 + i % 12 )); done
  } > "$work/farm$n.yaml"
  on f "" discovery -- /usr/bin/fast-discovery-server -i 0 -l "$net.1" -p 11811
  sleep 1
  for h in $(seq 1 "$hosts_used"); do
    local first last range=()
    first=$(printf 'T%03d' $(( (h - 1) * share + 1 ))); last=$(printf 'T%03d' $(( h == hosts_used ? n : h * share )))
    [ "$hosts_used" -gt 1 ] && range=(--turbine "$first..$last")
    for service in $services; do
      on "s$h" "s$h" "$service.s$h.$n" -- "$bin/windfdi-$service" --config "$top/deploy/config/${service//-/_}.yaml" \
        --log-level warn "${range[@]}"
    done
  done
  on f "" "arbiter.$n" -- "$bin/windfdi-arbiter" --config "$top/deploy/config/arbiter.yaml" --log-level warn
  on f "" "health.$hosts_used.$n" -- "$meter" --mode health --domain "$domain" --turbines "$n" \
    --duration "$(( secs + 2 ))" --warmup "$(( warm + 2 ))"
  local meter_pid=${pids[-1]}
  sleep 2
  on p "" "plant.$n" -- "$bin/windfdi-plant" --scenario "$work/farm$n.yaml" --rate realtime --progress 0 --log-level warn
  sleep "$warm"
  local a1 a2 ap b1 b2 bp ta tb ticks ra1 ra2 rb1 rb2
  ticks=$(getconf CLK_TCK)
  a1=$(cpu_of_host s1); a2=$(cpu_of_host s2); ap=$(cpu_of_host p); ra1=$(rx_of s1); ra2=$(rx_of s2); ta=$(date +%s.%N)
  sleep $(( secs - warm ))
  b1=$(cpu_of_host s1); b2=$(cpu_of_host s2); bp=$(cpu_of_host p); rb1=$(rx_of s1); rb2=$(rx_of s2); tb=$(date +%s.%N)
  wait "$meter_pid" || true
  stop_all
  echo "== $hosts_used service host(s) at $quota % of a core each, N=$n turbines at 100 Hz (load average $(cut -d' ' -f1 /proc/loadavg))"
  sed 's/^/  /' "$work/health.$hosts_used.$n.log"
  echo "  CPU, % of one core: service host s1 $(python3 -c "print(round(100*($b1-$a1)/$ticks/($tb-$ta),1))")," \
    "s2 $(python3 -c "print(round(100*($b2-$a2)/$ticks/($tb-$ta),1))"), plant $(python3 -c "print(round(100*($bp-$ap)/$ticks/($tb-$ta),1))")"
  echo "  received by the service hosts, MB/s: s1 $(python3 -c "print(round(($rb1-$ra1)/1e6/($tb-$ta),2))")," \
    "s2 $(python3 -c "print(round(($rb2-$ra2)/1e6/($tb-$ta),2))") (each host's frame writer filters for it)"
  host_pids=()
  grep -q "KEEPS_UP 1" "$work/health.$hosts_used.$n.log"
}

echo "farm_shards: domain $domain, ${secs} s per N, service hosts at $quota % of one core, load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
declare -A largest=([1]=0 [2]=0)
for hosts_used in 1 2; do
  for n in "${list[@]}"; do
    total=$(( n * hosts_used ))
    if run "$hosts_used" "$total"; then largest[$hosts_used]=$total; else echo "  N=$total does not keep up: stopping"; break; fi
  done
done
echo "farm_shards: largest N kept up: one service host ${largest[1]}, two service hosts ${largest[2]}" \
  "(ratio $(python3 -c "print(round(${largest[2]}/max(${largest[1]},1),2))"))"
