#!/usr/bin/env python3
"""The reliability campaign's process cases: a small farm runs with injected faults while every process is
killed (SIGKILL) and restarted in turn, or frozen (SIGSTOP for 10 s, then SIGCONT), and the farm store and the
processes' own logs are judged.

  reliability.py processes [--only NAME[:CASE+CASE],...] [--cases kill,freeze] [--rate R] [--turbines N] [--work DIR]
                           [--json FILE] [--require]

For each process and case: how long until the farm store shows it lost and back (the primary arbiter: until the
plant follows the standby, and the primary again; the standby and the farm monitor show nothing while the other
runs); whether the faults raised
before stayed raised in the store after; whether a report the services logged never reached the store; whether
the plant applied a configuration revision out of order; whether the restart itself caused an action (a fault
raised that was not raised before, a class changed, a safe stop, a derate no fault warrants). Exit 1 with
--require when any of these fails (CI runs a subset that way), 2 on bad arguments.

  reliability.py hostile [--ids 10000] [--huge BYTES] [--hold S] [--max-turbines N] [--filtered]
                         [--report-keys N] [--work DIR] [--json FILE] [--require]

A hostile peer (windfdi-test-peer hostile) on the farm's unsecured domain for --hold s: frames for --ids made-up
turbines, NaN / infinite / 1e308 samples of WT03, reports and health with unknown components, services and
turbines, ids of 200 bytes and strings of --huge bytes. Reported: every process's resident memory before and
after, which ended, what was raised on the real turbines, safe stops, unknown turbines in the farm store.

  reliability.py network [--cases loss10,loss30,jitter50,down] [--hold S] [--outage S] [--work DIR]
                          [--json FILE] [--require]

A lossy, jittery or partitioned network (every process's UDP transport drops or holds what it sends:
WINDFDI_NETWORK_EMULATION, common/dds/network_emulation.hpp; shared memory off, so that every message crosses
it): "lossP" drops P % of the messages at random for --hold s, "jitterMS" holds each a random 0..MS ms for
--hold s, "down" drops all of them for --outage s. Reported per case: which services the
farm store showed lost and how long until all were back, the faults kept, what was raised, safe stops, how
long the arbiter's configuration was not the normal one, and (over the run) reports the services logged that
the store lacks and configurations applied out of order.

  reliability.py soak [--hours 24] [--turbines 20] [--rate R] [--block N] [--sample S] [--retention H]
                       [--work DIR] [--json FILE] [--require]

The farm (up to 20 turbines) runs --hours of sample time; the resident memory of every process and the farm
store's size are taken every --sample s. Reported: memory in the first and last third of the run (medians) and
its peak, the store against what its retention (the farm monitor's --estimate-retention, wall hours) holds,
what was raised besides the injected faults, safe stops, processes that ended. --block sets the plant's samples
per frame (default its own, 10): at R times real time, blocks of 10 R samples send the frames as often and give
each frame history as much wall time as real time does with blocks of 10 (the plant takes at most 32).

Processes: plant, the five diagnostic services, arbiter (primary, strength 100), standby (strength 10), farm.
Everything runs as real DDS participants on a private domain (loopback discovery), the plant in closed loop at
--rate times real time (default 4); logs and the store go to --work (default a temporary directory).
"""
import argparse
import json
import os
import re
import shutil
import signal
import sqlite3
import subprocess
import sys
import tempfile
import time

TOP = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BUILD = os.environ.get("WINDFDI_BUILD_DIR", os.path.join(TOP, "build"))
BIN = os.path.join(BUILD, "bin")
SERVICES = ["blade_load", "sensor_bias", "pitch_diag", "ice_detect", "drive_train"]
PROCESSES = ["plant"] + SERVICES + ["arbiter", "standby", "farm"]
FREEZE_SECONDS = 10.0
# The wt/health liveliness lease is 3 s (deploy/qos/windfdi_qos.xml): a death is shown within it plus one
# farm loop pass; a restarted service names its turbines at its first health tick.
LOST_TIMEOUT = 15.0
BACK_TIMEOUT = 30.0

# The injected faults, active from 5 s of simulated time so that a restarted plant (whose simulation starts
# again at 0) meets them as the running one did. Each raises a warning (no stop): the campaign judges what the
# restarts do, and a healthy third turbine shows whether they raise anything by themselves.
FAULTS = [
    {"turbine": "WT01", "target": "pitch_actuator_1", "type": "pump_wear", "start": 5},
    {"turbine": "WT02", "target": "pitch_2", "type": "bias", "value": 1.0, "start": 5},
]
EXPECTED = {("WT01", "pitch_actuator_1", "pump_wear"), ("WT02", "pitch_sensor_2", "sensor_bias")}
WINDS = [16.0, 15.0, 17.0, 14.0, 18.0]

# Log lines (spdlog: "DATE TIME EXECUTABLE LEVEL: MESSAGE") of a published FaultReport and an applied configuration.
PUBLISHED = re.compile(r" (?:info|warning): (\S+) (\S+) (\S+) (RAISED|cleared) \((\w+), statistic")
LOST_SEEN = re.compile(r" warning: service (\S+) for turbine (\S+) lost its liveliness")
APPLIED = re.compile(r" info: (\S+): applying configuration r(\d+) from (\S+): mode (\d+)")


def scenario_yaml(turbines, duration):
    lines = ["# The reliability campaign's farm (tests/reliability/reliability.py writes it).",
             f"duration: {duration}", "seed: 11", "turbines:"]
    for i in range(turbines):
        lines.append(f"  - {{id: WT{i + 1:02d}, wind: {{mean: {WINDS[i % len(WINDS)]}, turbulence_intensity: 0.1}}}}")
    lines.append("faults:")
    for f in FAULTS:
        lines.append("  - {" + ", ".join(f"{k}: {v}" for k, v in f.items()) + "}")
    return "\n".join(lines) + "\n"


