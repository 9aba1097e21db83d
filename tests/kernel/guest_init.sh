#!/bin/busybox sh
# /init of the driver-test guest: modules, vcan0, the checkers, a verdict, power off.
/bin/busybox --install -s /bin
export PATH=/bin
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev
mount -t tmpfs tmpfs /tmp
mount -t debugfs debugfs /sys/kernel/debug
echo 3 > /proc/sys/kernel/printk

verdict=PASS
while read -r mod; do
  case "$mod" in
    vivid.ko) args="n_devs=1 node_types=0x1" ;;
    *) args="" ;;
  esac
  insmod "/modules/$mod" $args || { echo "KERNEL-TEST modules FAIL insmod $mod"; verdict=FAIL; }
done < /modules/load.list
ip link add dev vcan0 type vcan && ip link set vcan0 up || { echo "KERNEL-TEST vcan FAIL"; verdict=FAIL; }

for checker in /checkers/kernel_check_*; do
  [ -x "$checker" ] || continue
  if ! "$checker" /files; then
    verdict=FAIL
  fi
done
echo "KERNEL-VERDICT $verdict"
poweroff -f
