#!/usr/bin/env python3
"""Writes the base-board recording played into vcan0 by the real-kernel CAN check.

data/base_board.log: candump -l format, 1 s of traffic from docs/can.md's message map: gyro
0x102 at 100 Hz, encoders 0x101 at 20 Hz, plus the faults the driver must survive (a gyro frame
of 5 bytes, a frame of unknown id, two gyro frames missing from the sequence, bus-off followed by
a controller restart). data/base_board_expected.csv: what the driver must deliver, in order,
computed here from the physical values, independently of the C++ decoder.
"""
import math
import os
import struct

here = os.path.dirname(os.path.abspath(__file__))
t0 = 1700000000.0


def wrap24(v):
    return ((v + (1 << 23)) % (1 << 24)) - (1 << 23)


frames = []    # (t, id_text, payload bytes)
expected = []  # (kind, a, b)

left0, right0 = 8388000, -100  # left crosses the signed 24-bit wrap
for k in range(20):
    t = k * 0.050 + 0.004
    left = left0 + 300 * k
    right = right0 - 150 * k
    data = (struct.pack("<i", wrap24(left))[:3] + struct.pack("<i", wrap24(right))[:3]
            + bytes([k & 0xFF, 0]))
    frames.append((t, "101", data))
    expected.append((t, "encoder", left, right))

for k in range(100):
    t = k * 0.010
    seq = (250 + k) & 0xFF  # wraps through 255 -> 0
    if k in (40, 41):
        continue  # lost on the bus: a sequence gap of 2
    rate = 0.8 * math.sin(2 * math.pi * t) - 0.1
    raw = round(rate * 1e6)
    temp = round(31.5 / 0.01)
    data = struct.pack("<ihBB", raw, temp, seq, 0)
    frames.append((t, "102", data))
    expected.append((t, "gyro", raw, 0))

# Faults.
frames.append((0.2051, "102", bytes([1, 2, 3, 4, 5])))           # wrong length
frames.append((0.3051, "321", bytes(8)))                          # unknown id (kernel filter)
frames.append((0.6001, "20000040", bytes(8)))                     # CAN_ERR_FLAG | CAN_ERR_BUSOFF
frames.append((0.6501, "20000100", bytes(8)))                     # CAN_ERR_FLAG | CAN_ERR_RESTARTED

frames.sort(key=lambda f: f[0])
expected.sort(key=lambda e: e[0])
os.makedirs(os.path.join(here, "data"), exist_ok=True)
with open(os.path.join(here, "data", "base_board.log"), "w") as f:
    for t, ident, data in frames:
        f.write(f"({t0 + t:.6f}) vcan0 {ident}#{data.hex().upper()}\n")
with open(os.path.join(here, "data", "base_board_expected.csv"), "w") as f:
    f.write("# kind,a,b: encoder left_ticks right_ticks (32-bit cumulative) | gyro rate_urad_s 0\n")
    for _, kind, a, b in expected:
        f.write(f"{kind},{a},{b}\n")