class Farm:
    """The processes of a small farm, each restartable; every log of every incarnation is kept."""

    def __init__(self, work, rate, turbines, max_turbines=None, filtered=False, network=False, duration=100000,
                 farm_args=(), block=None):
        self.work, self.rate = work, rate
        self.block = block  # the plant's --block (samples per frame); None: the plant's default
        self.farm_args = list(farm_args)  # more options of the farm monitor
        # --max-turbines for every process (a deployment sets it to the farm's size); None: the default.
        self.max_turbines = max_turbines
        # Every process but the plant given the farm's turbines (--turbine WT01..WTnn, a DDS content filter).
        self.selection = [f"WT01..WT{turbines:02d}"] if filtered else []
        self.logs = os.path.join(work, "logs")
        os.makedirs(self.logs, exist_ok=True)
        self.db = os.path.join(work, "farm.sqlite")
        self.scenario = os.path.join(work, "scenario.yaml")
        with open(self.scenario, "w") as f:
            f.write(scenario_yaml(turbines, duration))
        self.env = dict(os.environ)
        self.env["WINDFDI_DOMAIN"] = str(int(os.environ.get("WINDFDI_DOMAIN", 150 + os.getpid() % 50)))
        self.env["WINDFDI_PARTICIPANT_PROFILE"] = "windfdi_participant_loopback"
        for var in ("FASTRTPS_DEFAULT_PROFILES_FILE", "FASTDDS_DEFAULT_PROFILES_FILE", "ROS_DISCOVERY_SERVER",
                    "FASTDDS_ENVIRONMENT_FILE", "WINDFDI_QOS_FILE"):
            self.env.pop(var, None)
        # Every process follows this file's "loss P", "jitter MS" or "down" (network_emulation.hpp); no file:
        # nothing.
        self.network_file = os.path.join(work, "network") if network else None
        if self.network_file:
            self.env["WINDFDI_NETWORK_EMULATION"] = self.network_file
        self.procs, self.incarnations, self.started = {}, {}, {}

    def set_network(self, text):
        """The emulated network from now on: "loss P", "jitter MS", "down", or None (no loss)."""
        if text is None:
            if os.path.exists(self.network_file):
                os.remove(self.network_file)
            return
        with open(self.network_file + ".new", "w") as f:
            f.write(text + "\n")
        os.replace(self.network_file + ".new", self.network_file)

    def argv(self, name):
        if name == "plant":
            return self.base_argv(name)
        return (self.base_argv(name) + ([] if self.max_turbines is None else ["--max-turbines", str(self.max_turbines)])
                + sum((["--turbine", v] for v in self.selection), []))

    def base_argv(self, name):
        if name in SERVICES:
            exe = os.path.join(BIN, "windfdi-" + name.replace("_", "-"))
            cfg = os.path.join(TOP, "deploy", "config", name + ".yaml")
            return [exe] + (["--config", cfg] if os.path.exists(cfg) else [])
        arbiter_cfg = os.path.join(TOP, "deploy", "config", "arbiter.yaml")
        if name == "arbiter":
            return [os.path.join(BIN, "windfdi-arbiter"), "--config", arbiter_cfg, "--arbiter-id", "primary",
                    "--strength", "100"]
        if name == "standby":
            return [os.path.join(BIN, "windfdi-arbiter"), "--config", arbiter_cfg, "--arbiter-id", "standby",
                    "--strength", "10"]
        if name == "farm":
            return [os.path.join(BIN, "windfdi-farm"), "--db", self.db, "--table-period", "0"] + self.farm_args
        if name == "plant":
            return ([os.path.join(BIN, "windfdi-plant"), "--scenario", self.scenario, "--rate", str(self.rate),
                     "--progress", "0"] + (["--block", str(self.block)] if self.block else []))
        raise ValueError(name)

    def log_paths(self, name):
        return [os.path.join(self.logs, f"{name}.{k}.log") for k in range(self.incarnations.get(name, 0))]

    def log_lines(self, name):
        """Every line the process `name` logged, over its incarnations in order."""
        for path in self.log_paths(name):
            with open(path, errors="replace") as f:
                yield from f

    def start(self, name):
        k = self.incarnations.get(name, 0)
        self.incarnations[name] = k + 1
        log = open(os.path.join(self.logs, f"{name}.{k}.log"), "w")
        self.procs[name] = subprocess.Popen(self.argv(name), env=self.env, stdout=log, stderr=subprocess.STDOUT)
        self.started[name] = time.time()
        log.close()

    def signal(self, name, sig):
        self.procs[name].send_signal(sig)
        if sig == signal.SIGKILL:
            self.procs[name].wait()

    def exited(self):
        return [n for n, p in self.procs.items() if p.poll() is not None]

    def stop_all(self):
        for p in self.procs.values():
            if p.poll() is None:
                p.send_signal(signal.SIGCONT)
                p.terminate()
        deadline = time.time() + 10
        for p in self.procs.values():
            try:
                p.wait(max(0.1, deadline - time.time()))
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        self.remove_shared_memory()

    def remove_shared_memory(self):
        """The shared-memory files the killed processes left: the segments whose owner is gone (`fastdds shm
        clean`) and this domain's port files, which it misses (docs/fastdds.md)."""
        if shutil.which("fastdds"):
            subprocess.run(["fastdds", "shm", "clean"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        domain = int(self.env["WINDFDI_DOMAIN"])
        for offset in range(250):
            port = 7400 + 250 * domain + offset
            for name in (f"fastrtps_port{port}", f"fastrtps_port{port}_el", f"sem.fastrtps_port{port}_mutex"):
                try:
                    os.remove(os.path.join("/dev/shm", name))
                except OSError:
                    pass

    def query(self, sql, args=()):
        """Rows of the farm store (read-only, beside the running farm monitor: the store is in WAL mode)."""
        if not os.path.exists(self.db):
            return []
        for _ in range(20):
            try:
                con = sqlite3.connect(f"file:{self.db}?mode=ro", uri=True, timeout=5)
                try:
                    return con.execute(sql, args).fetchall()
                finally:
                    con.close()
            except sqlite3.OperationalError:
                time.sleep(0.2)
        return []


def active_faults(farm, before=None):
    """(turbine, component, fault) raised and not cleared in the store, from the rows received before `before`."""
    rows = farm.query("SELECT turbine_id, component, fault, state FROM fault_events"
                      + (" WHERE received_at < ?" if before else "") + " ORDER BY id", (before,) if before else ())
    active = set()
    for turbine, component, fault, state in rows:
        (active.add if state == "raised" else active.discard)((turbine, component, fault))
    return active


def health_after(farm, service, since, lost):
    rows = farm.query("SELECT received_at FROM health_events WHERE service = ? AND received_at > ? AND "
                      + ("event = 'lost'" if lost else "event != 'lost'") + " ORDER BY id LIMIT 1",
                      (service, since))
    return rows[0][0] if rows else None


def wait_for(pred, timeout, poll=0.2):
    end = time.time() + timeout
    while time.time() < end:
        value = pred()
        if value:
            return value
        time.sleep(poll)
    return pred()


def published_by_services(farm):
    """Every FaultReport the services logged as published: (source, turbine, component, fault, state)."""
    events = []
    for service in SERVICES:
        for m in filter(None, map(PUBLISHED.search, farm.log_lines(service))):
            events.append((service, m[1], m[2], m[3], "raised" if m[4] == "RAISED" else "cleared"))
    return events


def configurations_out_of_order(farm):
    """Revisions the plant applied that went back from one arbiter's revision it had applied before."""
    bad = []
    for path in farm.log_paths("plant"):
        last = {}
        with open(path, errors="replace") as f:
            for line in f:
                m = APPLIED.search(line)
                if not m:
                    continue
                key, revision = (m[1], m[3]), int(m[2])
                if key in last and revision < last[key]:
                    bad.append(f"{m[1]} r{revision} from {m[3]} after r{last[key]}")
                last[key] = revision
    return bad


def plant_applied_from(farm, arbiter_id, since):
    """Wall time of the first configuration the plant applied from `arbiter_id` after `since` (its log)."""
    for line in farm.log_lines("plant"):
        m = APPLIED.search(line)
        if m and m[3] == arbiter_id and log_time(line) > since:
            return log_time(line)
    return None


def log_time(line):
    """Wall time of a spdlog line ("DATE TIME.mmm ...")."""
    return time.mktime(time.strptime(line[:19], "%Y-%m-%d %H:%M:%S")) + float(line[19:23])


def losses_seen_by_arbiters(farm, since):
    """(arbiter, service, turbine) of every service loss the arbiters logged after `since`."""
    seen = set()
    for name in ("arbiter", "standby"):
        for line in farm.log_lines(name):
            m = LOST_SEEN.search(line)
            if m and log_time(line) > since:
                seen.add((name, m[1], m[2]))
    return sorted(" ".join(k) for k in seen)


def run_case(farm, name, case, settle, freeze):
    """One process killed and restarted, or frozen and thawed; returns the row of the report."""
    health_name = {"standby": "arbiter"}.get(name, name)
    before = active_faults(farm)
    t0 = time.time()
    if case == "kill":
        farm.signal(name, signal.SIGKILL)
    else:
        farm.signal(name, signal.SIGSTOP)
    lost_at = None
    if name == "arbiter":
        # The standby speaks for "arbiter" on wt/health: the loss shows as the plant following the standby.
        lost_at = wait_for(lambda: plant_applied_from(farm, "standby", t0), LOST_TIMEOUT if case == "kill"
                           else freeze)
    elif name not in ("farm", "standby"):
        lost_at = wait_for(lambda: health_after(farm, health_name, t0, True), LOST_TIMEOUT if case == "kill"
                           else freeze)
    if case == "kill":
        time.sleep(max(0.0, 2.0 - (time.time() - t0)))
        farm.start(name)
    else:
        time.sleep(max(0.0, freeze - (time.time() - t0)))
        farm.signal(name, signal.SIGCONT)
    t1 = time.time()
    back_at = None
    if name == "farm":
        # The farm monitor is back when its restarted incarnation stores again (its own health is not on DDS).
        back_at = wait_for(lambda: (farm.query("SELECT max(received_at) FROM health_events")[0][0] or 0) > t1
                           and time.time(), BACK_TIMEOUT)
    elif name == "arbiter" and lost_at:
        back_at = wait_for(lambda: plant_applied_from(farm, "primary", t1), BACK_TIMEOUT)
    elif lost_at:
        back_at = wait_for(lambda: health_after(farm, health_name, lost_at, False), BACK_TIMEOUT)
    evidence = arbiter_evidence(farm, t0) if name == "arbiter" and lost_at and not back_at else []
    time.sleep(settle)
    # The arbiters' answer to a lost diagnostic service (the reason names service_lost), published from `t0` on.
    fallbacks = farm.query("SELECT DISTINCT turbine_id || ' ' || arbiter_id FROM configurations WHERE received_at > ? "
                           "AND reasons LIKE '%service_lost%'", (t0,))
    return dict({"process": name, "case": case, "losses_seen": losses_seen_by_arbiters(farm, t0),
                 "fallbacks": sorted(f[0] for f in fallbacks),
                 "lost_after_s": round(lost_at - t0, 2) if lost_at else None,
                 "back_after_s": round(back_at - t1, 2) if back_at else None, "evidence": evidence},
                **judged_since(farm, t0, before))


def arbiter_evidence(farm, since):
    """What the plant applied and what both arbiters warned of from `since` on (the last 40 lines, in time
    order): printed when the plant never followed the primary again, so that a CI log shows which side
    stopped talking."""
    lines = [(log_time(line), line.rstrip()) for line in farm.log_lines("plant")
             if APPLIED.search(line) and log_time(line) > since]
    for name in ("arbiter", "standby"):
        lines += [(log_time(line), f"{line.rstrip()} [{name}]") for line in farm.log_lines(name)
                  if " warning: " in line and line[:2] == "20" and log_time(line) > since]
    return [text for _, text in sorted(lines)][-40:]


def judged_since(farm, t0, before):
    """What the store shows from `t0` on against the faults active `before`: whether they are all still
    raised, raises of faults that were not raised before, safe stops."""
    after = active_faults(farm)
    new_raises = sorted({f"{t} {c} {f} ({s})" for t, c, f, s in farm.query(
        "SELECT turbine_id, component, fault, source FROM fault_events WHERE state = 'raised' AND received_at > ?",
        (t0,)) if (t, c, f) not in before})
    stops = farm.query("SELECT DISTINCT turbine_id FROM configurations WHERE mode = 'safe_stop' AND received_at > ?",
                       (t0,))
    return {
        "faults_before": sorted(" ".join(k) for k in before),
        "faults_kept": before <= after,
        "faults_after": sorted(" ".join(k) for k in after),
        "new_raises": new_raises,
        "safe_stops": sorted(s[0] for s in stops),
    }


def check_row(row):
    problems = []
    shown = row["process"] in ("farm", "standby") or row["lost_after_s"] is not None
    if not shown:
        problems.append("never shown lost")
    if row["process"] != "farm" and row["lost_after_s"] is not None and row["back_after_s"] is None:
        problems.append("never shown back")
    if row["process"] == "farm" and row["back_after_s"] is None:
        problems.append("the restarted farm monitor stored nothing")
    if not row["faults_kept"]:
        problems.append("faults before: " + ", ".join(row["faults_before"]) + "; after: "
                        + ", ".join(row["faults_after"]))
    if row["new_raises"]:
        problems.append("raised by the case: " + ", ".join(row["new_raises"]))
    if row["safe_stops"]:
        problems.append("safe stop of " + ", ".join(row["safe_stops"]))
    return problems + lost_without_cause(row)


def lost_without_cause(row):
    """No diagnostic service is lost when an arbiter or the farm monitor is killed or frozen, so a service an
    arbiter saw lost, or a lost-service fallback, is the case's own doing. Judged since the arbiter keeps off
    shared memory (stop 74): before, a thawed arbiter whose shared-memory ports its peers had torn down saw
    services lost for 8 s or more in 5 of 6 freezes on a loaded host (docs/fastdds.md "A stopped process")."""
    problems = []
    if row["process"] in ("arbiter", "standby", "farm"):
        if row["losses_seen"]:
            problems.append("services seen lost that were not: " + ", ".join(row["losses_seen"]))
        if row["fallbacks"]:
            problems.append("lost-service fallback with no service lost: " + ", ".join(row["fallbacks"]))
    return problems


def rss_mb(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return None


def cpu_s(pid):
    """CPU seconds (user and system) the process has used, or None when it is gone."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, IndexError, ValueError):
        return None


def run_hostile(farm, ids, huge, hold, settle, report_keys=0):
    """A hostile peer (windfdi-test-peer hostile) on the farm's unsecured domain for `hold` s; returns the report."""
    before = active_faults(farm)
    rss0 = {n: rss_mb(p.pid) for n, p in farm.procs.items()}
    t0 = time.time()
    peer = subprocess.run([os.path.join(BIN, "windfdi-test-peer"), "hostile", "--farm", str(ids), "--huge", str(huge),
                           "--hold", str(hold), "--turbine-id", "WT03", "--report-keys", str(report_keys)],
                          env=farm.env, capture_output=True, text=True, timeout=hold + 60)
    sent = {}
    for line in peer.stdout.splitlines():
        try:
            sent.update(json.loads(line))
        except ValueError:
            pass
    if peer.returncode != 0:
        print(f"reliability: windfdi-test-peer hostile exited {peer.returncode}: {peer.stderr.strip()}", file=sys.stderr)
    time.sleep(settle)
    rss1 = {n: rss_mb(p.pid) for n, p in farm.procs.items()}
    new_raises = sorted({f"{t} {c} {f} ({s})" for t, c, f, s in farm.query(
        "SELECT turbine_id, component, fault, source FROM fault_events WHERE state = 'raised' AND received_at > ?",
        (t0,)) if (t, c, f) not in before})
    stops = farm.query("SELECT DISTINCT turbine_id FROM configurations WHERE mode = 'safe_stop' AND received_at > ?",
                       (t0,))
    hostile_turbines = farm.query(
        "SELECT count(DISTINCT turbine_id) FROM (SELECT turbine_id FROM fault_events UNION "
        "SELECT turbine_id FROM health_events UNION SELECT turbine_id FROM configurations) "
        "WHERE turbine_id NOT LIKE 'WT%' AND turbine_id != '*'")[0][0]
    return {
        "sent": sent, "peer_exit": peer.returncode,
        "rss_mb_before": rss0, "rss_mb_after": rss1, "exited": farm.exited(),
        "faults_kept": before <= active_faults(farm), "new_raises": new_raises,
        "safe_stops": sorted(s[0] for s in stops), "unknown_turbines_stored": hostile_turbines,
    }


def fmt(v):
    return "-" if v is None else f"{v:.1f}"


def start_farm(a):
    """The farm of `a.turbines` turbines with every process, its injected faults raised and `a.warmup` s more."""
    work = a.work or tempfile.mkdtemp(prefix="windfdi_reliability_")
    os.makedirs(work, exist_ok=True)
    soak = a.command == "soak"
    farm = Farm(work, a.rate, a.turbines, getattr(a, "max_turbines", None), getattr(a, "filtered", False),
                a.command == "network", round(a.hours * 3600) if soak else 100000,
                ["--estimate-retention", str(a.retention)] if soak else [], getattr(a, "block", None))
    for n in PROCESSES:
        if not os.access(farm.argv(n)[0], os.X_OK):
            print(f"reliability: {farm.argv(n)[0]} not built (deploy/scripts/setup.sh)", file=sys.stderr)
            return None
    for n in ["farm"] + SERVICES + ["arbiter", "standby"]:
        farm.start(n)
    time.sleep(3)  # the services and arbiters discover each other before the first frame
    farm.start("plant")
    print(f"reliability: domain {farm.env['WINDFDI_DOMAIN']}, {a.turbines} turbines at {a.rate}x, work {work}",
          flush=True)
    # The injected faults raised and settled before the first case.
    ok = wait_for(lambda: EXPECTED <= active_faults(farm), a.warmup + 120)
    time.sleep(a.warmup)
    if not ok:
        print("reliability: the injected faults were not raised: " + ", ".join(
            " ".join(k) for k in active_faults(farm)), file=sys.stderr)
    return farm


def run_cases(a, cases, run_one, check, describe, header, line):
    """Starts the farm, runs `run_one(farm, case)` for each case and prints `describe(row, problems)`, stops the
    farm, and reports the run (report_run: `header`, `line`); the exit code (2: the farm did not start)."""
    rows, problems = [], {}
    farm = None
    try:
        farm = start_farm(a)
        if farm is None:
            return 2
        for case in cases:
            dead = farm.exited()
            if dead:
                print("reliability: exited on their own: " + ", ".join(dead), file=sys.stderr)
            row = run_one(farm, case)
            rows.append(row)
            problems[case] = check(row)
            dead = farm.exited()
            if dead:
                problems[case].append("exited: " + ", ".join(dead))
            print(describe(row, problems[case]), flush=True)
            if problems[case]:
                for line in row.get("evidence", []):
                    print("    " + line, flush=True)
    finally:
        if farm:
            farm.stop_all()
    return report_run(farm, a, rows, problems, header, line)


def processes(a):
    cases = [c for c in a.cases.split(",") if c]
    # NAME:CASE+CASE gives a process cases of its own (CI freezes the primary arbiter only).
    plan = []
    for entry in (e for e in a.only.split(",") if e):
        name, _, own = entry.partition(":")
        plan += [(name, c) for c in (own.split("+") if own else cases)]
    bad = [n for n, _ in plan if n not in PROCESSES] + [c for _, c in plan if c not in ("kill", "freeze")]
    if bad:
        print(f"reliability: bad --only/--cases: {bad}; processes are " + ", ".join(PROCESSES), file=sys.stderr)
        return 2
    return run_cases(a, plan, lambda farm, c: run_case(farm, c[0], c[1], a.settle, a.freeze), check_row,
                     lambda r, p: f"  {r['process']:12s} {r['case']:6s} lost {fmt(r['lost_after_s'])} s, back "
                                 f"{fmt(r['back_after_s'])} s" + ("" if not p else ": " + "; ".join(p)),
                     "| process | case | shown lost after s | shown back after s | faults kept | raised by it | "
                     "safe stops |\n|---|---|---|---|---|---|---|",
                     lambda r: f"| {r['process']} | {r['case']} | {fmt(r['lost_after_s'])} | "
                                f"{fmt(r['back_after_s'])} | {'yes' if r['faults_kept'] else 'NO'} | "
                                f"{', '.join(r['new_raises']) or 'none'} | {', '.join(r['safe_stops']) or 'none'} |")


def report_run(farm, a, rows, problems, header, line):
    """The end of a run of cases: the table (`header` its first two lines, `line` a row's), the reports the
    services logged that the store lacks, configurations applied out of order, the JSON; the exit code."""
    # Every report a service logged as published is in the store (source, turbine, component, fault, state);
    # duplicates are kept apart only by their sample time, which the log does not give, so this counts kinds.
    stored = {tuple(r) for r in farm.query(
        "SELECT source, turbine_id, component, fault, state FROM fault_events")}
    missing = sorted({" ".join(e) for e in published_by_services(farm) if e not in stored})
    out_of_order = configurations_out_of_order(farm)
    print()
    print(header)
    for r in rows:
        print(line(r))
    print()
    print(f"reports the services logged that the store lacks: {len(missing)}" + "".join("\n  " + m for m in missing))
    print(f"configurations the plant applied out of order: {len(out_of_order)}"
          + "".join("\n  " + m for m in out_of_order))
    print(f"work: {farm.work}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"rows": rows, "missing_reports": missing, "out_of_order": out_of_order}, f, indent=1)
    failed = any(problems.values()) or missing or out_of_order
    return 1 if a.require and failed else 0


# The memory a hostile peer may cost a process (MB of resident memory, measured after it stopped): each keeps
# state for at most --max-turbines turbines, and DDS drops what does not fit its resource limits.
HOSTILE_RSS_GROWTH_MB = 64.0


def hostile(a):
    farm = None
    try:
        farm = start_farm(a)
        if farm is None:
            return 2
        r = run_hostile(farm, a.ids, a.huge, a.hold, a.settle, a.report_keys)
    finally:
        if farm:
            farm.stop_all()
    problems = [] if r["peer_exit"] == 0 else [f"the hostile peer failed (exit {r['peer_exit']})"]
    if r["exited"]:
        problems.append("exited: " + ", ".join(r["exited"]))
    grown = {n: r["rss_mb_after"][n] - r["rss_mb_before"][n] for n in r["rss_mb_before"]
             if r["rss_mb_before"][n] is not None and r["rss_mb_after"].get(n) is not None}
    problems += [f"{n} grew {g:.0f} MB" for n, g in grown.items() if g > HOSTILE_RSS_GROWTH_MB]
    if not r["faults_kept"]:
        problems.append("a raised fault cleared")
    if r["new_raises"]:
        problems.append("raised: " + ", ".join(r["new_raises"]))
    if r["safe_stops"]:
        problems.append("safe stop of " + ", ".join(r["safe_stops"]))
    print(f"hostile peer: {a.ids} unknown turbine ids, strings of {a.huge} bytes, {a.hold:.0f} s: sent {r['sent']}; "
          f"every process with --max-turbines {a.max_turbines or 'default'}"
          + (f" and --turbine {farm.selection[0]}" if farm.selection else ""))
    print()
    print("| process | resident MB before | after | alive |")
    print("|---|---|---|---|")
    for n in r["rss_mb_before"]:
        before, after = r["rss_mb_before"][n], r["rss_mb_after"].get(n)
        print(f"| {n} | {fmt(before)} | {fmt(after)} | {'no' if n in r['exited'] else 'yes'} |")
    print()
    print(f"unknown turbines in the farm store: {r['unknown_turbines_stored']}")
    print(f"raised on the real turbines: {', '.join(r['new_raises']) or 'nothing'}; safe stops: "
          f"{', '.join(r['safe_stops']) or 'none'}; faults kept: {'yes' if r['faults_kept'] else 'NO'}")
    print("problems: " + ("; ".join(problems) or "none"))
    print(f"work: {farm.work}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(dict(r, problems=problems), f, indent=1)
    return 1 if a.require and problems else 0


def not_normal_seconds(farm, since, until):
    """Seconds of [since, until] (wall) in which some turbine's configuration from the primary arbiter (the
    one the plant follows) was not the normal mode, in the store."""
    rows = farm.query("SELECT turbine_id, received_at, mode, reasons FROM configurations WHERE received_at <= ? "
                      "AND arbiter_id = 'primary' ORDER BY received_at", (until,))
    state, spans, start = {}, 0.0, None
    for turbine, at, mode, _ in rows:
        state[turbine] = mode
        bad = any(m != "normal" for m in state.values())
        if at >= since and bad and start is None:
            start = at
        elif at >= since and not bad and start is not None:
            spans += at - start
            start = None
        elif at < since:
            start = since if bad else None
    if start is not None:
        spans += until - start
    return round(spans, 1)


def run_network_case(farm, case, hold, outage, settle):
    """One network case: loss of P % or jitter of MS for `hold` s, or an outage of `outage` s; returns the row of the report."""
    before = active_faults(farm)
    t0 = time.time()
    if case == "down":
        farm.set_network("down")
        time.sleep(outage)
    elif case.startswith("jitter"):
        farm.set_network(f"jitter {int(case[6:])}")
        time.sleep(hold)
    else:
        farm.set_network(f"loss {int(case[4:])}")
        time.sleep(hold)
    farm.set_network(None)
    t1 = time.time()
    lost = sorted({r[0] for r in farm.query(
        "SELECT service FROM health_events WHERE event = 'lost' AND received_at > ?", (t0,))})

    def all_back():
        if not lost:
            return time.time()
        latest = {}
        for service, turbine, event, at in farm.query(
                "SELECT service, turbine_id, event, received_at FROM health_events WHERE received_at > ? "
                "ORDER BY id", (t0,)):
            latest[(service, turbine)] = (event, at)
        if any(e == "lost" for e, _ in latest.values()):
            return None
        return max(at for _, at in latest.values())
    back_at = wait_for(all_back, BACK_TIMEOUT)
    time.sleep(settle)
    # The injected faults derate a blade (pump wear) and correct a pitch (bias), in normal mode: seconds in
    # which a turbine's mode was not normal are what the network did.
    return dict({"case": case, "seconds": round(t1 - t0, 1), "services_lost": lost,
                 "back_after_s": round(back_at - t1, 1) if back_at and lost else (0.0 if not lost else None),
                 "not_normal_s": not_normal_seconds(farm, t0, time.time())}, **judged_since(farm, t0, before))


def network(a):
    cases = [c for c in a.cases.split(",") if c]
    bad = [c for c in cases if c != "down" and not re.fullmatch(r"loss([0-9]|[1-9][0-9]|100)", c)
           and not re.fullmatch(r"jitter[1-9][0-9]{0,3}", c)]
    if bad:
        print(f"reliability: bad --cases {bad}: lossP (P in 0..100), jitterMS (MS in 1..9999) or down",
              file=sys.stderr)
        return 2
    return run_cases(a, cases, lambda farm, c: run_network_case(farm, c, a.hold, a.outage, a.settle),
                     lambda row: check_row(dict(row, process="network", lost_after_s=0.0)),
                     lambda r, p: f"  {r['case']:7s} {r['seconds']:.0f} s: lost "
                                 f"{', '.join(r['services_lost']) or 'none'}, back {fmt(r['back_after_s'])} s, "
                                 f"not normal {r['not_normal_s']:.1f} s" + ("" if not p else ": " + "; ".join(p)),
                     "| case | seconds | services shown lost | all back after s | faults kept | raised | safe stops | "
                     "a turbine not normal s |\n|---|---|---|---|---|---|---|---|",
                     lambda r: f"| {r['case']} | {r['seconds']:.0f} | {', '.join(r['services_lost']) or 'none'} | "
                                f"{fmt(r['back_after_s'])} | {'yes' if r['faults_kept'] else 'NO'} | "
                                f"{', '.join(r['new_raises']) or 'none'} | {', '.join(r['safe_stops']) or 'none'} | "
                                f"{r['not_normal_s']:.1f} |")


LOST = re.compile(r": (\d+) samples lost before sequence")


def samples_lost(farm, service):
    """Samples the service's logs say were lost (sequence gaps), over every incarnation."""
    return sum(int(m[1]) for m in map(LOST.search, farm.log_lines(service)) if m)


def store_bytes(farm):
    """Bytes of the farm store: the SQLite file and its write-ahead log."""
    return sum(os.path.getsize(p) for p in (farm.db, farm.db + "-wal") if os.path.exists(p))


def soak(a):
    """The farm runs --hours of sample time; every --sample wall seconds the resident memory of each process and
    the store's size are taken. Judged: memory flat (the last third's median against the first third's), the
    store no larger than its retention holds, nothing raised but the injected faults, no safe stop, no exit."""
    farm = None
    samples = []
    try:
        farm = start_farm(a)
        if farm is None:
            return 2
        before = active_faults(farm)
        # Samples lost while the farm started (every service makes 20 diagnosers at once, each frame history
        # holds 80 ms of a turbine at 10x) are told apart from those lost while it ran.
        lost_starting = {n: samples_lost(farm, n) for n in SERVICES}
        t0 = time.time()
        while farm.procs["plant"].poll() is None:
            samples.append({"wall_s": round(time.time() - t0, 1), "store_mb": store_bytes(farm) / 1e6,
                            "rss_mb": {n: rss_mb(p.pid) for n, p in farm.procs.items()},
                            "cpu_s": {n: cpu_s(p.pid) for n, p in farm.procs.items()}})
            print(f"  {samples[-1]['wall_s']:7.0f} s: store {samples[-1]['store_mb']:.0f} MB, "
                  + ", ".join(f"{n} {fmt(v)}" for n, v in samples[-1]["rss_mb"].items()), flush=True)
            if time.time() - t0 > 3 * a.hours * 3600 / a.rate + 600:
                print("reliability: the plant did not finish in three times its expected time", file=sys.stderr)
                break
            time.sleep(a.sample)
        wall = time.time() - farm.started["plant"]
        plant_exit = farm.procs["plant"].poll()
        raised = active_faults(farm)
        judged = judged_since(farm, t0, before)
        exited = [n for n in farm.exited() if n != "plant"]
        events = farm.query("SELECT count(*) FROM fault_events")[0][0]
        estimates = farm.query("SELECT count(*) FROM estimates")[0][0]
    finally:
        if farm:
            farm.stop_all()
    third = max(1, len(samples) // 3)

    def median(values):
        values = sorted(v for v in values if v is not None)
        return values[len(values) // 2] if values else None

    rows = []
    problems = []
    for n in farm.procs:
        first = median(x["rss_mb"].get(n) for x in samples[:third])
        last = median(x["rss_mb"].get(n) for x in samples[-third:])
        peak = max((x["rss_mb"].get(n) or 0.0 for x in samples), default=0.0)
        # CPU over the sampled span, in % of one core (2 cores: 200 %): what to make cheaper for a faster soak.
        used = [(x["wall_s"], x["cpu_s"][n]) for x in samples if x["cpu_s"].get(n) is not None]
        cpu = (100.0 * (used[-1][1] - used[0][1]) / (used[-1][0] - used[0][0])
               if len(used) > 1 and used[-1][0] > used[0][0] else None)
        rows.append((n, first, last, peak, cpu))
        if first and last and last - first > max(SOAK_RSS_GROWTH_MB, 0.1 * first):
            problems.append(f"{n} grew from {first:.0f} to {last:.0f} MB")
    # The documented size (README, farm monitor): about 150 bytes a stored estimate, one a second of estimate
    # time per turbine and service, kept --retention hours of wall time.
    kept_hours = min(a.hours, a.retention * a.rate)
    documented_mb = 150e-6 * 3600 * kept_hours * len(SERVICES) * a.turbines
    store_mb = samples[-1]["store_mb"] if samples else 0.0
    if store_mb > 1.5 * documented_mb + 50:
        problems.append(f"store {store_mb:.0f} MB beyond its retention's {documented_mb:.0f} MB")
    if plant_exit != 0:
        problems.append(f"the plant did not finish its {a.hours} h (exit {plant_exit})")
    if exited:
        problems.append("exited: " + ", ".join(exited))
    if judged["new_raises"]:
        problems.append("raised: " + ", ".join(judged["new_raises"]))
    if judged["safe_stops"]:
        problems.append("safe stop of " + ", ".join(judged["safe_stops"]))
    if not judged["faults_kept"]:
        problems.append("an injected fault cleared")
    if not EXPECTED <= raised:
        problems.append("injected faults not raised: " + ", ".join(" ".join(k) for k in sorted(EXPECTED - raised)))
    # Samples the services lost (their logs' sequence gaps): a soak that does not keep up is no soak.
    lost = {n: samples_lost(farm, n) - lost_starting[n] for n in SERVICES}
    if any(lost.values()):
        problems.append("samples lost (the farm did not keep up): " + ", ".join(
            f"{n} {v}" for n, v in lost.items() if v))
    print(f"\nsoak: {a.turbines} turbines, {a.hours:g} h of sample time at {a.rate:g}x "
          f"(blocks of {a.block} samples) in {wall / 60:.0f} min "
          f"(effective {a.hours * 3600 / wall:.1f}x), {len(samples)} samples every {a.sample:g} s\n")
    print("| process | resident MB, first third (median) | last third (median) | peak | CPU, % of one core |")
    print("|---|---|---|---|---|")
    for n, first, last, peak, cpu in rows:
        print(f"| {n} | {fmt(first)} | {fmt(last)} | {peak:.1f} | {fmt(cpu)} |")
    print(f"\nstore: {store_mb:.0f} MB at the end ({estimates} estimates, {events} fault events; its retention of "
          f"{a.retention:g} h holds about {documented_mb:.0f} MB)")
    print("samples lost by the services while it ran: " + ", ".join(f"{n} {v}" for n, v in lost.items())
          + "; while the farm started: " + ", ".join(f"{n} {v}" for n, v in lost_starting.items()))
    print(f"raised besides the injected faults: {', '.join(judged['new_raises']) or 'nothing'}; safe stops: "
          f"{', '.join(judged['safe_stops']) or 'none'}; injected faults kept: "
          f"{'yes' if judged['faults_kept'] else 'NO'}")
    print("problems: " + ("; ".join(problems) or "none"))
    print(f"work: {farm.work}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"samples": samples, "rows": rows, "problems": problems, "wall_s": wall, "lost": lost,
                       "lost_starting": lost_starting,
                       "store_mb": store_mb, "documented_mb": documented_mb, **judged}, f, indent=1)
    return 1 if a.require and problems else 0


# A soak's process may grow this much (MB, or a tenth of its size) between the first and the last third.
SOAK_RSS_GROWTH_MB = 20.0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("processes", help="kill and freeze every process in turn")
    p.add_argument("--only", default=",".join(PROCESSES),
                   help="processes to kill or freeze, in this order; NAME:kill+freeze gives one its own cases")
    p.add_argument("--cases", default="kill,freeze", help="kill, freeze or both")
    p.add_argument("--freeze", type=float, default=FREEZE_SECONDS, help="wall seconds a frozen process stays stopped")
    h = sub.add_parser("hostile", help="a hostile peer on the unsecured domain")
    h.add_argument("--ids", type=int, default=10000, help="unknown turbine ids it sends frames for")
    h.add_argument("--huge", type=int, default=1 << 20, help="bytes of the strings in its IDL string fields")
    h.add_argument("--hold", type=float, default=60.0, help="wall seconds it sends")
    h.add_argument("--max-turbines", type=int, default=10,
                   help="every process's --max-turbines (default 10: the farm's 3 and room; 0: the default 1000)")
    h.add_argument("--filtered", action="store_true",
                   help="every process but the plant also given --turbine WT01..WTnn (the farm's turbines)")
    h.add_argument("--report-keys", type=int, default=0,
                   help="the peer also sends canonical FaultReports under this many distinct keys a round")
    n = sub.add_parser("network", help="a lossy network, a jittery one, then an outage")
    n.add_argument("--cases", default="loss10,loss30,jitter50,down",
                   help="lossP (P %% of messages dropped), jitterMS (each held 0..MS ms) or down")
    n.add_argument("--hold", type=float, default=60.0, help="wall seconds of each loss or jitter case")
    n.add_argument("--outage", type=float, default=10.0, help="wall seconds of the outage")
    k = sub.add_parser("soak", help="hours of sample time: memory, the store, false alarms")
    k.add_argument("--hours", type=float, default=24.0, help="hours of sample time (default 24)")
    k.add_argument("--sample", type=float, default=60.0, help="wall seconds between measurements")
    k.add_argument("--retention", type=float, default=0.5,
                   help="the farm monitor's --estimate-retention, hours of wall time (default 0.5: the store "
                        "reaches its plateau within the run)")
    k.add_argument("--block", type=int, default=10,
                   help="the plant's samples per frame, 1..32 (default 10, the plant's)")
    for q in (p, h, n, k):
        q.add_argument("--rate", type=float, default=4.0, help="plant speed-up (default 4)")
        q.add_argument("--turbines", type=int, default=3, help="turbines of the farm (3..10; soak: 3..20)")
        q.add_argument("--warmup", type=float, default=60.0, help="wall seconds before the first case")
        q.add_argument("--settle", type=float, default=15.0, help="wall seconds judged after each case")
        q.add_argument("--work", help="directory for logs and the store (default: a new temporary one)")
        q.add_argument("--json", help="also write the results as JSON here")
        q.add_argument("--require", action="store_true", help="exit 1 when anything fails")
    a = ap.parse_args()
    if not 3 <= a.turbines <= (20 if a.command == "soak" else 10) or a.rate <= 0:
        print(f"reliability: bad --turbines/--rate: {a.turbines}, {a.rate}", file=sys.stderr)
        return 2
    if getattr(a, "block", None) is not None and not 1 <= a.block <= 32:
        print(f"reliability: bad --block: {a.block} (1..32 samples per frame)", file=sys.stderr)
        return 2
    # A SIGTERM (ctest's timeout, a Ctrl-C'd script) stops the farm like the end of the run does.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(1))
    if a.command == "hostile" and a.max_turbines == 0:
        a.max_turbines = None
    return {"processes": processes, "hostile": hostile, "network": network, "soak": soak}[a.command](a)


if __name__ == "__main__":
    sys.exit(main())
