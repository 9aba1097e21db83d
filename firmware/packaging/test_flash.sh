#!/bin/bash
# tools/flash.sh against a fake robot: ssh and scp replaced by scripts that record the commands
# and answer like a healthy (or a failing) robot.
#   test_flash.sh SOURCE_DIR WORK_DIR
set -euo pipefail
src=$1
work=$2
rm -rf "$work"
mkdir -p "$work/pkg/DEBIAN" "$work/pkg/usr/bin"
printf 'Package: cleanslam\nVersion: 9.9.9\nArchitecture: arm64\nMaintainer: t <t@t>\nDescription: t\n' >"$work/pkg/DEBIAN/control"
dpkg-deb --build -Zgzip "$work/pkg" "$work/cleanslam_9.9.9_arm64.deb" >/dev/null

cat >"$work/ssh" <<'EOS'
#!/bin/bash
while [ $# -gt 0 ] && [[ "$1" == -* ]]; do shift 2; done
host=$1; shift
echo "ssh $host $*" >>"$FAKE_LOG"
case "$*" in
  "dpkg --print-architecture") echo arm64 ;;
  systemctl\ show*) echo "$FAKE_STATE" ;;
  dpkg-query*) echo -n 9.9.9 ;;
  "command -v candump >/dev/null") exit 1 ;;
  journalctl*) echo "journal lines" ;;
esac
EOS
cat >"$work/scp" <<'EOS'
#!/bin/bash
echo "scp ${@: -2}" >>"$FAKE_LOG"
EOS
chmod +x "$work/ssh" "$work/scp"

export FAKE_LOG="$work/log" SSH="$work/ssh" SCP="$work/scp"
FAKE_STATE="active running 0 success" "$src/tools/flash.sh" --settle 0 --user robot \
  --deb "$work/cleanslam_9.9.9_arm64.deb" robot.local >"$work/out" 2>&1 ||
  { cat "$work/out"; echo "flash test: FAIL: healthy robot reported unhealthy"; exit 1; }
grep -q "scp .*cleanslam_9.9.9_arm64.deb robot@robot.local:/tmp/cleanslam.deb" "$work/log" ||
  { cat "$work/log"; echo "flash test: FAIL: package not copied"; exit 1; }
grep -q "apt-get install -y --allow-downgrades /tmp/cleanslam.deb" "$work/log" &&
  grep -q "systemctl restart cleanslam.service" "$work/log" ||
  { cat "$work/log"; echo "flash test: FAIL: not installed and restarted"; exit 1; }
grep -q "robot@robot.local healthy" "$work/out" || { cat "$work/out"; exit 1; }

if FAKE_STATE="activating auto-restart 3 watchdog" "$src/tools/flash.sh" --settle 0 \
  --deb "$work/cleanslam_9.9.9_arm64.deb" robot.local >"$work/out2" 2>&1; then
  cat "$work/out2"; echo "flash test: FAIL: a restarting service passed"; exit 1
fi
grep -q "restarted 3 times" "$work/out2" && grep -q "journal lines" "$work/out2" ||
  { cat "$work/out2"; echo "flash test: FAIL: failure not explained"; exit 1; }
echo "flash test: PASS"
