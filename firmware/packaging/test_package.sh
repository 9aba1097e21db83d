#!/bin/bash
# The package test: builds the .deb from an aarch64 build tree, inspects it (control fields,
# files, conffiles, hardened unit, udev rules) and runs the packaged binary under qemu-user
# against a simulated dataset.
#   test_package.sh BUILD_DIR WORK_DIR [--run-dataset]
set -euo pipefail
build=$1
work=$2
run_dataset=${3:-}
fail() { echo "package test: FAIL: $*" >&2; exit 1; }

rm -rf "$work"
mkdir -p "$work"
cpack --config "$build/CPackConfig.cmake" -B "$work" >"$work/cpack.log" 2>&1 || {
  cat "$work/cpack.log" >&2; fail "cpack failed"; }
deb=$(ls "$work"/cleanslam_*_arm64.deb 2>/dev/null | head -1)
[ -n "$deb" ] || fail "no cleanslam_*_arm64.deb in $work"
echo "package: $(basename "$deb"), $(stat -c %s "$deb") bytes"

field() { dpkg-deb -f "$deb" "$1"; }
[ "$(field Package)" = cleanslam ] || fail "Package is '$(field Package)'"
[ "$(field Architecture)" = arm64 ] || fail "Architecture is '$(field Architecture)'"
for dep in libc6 libstdc++6 libgpiod2 adduser; do
  field Depends | grep -q "$dep" || fail "Depends lacks $dep: $(field Depends)"
done

contents=$(dpkg-deb -c "$deb" | awk '{print $6}')
for f in ./usr/bin/cleanslam ./etc/cleanslam/cleanslam.yaml \
         ./usr/lib/systemd/system/cleanslam.service ./usr/lib/udev/rules.d/60-cleanslam.rules \
         ./usr/lib/systemd/network/80-cleanslam-can0.network \
         ./usr/share/doc/cleanslam/can.md ./usr/share/doc/cleanslam/cleanslam.dbc; do
  grep -qx "$f" <<<"$contents" || fail "the package lacks $f"
done

dpkg-deb -e "$deb" "$work/control"
grep -qx /etc/cleanslam/cleanslam.yaml "$work/control/conffiles" || fail "config is not a conffile"
for script in postinst prerm postrm; do
  [ -x "$work/control/$script" ] || fail "$script missing or not executable"
  sh -n "$work/control/$script" || fail "$script: syntax error"
done
grep -q "adduser --system" "$work/control/postinst" || fail "postinst creates no system user"
grep -q "install -d .*/var/lib/cleanslam" "$work/control/postinst" ||
  fail "postinst does not create /var/lib/cleanslam (the map's directory)"

dpkg-deb -x "$deb" "$work/root"
file -L "$work/root/usr/bin/cleanslam" | grep -q "ARM aarch64" || fail "binary is not aarch64"
grep -qF 'path: "/var/lib/cleanslam/map.bin"' "$work/root/etc/cleanslam/cleanslam.yaml" ||
  fail "the packaged configuration keeps no map in /var/lib/cleanslam"

unit="$work/root/usr/lib/systemd/system/cleanslam.service"
for line in "Type=notify" "User=cleanslam" "Restart=on-failure" "WatchdogSec=5s" \
            "CapabilityBoundingSet=" "AmbientCapabilities=" "NoNewPrivileges=yes" \
            "ProtectSystem=strict" "PrivateTmp=yes" "DevicePolicy=closed" \
            "DeviceAllow=char-video4linux rw" "DeviceAllow=char-gpiochip rw" \
            "SupplementaryGroups=video" "RestrictAddressFamilies=AF_CAN AF_UNIX" \
            "StateDirectoryMode=0750" "RestrictRealtime=yes" "IPAddressDeny=any" \
            "ExecStart=/usr/bin/cleanslam --config /etc/cleanslam/cleanslam.yaml"; do
  grep -qxF "$line" "$unit" || fail "the unit lacks '$line'"
done
grep -q 'SUBSYSTEM=="gpio", KERNEL=="gpiochip\*", GROUP="cleanslam"' \
  "$work/root/usr/lib/udev/rules.d/60-cleanslam.rules" || fail "no udev rule for gpiochip"
if command -v systemd-analyze >/dev/null; then
  # The unit as systemd reads it (the binary path swapped for one that exists here).
  mkdir -p "$work/unit"
  sed 's|^ExecStart=/usr/bin/cleanslam|ExecStart=/bin/true|' "$unit" >"$work/unit/cleanslam.service"
  if systemd-analyze verify "$work/unit/cleanslam.service" 2>&1 | grep -v "^$" >"$work/verify.log"; then
    cat "$work/verify.log" >&2
    fail "systemd-analyze verify complains about the unit"
  fi
  exposure=$(systemd-analyze security --offline=yes "$work/unit/cleanslam.service" 2>/dev/null |
    sed -n 's/.*Overall exposure level for cleanslam.service: \([0-9.]*\).*/\1/p')
  echo "systemd-analyze security: exposure $exposure"
  awk -v e="$exposure" 'BEGIN { exit !(e != "" && e <= 1.4) }' || fail "exposure '$exposure' is above 1.4"
  grep -q "^LogsDirectory=" "$unit" && fail "LogsDirectory= in the unit, though the packaged configuration records nothing"
fi
echo "package contents, control and unit: as expected"

# The packaged binary under qemu-user.
qemu=(qemu-aarch64 -L /usr/aarch64-linux-gnu)
bin="$work/root/usr/bin/cleanslam"
"${qemu[@]}" "$bin" --version >"$work/version.txt" 2>&1 || fail "cleanslam --version failed: $(cat "$work/version.txt")"
echo "packaged binary: $(head -1 "$work/version.txt")"

if [ "$run_dataset" != "--run-dataset" ]; then
  echo "package test: PASS (contents; no dataset run asked)"
  exit 0
fi
sim="${CLEANSLAM_SIM:-$build/bin/cleanslam-sim}"
[ -x "$sim" ] || fail "no $sim to make a dataset"
"${qemu[@]}" "$sim" corridor "$work/dataset" --set duration_s=6 >"$work/sim.log" 2>&1 ||
  "${qemu[@]}" "$sim" corridor "$work/dataset" >"$work/sim.log" 2>&1 ||
  { cat "$work/sim.log" >&2; fail "cleanslam-sim corridor failed"; }
"${qemu[@]}" "$bin" --config "$work/root/etc/cleanslam/cleanslam.yaml" \
  --set source.kind=dataset --set source.path="$work/dataset" \
  --set calibration_from_dataset=true --set sinks.can=false \
  --set sinks.tum="$work/trajectory.tum" --set map.path="$work/map.bin" >"$work/run.log" 2>&1 ||
  { tail -20 "$work/run.log" >&2; fail "the packaged cleanslam failed on the dataset"; }
poses=$(grep -vc '^#' "$work/trajectory.tum" || true)
[ "$poses" -ge 10 ] || fail "only $poses poses written from the dataset"
[ -s "$work/map.bin" ] || fail "no map saved to $work/map.bin: $(grep 'map:' "$work/run.log")"
echo "packaged binary on a simulated dataset: $poses poses, $(grep 'map: saved' "$work/run.log" | tail -1)"
echo "package test: PASS"
