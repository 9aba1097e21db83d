#!/bin/bash
# Boots Debian's arm64 kernel under qemu-system-aarch64 (TCG) with an initramfs holding static
# busybox, the modules of docs/platform-notes.md (vcan, can-raw, vivid; the PL061 GPIO is built
# in) and the static aarch64 checkers, and reports the guest's KERNEL-TEST lines.
#   run_guest.sh --checkers DIR --cache DIR --work DIR [--timeout S] [--files DIR] [--any-verdict]
#                [--program FILE]   (a dynamically linked aarch64 program, copied to /program/ with
#                                    its shared libraries)
# Exit status 0 when the guest printed "KERNEL-VERDICT PASS" and no check failed (with
# --any-verdict: when it printed a verdict at all). The console log is WORK/console.log.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
checkers="" cache="" work="" timeout=100 files="" any_verdict="" program=""
while [ $# -gt 0 ]; do
  case "$1" in
    --checkers) checkers=$2; shift 2 ;;
    --cache) cache=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --timeout) timeout=$2; shift 2 ;;
    --files) files=$2; shift 2 ;;
    --any-verdict) any_verdict=--any-verdict; shift ;;
    --program) program=$2; shift 2 ;;
    "") shift ;;  # an empty generator expression from CTest
    *) echo "run_guest.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
[ -n "$checkers" ] && [ -n "$cache" ] && [ -n "$work" ] || {
  echo "usage: run_guest.sh --checkers DIR --cache DIR --work DIR [--timeout S] [--files DIR]" >&2
  exit 2
}
for tool in qemu-system-aarch64 apt-get dpkg-deb depmod modprobe cpio gzip python3; do
  command -v "$tool" >/dev/null || { echo "run_guest.sh: '$tool' not found (setup installs qemu-system-arm, kmod, cpio)" >&2; exit 2; }
done

mkdir -p "$cache" "$work"
cache=$(cd "$cache" && pwd)
work=$(cd "$work" && pwd)

# 1. Kernel and busybox from Debian's archive, downloaded once into the cache.
kver_file="$cache/kernel-version"
if [ ! -s "$kver_file" ] || [ ! -d "$cache/root/lib/modules/$(cat "$kver_file")" ]; then
  pkg=$(apt-cache depends linux-image-arm64:arm64 | awk '/Depends: linux-image-[0-9]/ {print $2; exit}')
  pkg=${pkg%:arm64}
  [ -n "$pkg" ] || { echo "run_guest.sh: cannot resolve linux-image-arm64:arm64 (is arm64 added to dpkg and apt-get update done?)" >&2; exit 2; }
  kver=${pkg#linux-image-}
  rm -rf "$cache/root" "$cache"/*.deb
  (cd "$cache" && apt-get download "$pkg:arm64" busybox-static:arm64 >/dev/null 2>&1) || {
    echo "run_guest.sh: apt-get download $pkg:arm64 busybox-static:arm64 failed" >&2; exit 2; }
  mkdir -p "$cache/root"
  for deb in "$cache"/*.deb; do dpkg-deb -x "$deb" "$cache/root"; done
  rm -f "$cache"/*.deb
  depmod -b "$cache/root" "$kver"
  echo "$kver" > "$kver_file"
fi
kver=$(cat "$kver_file")
kroot="$cache/root"

# 2. The initramfs.
rd="$work/initramfs"
rm -rf "$rd"
mkdir -p "$rd"/{bin,sbin,proc,sys,dev,tmp,run,modules,checkers,files,etc}
cp "$kroot/bin/busybox" "$rd/bin/busybox"
: > "$rd/modules/load.list"
for mod in vcan can-raw vivid; do
  modprobe -d "$kroot" -S "$kver" --show-depends "$mod" | awk '$1 == "insmod" {print $2}' |
    while read -r path; do
      name=$(basename "$path")
      if ! grep -qx "$name" "$rd/modules/load.list"; then
        cp "$path" "$rd/modules/$name"
        echo "$name" >> "$rd/modules/load.list"
      fi
    done
done
cp "$checkers"/kernel_check_* "$rd/checkers/"
[ -n "$files" ] && cp -r "$files"/. "$rd/files/"
if [ -n "$program" ]; then
  # The program and, recursively, the shared libraries it needs, from the arm64 multiarch tree.
  mkdir -p "$rd/program" "$rd/lib/aarch64-linux-gnu"
  cp "$program" "$rd/program/"
  find_lib() {
    for dir in /usr/aarch64-linux-gnu/lib /usr/lib/aarch64-linux-gnu /lib/aarch64-linux-gnu; do
      [ -e "$dir/$1" ] && { readlink -f "$dir/$1"; return 0; }
    done
    return 1
  }
  pending=$(aarch64-linux-gnu-readelf -d "$program" | sed -n 's/.*Shared library: \[\(.*\)\]/\1/p')
  while [ -n "$pending" ]; do
    next=""
    for lib in $pending; do
      [ -e "$rd/lib/aarch64-linux-gnu/$lib" ] && continue
      path=$(find_lib "$lib") || { echo "run_guest.sh: $lib (needed by $program) not found" >&2; exit 2; }
      cp "$path" "$rd/lib/aarch64-linux-gnu/$lib"
      next="$next $(aarch64-linux-gnu-readelf -d "$path" | sed -n 's/.*Shared library: \[\(.*\)\]/\1/p')"
    done
    pending=$next
  done
  cp "$(find_lib ld-linux-aarch64.so.1)" "$rd/lib/ld-linux-aarch64.so.1"
fi
cp "$here/guest_init.sh" "$rd/init"
chmod +x "$rd/init" "$rd"/checkers/*
(cd "$rd" && find . | cpio -o -H newc --quiet | gzip -1) > "$work/initrd.cpio.gz"

# 3. Boot, feed the monitor what the guest asks for, read the verdict.
exec python3 "$here/guest_console.py" --timeout "$timeout" --log "$work/console.log" $any_verdict \
  --monitor "$work/monitor.sock" -- \
  qemu-system-aarch64 -M virt -cpu cortex-a57 -smp 1 -m 512 -nographic -no-reboot -nic none \
  -kernel "$kroot/boot/vmlinuz-$kver" -initrd "$work/initrd.cpio.gz" \
  -append "console=ttyAMA0 rdinit=/init panic=-1 quiet loglevel=3" \
  -monitor "unix:$work/monitor.sock,server,nowait"
