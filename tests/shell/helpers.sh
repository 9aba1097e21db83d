# Sourced by the shell tests' common.sh (after EMU and WORK are set): a fresh WORK, and helpers.
rm -rf "$WORK"
mkdir -p "$WORK"
run() {
  # shellcheck disable=SC2086
  $EMU "$@"
}
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
