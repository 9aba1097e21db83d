#!/usr/bin/env bash
# Installs every Debian package that building, testing and the demo need: host tools and
# libraries, cross compilers, qemu, and the arm64 multiarch libraries. Idempotent: quiet when
# everything is there; loud, and non-zero, when something cannot be installed.
#   tools/setup.sh              everything (tools/test.sh)
#   tools/setup.sh --host-tests what the host presets' tests need, no cross compilers or qemu
#                               (tools/test.sh host-release host-asan)
#   tools/setup.sh --host-only  what a host build and the demo need (tools/demo.sh)
#   tools/setup.sh --fuzz       that, and clang with libFuzzer (tools/fuzz.sh)
set -euo pipefail

demo_packages=(
  cmake ninja-build pkg-config g++ file python3 python3-numpy python3-matplotlib
  libeigen3-dev libyaml-dev libpng-dev libgtest-dev libbenchmark-dev libgpiod-dev
)
# clang-14, clang-tidy-14: tools/tidy.sh, run by tools/test.sh (its compile database is clang's).
# python3-skimage: its sample photographs (PNG, CC0 or public domain) texture the rendered room of
# the realistic-camera scenario; the simulator reads them as PNG (no Python at run time) and falls
# back to procedural textures, saying so, without them.
host_test_packages=(
  "${demo_packages[@]}" gpiod libopencv-dev python3-opencv python3-yaml valgrind clang-format
  can-utils v4l-utils python3-skimage python3-pytest flake8 clang-14 clang-tidy-14
)
host_packages=(
  "${host_test_packages[@]}" g++-aarch64-linux-gnu g++-arm-linux-gnueabihf qemu-user qemu-user-static
  qemu-system-arm busybox-static cpio kmod
)
arm64_packages=(libgtest-dev:arm64 libyaml-dev:arm64 libpng-dev:arm64 libgpiod-dev:arm64)
fuzz_packages=(clang-14 libclang-rt-14-dev)
host_only=0
fuzz=0
case "${1:-}" in
  "") ;;
  --host-only) host_only=1 ;;
  --host-tests) host_only=1 host_packages=("${host_test_packages[@]}") ;;
  --fuzz) host_only=1 fuzz=1 ;;
  *) echo "usage: tools/setup.sh [--host-tests | --host-only | --fuzz]" >&2; exit 2 ;;
esac

say() { printf 'setup: %s\n' "$*" >&2; }

if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    SUDO=(sudo)
  else
    say "must run as root (or with sudo available) to install packages"
    exit 1
  fi
else
  SUDO=()
fi

missing() {
  local pkg
  for pkg in "$@"; do
    if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q 'install ok installed'; then
      printf '%s\n' "$pkg"
    fi
  done
}

if [ "$host_only" -eq 1 ]; then
  [ "${1:-}" = --host-tests ] || host_packages=("${demo_packages[@]}")
  arm64_packages=()
  if [ "$fuzz" -eq 1 ]; then
    host_packages+=("${fuzz_packages[@]}")
  fi
elif ! dpkg --print-foreign-architectures | grep -qx arm64; then
  say "adding the arm64 architecture (multiarch libraries for the aarch64 cross build)"
  "${SUDO[@]}" dpkg --add-architecture arm64
  need_update=1
fi

mapfile -t todo < <(missing "${host_packages[@]}" "${arm64_packages[@]}")
if [ ${#todo[@]} -eq 0 ]; then
  exit 0
fi

say "installing ${#todo[@]} package(s): ${todo[*]}"
export DEBIAN_FRONTEND=noninteractive
log=$(mktemp /tmp/cleanslam-setup.XXXXXX.log)
if ! "${SUDO[@]}" apt-get -o DPkg::Lock::Timeout=600 update >"$log" 2>&1; then
  say "apt-get update failed; its output:"
  cat "$log" >&2
  exit 1
fi
if ! "${SUDO[@]}" apt-get -o DPkg::Lock::Timeout=600 install -y --no-install-recommends "${todo[@]}" >>"$log" 2>&1; then
  say "apt-get install failed; its output:"
  tail -n 40 "$log" >&2
  mapfile -t still < <(missing "${todo[@]}")
  say "still missing: ${still[*]}"
  exit 1
fi
mapfile -t still < <(missing "${todo[@]}")
if [ ${#still[@]} -ne 0 ]; then
  say "these packages did not install: ${still[*]} (log: $log)"
  exit 1
fi
rm -f "$log"
say "all packages installed"
