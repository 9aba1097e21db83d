#!/usr/bin/env bash
# The project's test command: installs what is needed, checks the layout (tools/check-format.sh)
# and clang-tidy's findings on slam_core and the firmware (tools/tidy.sh), then configures, builds
# and tests every suite: host (release), sanitizers (ASan+UBSan), aarch64 under qemu-user (with
# the real-kernel driver tests under qemu-system), armhf (hal and slam_core). Exits non-zero on
# any failure.
#   tools/test.sh                   every suite
#   tools/test.sh host-release ...  only the named presets
set -uo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

all_presets=(host-release host-asan aarch64-release armhf-release)
if [ $# -gt 0 ]; then presets=("$@"); else presets=("${all_presets[@]}"); fi

# Only host presets: no cross compilers, qemu or arm64 libraries.
setup_args=(--host-tests)
for p in "${presets[@]}"; do
  case $p in host-release | host-debug | host-asan) ;; *) setup_args=() ;; esac
done
if ! tools/setup.sh "${setup_args[@]}"; then
  echo "test: setup failed (see above)" >&2
  exit 1
fi

jobs=$(nproc 2>/dev/null || echo 2)
total_passed=0
total_failed=0
summary=()
failed_steps=()

if ! tools/check-format.sh; then
  failed_steps+=("format")
fi
if ! tools/tidy.sh; then
  failed_steps+=("tidy")
fi

run_suite() {
  local preset=$1 log_dir="$root/build/logs" start passed=0 failed=0 line
  mkdir -p "$log_dir"
  start=$(date +%s)
  echo "=== $preset: configure and build"
  if ! cmake --preset "$preset" >"$log_dir/$preset-configure.log" 2>&1; then
    tail -n 40 "$log_dir/$preset-configure.log"
    failed_steps+=("$preset configure")
    summary+=("$preset: configure FAILED")
    return
  fi
  if ! cmake --build --preset "$preset" -j "$jobs" >"$log_dir/$preset-build.log" 2>&1; then
    grep -E -A5 'error|Error' "$log_dir/$preset-build.log" | head -n 60
    failed_steps+=("$preset build")
    summary+=("$preset: build FAILED (log: build/logs/$preset-build.log)")
    return
  fi
  echo "=== $preset: tests"
  ctest --preset "$preset" -j "$jobs" 2>&1 | tee "$log_dir/$preset-test.log" | grep -vE '^ *([0-9]+/[0-9]+ Test +#[0-9]+: .* Passed|Start +[0-9]+:)'
  line=$(grep -E 'tests passed, [0-9]+ tests? failed out of [0-9]+' "$log_dir/$preset-test.log" | tail -n 1)
  if [ -z "$line" ]; then
    failed_steps+=("$preset tests (no summary)")
    summary+=("$preset: tests did not run")
    return
  fi
  local failed_n total_n
  failed_n=$(sed -E 's/.* ([0-9]+) tests? failed out of ([0-9]+).*/\1/' <<<"$line")
  total_n=$(sed -E 's/.* ([0-9]+) tests? failed out of ([0-9]+).*/\2/' <<<"$line")
  passed=$((total_n - failed_n))
  failed=$failed_n
  total_passed=$((total_passed + passed))
  total_failed=$((total_failed + failed))
  [ "$failed" -eq 0 ] || failed_steps+=("$preset tests")
  summary+=("$(printf '%-16s %4d passed, %d failed  (%ds)' "$preset:" "$passed" "$failed" $(($(date +%s) - start)))")
}

for p in "${presets[@]}"; do
  run_suite "$p"
done

echo
echo "=== summary"
printf '%s\n' "${summary[@]}"
if [ ${#failed_steps[@]} -gt 0 ]; then
  echo "failed: ${failed_steps[*]}"
  echo "$total_passed passed, $((total_failed > 0 ? total_failed : 1)) failed"
  exit 1
fi
echo "$total_passed passed, $total_failed failed"
