#!/usr/bin/env bash
# clang-tidy over the sources of slam_core and the firmware, and the project headers they include,
# with the repository's .clang-tidy (its checks and its header filter). Configures the host-tidy
# preset (clang, unity batches as the test builds compile them; nothing is built) for its compile
# database and runs run-clang-tidy-14 on $(nproc) jobs over the batches of slam_core's and the
# firmware's targets. A batch includes its sources, which the header filter covers, so each source
# is checked once, and Eigen's templates are parsed and matched once per batch instead of once per
# source. Fails, listing each finding once, when there is any. Prints the time taken; the whole
# output is kept in build/logs/tidy.log.
#   tools/tidy.sh
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1
root=$(pwd)
start=$(date +%s)
log_dir=build/logs
log=$log_dir/tidy.log
mkdir -p "$log_dir"

if ! cmake --preset host-tidy >"$log_dir/host-tidy-configure.log" 2>&1; then
  tail -n 40 "$log_dir/host-tidy-configure.log" >&2
  echo "tidy: configuring the host-tidy preset failed" >&2
  exit 1
fi

jobs=$(nproc 2>/dev/null || echo 2)
# run-clang-tidy selects the database's files by regular expressions on their absolute paths.
root_re=$(printf '%s' "$root" | sed 's/[].[^$*+?(){}|\\]/\\&/g')
# The batches (build/host-tidy/<dir>/CMakeFiles/<target>.dir/Unity/unity_N_cxx.cxx) and any source
# kept out of them. A batch is made of #include "<source>.cpp" lines, which is all that
# bugprone-suspicious-include would report.
run-clang-tidy-14 -p build/host-tidy -j "$jobs" -quiet -checks=-bugprone-suspicious-include \
  "^$root_re/(build/host-tidy/(slam_core|firmware)/.*/Unity/unity_[0-9]+_cxx\.cxx|(slam_core|firmware)/src/.*\.cpp)\$" \
  >"$log" 2>&1
status=$?
elapsed=$(($(date +%s) - start))

# run-clang-tidy colours clang-tidy's output; a header's finding comes once per file including it.
mapfile -t findings < <(sed 's/\x1b\[[0-9;]*m//g' "$log" |
  grep -E '^/[^ ]+:[0-9]+:[0-9]+: (warning|error): ' | sed "s|^$root/||" | sort -u)
files=$(grep -c '^clang-tidy-14 ' <(sed 's/\x1b\[[0-9;]*m//g' "$log"))

if [ ${#findings[@]} -gt 0 ]; then
  echo "tidy: ${#findings[@]} finding(s) in $files files (${elapsed} s; full output: $log):" >&2
  printf '  %s\n' "${findings[@]}" >&2
  echo "tidy: by check:" >&2
  printf '%s\n' "${findings[@]}" | sed -E 's/.*\[([^]]+)\]$/\1/' | sort | uniq -c | sort -nr |
    awk '{ printf "  %4d %s\n", $1, $2 }' >&2
  exit 1
fi
if [ "$status" -ne 0 ] || [ "$files" -eq 0 ]; then
  tail -n 40 "$log" >&2
  echo "tidy: run-clang-tidy failed (exit $status, $files files, ${elapsed} s; full output: $log)" >&2
  exit 1
fi
echo "tidy: $files files, no findings (${elapsed} s)"
