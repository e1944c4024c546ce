#!/usr/bin/env python3
"""Reference driver for Tactus's network device (docs/network-protocol.md).

Sends the pose of a handle moving on a horizontal circle at 1 kHz over UDP and prints the
forces Tactus sends back. Python 3 standard library only; a driver for a real device
replaces circle_position() with the device's own reading and applies the force.

    python3 examples/network_driver.py --port 47600 --radius 0.02 --period 2
"""
import argparse
import math
import socket
import struct
import sys
import time
import zlib

VERSION = 1
# Little-endian, no padding: the layout tables of docs/network-protocol.md.
POSE_BODY = struct.Struct("<4sHHIQ3d4dI")  # magic, version, device, sequence, time, p, q, buttons
FORCE_BODY = struct.Struct("<4sHHIIQ3d3dI")  # magic, version, device, seq, pose seq, time, f, tau, flags
CRC = struct.Struct("<I")
FLAG_NAMES = {0: "clamped", 1: "non-finite", 2: "ramping", 3: "watchdog", 4: "emergency-stop",
              8: "link-timeout"}


def encode_pose(device, sequence, timestamp_ns, position, quaternion_wxyz, buttons=0):
    body = POSE_BODY.pack(b"TPOS", VERSION, device, sequence & 0xFFFFFFFF, timestamp_ns,
                          *position, *quaternion_wxyz, buttons)
    return body + CRC.pack(zlib.crc32(body))


def decode_force(datagram):
    """A dict of the packet's fields, or a string saying why it was refused."""
    if len(datagram) < 8:
        return "wrong size"
    magic, version = struct.unpack_from("<4sH", datagram)
    if magic != b"TFRC":
        return "bad magic"
    if version != VERSION:
        return "unsupported version"
    if len(datagram) != FORCE_BODY.size + CRC.size:
        return "wrong size"
    (crc,) = CRC.unpack_from(datagram, FORCE_BODY.size)
    if crc != zlib.crc32(datagram[:FORCE_BODY.size]):
        return "bad checksum"
    fields = FORCE_BODY.unpack_from(datagram)
    force, torque = fields[6:9], fields[9:12]
    if not all(math.isfinite(v) for v in force + torque):
        return "non-finite number"
    return {"device": fields[2], "sequence": fields[3], "pose_sequence": fields[4],
            "timestamp_ns": fields[5], "force": force, "torque": torque, "flags": fields[12]}


def circle_position(t, center, radius, period):
    phase = 2.0 * math.pi * t / period
    return (center[0] + radius * math.cos(phase), center[1] + radius * math.sin(phase), center[2])


def flag_text(flags):
    names = [name for bit, name in FLAG_NAMES.items() if flags & (1 << bit)]
    return ",".join(names) if names else "-"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--address", default="127.0.0.1", help="Tactus's address")
    parser.add_argument("--port", type=int, default=47600)
    parser.add_argument("--device-index", type=int, default=0)
    parser.add_argument("--rate", type=float, default=1000.0, help="poses per second")
    parser.add_argument("--radius", type=float, default=0.02, help="[m]")
    parser.add_argument("--period", type=float, default=2.0, help="seconds per turn")
    parser.add_argument("--center", type=float, nargs=3, default=(0.0, 0.0, 0.0),
                        metavar=("X", "Y", "Z"), help="[m], device coordinates")
    parser.add_argument("--duration", type=float, default=0.0, help="seconds; 0 runs until Ctrl-C")
    parser.add_argument("--print-rate", type=float, default=10.0, help="force lines per second")
    args = parser.parse_args()

    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.setblocking(False)
    target = (args.address, args.port)
    step = 1.0 / args.rate
    start = time.monotonic()
    next_send = start
    next_print = start
    sequence = 0
    received = refused = 0
    last = None
    try:
        while args.duration <= 0.0 or time.monotonic() - start < args.duration:
            now = time.monotonic()
            if now >= next_send:
                position = circle_position(now - start, args.center, args.radius, args.period)
                sock.sendto(encode_pose(args.device_index, sequence, time.monotonic_ns(),
                                        position, (1.0, 0.0, 0.0, 0.0)), target)
                sequence += 1
                # Keep the schedule; after a stall skip ahead instead of sending a burst.
                next_send = max(next_send + step, now)
            while True:
                try:
                    datagram = sock.recv(512)
                except (BlockingIOError, ConnectionRefusedError):
                    break
                packet = decode_force(datagram)
                if isinstance(packet, str):
                    refused += 1
                    continue
                received += 1
                last = packet
            if last is not None and now >= next_print:
                f, tau = last["force"], last["torque"]
                lag = (sequence - 1 - last["pose_sequence"]) & 0xFFFFFFFF
                print(f"t={now - start:8.3f}s  F=[{f[0]:+8.4f} {f[1]:+8.4f} {f[2]:+8.4f}] N  "
                      f"T=[{tau[0]:+.4f} {tau[1]:+.4f} {tau[2]:+.4f}] N·m  "
                      f"answers pose {last['pose_sequence']} ({lag} behind)  "
                      f"flags {flag_text(last['flags'])}", flush=True)
                next_print = now + 1.0 / args.print_rate
            time.sleep(max(0.0, next_send - time.monotonic()))
    except KeyboardInterrupt:
        pass
    print(f"sent {sequence} poses, received {received} forces, refused {refused}",
          file=sys.stderr)


if __name__ == "__main__":
    main()
