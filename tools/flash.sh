#!/bin/bash
# Installs the cleanslam package on a robot over ssh and checks that it runs.
#   tools/flash.sh [--deb FILE] [--user USER] [--port N] [--settle S] ROBOT_HOST
# Copies the .deb (default: the newest build/aarch64-release/cleanslam_*_arm64.deb), installs it
# with apt (dependencies from the robot's Debian archive), restarts the service and checks its
# health: active, not restarting, watchdog kept, pose frames on the bus when can-utils is there.
# Exit status 0 only when the robot is healthy. SSH and SCP may be overridden (tests do).
set -euo pipefail

here=$(cd "$(dirname "$0")/.." && pwd)
deb="" user="" port="" settle=8
SSH=${SSH:-ssh}
SCP=${SCP:-scp}
while [ $# -gt 0 ]; do
  case "$1" in
    --deb) deb=$2; shift 2 ;;
    --user) user=$2; shift 2 ;;
    --port) port=$2; shift 2 ;;
    --settle) settle=$2; shift 2 ;;
    -h|--help) sed -n '2,8p' "$0"; exit 0 ;;
    -*) echo "flash.sh: unknown option '$1'" >&2; exit 2 ;;
    *) break ;;
  esac
done
[ $# -eq 1 ] || { echo "usage: tools/flash.sh [--deb FILE] [--user USER] [--port N] [--settle S] ROBOT_HOST" >&2; exit 2; }
host=$1
target=${user:+$user@}$host

if [ -z "$deb" ]; then
  deb=$(ls -t "$here"/build/aarch64-release/cleanslam_*_arm64.deb 2>/dev/null | head -1 || true)
  [ -n "$deb" ] || { echo "flash.sh: no package; build it: cmake --build --preset aarch64-release --target package" >&2; exit 2; }
fi
[ -f "$deb" ] || { echo "flash.sh: '$deb' not found" >&2; exit 2; }
arch=$(dpkg-deb -f "$deb" Architecture)
version=$(dpkg-deb -f "$deb" Version)

ssh_opts=(-o BatchMode=yes -o ConnectTimeout=10 ${port:+-p "$port"})
scp_opts=(-o BatchMode=yes -o ConnectTimeout=10 ${port:+-P "$port"})
remote() { "$SSH" "${ssh_opts[@]}" "$target" "$@"; }

echo "flash: $target: checking the robot"
robot_arch=$(remote dpkg --print-architecture) || { echo "flash.sh: cannot reach $target over ssh" >&2; exit 1; }
[ "$robot_arch" = "$arch" ] || { echo "flash.sh: $target is $robot_arch, the package is $arch" >&2; exit 1; }

echo "flash: copying $(basename "$deb") ($version)"
"$SCP" "${scp_opts[@]}" "$deb" "$target:/tmp/cleanslam.deb"

echo "flash: installing and restarting"
remote "sudo apt-get install -y --allow-downgrades /tmp/cleanslam.deb >/tmp/cleanslam-install.log 2>&1 || { tail -20 /tmp/cleanslam-install.log; exit 1; }; rm -f /tmp/cleanslam.deb; sudo systemctl daemon-reload && sudo systemctl enable cleanslam.service && sudo systemctl restart cleanslam.service"

echo "flash: waiting ${settle} s, then checking health"
sleep "$settle"
status=$(remote "systemctl show cleanslam.service -p ActiveState -p SubState -p NRestarts -p Result --value | paste -sd' '")
read -r active sub restarts result <<<"$status"
installed=$(remote "dpkg-query -W -f='\${Version}' cleanslam")
echo "flash: installed $installed; service $active/$sub, $restarts restarts, result $result"
healthy=1
[ "$installed" = "$version" ] || { echo "flash: installed version $installed, expected $version" >&2; healthy=0; }
[ "$active" = active ] && [ "$sub" = running ] || { echo "flash: the service is not running" >&2; healthy=0; }
[ "$restarts" = 0 ] || { echo "flash: the service restarted $restarts times" >&2; healthy=0; }
[ "$result" = success ] || { echo "flash: last result $result (watchdog?)" >&2; healthy=0; }
if remote "command -v candump >/dev/null"; then
  if remote "timeout 3 candump -n 2 can0,201:7FF,202:7FF >/dev/null"; then
    echo "flash: pose frames 0x201/0x202 seen on can0"
  else
    echo "flash: no pose frames on can0 within 3 s" >&2
    healthy=0
  fi
fi
if [ "$healthy" = 1 ]; then
  echo "flash: $target healthy"
  exit 0
fi
echo "flash: $target NOT healthy; recent log:" >&2
remote "journalctl -u cleanslam.service -n 30 --no-pager" >&2 || true
exit 1
