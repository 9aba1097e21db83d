#!/usr/bin/env python3
"""Decodes a candump recording with docs/cleanslam.dbc, read by a generic DBC signal parser, and
compares with the expected values: the DBC describes the frames the driver decodes."""
import re
import sys

dbc_path, log_path, expected_path = sys.argv[1:4]
messages = {}
current = None
for line in open(dbc_path):
    m = re.match(r"BO_ (\d+) (\w+): (\d+) (\w+)", line)
    if m:
        current = messages.setdefault(int(m.group(1)), {"name": m.group(2), "signals": {}})
        continue
    m = re.match(r"\s+SG_ (\w+) : (\d+)\|(\d+)@([01])([+-]) \(([^,]+),([^)]+)\)", line)
    if m and current is not None:
        assert m.group(4) == "1", "only little-endian signals expected"
        current["signals"][m.group(1)] = (int(m.group(2)), int(m.group(3)), m.group(5) == "-",
                                          float(m.group(6)), float(m.group(7)))


def decode(can_id, data):
    raw = int.from_bytes(data, "little")
    out = {}
    for name, (start, length, signed, factor, offset) in messages[can_id]["signals"].items():
        v = (raw >> start) & ((1 << length) - 1)
        if signed and v >= 1 << (length - 1):
            v -= 1 << length
        out[name] = v * factor + offset
    return out


decoded = []
for line in open(log_path):
    _, _, body = line.split()
    ident, data = body.split("#")
    can_id = int(ident, 16)
    data = bytes.fromhex(data)
    if can_id in messages and len(data) == 8:
        decoded.append((can_id, decode(can_id, data)))

expected = [row.strip().split(",") for row in open(expected_path)
            if row.strip() and row[0] != "#"]
assert len(decoded) == len(expected), (len(decoded), len(expected))
left_base = right_base = None
for (can_id, d), (kind, a, b) in zip(decoded, expected):
    if kind == "gyro":
        assert can_id == 0x102 and abs(d["RateZ"] - int(a) * 1e-6) < 1e-9, (d, a)
        assert abs(d["Temperature"] - 31.5) < 1e-9, d
    else:
        # The DBC gives the wrapped 24-bit counter; the driver's 32-bit count agrees modulo 2^24.
        assert can_id == 0x101, can_id
        assert (int(d["LeftTicks"]) - int(a)) % (1 << 24) == 0, (d, a)
        assert (int(d["RightTicks"]) - int(b)) % (1 << 24) == 0, (d, b)
print(f"{len(decoded)} frames decoded with {dbc_path}: as expected")
