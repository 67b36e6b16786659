#!/usr/bin/env python3
"""Every reliable writer's history span on this host, from the RTPS heartbeats on the loopback interface.

A reliable writer's HEARTBEAT names the oldest (first) and newest (last) sequence number its history
holds. For a keep-last writer whose instances are all rewritten, last - first stays below the number of
instances; a span that grows with the run is a sample stuck at the front of the history, and each reader
then walks a GAP over the whole span (docs/fastdds.md). Needs root (a raw packet socket); sees UDP only
(not shared memory: the arbiters and the farm monitor speak UDP).

    rtps_heartbeats.py [--seconds 3] [--min-span 0]
"""
import argparse
import os
import re
import socket
import struct
import subprocess
import sys
import time

HEARTBEAT, ETH_P_ALL = 0x07, 0x0003


def port_owners():
    """UDP source port -> process name, from `ss`."""
    owners = {}
    try:
        out = subprocess.run(["ss", "-uapnH"], capture_output=True, text=True, check=False).stdout
    except FileNotFoundError:
        return owners
    for line in out.splitlines():
        m = re.search(r":(\d+)\s.*users:\(\(\"([^\"]+)\",pid=(\d+)", line)
        if m:
            owners[int(m.group(1))] = f"{m.group(2)}[{m.group(3)}]"
    return owners


def capture(seconds):
    sock = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.ntohs(ETH_P_ALL))
    sock.bind(("lo", 0))
    sock.settimeout(0.2)
    writers = {}  # (source port, guid prefix, writer entity) -> [heartbeats, first, last]
    end = time.time() + seconds
    while time.time() < end:
        try:
            packet, address = sock.recvfrom(65535)
        except socket.timeout:
            continue
        if address[2] == socket.PACKET_OUTGOING:  # loopback shows each packet leaving and arriving
            continue
        # Ethernet (14) + IPv4 + UDP (8) + RTPS header (20)
        if len(packet) < 62 or packet[12:14] != b"\x08\x00" or packet[23] != 17:
            continue
        udp = 14 + (packet[14] & 0xF) * 4
        source_port = struct.unpack(">H", packet[udp:udp + 2])[0]
        rtps = udp + 8
        if packet[rtps:rtps + 4] != b"RTPS":
            continue
        prefix = packet[rtps + 8:rtps + 20].hex()
        at = rtps + 20
        while at + 4 <= len(packet):
            kind, flags = packet[at], packet[at + 1]
            order = "<" if flags & 1 else ">"
            length = struct.unpack(order + "H", packet[at + 2:at + 4])[0]
            body = packet[at + 4:at + 4 + length] if length else packet[at + 4:]
            if kind == HEARTBEAT and len(body) >= 24:
                first_high, first_low, last_high, last_low = struct.unpack(order + "iIiI", body[8:24])
                entry = writers.setdefault((source_port, prefix, body[4:8].hex()), [0, 0, 0])
                entry[0] += 1
                entry[1] = (first_high << 32) | first_low
                entry[2] = (last_high << 32) | last_low
            if length == 0:
                break
            at += 4 + length
    return writers


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seconds", type=float, default=3.0, help="capture time (default 3)")
    parser.add_argument("--min-span", type=int, default=0, help="print only writers with last - first >= this")
    args = parser.parse_args()
    if args.seconds <= 0:
        print("rtps_heartbeats.py: --seconds must be positive", file=sys.stderr)
        return 2
    if os.geteuid() != 0:
        print("rtps_heartbeats.py: needs root (a raw packet socket on lo)", file=sys.stderr)
        return 2
    writers = capture(args.seconds)
    owners = port_owners()
    rows = sorted(writers.items(), key=lambda kv: kv[1][1] - kv[1][2])
    print(f"{'process':28} {'writer':8} {'heartbeats':>10} {'first':>12} {'last':>12} {'span':>8}")
    for (port, prefix, entity), (beats, first, last) in rows:
        if last - first < args.min_span:
            continue
        print(f"{owners.get(port, f'port {port}'):28} {entity:8} {beats:10d} {first:12d} {last:12d} "
              f"{last - first:8d}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
