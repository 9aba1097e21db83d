#!/usr/bin/env python3
"""Runs QEMU, copies the guest console to a log, and answers the guest's requests.

A guest line "KERNEL-REQUEST powerdown" makes this send "system_powerdown" on the QEMU monitor
(on the virt board that pulses PL061 line 3). QEMU does not return the guest's status: the exit
status here is 0 only when the guest printed "KERNEL-VERDICT PASS".
"""
import argparse
import os
import socket
import subprocess
import sys
import time


def monitor_command(path, command):
    for _ in range(50):
        try:
            s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
            s.connect(path)
            break
        except OSError:
            time.sleep(0.1)
    else:
        print(f"guest_console: cannot connect to the QEMU monitor at {path}", file=sys.stderr)
        return
    s.sendall((command + "\n").encode())
    time.sleep(0.2)
    s.close()


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--timeout", type=float, default=100)
    p.add_argument("--log", required=True)
    p.add_argument("--monitor", required=True)
    p.add_argument("--any-verdict", action="store_true",
                   help="exit 0 whenever the guest printed a verdict (CTest reads each check)")
    p.add_argument("qemu", nargs=argparse.REMAINDER)
    a = p.parse_args()
    cmd = a.qemu[1:] if a.qemu and a.qemu[0] == "--" else a.qemu
    if os.path.exists(a.monitor):
        os.unlink(a.monitor)
    start = time.monotonic()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            stdin=subprocess.DEVNULL)
    verdict = None
    failed = False
    os.set_blocking(proc.stdout.fileno(), False)
    buf = b""
    with open(a.log, "wb") as log:
        while True:
            if time.monotonic() - start > a.timeout:
                print(f"guest_console: guest still running after {a.timeout:.0f} s, killed",
                      file=sys.stderr)
                proc.kill()
                break
            chunk = proc.stdout.read()
            if chunk:
                log.write(chunk)
                log.flush()
                buf += chunk
                while b"\n" in buf:
                    line, buf = buf.split(b"\n", 1)
                    text = line.decode(errors="replace").strip()
                    if text.startswith("KERNEL-"):
                        print(text, flush=True)
                    if text == "KERNEL-REQUEST powerdown":
                        monitor_command(a.monitor, "system_powerdown")
                    if text.startswith("KERNEL-TEST") and text.endswith(" FAIL"):
                        failed = True
                    if text.startswith("KERNEL-VERDICT"):
                        verdict = text.split()[-1]
            elif proc.poll() is not None:
                break
            else:
                time.sleep(0.02)
    proc.wait()
    print(f"guest_console: guest ran {time.monotonic() - start:.1f} s, verdict {verdict}")
    if a.any_verdict:
        return 0 if verdict is not None else 1
    return 0 if verdict == "PASS" and not failed else 1


if __name__ == "__main__":
    sys.exit(main())
