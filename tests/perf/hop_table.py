#!/usr/bin/env python3
"""Hop-by-hop latency table from a WINDFDI_TRACE directory (common/hop_trace.hpp): where the time goes between
the plant writing the frame that makes a fault decidable and the plant applying the configuration the
arbiter decided on it.

  hop_table.py DIR [--skip SECONDS]     markdown table of each hop's p50 / p90 / p99 / max (ms)

Every process of the run writes DIR/<process>.<pid>.csv (hop,turbine_id,key,wall_time). A fault report is
followed by its key (component/fault/t) from its decisive frame to the arbiter; the arbiter's report_config
rows link it to the configuration revision the plant applies. Exit 1 when no report made it through.
"""
import argparse
import csv
import glob
import os
import sys

# (name, from hop, to hop, what the time is)
HOPS = [
    ("frame: plant write -> service DDS receive", "frame_write", "frame_receive", "DDS"),
    ("frame: DDS receive -> service loop wakes", "frame_receive", "frame_wake", "listener to thread"),
    ("frame: loop wakes -> frames taken", "frame_wake", "frame_take", "context, LIDAR, take"),
    ("service: take -> FaultReport write", "frame_take", "report_write", "estimator"),
    ("report: write -> arbiter DDS receive", "report_write", "report_receive", "DDS"),
    ("report: DDS receive -> arbiter take", "report_receive", "report_take", "listener thread or loop"),
    ("arbiter: take -> configuration write", "report_take", "config_write", "decision"),
    ("config: write -> plant DDS receive", "config_write", "config_receive", "DDS"),
    ("config: DDS receive -> plant control step", "config_receive", "config_apply", "control period"),
    ("total: frame write -> FaultReport write", "frame_write", "report_write", ""),
    ("total: frame write -> arbiter take", "frame_write", "report_take", ""),
    ("total: frame write -> configuration applied", "frame_write", "config_apply", ""),
]
REPORT_HOPS = {"frame_write", "frame_receive", "frame_wake", "frame_take", "report_write", "report_receive", "report_take"}
CONFIG_HOPS = {"config_write", "config_receive", "config_apply"}


def percentile(values, q):
    v = sorted(values)
    return v[min(len(v) - 1, int(q * len(v)))]


def load(directory):
    reports, configs, links = {}, {}, {}
    files = glob.glob(os.path.join(directory, "*.csv"))
    for path in files:
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                hop, turbine, key, t = row["hop"], row["turbine_id"], row["key"], float(row["wall_time"])
                if hop in REPORT_HOPS:
                    reports.setdefault((turbine, key), {})[hop] = t
                elif hop in CONFIG_HOPS:
                    configs.setdefault((turbine, key), {})[hop] = t
                elif hop == "report_config":
                    report, revision = key.rsplit(">", 1)
                    links[(turbine, report)] = revision
    return files, reports, configs, links


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir")
    ap.add_argument("--skip", type=float, default=0.0, help="leave out reports from the first SECONDS of the run")
    a = ap.parse_args()
    files, reports, configs, links = load(a.dir)
    if not files:
        sys.exit(f"hop_table: no trace files in {a.dir} (was WINDFDI_TRACE set?)")
    start = min((r["frame_write"] for r in reports.values() if "frame_write" in r), default=0.0)
    paths = []
    for (turbine, key), r in reports.items():
        if r.get("frame_write", start) - start < a.skip:
            continue
        # The loop may have woken for an earlier frame and taken this one with it: no wait of its own.
        if "frame_wake" in r and "frame_receive" in r:
            r = dict(r, frame_wake=max(r["frame_wake"], r["frame_receive"]))
        revision = links.get((turbine, key))
        if revision is not None:
            r = dict(r, **configs.get((turbine, revision), {}))
        paths.append(r)
    whole = [p for p in paths if all(h in p for h in ("frame_write", "report_take"))]
    if not whole:
        sys.exit(f"hop_table: no fault report reached the arbiter in {a.dir}")
    print(f"{len(whole)} fault reports traced to the arbiter, "
          f"{sum('config_apply' in p for p in whole)} of them to a configuration applied by the plant")
    print()
    print("| hop | what | n | p50 ms | p90 ms | p99 ms | max ms |")
    print("|---|---|---|---|---|---|---|")
    for name, a_hop, b_hop, what in HOPS:
        d = [1e3 * (p[b_hop] - p[a_hop]) for p in paths if a_hop in p and b_hop in p and p[a_hop] > 0]
        if not d:
            continue
        print(f"| {name} | {what} | {len(d)} | {percentile(d, 0.5):.3f} | {percentile(d, 0.9):.3f} | "
              f"{percentile(d, 0.99):.3f} | {max(d):.3f} |")


if __name__ == "__main__":
    main()
